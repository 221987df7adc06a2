"""The scripting API: bakegi.bake's report, both targets, remove_bake, and undo of the operator."""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

import metrics  # noqa: E402

NAMES = ("Floor", "Ceiling", "BackWall", "LeftWall", "RightWall", "ShortBox", "TallBox")


class Scripting(common.SmallCornellCase):

    def test_report(self):
        report = self.bakegi.bake(method="pathtrace", samples=16, seed=3, target="CORNER", objects="VISIBLE")
        for key in ("seconds", "bake_points", "method", "settings", "warnings"):
            self.assertIn(key, report)
        memory = [k for k in report if k.startswith("memory")]
        self.assertTrue(memory, "the report gives no memory figure")
        self.assertGreater(report[memory[0]], 0)
        corners = sum(len(self.objects[n].data.loops) for n in NAMES)
        self.assertEqual(report["bake_points"], corners)
        self.assertEqual(report["method"], "pathtrace")
        self.assertEqual(report["settings"]["samples"], 16)
        self.assertEqual(report["settings"]["seed"], 3)
        self.assertIsInstance(report["warnings"], list)
        self.assertGreater(report["seconds"]["total"], 0.0)
        print("report:", {k: report[k] for k in ["seconds", "bake_points", "warnings"] + memory})

    def test_corners_that_share_a_vertex_are_baked_once(self):
        """Corners of one vertex with one normal are offered to the core as one point
        (export/point_sharing.py), which bakes them once where no surface meets the mesh
        there (a ray between them is free): far fewer points are evaluated than corners are
        written, and on the back wall, which nothing inside the box touches, the corners of
        every vertex carry one value."""
        report = self.bakegi.bake(method="pathtrace", samples=4, seed=1, target="CORNER",
                                  objects="VISIBLE")
        corners = sum(len(self.objects[n].data.loops) for n in NAMES)
        self.assertEqual(report["bake_points"], corners)
        self.assertLess(report["evaluated_points"], corners / 2)
        mesh = self.objects["BackWall"].data
        colors = numpy.empty(len(mesh.loops) * 4, numpy.float32)
        mesh.color_attributes[common.ATTRIBUTE].data.foreach_get("color", colors)
        colors = colors.reshape(-1, 4)
        loop_vertex = numpy.empty(len(mesh.loops), numpy.int32)
        mesh.loops.foreach_get("vertex_index", loop_vertex)
        first = {}
        for corner, vertex in enumerate(loop_vertex):
            first.setdefault(int(vertex), corner)
        same = [numpy.array_equal(colors[c], colors[first[int(v)]]) for c, v in enumerate(loop_vertex)]
        self.assertTrue(all(same), f"{same.count(False)} back wall corners differ from their vertex's first")

    def test_denoise_reaches_the_core_and_lowers_the_noise(self):
        """The panel's Denoise asks the core to filter a path-traced bake; the core's
        prediction of the noise left (bake/point_denoiser.h) falls well below the noise
        before (measured 3-5x on rooms at 16 samples)."""
        scene = bpy.context.scene
        scene.bakegi.method = "pathtrace"
        scene.bakegi.denoise = True
        self.assertEqual(scene.bakegi.request().method_settings.get("denoise"), 1)
        report = self.bakegi.bake(method="pathtrace", samples=16, seed=1, target="CORNER",
                                  objects="VISIBLE", estimate_error=False,
                                  method_settings={"denoise": 1})
        self.assertEqual(report["settings"]["denoise"], 1)
        self.assertLess(report["denoise_noise_after"], 0.5 * report["denoise_noise_before"])
        scene.bakegi.denoise = False
        self.assertNotIn("denoise", scene.bakegi.request().method_settings)

    def test_quality_is_a_target_error(self):
        """Path tracing's Quality asks the core for an error (Draft 10%, Good 5%, Final 2%)
        with a high cap on samples; Fixed Samples asks for exactly Samples. A Draft bake
        reports what it predicts for itself, at or below the target."""
        scene = bpy.context.scene
        scene.bakegi.method = "pathtrace"
        scene.bakegi.samples = 32
        expected = {"DRAFT": 0.10, "GOOD": 0.05, "FINAL": 0.02}
        for quality, target in expected.items():
            scene.bakegi.quality = quality
            request = scene.bakegi.request()
            self.assertEqual(request.method_settings.get("target_error"), target)
            self.assertGreater(request.samples, 1000)
        scene.bakegi.quality = "SAMPLES"
        request = scene.bakegi.request()
        self.assertNotIn("target_error", request.method_settings)
        self.assertEqual(request.samples, 32)
        scene.bakegi.quality = "DRAFT"
        scene.bakegi.objects = "VISIBLE"
        scene.bakegi.estimate_error = False
        self.assertEqual(bpy.ops.bakegi.bake_indirect(), {"FINISHED"})
        report = json.loads(scene.bakegi.last_report)
        self.assertEqual(report["settings"]["target_error"], 0.1)
        self.assertLessEqual(report["sampling_predicted_error"], 0.1)
        scene.bakegi.quality = "GOOD"

    def test_add_on_preferences_reach_the_bake(self):
        """Threads and the memory budget come from the add-on preferences, unless the call
        names them."""
        preferences = bpy.context.preferences.addons["bakegi"].preferences
        self.addCleanup(setattr, preferences, "threads", 0)
        self.addCleanup(setattr, preferences, "memory_budget_mb", 0)
        preferences.threads = 1
        preferences.memory_budget_mb = 3000
        report = self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        self.assertEqual(report["settings"]["threads"], 1)
        self.assertEqual(report["settings"]["memory_budget_mb"], 3000)
        report = self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE",
                                  threads=2, method_settings={"memory_budget_mb": 2000})
        self.assertEqual(report["settings"]["threads"], 2)
        self.assertEqual(report["settings"]["memory_budget_mb"], 2000)
        # A budget too small for the method is the core's error, naming the setting.
        preferences.memory_budget_mb = 1
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="antiradiance", target="CORNER", objects="VISIBLE",
                             method_settings={"fallback": 0})
        self.assertIn("memory_budget_mb", str(caught.exception))

    def test_an_unsaved_file_writes_its_lightmap_to_the_add_on_user_folder(self):
        from bakegi import compat

        self.assertEqual(bpy.data.filepath, "")
        report = self.bakegi.bake(method="pathtrace", samples=4, target="LIGHTMAP", objects=["Floor"],
                                  texels_per_meter=8.0)
        folder = os.path.realpath(compat.user_folder("bakegi_lightmaps"))
        path = os.path.realpath(report["lightmap"]["path"])
        self.assertTrue(path.startswith(folder + os.sep), (path, folder))
        self.assertTrue(os.path.isfile(path))

    def test_rebake_is_deterministic_and_ignores_its_own_hook(self):
        """A second bake with the same seed reproduces the first exactly: the materials hooked by
        the first bake (albedo x baked indirect) must not feed back into the next export."""
        self.bakegi.bake(method="pathtrace", samples=64, seed=7, target="CORNER", objects="VISIBLE")
        first = common.read_color_attribute(NAMES, domain="CORNER")
        self.bakegi.bake(method="pathtrace", samples=64, seed=7, target="CORNER", objects="VISIBLE")
        second = common.read_color_attribute(NAMES, domain="CORNER")
        numpy.testing.assert_array_equal(first, second)

    def test_corner_and_point_targets_agree(self):
        """Every vertex lies in one flat face's plane (faces do not share vertices across edges),
        so a per-vertex bake equals the per-corner bake at the corners of that vertex, up to noise."""
        samples = 256
        self.bakegi.bake(method="pathtrace", samples=samples, seed=0, target="CORNER", objects="VISIBLE")
        corner = common.read_color_attribute(NAMES, domain="CORNER")
        self.bakegi.bake(method="pathtrace", samples=samples, seed=1, target="POINT", objects="VISIBLE")
        point_per_vertex = [common.read_color_attribute([n], domain="POINT") for n in NAMES]
        self.assertEqual(sum(len(p) for p in point_per_vertex), sum(len(self.objects[n].data.vertices) for n in NAMES))
        # Spread the vertex values over the corners.
        point = numpy.concatenate(
            [p[[loop.vertex_index for loop in self.objects[n].data.loops]] for n, p in zip(NAMES, point_per_vertex)]
        )
        # Noise: the two bakes use different seeds. Each corner value comes from `samples`
        # paths; at 256 samples the Cornell box's per-point noise is about 9 % (relative RMSE,
        # Cycles' 8192-sample bake measures 1.3 % and noise scales as 1/sqrt(samples)), so two
        # independent bakes differ by about 13 %. A wrong mapping (values of other vertices, other
        # objects) or a mis-scaled domain differs by 50-100 %.
        error = metrics.relative_rmse(point, corner)
        print(f"POINT vs CORNER at {samples} samples: relative RMSE {100 * error:.1f}%")
        self.assertLess(error, 0.25)
        # A vertex domain attribute, one per vertex, on every target.
        for name in NAMES:
            attribute = self.objects[name].data.color_attributes[common.ATTRIBUTE]
            self.assertEqual(attribute.domain, "POINT")
            self.assertEqual(attribute.data_type, "FLOAT_COLOR")

    def test_a_vertex_of_a_flat_box_gets_the_mean_of_its_corners(self):
        """A flat-shaded box shares each vertex between three faces of different normals: the
        vertex gets the mean of its three corners, as Cycles writes a vertex colour (one point
        at the vertex with the faces' mean normal lay inside the box: 0 on every vertex)."""
        bpy.ops.mesh.primitive_cube_add(size=0.3, location=(0.45, 0.45, 1.0))
        cube = bpy.context.active_object
        samples = 256
        self.bakegi.bake(method="pathtrace", samples=samples, seed=0, target="CORNER",
                         objects=[cube], estimate_error=False)
        corner = common.read_color_attribute([cube], domain="CORNER")
        self.bakegi.bake(method="pathtrace", samples=samples, seed=1, target="POINT",
                         objects=[cube], estimate_error=False)
        vertex = common.read_color_attribute([cube], domain="POINT")
        loop_vertex = numpy.array([loop.vertex_index for loop in cube.data.loops])
        means = numpy.zeros((len(cube.data.vertices), 3))
        numpy.add.at(means, loop_vertex, corner)
        means /= numpy.bincount(loop_vertex, minlength=len(means))[:, None]
        self.assertTrue((vertex.min(axis=1) > 0.0).all(), vertex)
        # Noise: about 9% a corner at 256 paths (the Cornell box, above), a mean of three
        # about 5%, two independent means about 7% apart. The faces' values differ by 20-60%
        # (the side facing the red wall, the top under the lamp), so a vertex that took one
        # face's value, or the old 0, lies far outside.
        error = metrics.relative_rmse(vertex, means)
        spread = metrics.relative_rmse(corner, means[loop_vertex])
        print(f"flat box: vertex bake against its corners' means {100 * error:.1f}%, "
              f"corners against their vertex's mean {100 * spread:.1f}%")
        self.assertLess(error, 0.15)

    def test_remove_bake_restores(self):
        before = common.scene_snapshot()
        self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        baked = common.scene_snapshot()
        self.assertNotEqual(common.snapshot_difference(before, baked), [], "the bake changed nothing")
        self.bakegi.remove_bake(objects="VISIBLE")
        differences = common.snapshot_difference(before, common.scene_snapshot())
        self.assertEqual(differences, [], "\n".join(differences[:20]))

    def test_remove_bake_operator_restores(self):
        before = common.scene_snapshot()
        self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        bpy.context.scene.bakegi.objects = "VISIBLE"
        self.assertEqual(bpy.ops.bakegi.remove_bake(), {"FINISHED"})
        differences = common.snapshot_difference(before, common.scene_snapshot())
        self.assertEqual(differences, [], "\n".join(differences[:20]))

    def test_operator_bakes_in_background(self):
        """In background mode the operator bakes synchronously (undo needs a window: see test_ui.py)."""
        scene = bpy.context.scene
        scene.bakegi.objects = "VISIBLE"
        scene.bakegi.samples = 4
        self.assertEqual(bpy.ops.bakegi.bake_indirect(), {"FINISHED"})
        for name in NAMES:
            self.assertIn(common.ATTRIBUTE, bpy.data.objects[name].data.color_attributes)

    def test_export_scene_file(self):
        path = os.path.join(bpy.app.tempdir or "/tmp", "bakegi_test_scene.bgs")
        result = self.bakegi.export_scene_file(path, target="CORNER", objects="VISIBLE")
        self.assertTrue(os.path.getsize(path) > 0)
        corners = sum(len(self.objects[n].data.loops) for n in NAMES)
        self.assertEqual(sum(t["count"] for t in result["targets"]), corners)

    def test_curves_text_and_metaballs_are_exported_once(self):
        """The depsgraph hands a curve, text, surface or metaball over twice: as itself and as
        its evaluated mesh (an instance of its own). The bake takes the mesh once, as Cycles
        does; it used to take both, every triangle twice."""
        bpy.ops.curve.primitive_bezier_circle_add(radius=0.2, location=(0.4, 0.4, 1.0))
        bpy.context.active_object.data.bevel_depth = 0.03
        bpy.ops.object.text_add(location=(-0.5, 0.5, 1.5))
        bpy.context.active_object.data.extrude = 0.02
        bpy.ops.object.metaball_add(radius=0.2, location=(0.5, -0.5, 1.4))
        path = os.path.join(bpy.app.tempdir or "/tmp", "bakegi_test_curves.bgs")
        result = self.bakegi.export_scene_file(path, target="CORNER", objects="VISIBLE")
        expected = 0
        for instance in bpy.context.evaluated_depsgraph_get().object_instances:
            if instance.object.type == "MESH":
                mesh = instance.object.data
                mesh.calc_loop_triangles()
                expected += len(mesh.loop_triangles)
        curve_meshes = expected - sum(len(self.objects[n].data.polygons) * 2 for n in NAMES)
        self.assertGreater(curve_meshes, 100)  # the three made meshes
        self.assertEqual(result["counts"]["triangles"], expected)


class PanelAgreesWithTheCore(common.AddonCase):
    """The panel's method settings stay inside the core's schemas (docs/settings.md): same
    defaults, and no value the panel allows that the core would refuse (register() reads
    them from the schema; before it did, this test found the panel allowing iterations and
    epsilon the core refuses). The panel's default method is the core's."""

    def test_panel_defaults_and_ranges_lie_in_the_schema(self):
        from bakegi import native
        from bakegi.ui import properties
        panel = bpy.context.scene.bakegi.bl_rna.properties
        self.assertEqual(panel["method"].default, native.default_method())
        self.assertEqual(bpy.context.scene.bakegi.request().method, native.default_method())
        # The panel's defaults ask for the core's default bake (the path tracer to 5% through
        # the denoiser), as bakegi.bake() without a method does.
        from bakegi.request import BakeRequest
        panel_settings = bpy.context.scene.bakegi.request().core_settings()
        script_settings = BakeRequest().core_settings()
        for key, value in native.default_method_settings().items():
            with self.subTest(key=key):
                self.assertEqual(panel_settings[key], value)
                self.assertEqual(script_settings[key], value)
        self.assertEqual(script_settings["method"], native.default_method())
        for item in panel["method"].enum_items:
            self.assertIn(item.identifier, native.method_names())
        for prop_name, method, key in properties.SCHEMA_PROPERTIES:
            with self.subTest(prop=prop_name):
                spec = {s["key"]: s for s in native.describe_settings(method)["settings"]}[key]
                prop = panel[prop_name]
                self.assertAlmostEqual(prop.default, spec["default"], places=6)
                self.assertGreaterEqual(prop.hard_min, spec["min"])
                self.assertLessEqual(prop.hard_max, spec["max"])


class ScriptBuiltScene(common.AddonCase):
    """A script that makes objects with bpy.data and bakes at once: the view layer's object
    list is not updated until something updates it, and the add-on must do that itself."""

    def test_light_linking_is_named_in_the_warnings(self):
        """Light linking (Blender 4.0+) is not modelled: a bake says which lights set it."""
        if "light_linking" not in bpy.types.Object.bl_rna.properties:
            self.skipTest(f"Blender {bpy.app.version_string} has no light linking (it came in 4.0)")
        import cornell_box
        common.new_empty_scene()
        cornell_box.build_cornell_box(cornell_box.TEST_SUBDIVISIONS)
        report = self.bakegi.bake(method="pathtrace", samples=2, objects="VISIBLE")
        self.assertFalse([w for w in report["warnings"] if "light linking" in w])
        receivers = bpy.data.collections.new("Lit by the lamp only")
        receivers.objects.link(bpy.data.objects["Floor"])
        bpy.data.objects["CeilingLight"].light_linking.receiver_collection = receivers
        report = self.bakegi.bake(method="pathtrace", samples=2, objects="VISIBLE")
        linking = [w for w in report["warnings"] if "light linking is ignored" in w]
        self.assertEqual(len(linking), 1, report["warnings"])
        self.assertIn("CeilingLight", linking[0])

    def test_eevee_raytracing_is_named_in_the_warnings(self):
        """EEVEE Next's Raytracing spreads the camera-only emission that shows the bake
        (tools/eevee_double_light_probe.py measured it): a bake with it on says so."""
        if "use_raytracing" not in bpy.types.SceneEEVEE.bl_rna.properties:
            self.skipTest(f"Blender {bpy.app.version_string}'s EEVEE has no Raytracing (EEVEE Next came in 4.2)")
        import cornell_box
        common.new_empty_scene()
        cornell_box.build_cornell_box(cornell_box.TEST_SUBDIVISIONS)
        scene = bpy.context.scene
        scene.eevee.use_raytracing = False
        report = self.bakegi.bake(method="pathtrace", samples=2, objects="VISIBLE")
        self.assertFalse([w for w in report["warnings"] if "Raytracing" in w])
        scene.eevee.use_raytracing = True
        report = self.bakegi.bake(method="pathtrace", samples=2, objects="VISIBLE")
        self.assertEqual(len([w for w in report["warnings"] if "EEVEE's Raytracing is on" in w]), 1,
                         report["warnings"])

    def test_visible_objects_made_by_the_script_are_baked(self):
        common.new_empty_scene()
        scene = bpy.context.scene
        import bmesh
        mesh = bpy.data.meshes.new("Room")
        bm = bmesh.new()
        bmesh.ops.create_cube(bm, size=2.0)
        bmesh.ops.reverse_faces(bm, faces=bm.faces[:])  # normals inwards: a closed room
        bm.to_mesh(mesh)
        bm.free()
        room = bpy.data.objects.new("Room", mesh)
        scene.collection.objects.link(room)
        lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
        lamp.data.energy = 100.0
        scene.collection.objects.link(lamp)
        report = self.bakegi.bake(method="pathtrace", samples=4, objects="VISIBLE")
        self.assertEqual(report["bake_points"], len(mesh.loops))
        self.assertIn(common.ATTRIBUTE, mesh.color_attributes)


if __name__ == "__main__":
    common.run_tests(__name__)
