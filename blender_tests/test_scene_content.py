"""Scene content that reaches the bake through the depsgraph as something other than a plain
mesh object: collection instances and geometry-nodes instances (each a copy of a mesh the
export must place), and a mesh without faces (nothing to bake on). Each is checked by what the
export hands the core (its triangle count) and by the bake."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

NAMES = ("Floor", "Ceiling", "BackWall", "LeftWall", "RightWall", "ShortBox", "TallBox")
BOX_TRIANGLES = 12


def geometry_nodes_group(name):
    """An empty geometry-nodes group with one geometry input and output (the API that makes
    its sockets changed in 4.0)."""
    tree = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if hasattr(tree, "interface"):
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    return tree


class SceneContent(common.SmallCornellCase):

    def exported_triangles(self):
        path = os.path.join(bpy.app.tempdir or "/tmp", "bakegi_test_content.bgs")
        result = self.bakegi.export_scene_file(path, target="CORNER", objects=list(NAMES))
        return result["counts"]["triangles"]

    def bake(self):
        report = self.bakegi.bake(method="pathtrace", samples=16, seed=3, target="CORNER",
                                  objects=list(NAMES), estimate_error=False)
        return common.read_color_attribute(NAMES, domain="CORNER"), report

    def test_collection_instances_are_in_the_bake(self):
        """A box in a collection excluded from the view layer, instanced twice by empties: two
        boxes in the export (the excluded original none), and their shadow in the bake."""
        before = self.exported_triangles()
        plain, _ = self.bake()
        collection = bpy.data.collections.new("Props")
        bpy.context.scene.collection.children.link(collection)
        bpy.ops.mesh.primitive_cube_add(size=0.4, location=(0.0, 0.0, 0.0))
        box = bpy.context.active_object
        for owner in list(box.users_collection):
            owner.objects.unlink(box)
        collection.objects.link(box)
        bpy.context.view_layer.layer_collection.children[collection.name].exclude = True
        for i, location in enumerate(((0.0, 0.0, 1.5), (0.3, 0.3, 1.2))):
            empty = bpy.data.objects.new(f"Instancer{i}", None)
            empty.instance_type = "COLLECTION"
            empty.instance_collection = collection
            empty.location = location
            bpy.context.scene.collection.objects.link(empty)
        bpy.context.view_layer.update()
        self.assertEqual(self.exported_triangles() - before, 2 * BOX_TRIANGLES)
        shaded, _ = self.bake()
        floor = slice(0, len(bpy.data.objects["Floor"].data.loops))
        print(f"collection instances: the floor's mean light {shaded[floor].mean():.4f} with "
              f"them, {plain[floor].mean():.4f} without")
        # Two boxes under the lamp darken the floor (measured: its mean indirect light falls
        # by 44%; the bake's seed is the same, and its noise at 16 paths is a few percent).
        self.assertLess(shaded[floor].mean(), 0.95 * plain[floor].mean())

    def test_geometry_nodes_instances_are_in_the_bake(self):
        """A plane whose geometry nodes put a box on each of its 4 vertices (Instance on
        Points): the export has the 4 boxes and not the plane, which the nodes replaced."""
        before = self.exported_triangles()
        bpy.ops.mesh.primitive_plane_add(size=0.8, location=(0.0, 0.0, 1.4))
        plane = bpy.context.active_object
        tree = geometry_nodes_group("BoxesOnPoints")
        plane.modifiers.new("Boxes", "NODES").node_group = tree
        group_in = tree.nodes.new("NodeGroupInput")
        group_out = tree.nodes.new("NodeGroupOutput")
        instance = tree.nodes.new("GeometryNodeInstanceOnPoints")
        cube = tree.nodes.new("GeometryNodeMeshCube")
        cube.inputs["Size"].default_value = (0.1, 0.1, 0.1)
        tree.links.new(group_in.outputs[0], instance.inputs["Points"])
        tree.links.new(cube.outputs[0], instance.inputs["Instance"])
        tree.links.new(instance.outputs[0], group_out.inputs[0])
        bpy.context.view_layer.update()
        self.assertEqual(self.exported_triangles() - before, 4 * BOX_TRIANGLES)
        values, _ = self.bake()
        self.assertTrue(numpy.isfinite(values).all())

    def test_a_mesh_without_faces_is_named_and_skipped(self):
        """Edges only: no surface to bake on or to block light; the report names it and the
        other targets are baked."""
        mesh = bpy.data.meshes.new("Wire")
        mesh.from_pydata([(0.0, 0.0, 1.0), (0.5, 0.0, 1.0)], [(0, 1)], [])
        wire = bpy.data.objects.new("Wire", mesh)
        bpy.context.scene.collection.objects.link(wire)
        bpy.context.view_layer.update()
        report = self.bakegi.bake(method="pathtrace", samples=16, seed=3, target="CORNER",
                                  objects=list(NAMES) + ["Wire"], estimate_error=False)
        self.assertTrue(any("'Wire'" in w and "no faces" in w for w in report["warnings"]),
                        report["warnings"])
        self.assertIsNone(mesh.color_attributes.get(common.ATTRIBUTE))
        self.assertGreater(common.read_color_attribute(NAMES, domain="CORNER").mean(), 0.0)


if __name__ == "__main__":
    common.run_tests(__name__)
