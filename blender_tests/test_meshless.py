"""The meshless method in Blender: a bake with its statistics, and live indirect (a moved light
relit from the kept precomputation equals a full bake with the light there; what pauses it)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import unittest  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

NAMES = ("Floor", "Ceiling", "BackWall", "LeftWall", "RightWall", "ShortBox", "TallBox")
# A quicker precompute for the tests of live indirect's plumbing (the accuracy test keeps the
# defaults): fewer levels and gather rays.
QUICK = {"levels": 3, "gather_rays": 64}


class Meshless(common.SmallCornellCase):

    def tearDown(self):
        self.bakegi.live_stop()

    def _move_light(self, dx=0.25, dy=-0.15, power_scale=1.5):
        light = self.objects["CeilingLight"]
        light.location.x += dx
        light.location.y += dy
        light.data.energy *= power_scale

    def test_bake_reports_statistics_and_agrees_with_the_path_tracer(self):
        report = self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE")
        for key in ("meshless_points", "meshless_points_per_level", "meshless_links",
                    "meshless_potential_links", "meshless_links_kept_percent",
                    "meshless_refinement_rays", "meshless_bounces", "memory_bytes"):
            self.assertIn(key, report)
        self.assertEqual(sum(report["meshless_points_per_level"]), report["meshless_points"])
        self.assertLess(report["meshless_links"], report["meshless_potential_links"])
        self.assertIn("basis functions", bpy.context.scene.bakegi.last_result)
        meshless = common.read_color_attribute(NAMES, domain="CORNER")
        self.bakegi.bake(method="pathtrace", samples=256, seed=1, target="CORNER", objects="VISIBLE")
        traced = common.read_color_attribute(NAMES, domain="CORNER")
        # The mean over all corners: the path tracer's mean of about 1,000 corners x 256
        # paths is within 1% of converged; meshless is 6-7% off per point on the Cornell box
        # (docs/methods/meshless.md), with a mean bias of a few percent. 10% flags a wrong
        # scale (a missing 1/pi, a missing bounce: 20-40%) but not the method's own bias.
        ratio = meshless.mean(axis=0) / traced.mean(axis=0)
        print("meshless / path tracer, mean per channel:", ratio)
        numpy.testing.assert_allclose(ratio, 1.0, atol=0.10)

    def test_remove_bake_after_a_live_session_restores_the_scene_exactly(self):
        """Bake with live indirect, relight three times, stop, Remove Bake: every material
        (nodes, values, links), attribute and data-block count is as before the bake."""
        light = bpy.data.objects["CeilingLight"]
        start = tuple(light.location)
        before = common.scene_snapshot()
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE", live=True,
                         method_settings=QUICK)
        for _ in range(3):
            light.location.x += 0.1
            bpy.context.view_layer.update()
            self.bakegi.live_update()
        self.bakegi.live_stop()
        self.bakegi.remove_bake()
        light.location = start
        self.assertEqual(common.snapshot_difference(before, common.scene_snapshot()), [])

    def test_live_relight_equals_a_full_bake_with_the_moved_light(self):
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE", live=True,
                         method_settings=QUICK)
        before = common.read_color_attribute(NAMES, domain="CORNER")
        self._move_light()
        timings = self.bakegi.live_update()
        relit = common.read_color_attribute(NAMES, domain="CORNER")
        print("live update:", {k: round(v * 1000, 2) if isinstance(v, float) else v
                               for k, v in timings.items()}, "(ms)")
        self.assertEqual(timings["bake_points"], len(relit))
        # The light moved and got 1.5x brighter: the bake must follow.
        self.assertGreater(abs(relit.sum() / before.sum() - 1.0), 0.2)
        self.bakegi.live_stop()
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE",
                         method_settings=QUICK)
        full = common.read_color_attribute(NAMES, domain="CORNER")
        # Same geometry, settings and seed make the same precomputation; the relight then
        # runs the same lighting code, so the two agree to float rounding.
        numpy.testing.assert_allclose(relit, full, rtol=1e-5, atol=1e-7)

    def test_live_relight_turns_a_world_image(self):
        """With an HDRI world, a relight re-exports the world into the baked scene: the same
        image keeps its texture (the core refuses a relight whose textures changed), so
        turning the sky or moving a light relights, and the result equals a full bake."""
        import light_units
        world = light_units.set_image_world(bpy.context.scene)
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE", live=True,
                         method_settings=QUICK)
        mapping = next(n for n in world.node_tree.nodes if n.type == "MAPPING")
        mapping.inputs["Rotation"].default_value[2] += 0.5
        self._move_light()
        bpy.context.view_layer.update()
        self.bakegi.live_update()
        relit = common.read_color_attribute(NAMES, domain="CORNER")
        self.bakegi.live_stop()
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE",
                         method_settings=QUICK)
        numpy.testing.assert_allclose(relit, common.read_color_attribute(NAMES, domain="CORNER"),
                                      rtol=1e-5, atol=1e-7)

    def test_handler_relights_on_light_changes_and_ignores_its_own_writes(self):
        live = sys.modules["bakegi.live"]
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE", live=True,
                         method_settings=QUICK)
        bpy.context.view_layer.update()  # the bake's own write and material hooks
        state = live.state()
        self.assertIsNotNone(state)
        self.assertEqual(state.paused, "", "BakeGI's own write paused live indirect")
        self.assertFalse(state.pending)
        self._move_light()
        bpy.context.view_layer.update()
        self.assertTrue(state.pending, "moving the light did not ask for a relight")
        self.bakegi.live_update()
        bpy.context.view_layer.update()
        self.assertEqual(state.paused, "", "the relight's own write paused live indirect")
        self.objects["CeilingLight"].data.color = (0.5, 0.8, 1.0)
        bpy.context.view_layer.update()
        self.assertTrue(state.pending, "a light's colour change did not ask for a relight")

    def test_moved_mesh_or_changed_material_pauses_live_indirect(self):
        live = sys.modules["bakegi.live"]
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE", live=True,
                         method_settings=QUICK)
        bpy.context.view_layer.update()
        self.objects["TallBox"].location.x += 0.1
        with self.assertRaises(self.bakegi.BakeGIError) as raised:
            self.bakegi.live_update()
        self.assertIn("TallBox", raised.exception.message)
        self.assertIn("TallBox", live.status_text())
        # A new bake starts again from the changed scene; then a material edit pauses it.
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE", live=True,
                         method_settings=QUICK)
        bpy.context.view_layer.update()
        material = self.objects["LeftWall"].active_material
        bsdf = next(n for n in material.node_tree.nodes if n.type == "BSDF_DIFFUSE")
        bsdf.inputs["Color"].default_value = (0.1, 0.9, 0.1, 1.0)
        bpy.context.view_layer.update()
        self.assertIn(material.name, live.state().paused)

    def test_cache_from_the_panel_settings_hits_and_detects_a_changed_material(self):
        import json
        import tempfile

        settings = bpy.context.scene.bakegi
        settings.method = "meshless"
        settings.meshless_levels = 3
        settings.objects = "VISIBLE"
        settings.use_cache = True
        preferences = bpy.context.preferences.addons["bakegi"].preferences
        self.addCleanup(setattr, preferences, "cache_folder", "")
        with tempfile.TemporaryDirectory() as folder:
            preferences.cache_folder = folder
            results = []
            for _ in range(2):
                self.assertEqual(bpy.ops.bakegi.bake_indirect(), {"FINISHED"})
                results.append((json.loads(settings.last_report),
                                common.read_color_attribute(NAMES, domain="CORNER")))
            (first, first_values), (second, second_values) = results
            self.assertEqual(first["meshless_cache"], "miss")
            self.assertEqual(second["meshless_cache"], "hit")
            self.assertEqual(second["meshless_refinement_rays"], 0)
            self.assertEqual(second["meshless_links"], first["meshless_links"])
            numpy.testing.assert_array_equal(first_values, second_values)
            self.assertIn("cache hit", settings.last_result)
            # Another albedo is another precomputation: a new key, never the old file.
            material = self.objects["LeftWall"].active_material
            bsdf = next(n for n in material.node_tree.nodes if n.type == "BSDF_DIFFUSE")
            bsdf.inputs["Color"].default_value = (0.1, 0.9, 0.1, 1.0)
            self.assertEqual(bpy.ops.bakegi.bake_indirect(), {"FINISHED"})
            third = json.loads(settings.last_report)
            self.assertEqual(third["meshless_cache"], "miss")
            self.assertEqual(len(os.listdir(folder)), 2)
            # The panel's Clear Cache deletes them (and is unavailable on an empty folder).
            self.assertEqual(bpy.ops.bakegi.clear_cache(), {"FINISHED"})
            self.assertEqual(os.listdir(folder), [])
            self.assertFalse(bpy.ops.bakegi.clear_cache.poll())

    def test_a_blend_relative_cache_dir_is_not_the_filesystem_root(self):
        """method_settings={"cache_dir": "//x"} is Blender's "next to the .blend" (for an
        unsaved file: the add-on's user folder), as the panel's folders are; the core used to
        take it for /x and write the cache at the filesystem root."""
        compat = sys.modules["bakegi.compat"]
        report = self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE",
                                  method_settings={**QUICK, "cache_dir": "//bakegi_test_cache"})
        path = report["meshless_cache_path"]
        self.assertFalse(path.startswith("//"), path)
        self.assertFalse(os.path.exists("/bakegi_test_cache"), "the cache went to the root")
        if not bpy.data.filepath:
            folder = os.path.realpath(compat.user_folder("bakegi_cache"))
            self.assertTrue(os.path.realpath(path).startswith(folder + os.sep), (path, folder))
        self.assertTrue(os.path.isfile(path), path)
        os.remove(path)

    def test_live_needs_a_method_that_relights(self):
        before = common.scene_snapshot()
        with self.assertRaises(self.bakegi.BakeGIError) as raised:
            self.bakegi.bake(method="antiradiance", objects="VISIBLE", live=True)
        self.assertIn("meshless", raised.exception.message)
        with self.assertRaises(self.bakegi.BakeGIError):
            self.bakegi.live_update()
        self.assertEqual(common.snapshot_difference(before, common.scene_snapshot()), [])

    def test_another_bake_ends_live_indirect(self):
        live = sys.modules["bakegi.live"]
        self.bakegi.bake(method="meshless", target="CORNER", objects="VISIBLE", live=True,
                         method_settings=QUICK)
        self.assertIsNotNone(live.state())
        self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        self.assertIsNone(live.state(), "a path-traced bake left live indirect to overwrite it")


if __name__ == "__main__":
    common.run_tests(__name__)
