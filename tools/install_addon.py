"""Installs and enables the bakegi add-on zip in Blender, and saves the preferences.

    blender -b --factory-startup --python tools/install_addon.py -- dist/bakegi-0.1.0-linux-x64.zip

Prints where the add-on was installed. Exits with status 1 if it cannot be enabled or its
core library cannot be loaded.
"""

import os
import sys

import addon_utils
import bpy


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        print("usage: blender -b --factory-startup --python tools/install_addon.py -- "
              "<bakegi zip>", file=sys.stderr)
        return 1
    zip_path = os.path.abspath(argv[0])
    if not os.path.isfile(zip_path):
        print(f"install_addon: {zip_path} not found", file=sys.stderr)
        return 1
    # --factory-startup keeps the user's settings out of this session; saving must still
    # write the user's preferences file.
    bpy.context.preferences.use_preferences_save = True
    result = bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    if result != {"FINISHED"}:
        print(f"install_addon: installing {zip_path} failed: {result}", file=sys.stderr)
        return 1
    bpy.ops.preferences.addon_enable(module="bakegi")
    if not addon_utils.check("bakegi")[1]:
        print("install_addon: the add-on was installed but could not be enabled",
              file=sys.stderr)
        return 1
    import bakegi
    from bakegi import native

    try:
        version = native.version_string()
    except native.BakeGIError as error:
        print(f"install_addon: {error.message}", file=sys.stderr)
        return 1
    bpy.ops.wm.save_userpref()
    print(f"bakegi installed at {os.path.dirname(bakegi.__file__)} (core {version}); "
          f"enabled in {bpy.utils.user_resource('CONFIG')}")
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    if code:
        sys.exit(code)
