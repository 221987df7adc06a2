"""The export reads the normals Blender shades with, in every version: sharp edges and custom
normals (Blender 4.1 replaced Auto Smooth with a sharp_edge attribute and always-current
corner normals; 3.4 needs Auto Smooth for both).

A quad lit by a sun straight above, angle 0 (no noise): with custom normals tilted by theta,
its direct light is cos(theta) of the untilted quad's at every corner. A cube shaded smooth
with every edge sharp: its corners take their faces' normals, not the averaged ones.
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

import cornell_box  # noqa: E402

NEW_NORMALS = bpy.app.version >= (4, 1, 0)  # sharp_edge attribute, no Auto Smooth


def quad(name, x, collection, material):
    vertices, faces = [], []
    cornell_box.grid_faces((x - 0.5, -0.5, 0.0), (1.0, 0, 0), (0, 1.0, 0), 1, 1, vertices, faces)
    obj = cornell_box.mesh_object(name, vertices, faces, material, collection)
    for polygon in obj.data.polygons:
        polygon.use_smooth = True
    return obj


def set_custom_normals(mesh, normal):
    if not NEW_NORMALS:
        mesh.use_auto_smooth = True  # 3.4 ignores custom normals without it
    mesh.normals_split_custom_set([normal] * len(mesh.loops))


def mark_every_edge_sharp(mesh):
    if NEW_NORMALS:
        attribute = mesh.attributes.get("sharp_edge") or mesh.attributes.new("sharp_edge", "BOOLEAN", "EDGE")
        attribute.data.foreach_set("value", [True] * len(mesh.edges))
    else:
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.pi
        for edge in mesh.edges:
            edge.use_edge_sharp = True
    mesh.update()


class Normals(common.AddonCase):

    def setUp(self):
        common.new_empty_scene()
        self.scene = bpy.context.scene
        self.material = cornell_box.diffuse_material("Grey", (0.5, 0.5, 0.5))
        cornell_box.set_black_world(self.scene)
        sun = bpy.data.lights.new("Sun", "SUN")
        sun.energy = 2.0
        sun.angle = 0.0
        sun_object = bpy.data.objects.new("Sun", sun)  # pointing down (-Z)
        self.scene.collection.objects.link(sun_object)

    def test_custom_normals_tilt_the_direct_light(self):
        tilt = math.radians(40.0)
        plain = quad("Plain", -1.0, self.scene.collection, self.material)
        tilted = quad("Tilted", 1.0, self.scene.collection, self.material)
        set_custom_normals(tilted.data, (math.sin(tilt), 0.0, math.cos(tilt)))
        self.bakegi.bake(method="direct", samples=1, target="CORNER", objects=[plain, tilted])
        a = common.read_color_attribute([plain], domain="CORNER")
        b = common.read_color_attribute([tilted], domain="CORNER")
        self.assertGreater(a.min(), 0.0)
        numpy.testing.assert_allclose(b / a, math.cos(tilt), rtol=1e-4)

    def test_sharp_edges_give_face_normals(self):
        from bakegi.export import mesh_arrays as export

        vertices = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
        faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
        cube = cornell_box.mesh_object("Cube", vertices, faces, self.material, self.scene.collection)
        for polygon in cube.data.polygons:
            polygon.use_smooth = True
        smooth = export.corner_normals(cube.data.copy())
        self.assertLess(numpy.abs(smooth).max(axis=1).min(), 0.9)  # averaged: not axis-aligned
        mark_every_edge_sharp(cube.data)
        sharp = export.corner_normals(cube.data)
        face_of_corner = numpy.repeat(numpy.arange(6), 4)
        face_normals = numpy.array([list(p.normal) for p in cube.data.polygons])[face_of_corner]
        numpy.testing.assert_allclose(sharp, face_normals, atol=1e-5)


if __name__ == "__main__":
    common.run_tests(__name__)
