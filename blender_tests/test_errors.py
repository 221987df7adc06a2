"""Error paths in Blender: a clear message, and the scene exactly as before.

"Unchanged" is checked with common.scene_snapshot(): every mesh's attributes
(names, domains, types, a checksum of their values, active colour), every
material's nodes, socket values and links, and data-block counts.
"""

import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import unittest  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402



class ErrorPaths(common.SmallCornellCase):

    def assertSceneUnchanged(self, before):
        differences = common.snapshot_difference(before, common.scene_snapshot())
        self.assertEqual(differences, [], "the scene changed:\n" + "\n".join(differences[:20]))

    def test_nan_vertex_names_the_object(self):
        self.objects["ShortBox"].data.vertices[5].co = (math.nan, 0.1, 0.2)
        before = common.scene_snapshot()
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        message = str(caught.exception)
        print("NaN vertex message:", message)
        self.assertIn("ShortBox", message)
        self.assertTrue("nan" in message.lower() or "finite" in message.lower(), message)
        self.assertSceneUnchanged(before)

    def test_infinite_vertex_in_a_non_target_is_refused_too(self):
        # The floor takes part in the light transport even when only the ceiling is baked.
        self.objects["Floor"].data.vertices[0].co = (math.inf, 0.0, 0.0)
        before = common.scene_snapshot()
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects=[self.objects["Ceiling"]])
        self.assertIn("Floor", str(caught.exception))
        self.assertSceneUnchanged(before)

    def test_a_target_scaled_to_zero_is_named_and_skipped(self):
        """Scaling an object to 0 is a common way to hide it in an animation: it has no
        surface and no normals, and the whole bake used to fail on "bake point N: normal
        is the zero vector". It is named and left out; the rest is baked."""
        box = self.objects["ShortBox"]
        box.scale = (0.0, 0.0, 0.0)
        bpy.context.view_layer.update()
        report = self.bakegi.bake(method="pathtrace", samples=4, target="CORNER",
                                  objects="VISIBLE", estimate_error=False)
        self.assertTrue(any("'ShortBox'" in w and "scale is 0" in w for w in report["warnings"]),
                        report["warnings"])
        self.assertNotIn("ShortBox", report["objects"])
        self.assertIn("TallBox", report["objects"])

    def test_a_bad_material_or_light_is_named(self):
        """The core checks every material and light; its message names them by Blender's
        names, not by its own numbers ("material 1", "light 0")."""
        material = bpy.data.materials.new("TooHot")
        material.use_nodes = True
        bsdf = material.node_tree.nodes["Principled BSDF"]
        emission = "Emission Color" if "Emission Color" in bsdf.inputs else "Emission"
        bsdf.inputs[emission].default_value = (1.0, 1.0, 1.0, 1.0)
        bsdf.inputs["Emission Strength"].default_value = 1e30
        self.objects["ShortBox"].data.materials.clear()
        self.objects["ShortBox"].data.materials.append(material)
        before = common.scene_snapshot()
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        print("bad material message:", caught.exception)
        self.assertIn("material 'TooHot'", str(caught.exception))
        self.assertSceneUnchanged(before)
        self.objects["ShortBox"].data.materials.clear()
        light = next(o for o in bpy.context.scene.objects if o.type == "LIGHT")
        light.data.energy = 1e38
        light.data.color = (1e38, 1e38, 1e38)
        before = common.scene_snapshot()
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        print("bad light message:", caught.exception)
        self.assertIn(f"light '{light.name}'", str(caught.exception))
        self.assertSceneUnchanged(before)

    def test_bake_points_without_a_normal_get_their_faces(self):
        """Imported meshes carry corners whose normal is zero (a real living-room scene: a
        face without area holding custom normals; the whole export failed with "bake point
        15150: normal is the zero vector"). Such a point takes its face's normal, and where
        the face has none either, +z with a warning naming the object."""
        from bakegi.export import points as export
        normals = numpy.array([(0, 0, 2), (0, 0, 0), (numpy.nan, 0, 0), (0, 0, 0)], numpy.float32)
        fallback = numpy.array([(1, 0, 0), (0, 3, 0), (0, 0, -1), (0, 0, 0)], numpy.float64)
        warnings = []
        repaired = export.repair_normals(normals, fallback, "Sliver", warnings)
        numpy.testing.assert_allclose(repaired, [(0, 0, 2), (0, 1, 0), (0, 0, -1), (0, 0, 1)])
        self.assertEqual(len(warnings), 1)
        self.assertIn("Sliver", warnings[0])
        self.assertIn("1 bake points", warnings[0])
        untouched = export.repair_normals(normals[:1], fallback[:1], "Sliver", warnings)
        numpy.testing.assert_array_equal(untouched, normals[:1])
        self.assertEqual(len(warnings), 1)

    def test_a_method_that_cannot_model_the_scene_hands_it_to_the_path_tracer(self):
        """Antiradiance refused scenes too large for its model; now the path tracer bakes them
        and the report and the summary say so."""
        settings = {"bins": 3072, "memory_budget_mb": 8}
        report = self.bakegi.bake(method="antiradiance", target="CORNER", objects="VISIBLE",
                                  method_settings=settings)
        self.assertEqual(report["method_used"], "pathtrace")
        self.assertTrue(any("Baked with the path tracer instead" in w for w in report["warnings"]),
                        report["warnings"])
        from bakegi.ui import report_text as operators
        self.assertIn("baked by pathtrace", operators.summary(report))
        self.assertGreater(float(common.read_color_attribute(["Floor"]).mean()), 0.0)
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="antiradiance", target="CORNER", objects="VISIBLE",
                             method_settings={**settings, "fallback": 0})
        self.assertIn("memory_budget_mb", str(caught.exception))

    def test_no_light_gives_a_clear_message(self):
        bpy.data.objects.remove(self.objects["CeilingLight"])
        before = common.scene_snapshot()
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        message = str(caught.exception)
        print("no light message:", message)
        self.assertIn("light", message.lower())
        self.assertSceneUnchanged(before)

    def test_operator_reports_the_error_and_changes_nothing(self):
        bpy.data.objects.remove(self.objects["CeilingLight"])
        bpy.context.scene.bakegi.objects = "VISIBLE"
        before = common.scene_snapshot()
        with self.assertRaises(RuntimeError) as caught:  # an operator's ERROR report raises in scripts
            bpy.ops.bakegi.bake_indirect()
        self.assertIn("light", str(caught.exception).lower())
        self.assertSceneUnchanged(before)

    def test_cancel_leaves_the_scene_unchanged(self):
        from bakegi.request import BakeRequest
        from bakegi.session import BakeSession

        before = common.scene_snapshot()
        # Far more work than can finish in the moments before cancel.
        session = BakeSession(bpy.context, BakeRequest(method="pathtrace", samples=1 << 20, seed=0,
                                                       target="CORNER", objects="VISIBLE"))
        session.prepare()
        session.start()
        time.sleep(0.5)
        progress = session.poll()
        self.assertFalse(progress.done, "the bake finished before it could be cancelled")
        self.assertLess(progress.fraction, 1.0)
        start = time.perf_counter()
        session.cancel()
        cancel_seconds = time.perf_counter() - start
        print(f"cancel returned after {cancel_seconds:.3f} s at {100 * progress.fraction:.2f}% progress")
        self.assertLess(cancel_seconds, 2.0, "cancel is not prompt")
        self.assertSceneUnchanged(before)
        # A bake after a cancelled one works and writes the attribute.
        self.bakegi.bake(method="pathtrace", samples=4, target="CORNER", objects="VISIBLE")
        self.assertIn(common.ATTRIBUTE, self.objects["Floor"].data.color_attributes)

    def test_invalid_arguments(self):
        before = common.scene_snapshot()
        for arguments in ({"samples": 0}, {"method": "nonsense"}, {"target": "FACE"}, {"seed": -1}):
            with self.subTest(arguments=arguments):
                with self.assertRaises(self.bakegi.BakeGIError):
                    self.bakegi.bake(objects="VISIBLE", **arguments)
        self.assertSceneUnchanged(before)

    def test_bad_method_settings_are_refused_before_the_export(self):
        """A setting the core refuses (the path tracer's max_bounces beyond 65536, read by
        antiradiance's fallback) is refused before the scene is exported or a lightmap UV map
        made: it used to fail only when the job started, after the texels were rasterized."""
        before = common.scene_snapshot()
        uv_maps = {name: [uv.name for uv in obj.data.uv_layers] for name, obj in self.objects.items()
                   if obj.type == "MESH"}
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bakegi.bake(method="antiradiance", target="LIGHTMAP", objects="VISIBLE",
                             method_settings={"max_bounces": 2 ** 20})
        self.assertIn("max_bounces", str(caught.exception))
        self.assertIn("65536", str(caught.exception))
        self.assertEqual(uv_maps, {name: [uv.name for uv in obj.data.uv_layers]
                                   for name, obj in self.objects.items() if obj.type == "MESH"})
        self.assertSceneUnchanged(before)


if __name__ == "__main__":
    common.run_tests(__name__)
