"""What the add-on reads from Blender materials (addon/bakegi/materials.py), glossy lobes in
particular: the values are fixed by the documented mapping (Phong exponent from roughness,
reflectance from metallic and the dielectric's hemispherical-average Fresnel), so the
expected numbers below are computed from the formulas, not copied from a run."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import unittest  # noqa: E402

import bpy  # noqa: E402


def node_material(name, kind):
    """A material whose output is fed by one new shader node of `kind`; returns (material, node)."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    for node in list(nodes):
        if node.type != "OUTPUT_MATERIAL":
            nodes.remove(node)
    output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")
    shader = nodes.new(kind)
    material.node_tree.links.new(shader.outputs[0], output.inputs["Surface"])
    return material, shader


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
        from bakegi import materials

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
            diffuse = 0.5 * (1.0 - (f0 + (1.0 - f0) / 21.0))
        f_avg = f0 + (1.0 - f0) / 21.0
        info = self.materials.read_material(material)
        for got in info.albedo:
            self.assertAlmostEqual(got, diffuse, places=5)
        for got in info.glossy:
            self.assertAlmostEqual(got, f_avg, places=5)
        self.assertAlmostEqual(info.glossy_exponent, phong_exponent(0.5), places=3)

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


if __name__ == "__main__":
    common.run_tests(__name__)
