"""What renders have, the bake has: an object or a light disabled in renders (its own toggle or
a collection's) is left out as Cycles leaves it out, and the report says so; an object hidden
in the viewport but rendered, which the export cannot see, is named in the report."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

NAMES = ("Floor", "Ceiling", "BackWall", "LeftWall", "RightWall", "ShortBox", "TallBox")


class RenderVisibility(common.SmallCornellCase):

    def bake(self, names=NAMES):
        report = self.bakegi.bake(method="pathtrace", samples=16, seed=3, target="CORNER",
                                  objects=list(names), estimate_error=False)
        return common.read_color_attribute(names, domain="CORNER"), report

    def add_blocker(self, name="Stand-in"):
        """A large plane under the ceiling light: it changes the whole room's light."""
        bpy.ops.mesh.primitive_plane_add(size=1.6, location=(0.0, 0.0, 1.5))
        blocker = bpy.context.active_object
        blocker.name = name
        return blocker

    def assert_left_out(self, expected, words):
        """Bakes: the room's light is the bake's without the stand-in, and a warning with
        `words` names it."""
        got, report = self.bake()
        numpy.testing.assert_array_equal(got, expected)
        self.assertTrue(any(words in w and "Stand-in" in w for w in report["warnings"]),
                        report["warnings"])

    def test_objects_disabled_in_renders_are_left_out(self):
        expected, _ = self.bake()
        blocker = self.add_blocker()
        blocker.hide_render = True
        self.assert_left_out(expected, "disabled in renders")

        # The same through a collection disabled in renders (inside another collection).
        blocker.hide_render = False
        outer = bpy.data.collections.new("Helpers")
        inner = bpy.data.collections.new("Stand-ins")
        bpy.context.scene.collection.children.link(outer)
        outer.children.link(inner)
        for collection in list(blocker.users_collection):
            collection.objects.unlink(blocker)
        inner.objects.link(blocker)
        outer.hide_render = True
        got, _ = self.bake()
        numpy.testing.assert_array_equal(got, expected)

        # Rendered again, it changes the room's light (measured: 1.7 times the indirect light,
        # the plane throws the lamp's light back at the ceiling).
        outer.hide_render = False
        got, report = self.bake()
        self.assertGreater(abs(got.sum() / expected.sum() - 1.0), 0.2)
        self.assertFalse([w for w in report["warnings"] if "renders" in w], report["warnings"])

    def test_a_light_disabled_in_renders_is_left_out(self):
        bpy.ops.object.light_add(type="POINT", location=(0.3, 0.2, 1.0))
        extra = bpy.context.active_object
        extra.data.energy = 200.0
        lit, _ = self.bake()
        extra.hide_render = True
        got, report = self.bake()
        self.assertLess(got.sum(), 0.9 * lit.sum())
        self.assertTrue(any("disabled in renders" in w for w in report["warnings"]))

    def test_objects_hidden_in_the_viewport_but_rendered_are_named(self):
        self.objects["TallBox"].hide_set(True)
        _, report = self.bake([name for name in NAMES if name != "TallBox"])
        self.assertTrue(any("hidden in the viewport but rendered" in w and "TallBox" in w
                            for w in report["warnings"]), report["warnings"])

    def test_modifiers_that_differ_in_renders_are_named(self):
        """The bake evaluates the viewport; Cycles bakes the render's geometry: a modifier on
        in only one of them, or other subdivision levels, is named."""
        box = self.objects["TallBox"]
        array = box.modifiers.new("Copies", "ARRAY")
        array.show_viewport = False
        subdivision = self.objects["ShortBox"].modifiers.new("Smooth", "SUBSURF")
        subdivision.levels, subdivision.render_levels = 1, 2
        _, report = self.bake()
        lines = [w for w in report["warnings"] if "viewport's modifiers" in w]
        self.assertEqual(len(lines), 1, report["warnings"])
        self.assertIn("'TallBox' 'Copies' on only in renders", lines[0])
        self.assertIn("'ShortBox' 'Smooth' 1 levels in the viewport, 2 in renders", lines[0])
        array.show_viewport = True
        subdivision.levels = 2
        _, report = self.bake()
        self.assertFalse([w for w in report["warnings"] if "viewport's modifiers" in w])

    def add_particles(self, obj, kind):
        """A particle system of `kind` ('EMITTER' or 'HAIR') on obj, 10 particles."""
        bpy.context.view_layer.objects.active = obj
        bpy.ops.object.particle_system_add()
        settings = obj.particle_systems[-1].settings
        settings.type = kind
        settings.count = 10
        return settings

    def test_an_instancer_rendered_without_its_mesh_is_left_out(self):
        """An object with particles (or Instancing) and Show Instancer > Render off: Cycles
        renders its particles or instances but not its mesh, whatever the viewport shows."""
        expected, _ = self.bake()
        blocker = self.add_blocker()
        self.add_particles(blocker, "EMITTER").render_type = "NONE"
        blocker.show_instancer_for_render = False
        self.assert_left_out(expected, "Show Instancer")
        blocker.show_instancer_for_render = True
        got, report = self.bake()
        self.assertGreater(abs(got.sum() / expected.sum() - 1.0), 0.2)
        self.assertFalse([w for w in report["warnings"] if "Show Instancer" in w])

    def test_hair_strands_and_curves_objects_are_named(self):
        """Geometry Cycles renders that the bake has no form for: particle hair drawn as
        strands, and hair curves objects (3.3 on)."""
        blocker = self.add_blocker()
        self.add_particles(blocker, "HAIR").render_type = "PATH"
        if hasattr(bpy.data, "hair_curves"):
            curves = bpy.data.objects.new("Strands", bpy.data.hair_curves.new("Strands"))
            bpy.context.scene.collection.objects.link(curves)
        _, report = self.bake()
        lines = [w for w in report["warnings"] if w.startswith("not in the bake")]
        self.assertEqual(len(lines), 1, report["warnings"])
        self.assertIn("'Stand-in' (strands", lines[0])
        if hasattr(bpy.data, "hair_curves"):
            self.assertIn("'Strands' (hair curves)", lines[0])
            curves.hide_render = True
        blocker.modifiers[-1].show_render = False
        _, report = self.bake()
        self.assertFalse([w for w in report["warnings"] if w.startswith("not in the bake")],
                         report["warnings"])

if __name__ == "__main__":
    common.run_tests(__name__)
