"""Cycles' ray-visibility settings that change a diffuse bake: a light or a world invisible to
diffuse rays adds nothing to Cycles' diffuse light (direct or indirect; measured in 3.4 and
4.5), so the bake leaves it out and says so; a light with Cast Shadow off lights through
everything, against a Cycles bake made here; objects with Diffuse or Shadow visibility off are
named (not modelled)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import cornell_box  # noqa: E402  (scenes/: use_nodes)
import numpy  # noqa: E402

import light_units  # noqa: E402  (scenes/light_units.py)
import metrics  # noqa: E402

# Cycles' direct light in the test (1,024 samples: its noise about 0.3% on these receivers).
CYCLES_SAMPLES = 1024
BAKEGI_SAMPLES = 2048


def set_cast_shadow(light, on):
    """Cast Shadow as Cycles reads it: light.cycles.cast_shadow in 3.x, use_shadow from 4.0."""
    if hasattr(light.cycles, "cast_shadow"):
        light.cycles.cast_shadow = on
    else:
        light.use_shadow = on


class RayVisibility(common.AddonCase):

    def setUp(self):
        common.new_empty_scene()
        self.built = light_units.build_light_scene("POINT")
        self.receivers = [self.built[name] for name in light_units.RECEIVERS]
        self.light = next(o for o in bpy.context.scene.objects if o.type == "LIGHT")

    def bake(self, seed=0, samples=256):
        report = self.bakegi.bake(method="direct", samples=samples, seed=seed, target="CORNER",
                                  objects=self.receivers, estimate_error=False)
        return common.read_color_attribute(self.receivers, domain="CORNER"), report

    def test_a_light_invisible_to_diffuse_rays_is_left_out(self):
        expected, _ = self.bake()
        bpy.ops.object.light_add(type="POINT", location=(-0.5, 0.4, 1.2))
        extra = bpy.context.active_object
        extra.data.energy = 500.0
        lit, _ = self.bake()
        self.assertGreater(lit.sum(), 1.5 * expected.sum())
        extra.visible_diffuse = False
        got, report = self.bake()
        numpy.testing.assert_array_equal(got, expected)
        self.assertTrue(any("invisible to diffuse rays" in w and extra.name in w
                            for w in report["warnings"]), report["warnings"])

    def test_with_its_only_light_left_out_the_error_says_why(self):
        self.light.visible_diffuse = False
        with self.assertRaises(self.bakegi.BakeGIError) as caught:
            self.bake()
        message = str(caught.exception)
        self.assertIn("no light", message)
        self.assertIn("invisible to diffuse rays", message)

    def test_a_world_invisible_to_diffuse_rays_adds_no_light(self):
        expected, _ = self.bake()
        world = bpy.data.worlds.new("Sky")
        cornell_box.use_nodes(world)
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
        bpy.context.scene.world = world
        lit, _ = self.bake()
        self.assertGreater(lit.sum(), 1.2 * expected.sum())
        world.cycles_visibility.diffuse = False
        got, report = self.bake()
        numpy.testing.assert_array_equal(got, expected)
        self.assertTrue(any("world is invisible to diffuse rays" in w
                            for w in report["warnings"]), report["warnings"])

    def test_a_light_without_shadows_against_cycles(self):
        import cycles_bake
        set_cast_shadow(self.light.data, False)
        reference, seconds = cycles_bake.cycles_direct(self.receivers, CYCLES_SAMPLES)
        shadowless = [self.bake(seed, BAKEGI_SAMPLES)[0] for seed in (0, 1)]
        set_cast_shadow(self.light.data, True)
        shadowed = [self.bake(seed, BAKEGI_SAMPLES)[0] for seed in (0, 1)]
        error = metrics.relative_rmse(0.5 * (shadowless[0] + shadowless[1]), reference)
        error_shadowed = metrics.relative_rmse(0.5 * (shadowed[0] + shadowed[1]), reference)
        noise = metrics.noise_from_halves(shadowless[0], shadowless[1])
        print(f"Cycles {CYCLES_SAMPLES} samples {seconds:.1f} s; bakegi without shadows "
              f"{100 * error:.2f}% (its noise {100 * noise:.2f}%), with them "
              f"{100 * error_shadowed:.2f}%")
        # test_light_units' tolerance for direct light; the blocker's shadow is the difference.
        self.assertLessEqual(error, 0.02)
        self.assertGreater(error_shadowed, 0.05)

    def test_a_volume_without_a_surface_is_left_out(self):
        """A fog box (a Principled Volume on the Volume output, no Surface) around the lamp:
        Cycles lets light through its boundary; the bake, without participating media, leaves
        it out instead of baking a black box."""
        expected, _ = self.bake()
        # Around the lamp: baked as a surface, this closed box would hold all its light in.
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=self.light.location)
        fog = bpy.context.active_object
        fog.name = "Fog"
        material, _ = common.node_material("Fog", "ShaderNodeVolumePrincipled", socket="Volume")
        fog.data.materials.append(material)
        got, report = self.bake()
        numpy.testing.assert_array_equal(got, expected)
        self.assertTrue(any("left out Fog" in w and "Volume without a Surface" in w
                            for w in report["warnings"]), report["warnings"])

    def test_a_lights_max_bounces_is_named(self):
        self.light.data.cycles.max_bounces = 2
        _, report = self.bake()
        self.assertTrue(any("Max Bounces (2) is ignored" in w for w in report["warnings"]),
                        report["warnings"])

    def test_objects_hidden_from_diffuse_or_shadow_rays_are_named(self):
        self.built["Blocker"].visible_shadow = False
        _, report = self.bake()
        self.assertTrue(any("ray visibility is ignored" in w and "Blocker" in w
                            for w in report["warnings"]), report["warnings"])


if __name__ == "__main__":
    common.run_tests(__name__)
