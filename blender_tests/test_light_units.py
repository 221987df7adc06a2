"""bakegi's direct light agrees with Cycles for every light type: the unit conversion is pinned.

For each one-light scene of scenes/light_units.py, bakegi bakes the direct
light (method 'direct') at the receivers' face corners and the result is
compared with the stored Cycles direct bake (blender_tests/data/<version>/light_*.npy,
16384 samples, its noise about 0.01 %).

Tolerance: relative RMSE <= 2 %. The reference's noise is negligible
(<= 0.04 %) and bakegi's own noise is measured from two seeds and required
to be <= 0.8 % (in quadrature that leaves most of the budget for bias).
What a convention error costs, measured with Cycles on these scenes
against the stored references (1024 samples): spot blend ignored 28 %,
point light radius ignored 8.6 %, spot radius ignored 3.8 %, disk drawn as
a square 3.7 %, ellipse as a rectangle 3.5 %, sun angle ignored 3.0 %. Unit
errors are far larger: a factor pi or 4 in a power is 68-300 %, an area
light emitting P instead of pi P / 4 is 21-27 %, a spot concentrating its
power into the cone several hundred %.

Textured emission (blender_tests/textured_emitter.py): the same emissive quad with an image
on its emission colour (black block, gradient, a strip brighter than 1, UVs repeating across
the quad's edges), split into 8 x 8 faces (Cycles 3.4 gets a single large textured triangle
near a receiver wrong, see that file), against its own Cycles reference (8192 samples); and
bakegi's single quad against the same reference. Same tolerance. What the texture's errors
cost on this scene (bakegi's direct light, 8192 samples, against the reference, which it
matches to 0.65 % in one bake): the texture ignored (white, the add-on before textured
emission) 70 %, the HDR strip clamped to 1 instead of scaled into the emission 22 %, v
flipped 6.4 %, u flipped only 2.0 % (the pattern is nearly symmetric that way seen from the
receivers: the native test_lights_direct pins both axes). The same
emission through a Principled BSDF's Emission input (via a reroute) exports the same scene:
its bake is bit-identical.

The world image (WORLD_IMAGE: an HDR sky with a sun in an Environment Texture, turned by a
Mapping node, scenes/light_units.py) against Cycles 16384 samples: 0.26-0.27 % in Blender 3.4.
What its errors cost there (bakegi at 4096 samples, tools/world_image_costs.py): the Mapping
rotation ignored 18.8 %, the rotation inverted 16.9 %, the image
replaced by its mean colour (the add-on before the world image) 40.3 %, 33 % too dark.
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

import light_units  # noqa: E402
import metrics  # noqa: E402
import textured_emitter  # noqa: E402

SAMPLES = int(os.environ.get("BAKEGI_TEST_LIGHT_SAMPLES", "2048"))
# Area spread against Cycles bakes made in the test (1,024 samples): Cycles' own noise there
# is about 1% for a 20 degree spread (it clips its samples to the lit region; bakegi does not,
# and its 2 x 2,048 samples carry about 0.5%).
SPREAD_TOLERANCE = 0.03
# The world (found by cosine-weighted rays only) and the emissive quad (sampled by area, not
# solid angle) are about twice as noisy per sample as the lamps: measured 0.83-0.84 % at
# 2048 samples, so they get 4x the samples (noise about 0.42 %) to stay clear of NOISE_LIMIT;
# so does the textured emitter (measured 0.45 % at 4x).
SAMPLES_FOR_KIND = {"WORLD": 4 * SAMPLES, "WORLD_IMAGE": 4 * SAMPLES, "EMISSIVE_MESH": 4 * SAMPLES,
                    textured_emitter.KIND: 4 * SAMPLES}
TOLERANCE = 0.02
# The Sky Texture against a Cycles bake made in the test (Cycles' own noise: 0.07% at 1024
# samples, so about 0.14% at 256). Measured in 3.4: 3.25%, nearly all of it one floor corner inside the blocker's 6 mm
# penumbra (bakegi's sun is a uniform disc, the sky model's is limb-darkened); the sun's light
# itself within 0.4%. Leaving the sun in the 512 x 256 image instead: 5.8% and 2.4% bright.
SKY_CYCLES_SAMPLES = 256
SKY_TOLERANCE = 0.05
NOISE_LIMIT = 0.008


class LightUnitsAgainstCycles(common.AddonCase):

    def bake_receivers(self, kind, built, seeds=(0, 1)):
        """bakegi's direct light at the receivers' corners, one bake per seed; and the
        reports."""
        receivers = [built[name] for name in light_units.RECEIVERS]
        bakes, reports = [], []
        for seed in seeds:
            reports.append(self.bakegi.bake(method="direct", samples=SAMPLES_FOR_KIND.get(kind, SAMPLES),
                                            seed=seed, target="CORNER", objects=receivers))
            bakes.append(common.read_color_attribute(receivers, domain="CORNER"))
        return bakes, reports

    def check_kind(self, kind):
        reference, sidecar = common.load_reference(f"light_{kind}")
        common.new_empty_scene()
        if kind == textured_emitter.KIND:
            built = textured_emitter.build_textured_emitter_scene(
                sidecar["scene"]["variant"], sidecar["scene"]["subdivisions"],
                sidecar["scene"]["emitter_cells"])
        else:
            built = light_units.build_light_scene(kind, sidecar["scene"]["subdivisions"])
        receivers = [built[name] for name in light_units.RECEIVERS]
        self.assertEqual([[o.name, len(o.data.loops)] for o in receivers], sidecar["objects"])
        bakes, reports = self.bake_receivers(kind, built)
        self.compare(kind, bakes, reference)
        return bakes, reports

    def compare(self, kind, bakes, reference, tolerance=TOLERANCE):
        average = 0.5 * (bakes[0] + bakes[1])
        noise = metrics.noise_from_halves(bakes[0], bakes[1])
        error = metrics.relative_rmse(average, reference)
        ratio = metrics.luminance(average).sum() / metrics.luminance(reference).sum()
        # The metric is on luminance; the colour (a light's temperature) is checked per channel.
        channels = average.sum(axis=0) / reference.sum(axis=0)
        print(f"{kind}: relative RMSE {100 * error:.2f}%, bakegi noise {100 * noise:.2f}%, "
              f"total ratio bakegi/Cycles {ratio:.4f}, per channel {numpy.round(channels, 4)}")
        self.assertLessEqual(noise, NOISE_LIMIT, f"{kind}: bakegi's direct light too noisy to compare")
        self.assertLessEqual(error, tolerance, f"{kind}: bakegi's direct light differs from Cycles'")
        self.assertLessEqual(numpy.abs(channels - 1.0).max(), tolerance, f"{kind}: the colour differs")

    def test_point_with_radius(self):
        self.check_kind("POINT")

    def test_spot_with_blend(self):
        self.check_kind("SPOT")

    def test_sun_with_angle(self):
        self.check_kind("SUN")

    def test_area_square(self):
        self.check_kind("AREA_SQUARE")

    def test_area_rectangle(self):
        self.check_kind("AREA_RECTANGLE")

    def test_area_disk(self):
        self.check_kind("AREA_DISK")

    def test_area_ellipse(self):
        self.check_kind("AREA_ELLIPSE")

    def test_emissive_mesh_two_sided(self):
        self.check_kind("EMISSIVE_MESH")

    def test_world_color(self):
        self.check_kind("WORLD")

    def test_world_image_turned_by_a_mapping_node(self):
        """An HDR sky with a sun in an Environment Texture, turned by a Mapping node: the image,
        its orientation (Cycles' equirectangular mapping and Blender's Euler rotation) and its
        strength, against Cycles."""
        bakes, reports = self.check_kind("WORLD_IMAGE")
        warnings = reports[0]["warnings"]
        self.assertFalse([w for w in warnings if "world" in w], warnings)
        # The rotation the exporter reads is Blender's own Euler matrix.
        import mathutils
        from bakegi.export import world
        expected = mathutils.Euler(light_units.WORLD_IMAGE_ROTATION, "XYZ").to_matrix()
        got = world._euler_xyz_matrix(light_units.WORLD_IMAGE_ROTATION)
        for row in range(3):
            for column in range(3):
                self.assertAlmostEqual(got[row][column], expected[row][column], places=6)

    def test_world_tree_rendered_into_an_image(self):
        """A world tree bakegi does not read itself (the WORLD_IMAGE sky through a Gamma node,
        here of gamma 1) is rendered by Cycles into an equirectangular image, in a scratch
        scene that is removed again: against the same Cycles reference as the image read
        directly (the render's 512 x 256 texels blur the 64 x 32 image's sun a little)."""
        reference, sidecar = common.load_reference("light_WORLD_IMAGE")
        common.new_empty_scene()
        built = light_units.build_light_scene("WORLD_IMAGE", sidecar["scene"]["subdivisions"])
        tree = bpy.context.scene.world.node_tree
        gamma = tree.nodes.new("ShaderNodeGamma")
        gamma.inputs["Gamma"].default_value = 1.0
        texture = next(n for n in tree.nodes if n.type == "TEX_ENVIRONMENT")
        tree.links.new(texture.outputs["Color"], gamma.inputs["Color"])
        tree.links.new(gamma.outputs["Color"], tree.nodes["Background"].inputs["Color"])
        counts = [len(c) for c in (bpy.data.scenes, bpy.data.objects, bpy.data.cameras,
                                   bpy.data.images)]
        bakes, reports = self.bake_receivers("WORLD_IMAGE", built)
        self.assertEqual([len(c) for c in (bpy.data.scenes, bpy.data.objects, bpy.data.cameras,
                                           bpy.data.images)], counts)
        self.assertFalse([w for w in reports[0]["warnings"] if "world" in w],
                         reports[0]["warnings"])
        self.compare("WORLD_IMAGE rendered", bakes, reference)

    def test_world_image_missing_file_uses_the_background_color(self):
        """An Environment Texture whose file is missing (Cycles draws it magenta) or that has no
        image lights with the Background's own colour, and says so."""
        from bakegi.export import world as world_export
        common.new_empty_scene()
        world = light_units.set_image_world(bpy.context.scene)
        background = world.node_tree.nodes["Background"]
        background.inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
        texture = next(n for n in world.node_tree.nodes if n.type == "TEX_ENVIRONMENT")
        gone = bpy.data.images.new("gone", 4, 2, float_buffer=True)
        gone.source = "FILE"
        gone.filepath = "/nonexistent/sky.exr"
        for image in (gone, None):
            texture.image = image
            warnings = []
            light = world_export.world_light(world, warnings)
            self.assertIsNone(light.image)
            for got, expected in zip(light.radiance, (0.24, 0.36, 0.48)):  # x strength 1.2
                self.assertAlmostEqual(got, expected, places=5)
            self.assertTrue(any("no image" in w for w in warnings), warnings)

    def test_sky_texture_against_cycles(self):
        """Blender's Sky Texture (its default sky model, a low sun): the sky rendered into an
        image, its sun disc as a sun light, light the receivers as they light them in Cycles
        (a live Cycles bake: no stored reference, the sky model changes between versions)."""
        import cycles_bake
        common.new_empty_scene()
        built = light_units.build_light_scene("WORLD")
        tree = bpy.context.scene.world.node_tree
        sky = tree.nodes.new("ShaderNodeTexSky")
        if hasattr(sky, "sun_elevation"):
            sky.sun_elevation, sky.sun_rotation = 0.5, 0.7
        tree.links.new(sky.outputs["Color"], tree.nodes["Background"].inputs["Color"])
        tree.nodes["Background"].inputs["Strength"].default_value = 0.2
        receivers = [built[name] for name in light_units.RECEIVERS]
        reference, seconds = cycles_bake.cycles_direct(receivers, SKY_CYCLES_SAMPLES)
        bakes, reports = self.bake_receivers("WORLD_IMAGE", built)
        self.assertFalse([w for w in reports[0]["warnings"] if "world" in w],
                         reports[0]["warnings"])
        print(f"Cycles {SKY_CYCLES_SAMPLES} samples: {seconds:.1f} s")
        self.compare("SKY_TEXTURE", bakes, reference, tolerance=SKY_TOLERANCE)

    def test_a_camera_ray_world_against_cycles(self):
        """The camera-ray trick: a Mix Shader whose factor is Light Path's Is Camera Ray shows
        the camera one Background (a bright blue) and lights the scene with another (the
        scene's sky). Rendered as lighting rays see it (Is Camera Ray 0), against a live Cycles
        bake; read as the camera sees it (before), the light is the blue one."""
        import cycles_bake
        common.new_empty_scene()
        built = light_units.build_light_scene("WORLD")
        tree = bpy.context.scene.world.node_tree
        lighting = tree.nodes["Background"]
        shown = tree.nodes.new("ShaderNodeBackground")
        shown.inputs["Color"].default_value = (0.1, 0.3, 1.0, 1.0)
        shown.inputs["Strength"].default_value = 4.0
        mix = tree.nodes.new("ShaderNodeMixShader")
        path = tree.nodes.new("ShaderNodeLightPath")
        output = next(n for n in tree.nodes if n.type == "OUTPUT_WORLD")
        tree.links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
        tree.links.new(lighting.outputs[0], mix.inputs[1])
        tree.links.new(shown.outputs[0], mix.inputs[2])
        tree.links.new(mix.outputs[0], output.inputs["Surface"])
        receivers = [built[name] for name in light_units.RECEIVERS]
        reference, _ = cycles_bake.cycles_direct(receivers, 4 * SKY_CYCLES_SAMPLES)
        bakes, reports = self.bake_receivers("WORLD", built)
        self.assertFalse([w for w in reports[0]["warnings"] if "world" in w],
                         reports[0]["warnings"])
        self.compare("camera-ray world", bakes, reference, tolerance=SKY_TOLERANCE)

    def test_light_node_tree_against_cycles(self):
        """A light whose Emission node has strength 2.5 and its colour from a Blackbody node
        (3,000 K; how lights were tinted before 4.5's temperature setting), then from an RGB
        node: read as colour x strength, against a live Cycles bake of each."""
        import cycles_bake
        common.new_empty_scene()
        built = light_units.build_light_scene("POINT")
        light = next(o for o in bpy.context.scene.objects if o.type == "LIGHT").data
        light.use_nodes = True  # lights keep the setting in 5.0 too
        tree = light.node_tree
        emission = next(n for n in tree.nodes if n.type == "EMISSION")
        emission.inputs["Strength"].default_value = 2.5
        blackbody = tree.nodes.new("ShaderNodeBlackbody")
        blackbody.inputs["Temperature"].default_value = 3000.0
        tree.links.new(blackbody.outputs[0], emission.inputs["Color"])
        receivers = [built[name] for name in light_units.RECEIVERS]
        for kind in ("BLACKBODY", "RGB"):
            if kind == "RGB":
                rgb = tree.nodes.new("ShaderNodeRGB")
                rgb.outputs[0].default_value = (0.2, 0.9, 0.4, 1.0)
                tree.links.new(rgb.outputs[0], emission.inputs["Color"])
            reference, _ = cycles_bake.cycles_direct(receivers, SKY_CYCLES_SAMPLES)
            bakes, reports = self.bake_receivers("POINT", built)
            self.assertFalse([w for w in reports[0]["warnings"] if "nodes" in w],
                             reports[0]["warnings"])
            self.compare(f"light nodes: {kind}", bakes, reference)
        # A tree it cannot read warns.
        tree.nodes.new("ShaderNodeLightFalloff")
        falloff = next(n for n in tree.nodes if n.type == "LIGHT_FALLOFF")
        tree.links.new(falloff.outputs[0], emission.inputs["Strength"])
        _, reports = self.bake_receivers("POINT", built, seeds=(0,))
        self.assertTrue([w for w in reports[0]["warnings"] if "shader nodes are ignored" in w],
                        reports[0]["warnings"])

    def test_area_spread_against_cycles(self):
        """Area lights with a spread of 60 and then 20 degrees (Cycles' soft box: the same
        power, concentrated along the light's axis): a square and a disk, against live Cycles
        bakes (no stored reference: made here, 1,024 samples)."""
        import cycles_bake
        for kind in ("AREA_SQUARE", "AREA_DISK"):
            common.new_empty_scene()
            built = light_units.build_light_scene(kind)
            light = next(o for o in bpy.context.scene.objects if o.type == "LIGHT").data
            receivers = [built[name] for name in light_units.RECEIVERS]
            for degrees in (60.0, 20.0):
                light.spread = math.radians(degrees)
                reference, _ = cycles_bake.cycles_direct(receivers, 4 * SKY_CYCLES_SAMPLES)
                bakes, reports = self.bake_receivers("AREA_SQUARE", built)
                self.assertFalse([w for w in reports[0]["warnings"] if "spread" in w],
                                 reports[0]["warnings"])
                self.compare(f"{kind} spread {degrees:.0f} deg", bakes, reference,
                             tolerance=SPREAD_TOLERANCE)

    # Settings of later versions, against that version's Cycles.
    def check_newer_kind(self, kind):
        first = light_units.NEWER_LIGHT_KINDS[kind]
        if kind not in light_units.light_kinds():
            self.skipTest(f"Blender {bpy.app.version_string} has no such setting (it came in "
                          f"{first[0]}.{first[1]})")
        self.check_kind(kind)

    def test_spot_exposure_and_temperature(self):
        self.check_newer_kind("SPOT_EXPOSURE_TEMPERATURE")

    def test_sun_exposure_and_temperature(self):
        self.check_newer_kind("SUN_TEMPERATURE")

    def test_area_not_normalized(self):
        self.check_newer_kind("AREA_NOT_NORMALIZED")

    def test_point_not_normalized(self):
        self.check_newer_kind("POINT_NOT_NORMALIZED")

    def test_sun_not_normalized(self):
        self.check_newer_kind("SUN_NOT_NORMALIZED")

    def test_emissive_mesh_textured(self):
        bakes, reports = self.check_kind(textured_emitter.KIND)
        for report in reports:
            emission_warnings = [w for w in report["warnings"] if "emission" in w or "texture" in w]
            self.assertEqual(emission_warnings, [], "a supported textured emission warns")
        # The same emission wired through a Principled BSDF (and a reroute) is the same scene.
        common.new_empty_scene()
        built = textured_emitter.build_textured_emitter_scene("PRINCIPLED")
        principled, _ = self.bake_receivers(textured_emitter.KIND, built, seeds=(0,))
        numpy.testing.assert_array_equal(principled[0], bakes[0])
        # The emitter as one quad (two triangles, each light-sampled by cells of its texture)
        # emits the same light as the split one the reference was made with.
        reference, _ = common.load_reference(f"light_{textured_emitter.KIND}")
        common.new_empty_scene()
        built = textured_emitter.build_textured_emitter_scene("EMISSION", emitter_cells=1)
        bakes, _ = self.bake_receivers(textured_emitter.KIND, built)
        self.compare(textured_emitter.KIND + " (one quad)", bakes, reference)


if __name__ == "__main__":
    common.run_tests(__name__)
