"""Runs a script inside Blender-as-a-Python-module (the `bpy` package) the way

    blender -b --factory-startup --python-exit-code 1 --python SCRIPT -- ARGS

runs it inside the Blender program:

    <python with bpy> blender_tests/bpy_boot.py SCRIPT [-- ARGS]

Factory settings are loaded first (no user preferences, no user add-ons), sys.argv looks
like Blender's (what follows "--" is the script's), and an uncaught exception exits with
status 1. The script runs as __main__. Plain Python; needs only bpy.
"""

import os
import runpy
import sys
import traceback


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: python bpy_boot.py SCRIPT [-- ARGS]")
    script = os.path.abspath(sys.argv[1])
    rest = sys.argv[2:]
    import bpy

    # bpy as a module reads the user's preferences at import; a test must not see them.
    bpy.ops.wm.read_factory_settings(use_empty=False)
    sys.argv = [sys.executable, "-b", "--python", script] + (rest if rest[:1] == ["--"] else ["--"] + rest)
    code = 0
    try:
        runpy.run_path(script, run_name="__main__")
    except SystemExit as done:
        if isinstance(done.code, str):
            print(done.code, file=sys.stderr)  # sys.exit("message"), as Python prints it
        code = done.code if isinstance(done.code, int) else (0 if done.code is None else 1)
    except BaseException:
        traceback.print_exc()
        code = 1
    if bpy.app.version[:2] == (4, 2):
        # The bpy module of 4.2 crashes while Python finalizes once any registered property has
        # an update callback (a six-line script with one BoolProperty(update=...) does it; 4.5
        # and 5.0 do not). The Blender program unregisters add-ons before that; here the
        # process ends without finalizing, after flushing what it printed.
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)


if __name__ == "__main__":
    main()
