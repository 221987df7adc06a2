"""The Irradiance Vector Grid in Blender (issue 16): Bake Grid over a box or the scene,
Apply Grid on meshes that were not baked (a moved and an added prop, a level of detail made
with Simplify a Copy), the newest grid found by default, Export for Web, the operators, and a
refused grid that changes nothing."""

import json
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

import bakegi  # noqa: E402

NAMES = ("Floor", "Ceiling", "BackWall", "LeftWall", "RightWall", "ShortBox", "TallBox")
WALLS = ("Floor", "Ceiling", "BackWall", "LeftWall", "RightWall")


def luminance(rgb):
    return rgb @ numpy.array([0.2126, 0.7152, 0.0722])


class GridCase(common.SmallCornellCase):

    def setUp(self):
        super().setUp()
        # The scene object is reused between tests: forget the previous test's grid.
        bpy.context.scene.pop(bakegi.write.grid_file.GRID_PATH_PROPERTY, None)
        self.folder = tempfile.mkdtemp(prefix="bakegi_grid_test_")
        self.addCleanup(shutil.rmtree, self.folder, ignore_errors=True)

    def bake_grid(self, **kwargs):
        settings = dict(target="GRID", method="pathtrace", grid_cell_size=0.25, grid_rays=32,
                        grid_folder=self.folder)
        settings.update(kwargs)
        return bakegi.bake(**settings)

    def test_grid_lights_the_walls_like_a_bake(self):
        report = self.bake_grid()
        grid = report["grid"]
        self.assertTrue(os.path.isfile(grid["path"]), grid)
        self.assertEqual(os.path.dirname(grid["path"]), self.folder)
        self.assertEqual(grid["resolution"], [8, 8, 8])  # the 2 m box in 0.25 m cells
        self.assertEqual(bpy.context.scene[bakegi.write.grid_file.GRID_PATH_PROPERTY],
                         grid["path"])
        # The grid checked itself against the path tracer at probes in its box.
        self.assertGreater(report["estimated_error"], 0.0)
        self.assertLess(report["estimated_error"], 1.0)
        # Nothing was written on the meshes by the grid bake itself.
        self.assertIsNone(self.objects["Floor"].data.color_attributes.get(common.ATTRIBUTE))

        # Read as the paper does (no scene) the floor under the blocks gets the grid's light;
        # read with the scene (the default) none, as in a bake.
        paper = bakegi.apply_grid(list(NAMES), visibility=False, darken_buried=False)
        self.assertEqual((paper["buried_points"], paper["unsure_points"]), (0, 0))
        floor_paper = luminance(common.read_color_attribute(["Floor"]))
        applied = bakegi.apply_grid(list(NAMES))
        self.assertGreater(applied["buried_points"], 0)
        floor = luminance(common.read_color_attribute(["Floor"]))
        dark = floor == 0.0
        self.assertGreater(int(dark.sum()), 0)
        self.assertLessEqual(int(dark.sum()), applied["buried_points"] + applied["unsure_points"])
        self.assertTrue(numpy.all(floor_paper[dark] > 0.0))
        self.assertEqual(applied["path"], grid["path"])
        self.assertEqual(sorted(applied["objects"]), sorted(NAMES))
        from_grid = common.read_color_attribute(WALLS)
        bakegi.bake(method="pathtrace", samples=256, objects=list(NAMES), target="CORNER",
                    estimate_error=False)
        baked = common.read_color_attribute(WALLS)
        y, r = luminance(from_grid), luminance(baked)
        # The walls' mean light within 10% of the bake, point by point within 35% NRMSE (an
        # 8^3 grid of 32 rays a hemisphere: the coarse end of the resolution sweep in
        # docs/ivg.md; the bake has 256 paths a point).
        self.assertLess(abs(y.mean() / r.mean() - 1.0), 0.10, (y.mean(), r.mean()))
        nrmse = numpy.sqrt(numpy.mean((y - r) ** 2)) / r.mean()
        self.assertLess(nrmse, 0.35, nrmse)

    def test_a_moved_and_an_added_prop_are_lit_without_a_bake(self):
        self.bake_grid(grid_object=None)
        box = self.objects["ShortBox"]
        box.location.x += 0.2
        bpy.ops.mesh.primitive_ico_sphere_add(radius=0.2, location=(-0.4, 0.3, 1.2))
        sphere = bpy.context.active_object
        sphere.name = "Prop"
        report = bakegi.apply_grid(["ShortBox", "Prop"], interpolation="TRICUBIC")
        self.assertEqual(report["points"], len(box.data.loops) + len(sphere.data.loops))
        self.assertEqual(report["warnings"], [])
        lit = luminance(common.read_color_attribute(["Prop"]))
        self.assertTrue(numpy.all(numpy.isfinite(lit)))
        self.assertGreater(lit.mean(), 0.0)
        # The red wall is at -x: the prop's side facing it reflects more red than green.
        rgb = common.read_color_attribute(["Prop"])
        normals = numpy.array([sphere.data.vertices[l.vertex_index].normal
                               for l in sphere.data.loops])
        facing_red = normals[:, 0] < -0.7
        self.assertGreater(rgb[facing_red, 0].mean(), rgb[facing_red, 1].mean())

    def test_a_prop_scaled_to_zero_is_named_not_lit(self):
        """An object scaled to 0 (hidden that way in an animation) has no surface: Apply Grid
        names it and lights the others (its zero normals used to fail the whole call)."""
        self.bake_grid(grid_object=None)
        self.addCleanup(bakegi.grid_follow.forget)  # what Follow Moves would re-apply
        self.objects["TallBox"].scale = (0.0, 0.0, 0.0)
        bpy.context.view_layer.update()
        report = bakegi.apply_grid(["ShortBox", "TallBox"])
        self.assertEqual(report["objects"], ["ShortBox"])
        self.assertTrue(any("'TallBox'" in w and "scale is 0" in w for w in report["warnings"]),
                        report["warnings"])

    def test_follow_moves_lights_a_moved_prop_again(self):
        self.bake_grid(grid_object=None)
        scene = bpy.context.scene
        self.addCleanup(setattr, scene.bakegi, "grid_follow", False)
        self.addCleanup(bakegi.grid_follow.forget)
        options = dict(visibility=False, darken_buried=False, interpolation="TRICUBIC")
        bakegi.apply_grid(["ShortBox"], **options)
        before = common.read_color_attribute(["ShortBox"])
        box = self.objects["ShortBox"]

        # Off: a move queues nothing and update() finds nothing to do... once on, it does.
        box.location.z += 0.6
        bpy.context.view_layer.update()
        state = bakegi.grid_follow._states[scene.name]
        self.assertEqual(state.pending, set())
        scene.bakegi.grid_follow = True
        bpy.context.view_layer.update()
        box.location.x -= 0.1
        bpy.context.view_layer.update()  # the depsgraph handler sees the moved matrix
        self.assertEqual(state.pending, {"ShortBox"})
        report = bakegi.grid_follow.update()
        self.assertEqual(report["points"], len(box.data.loops))
        self.assertEqual(state.pending, set())
        followed = common.read_color_attribute(["ShortBox"])
        # 0.6 m higher the box reads other light from the grid.
        self.assertGreater(numpy.abs(luminance(followed) - luminance(before)).mean(),
                           0.01 * luminance(before).mean())
        self.assertIn("1 update(s)", bakegi.grid_follow.status_text(scene))

        # What it wrote is Apply Grid's own result where the box stands now, with the options
        # of the last Apply Grid (tricubic, no visibility).
        bakegi.apply_grid(["ShortBox"], **options)
        numpy.testing.assert_array_equal(common.read_color_attribute(["ShortBox"]), followed)
        # Its own write moved nothing: nothing left to do.
        bpy.context.view_layer.update()
        self.assertIsNone(bakegi.grid_follow.update())

        # Undo and redo bring back a matrix with the attribute lit there: nothing to re-apply.
        box.location.x += 0.1
        bpy.context.view_layer.update()
        self.assertEqual(state.pending, {"ShortBox"})
        bakegi.grid_follow.on_undo_redo(scene)
        self.assertEqual(state.pending, set())
        self.assertIsNone(bakegi.grid_follow.update())
        box.location.x -= 0.1
        bpy.context.view_layer.update()
        bakegi.grid_follow.update()

        # A shape change re-applies (the box flattened to half its height, its vertices moved;
        # the matrix stays); an edit in Edit Mode waits until it leaves; the add-on's own write
        # of the attribute is no change of shape.
        mesh = box.data
        for vertex in mesh.vertices:
            vertex.co.z *= 0.5
        mesh.update()
        bpy.context.view_layer.update()
        self.assertEqual(state.pending, {"ShortBox"})
        report = bakegi.grid_follow.update()
        self.assertEqual(report["points"], len(mesh.loops))
        bakegi.apply_grid(["ShortBox"], **options)
        bpy.context.view_layer.update()
        self.assertIsNone(bakegi.grid_follow.update())
        bpy.context.view_layer.objects.active = box
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.transform.resize(value=(1.0, 1.0, 1.5))
        bpy.context.view_layer.update()
        self.assertEqual(state.pending, set())
        bpy.ops.object.mode_set(mode="OBJECT")
        bpy.context.view_layer.update()
        self.assertEqual(state.pending, {"ShortBox"})
        bakegi.grid_follow.update()
        # After undo or redo the shape it brings back is the one lit; a later edit is not.
        bakegi.grid_follow.on_undo_redo(scene)
        for vertex in mesh.vertices:
            vertex.co.x *= 0.9
        mesh.update()
        bpy.context.view_layer.update()
        self.assertEqual(state.pending, {"ShortBox"})
        bakegi.grid_follow.update()
        followed = common.read_color_attribute(["ShortBox"])

        # A grid that is gone stops following with the reason, and changes nothing.
        box.location.x += 0.1
        os.remove(scene[bakegi.write.grid_file.GRID_PATH_PROPERTY])
        with self.assertRaises(bakegi.BakeGIError):
            bakegi.grid_follow.update()
        self.assertIn("Follow stopped", bakegi.grid_follow.status_text(scene))
        numpy.testing.assert_array_equal(common.read_color_attribute(["ShortBox"]), followed)

    def test_a_level_of_detail_is_lit_like_the_full_mesh(self):
        self.bake_grid(grid_object=None)
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4, radius=0.3, location=(0, 0, 1.2))
        prop = bpy.context.active_object
        prop.name = "Prop"
        for name in ("PropA", "PropB"):
            prop.data.materials.append(bpy.data.materials.new(name))
        indices = numpy.arange(len(prop.data.polygons)) % 2
        prop.data.polygons.foreach_set("material_index", indices.astype(numpy.int32))
        full_triangles = len(prop.data.polygons)  # 1,280: an icosphere is all triangles
        bakegi.apply_grid(["Prop"])
        full = luminance(common.read_color_attribute(["Prop"]))

        lod, info = bakegi.simplify_copy("Prop", 0.1)
        self.assertEqual(lod.name, "Prop_LOD10")
        self.assertEqual(info["triangles"], full_triangles)
        self.assertEqual(info["lod_triangles"], len(lod.data.polygons))
        # A closed sphere has no borders to hold collapses back: the ratio is reached (the
        # interleaved materials do not hold it back either), and both materials are kept.
        self.assertLessEqual(len(lod.data.polygons), 0.1 * full_triangles + 2)
        self.assertEqual([m.name for m in lod.data.materials], ["PropA", "PropB"])
        kept = numpy.zeros(len(lod.data.polygons), numpy.int32)
        lod.data.polygons.foreach_get("material_index", kept)
        self.assertEqual(sorted(set(kept.tolist())), [0, 1])
        self.assertTrue(prop.hide_get())
        self.assertGreater(info["deviation"], 0.0)

        bakegi.apply_grid(["Prop_LOD10"])
        coarse = luminance(common.read_color_attribute(["Prop_LOD10"]))
        self.assertTrue(numpy.all(numpy.isfinite(coarse)))
        # The coarse sphere's corners face the same room: its mean light within 15% of the
        # full sphere's (the corners' normals are their faces', which coarsening tilts).
        self.assertLess(abs(coarse.mean() / full.mean() - 1.0), 0.15,
                        (coarse.mean(), full.mean()))
        with self.assertRaises(bakegi.BakeGIError):
            bakegi.simplify_copy("Prop", 0.0)
        with self.assertRaises(bakegi.BakeGIError):
            bakegi.simplify_copy("NoSuchObject", 0.5)

    def test_export_for_web_writes_the_scene_the_grid_and_the_page(self):
        self.bake_grid(grid_object=None)
        folder = os.path.join(self.folder, "web")
        report = bakegi.export_web(folder)
        self.assertEqual(report["folder"], folder)
        # Lit by its lamp alone: nothing the page leaves out. With a sky, it says so.
        self.assertEqual(report["warnings"], [])
        scene = bpy.context.scene
        self.addCleanup(setattr, scene, "world", scene.world)
        scene.world = bpy.data.worlds.new("Sky")  # a plain colour (or nodes' default grey)
        scene.world.color = (0.1, 0.1, 0.1)
        # The grid, baked before the sky, holds only its bounce; baked under it, its direct
        # light too, which the page then draws from the grid.
        sky = bakegi.export_web(os.path.join(self.folder, "web_sky"))
        self.assertEqual(len(sky["warnings"]), 1)
        self.assertIn("the world (sky) lights this scene", sky["warnings"][0])
        self.assertIn("not its direct light", sky["warnings"][0])
        self.bake_grid(grid_object=None)
        sky = bakegi.export_web(os.path.join(self.folder, "web_sky"))
        self.assertEqual(len(sky["warnings"]), 1)
        self.assertIn("its direct light comes from the grid", sky["warnings"][0])
        with open(os.path.join(self.folder, "web_sky", "scene.gltf")) as f:
            self.assertIs(json.load(f)["extras"]["bakegi"]["grid_has_emitted_light"], True)
        for name in ("scene.gltf", "scene.bin", "grid.bgivg", "grid_visibility.bin",
                     "index.html", "viewer.js"):
            self.assertIn(name, report["files"])
            self.assertGreater(report["bytes"][name], 0)
        with open(os.path.join(folder, "scene.gltf")) as f:
            gltf = json.load(f)
        self.assertEqual(gltf["asset"]["version"], "2.0")
        self.assertEqual(gltf["extras"]["bakegi"]["grid"], "grid.bgivg")
        self.assertEqual(gltf["extras"]["bakegi"]["grid_visibility"], "grid_visibility.bin")
        self.assertIs(gltf["extras"]["bakegi"]["grid_has_emitted_light"], False)
        primitives = [p for m in gltf["meshes"] for p in m["primitives"]]
        self.assertGreaterEqual(len(primitives), len(NAMES))
        self.assertTrue(all("bakegi_progressive" in p["extras"] for p in primitives))
        # The scene's camera, turned to glTF's Y-up axes: Blender's (x, y, z) is (x, z, -y).
        camera = bpy.context.scene.camera
        if camera is not None:
            node = next(n for n in gltf["nodes"] if "camera" in n)
            x, y, z = camera.matrix_world.translation
            self.assertEqual([round(v, 4) for v in node["translation"]],
                             [round(v, 4) for v in (x, z, -y)])
        # The operator writes into the folder it is given; without a grid it is unavailable.
        self.assertEqual(bpy.ops.bakegi.export_web(directory=os.path.join(self.folder, "op")),
                         {"FINISHED"})
        self.assertTrue(os.path.isfile(os.path.join(self.folder, "op", "scene.gltf")))
        bpy.context.scene.pop(bakegi.write.grid_file.GRID_PATH_PROPERTY, None)
        self.assertFalse(bpy.ops.bakegi.export_web.poll())

    def test_method_grid_bakes_corners_and_lightmaps_from_the_grid(self):
        path = self.bake_grid(grid_object=None)["grid"]["path"]
        bakegi.apply_grid(list(NAMES))
        applied = common.read_color_attribute(WALLS)
        # The same reading as a bake method: the same values at the same corners, up to the
        # bake's own handling of its points (coincident corners share a value; measured: 0.4%
        # at most).
        report = bakegi.bake(method="grid", method_settings={"grid_file": path},
                             objects=list(NAMES), target="CORNER")
        self.assertEqual(report["method"], "grid")
        numpy.testing.assert_allclose(common.read_color_attribute(WALLS), applied, rtol=0.01,
                                      atol=1e-6)
        self.assertIn("estimated_error", report)
        # And lightmap texels: an EXR atlas lit from the grid.
        folder = os.path.join(self.folder, "lightmaps")
        report = bakegi.bake(method="grid", method_settings={"grid_file": path},
                             target="LIGHTMAP", objects="VISIBLE", lightmap_folder=folder,
                             texels_per_meter=16.0)
        self.assertTrue(os.path.isfile(report["lightmap"]["path"]), report["lightmap"])
        with self.assertRaises(bakegi.BakeGIError):
            bakegi.bake(method="grid", objects=list(NAMES), target="CORNER")

    def test_a_grid_box_sets_the_bounds_and_far_points_are_named(self):
        bpy.ops.bakegi.add_grid_box()
        box = bpy.context.scene.bakegi.grid_object
        self.assertIsNotNone(box)
        box.scale = (0.5, 0.5, 0.5)
        box.location = (0.0, 0.0, 1.0)
        report = self.bake_grid(grid_object=box.name)
        self.assertAlmostEqual(report["grid"]["bounds_min"][0], -0.5, places=4)
        self.assertAlmostEqual(report["grid"]["bounds_max"][2], 1.5, places=4)
        applied = bakegi.apply_grid(["Floor"])
        self.assertTrue(any("outside the grid" in w for w in applied["warnings"]),
                        applied["warnings"])

    def test_operators_bake_and_apply(self):
        settings = bpy.context.scene.bakegi
        settings.target = "GRID"
        settings.grid_cell_size = 0.5
        settings.grid_rays = 8
        settings.grid_folder = self.folder
        settings.objects = "VISIBLE"
        self.assertEqual(bpy.ops.bakegi.bake_indirect(), {"FINISHED"})
        self.assertIn("grid of", settings.last_result)
        self.assertEqual(bpy.ops.bakegi.apply_grid(), {"FINISHED"})
        self.assertIsNotNone(self.objects["TallBox"].data.color_attributes.get(common.ATTRIBUTE))
        floor = self.objects["Floor"]  # a grid of quads: its inside collapses freely
        bpy.context.view_layer.objects.active = floor
        self.assertEqual(bpy.ops.bakegi.simplify_copy(ratio=0.5), {"FINISHED"})
        lod = bpy.context.blend_data.objects["Floor_LOD50"]
        triangles = sum(len(p.vertices) - 2 for p in floor.data.polygons)
        self.assertLess(len(lod.data.polygons), triangles)
        self.assertIs(bpy.context.view_layer.objects.active, lod)

    def test_refused_grid_changes_nothing(self):
        with self.assertRaises(bakegi.BakeGIError):
            self.bake_grid(grid_max_vertices=4)
        self.assertEqual(os.listdir(self.folder), [])
        self.assertNotIn(bakegi.write.grid_file.GRID_PATH_PROPERTY, bpy.context.scene)
        with self.assertRaises(bakegi.BakeGIError):
            bakegi.apply_grid(["Floor"])  # no grid baked yet
        self.assertIsNone(self.objects["Floor"].data.color_attributes.get(common.ATTRIBUTE))


if __name__ == "__main__":
    common.run_tests(__name__)
