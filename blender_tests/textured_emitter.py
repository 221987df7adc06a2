"""The light-units scene of a two-sided emissive quad (scenes/light_units.py, EMISSIVE_MESH)
with its emission colour read from an image texture, for test_light_units.py and its Cycles
reference (make_references.py).

The image is a 16 x 16 float (linear) image made here: a black block (a quarter of it less a
little), a colour gradient, and a strip brighter than 1 (an HDR emitter, which the add-on
passes to the core scaled into [0,1]). The quad's UVs run over u in [-0.2, 1.3] and
v in [0, 1.5], so the texture repeats across the quad's edges as Cycles' Repeat extension
does.

The quad is split into EMITTER_CELLS x EMITTER_CELLS faces (same plane, same UVs) for the
reference: Cycles 3.4's light sampling gets a large textured triangle close to a receiver
wrong. With the single quad of light_units, its direct bake of the blocker (0.6 m below)
comes out up to 9 % brighter than the brute-force integral of emission x texture over the
quad (600 x 600 points) and than its own bake with light sampling off for the emitter
(the material's "Multiple Importance"), while 8 x 8 and 24 x 24 faces agree with that
integral within 0.5 % (their noise at 2048 samples): the lookups at light-sampled points, not the emission, are off (an EMIT
bake of the quad reads the image exactly as bakegi does). bakegi's light is the same
whichever way the quad is split, so the test also bakes the single quad against the
reference. Two ways of wiring the same emission:
  - "EMISSION": Image Texture -> Emission shader Color (strength 12);
  - "PRINCIPLED": Image Texture -> Reroute -> Principled BSDF Emission (strength 12, black
    base colour): the same emitted radiance, so a direct-light bake of the receivers is the
    same.
"""

import bpy

import cornell_box
import light_units

KIND = "EMISSIVE_TEXTURED"
VARIANTS = ("EMISSION", "PRINCIPLED")
STRENGTH = 12.0
EMITTER_CELLS = 8
IMAGE_SIZE = 16
UV_MIN, UV_MAX = (-0.2, 0.0), (1.3, 1.5)


def texel(i, j):
    """Linear RGB of texel (column i, row j from the bottom)."""
    if i < 7 and j < 8:
        return (0.0, 0.0, 0.0)
    if j >= 13:
        return (2.5, 2.0, 1.2)
    return (0.15 + 0.05 * i, 0.6, 1.0 - 0.05 * j)


def make_image():
    image = bpy.data.images.new("EmitterPattern", IMAGE_SIZE, IMAGE_SIZE, alpha=False, float_buffer=True)
    pixels = []
    for j in range(IMAGE_SIZE):
        for i in range(IMAGE_SIZE):
            pixels.extend((*texel(i, j), 1.0))
    image.pixels.foreach_set(pixels)
    image.update()
    return image


def textured_material(image, variant):
    material = bpy.data.materials.new("TexturedEmitter")
    cornell_box.use_nodes(material)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Linear"
    texture.extension = "REPEAT"
    output = nodes.new("ShaderNodeOutputMaterial")
    if variant == "EMISSION":
        shader = nodes.new("ShaderNodeEmission")
        shader.inputs["Strength"].default_value = STRENGTH
        links.new(texture.outputs["Color"], shader.inputs["Color"])
    elif variant == "PRINCIPLED":
        shader = nodes.new("ShaderNodeBsdfPrincipled")
        shader.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        emission = shader.inputs.get("Emission Color") or shader.inputs["Emission"]
        shader.inputs["Emission Strength"].default_value = STRENGTH
        reroute = nodes.new("NodeReroute")
        links.new(texture.outputs["Color"], reroute.inputs[0])
        links.new(reroute.outputs[0], emission)
    else:
        raise ValueError(f"unknown variant {variant!r}; expected one of {VARIANTS}")
    links.new(shader.outputs[0], output.inputs["Surface"])
    return material


def set_uvs(obj):
    """UVs linear in the quad's local x, y (the quad spans [-0.3, 0.3]^2), from UV_MIN to UV_MAX."""
    mesh = obj.data
    layer = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        co = mesh.vertices[loop.vertex_index].co
        s, t = (co.x + 0.3) / 0.6, (co.y + 0.3) / 0.6
        layer.data[loop.index].uv = (UV_MIN[0] + s * (UV_MAX[0] - UV_MIN[0]),
                                     UV_MIN[1] + t * (UV_MAX[1] - UV_MIN[1]))


def split_quad(obj, cells):
    """Gives the emitter quad (local [-0.3, 0.3]^2) a mesh of cells x cells faces."""
    vertices, faces = [], []
    cornell_box.grid_faces((-0.3, -0.3, 0.0), (0.6, 0, 0), (0, 0.6, 0), cells, cells, vertices, faces)
    mesh = bpy.data.meshes.new(obj.data.name + "_split")
    mesh.from_pydata(vertices, [], faces)
    for polygon in mesh.polygons:
        polygon.use_smooth = False
    for material in obj.data.materials:
        mesh.materials.append(material)
    obj.data = mesh


def build_textured_emitter_scene(variant="EMISSION", subdivisions=light_units.DEFAULT_SUBDIVISIONS,
                                 emitter_cells=EMITTER_CELLS):
    """light_units' EMISSIVE_MESH scene with the emitter split into emitter_cells^2 faces and
    its material replaced; {name: object}."""
    objects = light_units.build_light_scene("EMISSIVE_MESH", subdivisions)
    emitter = objects["Emitter"]
    if emitter_cells > 1:
        split_quad(emitter, emitter_cells)
    set_uvs(emitter)
    emitter.data.materials[0] = textured_material(make_image(), variant)
    bpy.context.view_layer.update()
    return objects


def scene_parameters(subdivisions=light_units.DEFAULT_SUBDIVISIONS):
    return {
        "builder": "blender_tests/textured_emitter.py build_textured_emitter_scene",
        "kind": KIND,
        "variant": "EMISSION",
        "subdivisions": subdivisions,
        "emitter_cells": EMITTER_CELLS,
        "image_size": IMAGE_SIZE,
        "uv_range": [list(UV_MIN), list(UV_MAX)],
        "strength": STRENGTH,
    }
