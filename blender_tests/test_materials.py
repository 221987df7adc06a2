"""What the add-on reads from Blender materials (addon/bakegi/export/materials.py), glossy lobes in
particular: the values are fixed by the documented mapping (Phong exponent from roughness,
reflectance from metallic and the dielectric's hemispherical-average Fresnel), so the
expected numbers below are computed from the formulas, not copied from a run."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import unittest  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402


node_material = common.node_material


def phong_exponent(roughness):
    """The mapping's formula: Beckmann alpha = roughness², half-vector exponent 2/alpha² − 2, a
    quarter of it around the mirror direction."""
    alpha = roughness * roughness
    return (2.0 / (alpha * alpha) - 2.0) / 4.0


class Materials(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        common.new_empty_scene()
        cls.bakegi = common.enable_addon()
        from bakegi.export import materials

        cls.materials = materials

    def test_diffuse_bsdf_has_no_glossy_lobe(self):
        material, node = node_material("diffuse", "ShaderNodeBsdfDiffuse")
        node.inputs["Color"].default_value = (0.2, 0.4, 0.6, 1.0)
        info = self.materials.read_material(material)
        for got, expected in zip(info.albedo, (0.2, 0.4, 0.6)):
            self.assertAlmostEqual(got, expected, places=6)
        self.assertEqual(tuple(info.glossy), (0.0, 0.0, 0.0))
        self.assertEqual(info.glossy_exponent, 0.0)

    def test_metal_reflects_its_color_with_the_roughness_exponent(self):
        material, node = node_material("metal", "ShaderNodeBsdfPrincipled")
        node.inputs["Base Color"].default_value = (0.9, 0.6, 0.3, 1.0)
        node.inputs["Metallic"].default_value = 1.0
        node.inputs["Roughness"].default_value = 0.3
        info = self.materials.read_material(material)
        self.assertEqual(tuple(info.albedo), (0.0, 0.0, 0.0))  # a metal has no diffuse base
        for got, expected in zip(info.glossy, (0.9, 0.6, 0.3)):
            self.assertAlmostEqual(got, expected, places=6)
        self.assertAlmostEqual(info.glossy_exponent, phong_exponent(0.3), places=3)
        # A strong glossy lobe is approximated (docs/compatibility.md): the user is told.
        self.assertEqual(len([w for w in info.warnings if "Phong lobe" in w]), 1, info.warnings)

    def test_dielectric_adds_average_fresnel_and_keeps_its_diffuse_in_3x(self):
        material, node = node_material("plastic", "ShaderNodeBsdfPrincipled")
        node.inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1.0)
        node.inputs["Roughness"].default_value = 0.5
        if "Specular" in node.inputs:  # Blender 3.x: F0 = 0.08 × Specular
            node.inputs["Specular"].default_value = 0.5
            f0 = 0.04
            diffuse = 0.5
        else:  # 4.x: F0 from the IOR and Specular IOR Level; the base is layered under it
            node.inputs["IOR"].default_value = 1.5
            node.inputs["Specular IOR Level"].default_value = 0.5
            f0 = ((1.5 - 1.0) / (1.5 + 1.0)) ** 2
            diffuse = 0.5 * (1.0 - self.materials.fresnel_hemispherical_average(f0))
        f_avg = self.materials.fresnel_hemispherical_average(f0)
        info = self.materials.read_material(material)
        for got in info.albedo:
            self.assertAlmostEqual(got, diffuse, places=5)
        for got in info.glossy:
            self.assertAlmostEqual(got, f_avg, places=5)
        self.assertAlmostEqual(info.glossy_exponent, phong_exponent(0.5), places=3)
        self.assertEqual([w for w in info.warnings if "Phong lobe" in w], [])  # a coat is no metal

    def test_average_fresnel_is_the_exact_dielectric_one(self):
        """The hemispherical reflectance of a dielectric: none without an interface, 0.0918
        for glass (n = 1.5, f0 = 0.04; the known reflectance of glass for diffuse light,
        0.092), all for a perfect reflector."""
        average = self.materials.fresnel_hemispherical_average
        self.assertEqual(average(0.0), 0.0)
        self.assertAlmostEqual(average(0.04), 0.0918, places=4)
        self.assertEqual(average(1.0), 1.0)
        # The specular of Principled v2 with Specular IOR Level 0 is gone, so its base is whole.
        material, node = node_material("matte", "ShaderNodeBsdfPrincipled")
        node.inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1.0)
        node.inputs["Specular IOR Level" if "Specular IOR Level" in node.inputs else "Specular"].default_value = 0.0
        info = self.materials.read_material(material)
        self.assertEqual(tuple(info.albedo), (0.5, 0.5, 0.5))
        self.assertFalse(info.glossy is not None and max(info.glossy) > 0.0)

    def test_glossy_bsdf_and_total_reflectance_stays_at_most_one(self):
        material, node = node_material("mirror", "ShaderNodeBsdfGlossy")
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        node.inputs["Roughness"].default_value = 0.0
        info = self.materials.read_material(material)
        self.assertEqual(tuple(info.glossy), (1.0, 1.0, 1.0))
        self.assertEqual(info.glossy_exponent, self.materials.MAX_GLOSSY_EXPONENT)

        # A white diffuse base with a metal-free specular on top sums above 1 in 3.x: the
        # glossy part gives way, so the core never sees albedo + glossy > 1.
        material, node = node_material("white", "ShaderNodeBsdfPrincipled")
        node.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        info = self.materials.read_material(material)
        for a, g in zip(info.albedo, info.glossy):
            self.assertLessEqual(a + g, 1.0 + 1e-9)


    # ---- textured emission -------------------------------------------------------------

    def image(self, name="pattern"):
        image = bpy.data.images.new(name, 4, 4, float_buffer=True)
        return image

    def test_surfaces_that_let_light_through_are_read(self):
        """Glass, transparent and cut-out surfaces become the core's see-through materials:
        the share passing straight on (transmission), the share present (opacity, or an alpha
        texture), and the reflectances of a surface a ray stopped at (what Cycles reflects of
        all the light meeting it, divided by the share that stops)."""
        m = self.materials
        opaque, _ = node_material("opaque", "ShaderNodeBsdfPrincipled")
        info = m.read_material(opaque)
        self.assertFalse(info.lets_light_pass())
        self.assertFalse([w for w in info.warnings if "thin glass" in w or "opaque" in w])

        # A Principled window (transmission 1, roughness 0): F_avg reflected, the rest passes.
        window, node = node_material("window", "ShaderNodeBsdfPrincipled")
        (node.inputs.get("Transmission Weight") or node.inputs["Transmission"]).default_value = 1.0
        node.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        node.inputs["Roughness"].default_value = 0.0
        info = m.read_material(window)
        f_avg = m.fresnel_hemispherical_average(m._principled_f0(node, info, "window"))
        self.assertGreater(f_avg, 0.05)
        self.assertLess(f_avg, 0.15)
        self.assertAlmostEqual(info.transmission, 1.0 - f_avg, places=6)
        self.assertEqual(info.opacity, 1.0)
        self.assertEqual(tuple(info.albedo), (0.0, 0.0, 0.0))
        for g in info.glossy:  # F_avg / (1 - transmission): a mirror where a ray stops
            self.assertAlmostEqual(g, 1.0, places=5)
        self.assertTrue(any("thin glass" in w for w in info.warnings), info.warnings)
        self.assertAlmostEqual(info.transmission_ior, 1.5, places=3)  # F0 0.04

        # Glass BSDF (IOR 1.5): the same split; Transparent BSDF: everything passes.
        glass, node = node_material("glass", "ShaderNodeBsdfGlass")
        node.inputs["IOR"].default_value = 1.5
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        info = m.read_material(glass)
        f_avg = m.fresnel_hemispherical_average(0.04)
        self.assertAlmostEqual(info.transmission, 1.0 - f_avg, places=6)
        self.assertAlmostEqual(max(info.glossy), 1.0, places=5)
        self.assertTrue(any("Glass BSDF" in w and "thin glass" in w for w in info.warnings))
        self.assertAlmostEqual(info.transmission_ior, 1.5, places=6)
        clear, node = node_material("clear", "ShaderNodeBsdfTransparent")
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        info = m.read_material(clear)
        self.assertEqual(info.transmission, 1.0)
        self.assertEqual(info.transmission_ior, 0.0)  # no Fresnel: the same at every angle
        self.assertEqual(tuple(info.albedo), (0.0, 0.0, 0.0))

        # A constant alpha: the share present; the albedo is the base colour's.
        veil, node = node_material("veil", "ShaderNodeBsdfPrincipled")
        node.inputs["Alpha"].default_value = 0.25
        info = m.read_material(veil)
        self.assertAlmostEqual(info.opacity, 0.25, places=6)
        self.assertEqual(info.transmission, 0.0)
        self.assertIsNone(info.opacity_texture)

        # A leaf: an image's alpha into Alpha; and the old cut-out mix (Transparent | diffuse,
        # by the image's alpha): both an opacity texture of the image's alpha channel.
        mask = bpy.data.images.new("leaf_mask", 4, 4, alpha=True)
        leaf, node = node_material("leaf", "ShaderNodeBsdfPrincipled")
        image = leaf.node_tree.nodes.new("ShaderNodeTexImage")
        image.image = mask
        leaf.node_tree.links.new(image.outputs["Alpha"], node.inputs["Alpha"])
        info = m.read_material(leaf)
        self.assertEqual(info.opacity_texture.image, mask)
        self.assertEqual(info.opacity_texture.channel, "alpha")
        self.assertFalse([w for w in info.warnings if "opaque" in w], info.warnings)

        # glTF's alpha cut-off as Blender 4.x imports it: Alpha = 1 - (alpha < 0.5), two Math
        # nodes; the export applies them to the image's alpha, texel by texel.
        clip, node = node_material("clip", "ShaderNodeBsdfPrincipled")
        nodes, links = clip.node_tree.nodes, clip.node_tree.links
        image = nodes.new("ShaderNodeTexImage")
        image.image = mask
        less, one_minus = nodes.new("ShaderNodeMath"), nodes.new("ShaderNodeMath")
        less.operation, one_minus.operation = "LESS_THAN", "SUBTRACT"
        less.inputs[1].default_value, one_minus.inputs[0].default_value = 0.5, 1.0
        links.new(image.outputs["Alpha"], less.inputs[0])
        links.new(less.outputs[0], one_minus.inputs[1])
        links.new(one_minus.outputs[0], node.inputs["Alpha"])
        info = m.read_material(clip)
        self.assertEqual(info.opacity_texture.math,
                         (("LESS_THAN", 0.5, 0, False), ("SUBTRACT", 1.0, 1, False)))
        alpha = numpy.linspace(0.0, 1.0, 16, dtype=numpy.float32).reshape(4, 4)
        pixels = numpy.ones((4, 4, 4), numpy.float32)
        pixels[:, :, 3] = alpha
        mask.pixels.foreach_set(pixels.ravel())
        opacity = m.image_opacity(mask, "alpha", [], info.opacity_texture.math)
        numpy.testing.assert_array_equal(opacity, (alpha >= 0.5).astype(numpy.float32))
        self.assertFalse([w for w in info.warnings if "opaque" in w], info.warnings)

        cut, mix = node_material("cut", "ShaderNodeMixShader")
        nodes, links = cut.node_tree.nodes, cut.node_tree.links
        transparent = nodes.new("ShaderNodeBsdfTransparent")
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = (0.6, 0.2, 0.1, 1.0)
        image = nodes.new("ShaderNodeTexImage")
        image.image = mask
        links.new(image.outputs["Alpha"], mix.inputs[0])
        links.new(transparent.outputs[0], mix.inputs[1])
        links.new(diffuse.outputs[0], mix.inputs[2])
        info = m.read_material(cut)
        self.assertEqual(info.opacity_texture.image, mask)
        self.assertEqual(info.transmission, 0.0)
        for a, e in zip(info.albedo, (0.6, 0.2, 0.1)):
            self.assertAlmostEqual(a, e, places=5)

        # Half transparent, half white diffuse (Fac 0.5): half passes; where a ray stops, white.
        half, mix = node_material("half", "ShaderNodeMixShader")
        nodes, links = half.node_tree.nodes, half.node_tree.links
        transparent = nodes.new("ShaderNodeBsdfTransparent")
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        links.new(transparent.outputs[0], mix.inputs[1])
        links.new(diffuse.outputs[0], mix.inputs[2])
        info = m.read_material(half)
        self.assertAlmostEqual(info.transmission, 0.5, places=6)
        for a in info.albedo:
            self.assertAlmostEqual(a, 1.0, places=5)

        # Alpha from a node the export does not evaluate: opaque, and said so.
        odd, node = node_material("odd", "ShaderNodeBsdfPrincipled")
        value = odd.node_tree.nodes.new("ShaderNodeMath")
        odd.node_tree.links.new(value.outputs[0], node.inputs["Alpha"])
        info = m.read_material(odd)
        self.assertFalse(info.lets_light_pass())
        self.assertTrue(any("read as opaque" in w for w in info.warnings), info.warnings)

    def test_coat_and_sheen_are_named(self):
        """A Principled coat or sheen (4.x: Coat Weight, Sheen Weight; 3.x: Clearcoat, Sheen)
        is not in the core's material: the export says so, and not for the defaults."""
        plain, _ = node_material("plain", "ShaderNodeBsdfPrincipled")
        self.assertFalse([w for w in self.materials.read_material(plain).warnings
                          if "not modelled" in w])
        for layer, names in (("coat", ("Coat Weight", "Clearcoat")),
                             ("sheen", ("Sheen Weight", "Sheen"))):
            material, node = node_material(layer, "ShaderNodeBsdfPrincipled")
            socket = node.inputs.get(names[0]) or node.inputs[names[1]]
            socket.default_value = 0.5
            warnings = self.materials.read_material(material).warnings
            self.assertTrue(any(f"its {layer}" in w and "not modelled" in w for w in warnings),
                            warnings)

    def test_volumes_are_named_and_volume_only_materials_marked(self):
        surface, _ = node_material("smoky", "ShaderNodeBsdfDiffuse")
        output = next(n for n in surface.node_tree.nodes if n.type == "OUTPUT_MATERIAL")
        volume = surface.node_tree.nodes.new("ShaderNodeVolumeAbsorption")
        surface.node_tree.links.new(volume.outputs[0], output.inputs["Volume"])
        info = self.materials.read_material(surface)
        self.assertFalse(info.volume_only)
        self.assertTrue(any("Volume is ignored" in w for w in info.warnings), info.warnings)
        surface.node_tree.links.remove(output.inputs["Surface"].links[0])
        info = self.materials.read_material(surface)
        self.assertTrue(info.volume_only)

    def test_image_into_emission_shader_is_an_emission_texture(self):
        material, node = node_material("screen", "ShaderNodeEmission")
        node.inputs["Strength"].default_value = 5.0
        tree = material.node_tree
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = self.image()
        tree.links.new(texture.outputs["Color"], node.inputs["Color"])
        info = self.materials.read_material(material)
        self.assertEqual(info.warnings, [])
        self.assertIsNotNone(info.emission_texture)
        self.assertEqual(info.emission_texture.image, texture.image)
        self.assertEqual(info.emission_texture.uv_map, "")
        self.assertIsNone(info.texture)
        # White times the strength: the texture carries the colour.
        for got in info.emission:
            self.assertAlmostEqual(got, 5.0, places=6)
        self.assertEqual(self.materials.sampled_uv_map(info), "")

    def test_image_through_reroute_into_principled_emission_with_its_uv_map(self):
        material, node = node_material("sign", "ShaderNodeBsdfPrincipled")
        tree = material.node_tree
        emission = node.inputs.get("Emission Color") or node.inputs["Emission"]
        node.inputs["Emission Strength"].default_value = 3.0
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = self.image()
        uv = tree.nodes.new("ShaderNodeUVMap")
        uv.uv_map = "Printed"
        tree.links.new(uv.outputs["UV"], texture.inputs["Vector"])
        reroute = tree.nodes.new("NodeReroute")
        tree.links.new(texture.outputs["Color"], reroute.inputs[0])
        tree.links.new(reroute.outputs[0], emission)
        info = self.materials.read_material(material)
        self.assertEqual([w for w in info.warnings if "emission" in w or "texture" in w], [])
        self.assertIsNotNone(info.emission_texture)
        self.assertEqual(info.emission_texture.uv_map, "Printed")
        for got in info.emission:
            self.assertAlmostEqual(got, 3.0, places=6)
        self.assertEqual(self.materials.sampled_uv_map(info), "Printed")

    def test_unsupported_emission_inputs_warn_precisely(self):
        # A colour node between image and emission is not evaluated: its default colour, and
        # a warning that names the node and the input.
        material, node = node_material("mixed", "ShaderNodeEmission")
        tree = material.node_tree
        node.inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = self.image()
        invert = tree.nodes.new("ShaderNodeInvert")
        invert.name = "Invert Screen"
        tree.links.new(texture.outputs["Color"], invert.inputs["Color"])
        tree.links.new(invert.outputs["Color"], node.inputs["Color"])
        info = self.materials.read_material(material)
        self.assertIsNone(info.emission_texture)
        self.assertEqual(len(info.warnings), 1, info.warnings)
        self.assertIn("'Invert Screen' node feeding 'Color' of 'Emission' is not evaluated",
                      info.warnings[0])
        for got, expected in zip(info.emission, (0.2, 0.3, 0.4)):
            self.assertAlmostEqual(got, expected, places=6)

        # Sampling the core does not do is named (Closest, Extend).
        material, node = node_material("pixelated", "ShaderNodeEmission")
        tree = material.node_tree
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = self.image()
        texture.interpolation = "Closest"
        texture.extension = "EXTEND"
        tree.links.new(texture.outputs["Color"], node.inputs["Color"])
        info = self.materials.read_material(material)
        self.assertIsNotNone(info.emission_texture)
        self.assertEqual(len(info.warnings), 2, info.warnings)
        self.assertIn("'Closest' interpolation; it is read as Linear", info.warnings[0])
        self.assertIn("extension 'EXTEND'; it is read as Repeat", info.warnings[1])

        # A textured emission mixed with another emission cannot be one texture x one colour.
        material, mix = node_material("two lights", "ShaderNodeMixShader")
        tree = material.node_tree
        textured = tree.nodes.new("ShaderNodeEmission")
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = self.image()
        tree.links.new(texture.outputs["Color"], textured.inputs["Color"])
        plain = tree.nodes.new("ShaderNodeEmission")
        tree.links.new(textured.outputs[0], mix.inputs[1])
        tree.links.new(plain.outputs[0], mix.inputs[2])
        info = self.materials.read_material(material)
        self.assertIsNone(info.emission_texture)
        self.assertTrue(any("textured emission mixed with another emission is read with its "
                            "texture as white" in w for w in info.warnings), info.warnings)

    def test_base_color_and_emission_textures_on_different_uv_maps(self):
        material, node = node_material("both", "ShaderNodeBsdfPrincipled")
        tree = material.node_tree
        emission = node.inputs.get("Emission Color") or node.inputs["Emission"]
        node.inputs["Emission Strength"].default_value = 1.0  # 0 by default since Blender 4.0
        for socket, uv_map in ((node.inputs["Base Color"], "Albedo"), (emission, "Glow")):
            texture = tree.nodes.new("ShaderNodeTexImage")
            texture.image = self.image()
            uv = tree.nodes.new("ShaderNodeUVMap")
            uv.uv_map = uv_map
            tree.links.new(uv.outputs["UV"], texture.inputs["Vector"])
            tree.links.new(texture.outputs["Color"], socket)
        info = self.materials.read_material(material)
        self.assertEqual(info.texture.uv_map, "Albedo")
        self.assertEqual(info.emission_texture.uv_map, "Glow")
        self.assertEqual(self.materials.sampled_uv_map(info), "Glow")
        self.assertTrue(any("different UV maps ('Albedo', 'Glow'); both are sampled with the "
                            "emission's" in w for w in info.warnings), info.warnings)

    def test_export_shares_plain_images_and_scales_hdr_ones(self):
        # One image as both base colour and emission of a material: one core texture. A float
        # image brighter than 1 on an emission: a second texture, scaled into [0,1] (the core
        # refuses texels above 1; the scale goes into the emission, see export/scene.py).
        import tempfile

        import cornell_box

        common.new_empty_scene()
        plain = bpy.data.images.new("plain", 2, 2, float_buffer=True)
        plain.pixels.foreach_set([0.5, 0.25, 1.0, 1.0] * 4)
        hdr = bpy.data.images.new("hdr", 2, 2, float_buffer=True)
        hdr.pixels.foreach_set([4.0, 2.0, 1.0, 1.0] * 4)
        both, node = node_material("both", "ShaderNodeBsdfPrincipled")
        tree = both.node_tree
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = plain
        tree.links.new(texture.outputs["Color"], node.inputs["Base Color"])
        tree.links.new(texture.outputs["Color"], node.inputs.get("Emission Color") or node.inputs["Emission"])
        node.inputs["Emission Strength"].default_value = 2.0
        bright, node = node_material("bright", "ShaderNodeEmission")
        texture = bright.node_tree.nodes.new("ShaderNodeTexImage")
        texture.image = hdr
        bright.node_tree.links.new(texture.outputs["Color"], node.inputs["Color"])
        objects = []
        for k, material in enumerate((both, bright)):
            vertices, faces = [], []
            cornell_box.grid_faces((k * 2.0, 0, 0), (1, 0, 0), (0, 1, 0), 1, 1, vertices, faces)
            obj = cornell_box.mesh_object(f"Panel{k}", vertices, faces, material, bpy.context.scene.collection)
            obj.data.uv_layers.new(name="UVMap")
            objects.append(obj)
        bpy.context.view_layer.update()
        with tempfile.TemporaryDirectory() as folder:
            result = self.bakegi.export_scene_file(os.path.join(folder, "s.bgs"), objects=objects)
        self.assertEqual(result["counts"]["textures"], 2)
        self.assertEqual([w for w in result["warnings"] if "texture" in w or "image" in w], [])


if __name__ == "__main__":
    common.run_tests(__name__)
