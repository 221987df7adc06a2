"""Does EEVEE light other surfaces with an emission gated by Light Path "Is Camera Ray"?

The Material Preview hook shows a bake as such an emission (write/material_hook.py): Cycles does not
pass it on to other surfaces. This renders, with EEVEE, a white floor in front of a wall whose
red emission is 0, gated by Is Camera Ray, or always 1, and prints the floor's mean colour:

    <python with bpy 4.2+> blender_tests/bpy_boot.py tools/eevee_double_light_probe.py [-- --raytracing]

Measured (2026-11-25, software OpenGL, 96 x 64 pixels, 4 samples): with Raytracing off (the
default) the floor stays black in all three cases on 4.2, 4.5 and 5.0; with it on, the gated
emission lights the floor exactly as much as the ungated one (red 0.466-0.468). So the bake
warns when EEVEE's Raytracing is on (compat.eevee_raytracing_on).
"""

import sys
import time

import bpy
import numpy

WIDTH, HEIGHT = 96, 64
FLOOR_ROWS = 20  # the bottom rows of the frame show only the floor


def node_material(name, wall_emission):
    """White diffuse; with wall_emission (0.0, 1.0 or "CAMERA") plus a red emission."""
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
    if wall_emission is None:
        tree.links.new(diffuse.outputs[0], output.inputs["Surface"])
        return material
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (1.0, 0.0, 0.0, 1.0)
    if wall_emission == "CAMERA":
        light_path = tree.nodes.new("ShaderNodeLightPath")
        tree.links.new(light_path.outputs["Is Camera Ray"], emission.inputs["Strength"])
    else:
        emission.inputs["Strength"].default_value = wall_emission
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(diffuse.outputs[0], add.inputs[0])
    tree.links.new(emission.outputs[0], add.inputs[1])
    tree.links.new(add.outputs[0], output.inputs["Surface"])
    return material


def quad(scene, name, vertices, material):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], [(0, 1, 2, 3)])
    if material is not None:
        mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def main():
    raytracing = "--raytracing" in sys.argv
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    engines = bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items.keys()
    scene.render.engine = "BLENDER_EEVEE_NEXT" if "BLENDER_EEVEE_NEXT" in engines else "BLENDER_EEVEE"
    if not hasattr(scene.eevee, "use_raytracing"):
        sys.exit(f"Blender {bpy.app.version_string}'s EEVEE has no Raytracing (EEVEE Next came in 4.2)")
    scene.eevee.use_raytracing = raytracing
    scene.eevee.taa_render_samples = 4
    world = bpy.data.worlds.new("Black")
    scene.world = world
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    quad(scene, "Floor", [(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)], node_material("Floor", None))
    wall = quad(scene, "Wall", [(-2, 0, 0), (-2, 0, 2), (2, 0, 2), (2, 0, 0)], None)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.0, -4.0, 1.2)
    camera.rotation_euler = (1.35, 0.0, 0.0)
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    for wall_emission in (0.0, "CAMERA", 1.0):
        wall.data.materials.clear()
        wall.data.materials.append(node_material(f"Wall {wall_emission}", wall_emission))
        scene.render.filepath = f"{bpy.app.tempdir or '/tmp/'}eevee_probe_{wall_emission}.png"
        start = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath, check_existing=False)
        pixels = numpy.array(image.pixels[:]).reshape(HEIGHT, WIDTH, 4)
        floor = pixels[:FLOOR_ROWS, :, :3].mean(axis=(0, 1))  # row 0 is the bottom
        print(f"eevee_double_light_probe: Blender {bpy.app.version_string}, raytracing {raytracing}, "
              f"wall emission {wall_emission}: floor mean RGB {numpy.round(floor, 4).tolist()} "
              f"({time.perf_counter() - start:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
