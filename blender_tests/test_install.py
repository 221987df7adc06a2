"""The add-on zip installs the way this version of Blender installs it, and bakes, with nothing else.

Builds the zip with tools/make_addon_zip.py from the library under test
($BAKEGI_LIBRARY's folder, else build/), then starts a separate Blender with
an empty user-scripts folder and config folder and WITHOUT $BAKEGI_LIBRARY,
so the only way it can find the core is the library inside the zip. That
Blender installs the zip (Blender 4.2 and later: as an extension from disk, with
bpy.ops.extensions.package_install_files into the user repository; before: as a legacy
add-on, with bpy.ops.preferences.addon_install), enables it, and bakes a tiny Cornell box.
On 4.2 and later the zip also passes Blender's own extension validator.

BAKEGI_INSTALL_ZIP=<zip> tests that zip instead of packing one: tools/run_tests.sh passes the
portable zip (tools/build_portable.sh) so that the library shipped to users is loaded next to
each version's own TBB and OpenEXR, not only in a root without Blender.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import unittest  # noqa: E402

import bpy  # noqa: E402

CHILD_SCRIPT = r'''
import json, math, os, sys
import addon_utils, bpy
zip_path, scenes = sys.argv[sys.argv.index("--") + 1:]
result = {}
if bpy.app.version >= (4, 2, 0):
    result["install"] = sorted(bpy.ops.extensions.package_install_files(
        filepath=zip_path, repo="user_default", enable_on_install=True))
    result["enabled"] = addon_utils.check("bl_ext.user_default.bakegi")[1]
else:
    result["install"] = sorted(bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True))
    result["enabled"] = addon_utils.enable("bakegi", default_set=True, handle_error=None) is not None
import bakegi
result["module_file"] = bakegi.__file__
from bakegi import native
native.load_library()
result["library"] = native.default_library_path()
result["user_folder"] = sys.modules[bakegi.__name__ + ".compat"].user_folder("bakegi_cache")
sys.path.insert(0, scenes)
import cornell_box
cornell_box.build_cornell_box(subdivisions=2)
report = bakegi.bake(method="pathtrace", samples=8, target="CORNER", objects="VISIBLE")
values = []
for obj in bpy.context.scene.objects:
    if obj.type == "MESH":
        attribute = obj.data.color_attributes["BakeGI_Indirect"]
        values += [c for d in attribute.data for c in d.color[:3]]
result["points"] = report["bake_points"]
result["finite"] = all(math.isfinite(v) for v in values)
result["mean"] = sum(values) / len(values)
print("INSTALL_RESULT " + json.dumps(result), flush=True)
'''


def library_under_test():
    library = os.environ.get("BAKEGI_LIBRARY") or os.path.join(common.ROOT, "build", "libbakegi.so")
    return library if os.path.isfile(library) else None


class InstallFromZip(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scratch = tempfile.mkdtemp(prefix="bakegi_install_test_")
        cls.zip_path = None
        given = os.environ.get("BAKEGI_INSTALL_ZIP")
        if given:
            if not os.path.isfile(given):
                raise AssertionError(f"BAKEGI_INSTALL_ZIP={given}: no such file")
            cls.zip_path = os.path.abspath(given)
            return
        library = library_under_test()
        if library is None:
            return
        dist = os.path.join(cls.scratch, "dist")
        packed = subprocess.run(
            [shutil.which("python3") or "/usr/bin/python3", os.path.join(common.ROOT, "tools", "make_addon_zip.py"),
             "--build-dir", os.path.dirname(os.path.abspath(library)), "--out", dist],
            capture_output=True, text=True, timeout=120)
        if packed.returncode != 0:
            raise AssertionError("make_addon_zip.py failed: " + packed.stdout + packed.stderr)
        zips = [f for f in os.listdir(dist) if f.endswith(".zip")]
        if len(zips) != 1:
            raise AssertionError(f"expected one zip, got {zips}")
        cls.zip_path = os.path.join(dist, zips[0])

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.scratch, ignore_errors=True)

    def setUp(self):
        if self.zip_path is None:
            self.skipTest("no libbakegi.so to pack: run with blender_tests/run.py --library or build into build/")

    def test_install_zip_and_bake(self):
        scratch = tempfile.mkdtemp(dir=self.scratch)
        script = os.path.join(scratch, "child.py")
        with open(script, "w") as f:
            f.write(CHILD_SCRIPT)
        env = {k: v for k, v in os.environ.items() if k not in ("BAKEGI_LIBRARY", "BLENDER_USER_SCRIPTS")}
        env["BLENDER_USER_SCRIPTS"] = os.path.join(scratch, "scripts")
        env["BLENDER_USER_CONFIG"] = os.path.join(scratch, "config")
        env["BLENDER_USER_EXTENSIONS"] = os.path.join(scratch, "extensions")
        env["BLENDER_USER_DATAFILES"] = os.path.join(scratch, "datafiles")
        child = subprocess.run(
            common.blender_script_command(script, [self.zip_path, os.path.join(common.ROOT, "scenes")]),
            capture_output=True, text=True, timeout=300, env=env)
        lines = [l for l in child.stdout.splitlines() if l.startswith("INSTALL_RESULT ")]
        self.assertEqual(child.returncode, 0, child.stdout[-3000:] + child.stderr[-3000:])
        self.assertEqual(len(lines), 1, child.stdout[-3000:])
        result = json.loads(lines[0][len("INSTALL_RESULT "):])
        print("installed:", result)
        installed_root = os.path.realpath(
            env["BLENDER_USER_EXTENSIONS" if bpy.app.version >= (4, 2, 0) else "BLENDER_USER_SCRIPTS"])
        self.assertEqual(result["install"], ["FINISHED"])
        self.assertTrue(result["enabled"], result)
        self.assertTrue(os.path.realpath(result["module_file"]).startswith(installed_root), result)
        self.assertTrue(os.path.realpath(result["library"]).startswith(installed_root), result)
        # Unsaved files' caches: the extension's own user folder (4.2+), else user datafiles.
        user_root = os.path.realpath(
            env["BLENDER_USER_EXTENSIONS" if bpy.app.version >= (4, 2, 0) else "BLENDER_USER_DATAFILES"])
        self.assertTrue(os.path.realpath(result["user_folder"]).startswith(user_root), result)
        self.assertGreater(result["points"], 0)
        self.assertTrue(result["finite"])
        self.assertGreater(result["mean"], 0.0)

    def test_extension_validator_accepts_the_zip(self):
        """Blender's own extension validator (4.2 and later; `blender -c extension validate`)."""
        if bpy.app.version < (4, 2, 0):
            self.skipTest(f"Blender {bpy.app.version_string} has no extension platform (it came in 4.2)")
        validator = os.path.join(bpy.utils.system_resource("SCRIPTS"), "addons_core", "bl_pkg", "cli",
                                 "blender_ext.py")
        self.assertTrue(os.path.isfile(validator), validator)
        checked = subprocess.run([sys.executable, validator, "validate", self.zip_path],
                                 capture_output=True, text=True, timeout=120)
        print(checked.stdout, checked.stderr)
        self.assertEqual(checked.returncode, 0, checked.stdout + checked.stderr)


if __name__ == "__main__":
    common.run_tests(__name__)
