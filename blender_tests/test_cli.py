"""The command-line tool on a scene file the add-on exported: bake, relight, converge.

The CLI (`bakegi`, built next to libbakegi.so) only calls the C API, so these tests check the
commands themselves: exit codes, the files and JSON they write, and the relight check
(a relight must equal a full bake with the changed lights, error exactly 0).
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import numpy  # noqa: E402


def cli_path():
    library = os.environ.get("BAKEGI_LIBRARY", "")
    return os.path.join(os.path.dirname(library), "bakegi") if library else ""


class CommandLine(common.SmallCornellCase):
    def setUp(self):
        super().setUp()
        self.cli = cli_path()
        if not os.path.isfile(self.cli):
            self.skipTest("no bakegi CLI next to the library (run with --library build/libbakegi.so)")
        self.work = tempfile.mkdtemp(prefix="bakegi_cli_")
        self.addCleanup(shutil.rmtree, self.work, ignore_errors=True)
        self.scene = os.path.join(self.work, "cornell.bgs")
        self.bakegi.export_scene_file(self.scene, target="CORNER", objects="VISIBLE")

    def run_cli(self, *arguments, expect=0):
        completed = subprocess.run([self.cli, *arguments], capture_output=True, text=True)
        self.assertEqual(completed.returncode, expect, completed.stderr)
        return completed

    def test_bake_writes_values_and_a_report(self):
        out = os.path.join(self.work, "values.npy")
        report = json.loads(self.run_cli("bake", self.scene, "--method", "antiradiance", "--set", "bins=48",
                                         "--out", out).stdout)
        self.assertEqual(report["method"], "antiradiance")
        self.assertEqual(report["status"], "BAKEGI_OK")
        values = numpy.load(out)
        self.assertEqual(values.shape, (report["bake_points"], 3))
        self.assertTrue(numpy.isfinite(values).all())
        self.assertGreater(float(values.mean()), 0.0)

    def test_bake_states_its_estimated_error(self):
        """The report's estimate, and a line on stderr; a warning above 10% (4 paths)."""
        completed = self.run_cli("bake", self.scene, "--method", "pathtrace", "--samples", "4",
                                 "--out", os.path.join(self.work, "noisy.npy"))
        report = json.loads(completed.stdout)
        self.assertGreater(report["estimated_error"], 0.10)
        self.assertIn(f"estimated error {100 * report['estimated_error']:.1f}%", completed.stderr)
        self.assertIn("WARNING, above 10%", completed.stderr)

    def test_subset_keeps_the_chosen_points_of_the_scene(self):
        """subset writes K distinct points of the file, in file order, the same for a seed."""
        subset = os.path.join(self.work, "subset.bgs")
        indices_path = os.path.join(self.work, "indices.npy")
        self.run_cli("subset", self.scene, "--count", "50", "--seed", "3", "--out", subset,
                     "--indices", indices_path)
        indices = numpy.load(indices_path).astype(numpy.int64)
        self.assertEqual(len(indices), 50)
        self.assertTrue((numpy.diff(indices) > 0).all())
        every, chosen = (os.path.join(self.work, name) for name in ("all.npy", "chosen.npy"))
        self.run_cli("points", self.scene, "--positions", every)
        self.run_cli("points", subset, "--positions", chosen)
        numpy.testing.assert_array_equal(numpy.load(chosen), numpy.load(every)[indices])
        again = os.path.join(self.work, "again.npy")
        self.run_cli("subset", self.scene, "--count", "50", "--seed", "3", "--out", subset,
                     "--indices", again)
        numpy.testing.assert_array_equal(numpy.load(again), numpy.load(indices_path))
        self.run_cli("subset", self.scene, "--count", "50", "--seed", "4", "--out", subset,
                     "--indices", again)
        self.assertFalse(numpy.array_equal(numpy.load(again), numpy.load(indices_path)))

    def test_relight_equals_a_full_bake_of_the_moved_lights(self):
        out = os.path.join(self.work, "relit.npy")
        result = json.loads(self.run_cli("relight", self.scene, "--method", "antiradiance", "--set", "bins=48",
                                         "--move", "0.2,0,-0.1", "--scale", "1.5", "--check", "--out", out).stdout)
        self.assertEqual(result["check"]["error"], 0.0)
        self.assertGreater(result["full_seconds"], 0.0)
        self.assertGreater(result["relight_seconds"], 0.0)
        self.assertEqual(numpy.load(out).shape, (result["points"], 3))

    def test_a_setting_the_method_does_not_read_fails_naming_it(self):
        completed = self.run_cli("bake", self.scene, "--method", "pathtrace", "--set", "bins=300", "--out",
                                 os.path.join(self.work, "x.npy"), expect=1)
        self.assertIn('setting "bins" is not read by method "pathtrace"', completed.stderr)
        listing = self.run_cli("settings", "antiradiance").stdout
        self.assertIn("bins", listing)
        self.assertIn("lighting", listing)

    def test_relight_refuses_a_method_without_precomputation(self):
        completed = self.run_cli("relight", self.scene, "--method", "pathtrace", "--samples", "1",
                                 "--out", os.path.join(self.work, "x.npy"), expect=2)
        self.assertIn("cannot relight", completed.stderr)

    def test_converge_reaches_its_reference(self):
        out = os.path.join(self.work, "convergence.json")
        self.run_cli("converge", self.scene, "--method", "antiradiance", "--set", "bins=48", "--iterations", "4",
                     "--reference-iterations", "4", "--out", out)
        with open(out) as f:
            study = json.load(f)
        symmetric = study["schemes"]["symmetric"]
        self.assertEqual([r["iterations"] for r in symmetric], [1, 2, 3, 4])
        self.assertEqual(len(study["schemes"]["asymmetric"]), 4)
        # Four symmetric iterations are the reference itself; one is far from it.
        self.assertEqual(symmetric[-1]["error"], 0.0)
        self.assertGreater(symmetric[0]["error"], 0.05)

    def test_bake_writes_the_lightmap_exr_of_an_exported_scene(self):
        """export_scene_file(target='LIGHTMAP') writes the .bgs and its .bgl layout; the CLI
        bakes them into the same atlas as the add-on (same method, same seed: identical
        texels, read back through Blender's EXR loader)."""
        import bpy
        scene = os.path.join(self.work, "cornell_lightmap.bgs")
        exported = self.bakegi.export_scene_file(scene, target="LIGHTMAP", objects="VISIBLE",
                                                 texels_per_meter=16.0)
        self.assertTrue(os.path.isfile(exported["lightmap_layout"]))
        out = os.path.join(self.work, "exr")
        completed = self.run_cli("bake", scene, "--method", "antiradiance", "--set", "bins=48",
                                 "--lightmaps", exported["lightmap_layout"], "--exr-dir", out)
        self.assertIn("lightmap_0.exr", completed.stderr)
        cli_image = bpy.data.images.load(os.path.join(out, "lightmap_0.exr"))
        # The UV maps exist now, so the add-on's bake lays out the same atlas.
        report = self.bakegi.bake(method="antiradiance", method_settings={"bins": 48},
                                  target="LIGHTMAP", objects="VISIBLE", texels_per_meter=16.0,
                                  lightmap_folder=self.work)
        self.assertEqual(report["lightmap"]["uv_maps_created"], [])
        addon_image = bpy.data.images[report["lightmap"]["image"]]
        self.assertEqual(tuple(cli_image.size), tuple(addon_image.size))
        a = numpy.empty(len(cli_image.pixels), numpy.float32)
        b = numpy.empty_like(a)
        cli_image.pixels.foreach_get(a)
        addon_image.pixels.foreach_get(b)
        self.assertGreater(float(a.max()), 0.0)
        numpy.testing.assert_array_equal(a, b)


if __name__ == "__main__":
    common.run_tests(__name__)
