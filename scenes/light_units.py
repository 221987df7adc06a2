"""Small scenes with one light each, to pin bakegi's light units to Cycles.

Run:
    blender -b --factory-startup --python scenes/light_units.py -- --kind SPOT --out spot.blend

or import it and call ``build_light_scene(kind)``. Kinds: LIGHT_KINDS, and on the Blender
versions that have their settings NEWER_LIGHT_KINDS (``light_kinds()`` lists this version's).

Every scene has the same receivers: a 4 m x 4 m floor, a 4 m x 2 m back wall
and a small square blocker floating above the floor that casts a shadow, so
the comparison covers cosine fall-off, distance fall-off, the spot cone and
its blend, and the penumbra a light of finite size casts. The light sits in
front of the wall, tilted where its orientation matters. Light sizes,
powers and colours are not round-trip defaults, so a unit or shape mix-up
shows. Receivers are white-ish diffuse; the scene has no indirect light in a
direct-light bake, only the direct term is compared.
"""

import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cornell_box  # noqa: E402  (shared helpers: materials, grids, clearing)

LIGHT_KINDS = (
    "POINT",
    "SPOT",
    "SUN",
    "AREA_SQUARE",
    "AREA_RECTANGLE",
    "AREA_DISK",
    "AREA_ELLIPSE",
    "EMISSIVE_MESH",
    "WORLD",
    "WORLD_IMAGE",
)

# Light settings later Blender versions added, each kind with the first version that has them:
# exposure, blackbody temperature and 'Normalize' (4.5).
NEWER_LIGHT_KINDS = {
    "SPOT_EXPOSURE_TEMPERATURE": (4, 5),
    "SUN_TEMPERATURE": (4, 5),
    "AREA_NOT_NORMALIZED": (4, 5),
    "POINT_NOT_NORMALIZED": (4, 5),
    "SUN_NOT_NORMALIZED": (4, 5),
}


def light_kinds(version=None):
    """The kinds this Blender version can build."""
    version = tuple((version or bpy.app.version)[:2])
    return LIGHT_KINDS + tuple(k for k, first in NEWER_LIGHT_KINDS.items() if version >= first)


RECEIVER_ALBEDO = (0.8, 0.8, 0.8)
RECEIVERS = ("Floor", "Wall", "Blocker")
DEFAULT_SUBDIVISIONS = 20  # cells along 4 m: about 2.5k face corners


def _add_light(kind, collection):
    """Add the one light of `kind`; return its object (None for the world)."""
    area_shapes = {
        "AREA_SQUARE": ("SQUARE", 0.8, 0.8),
        "AREA_RECTANGLE": ("RECTANGLE", 1.2, 0.4),
        "AREA_DISK": ("DISK", 0.9, 0.9),
        "AREA_ELLIPSE": ("ELLIPSE", 1.1, 0.5),
    }
    if kind in NEWER_LIGHT_KINDS:
        return _add_newer_light(kind, collection)
    if kind == "POINT":
        data = bpy.data.lights.new("Light", "POINT")
        data.energy = 150.0
        data.shadow_soft_size = 0.25  # radius
        data.color = (1.0, 0.85, 0.7)
        location, rotation = (0.4, -0.3, 1.6), (0.0, 0.0, 0.0)
    elif kind == "SPOT":
        data = bpy.data.lights.new("Light", "SPOT")
        data.energy = 300.0
        data.shadow_soft_size = 0.1
        data.spot_size = math.radians(75.0)
        data.spot_blend = 0.35
        data.color = (0.9, 0.95, 1.0)
        # Tilted towards the wall so the cone edge falls on the floor and the wall.
        location, rotation = (-0.3, -1.0, 2.2), (math.radians(35.0), 0.0, math.radians(10.0))
    elif kind == "SUN":
        data = bpy.data.lights.new("Light", "SUN")
        data.energy = 3.0  # W/m^2 irradiance at normal incidence
        data.angle = math.radians(12.0)
        data.color = (1.0, 0.95, 0.85)
        location, rotation = (0.0, 0.0, 5.0), (math.radians(35.0), 0.0, math.radians(-20.0))
    elif kind in area_shapes:
        shape, size_x, size_y = area_shapes[kind]
        data = bpy.data.lights.new("Light", "AREA")
        data.shape = shape
        data.size = size_x
        data.size_y = size_y
        data.energy = 120.0
        data.color = (1.0, 0.9, 0.8)
        location, rotation = (0.2, -0.4, 1.5), (math.radians(20.0), math.radians(-10.0), math.radians(15.0))
    else:
        raise ValueError(f"unknown light kind {kind!r}; expected one of {LIGHT_KINDS}")
    light = bpy.data.objects.new("Light", data)
    light.location = location
    light.rotation_euler = rotation
    collection.objects.link(light)
    return light


def _add_newer_light(kind, collection):
    """The kinds of NEWER_LIGHT_KINDS: a base kind with the later settings changed."""
    if kind == "SPOT_EXPOSURE_TEMPERATURE":
        light = _add_light("SPOT", collection)
        light.data.exposure = -0.6
        light.data.use_temperature = True
        light.data.temperature = 3200.0
    elif kind == "SUN_TEMPERATURE":
        light = _add_light("SUN", collection)
        light.data.exposure = 1.3
        light.data.use_temperature = True
        light.data.temperature = 9500.0
    elif kind == "AREA_NOT_NORMALIZED":
        light = _add_light("AREA_RECTANGLE", collection)
        light.data.normalize = False
        light.data.energy = 25.0  # per m^2 of a 1.2 x 0.4 m light: about 1/2 of AREA_RECTANGLE
    elif kind == "POINT_NOT_NORMALIZED":
        light = _add_light("POINT", collection)
        light.data.normalize = False
        light.data.energy = 600.0  # x 4 pi (0.25 m)^2: about 3x POINT
    elif kind == "SUN_NOT_NORMALIZED":
        light = _add_light("SUN", collection)
        light.data.normalize = False
        light.data.energy = 80.0  # x pi sin^2(6 deg): about the irradiance of SUN
    else:
        raise ValueError(f"unknown light kind {kind!r}")
    return light


def _add_emissive_quad(collection):
    """A 0.6 m square emitter, tilted so both of its sides light the receivers."""
    material = cornell_box.emission_material("Emitter", (1.0, 0.8, 0.6), 12.0)
    size = 0.6
    vertices, faces = [], []
    cornell_box.grid_faces((-size / 2, -size / 2, 0.0), (size, 0, 0), (0, size, 0), 1, 1, vertices, faces)
    emitter = cornell_box.mesh_object("Emitter", vertices, faces, material, collection)
    emitter.location = (0.2, -0.3, 1.2)
    # Nearly vertical: one side faces the wall, the other the open front; both see the floor.
    emitter.rotation_euler = (math.radians(70.0), 0.0, math.radians(20.0))
    return emitter


# The world image of WORLD_IMAGE: a 64 x 32 equirectangular sky, bluish and brighter towards
# the horizon, an orange ground below it, and a sun of 2 x 2 texels (5.6 degrees) 40 times the
# sky's brightness; turned by a Mapping node so that the sun falls obliquely on the receivers
# and the image's u = 0 seam crosses the sky above them.
WORLD_IMAGE_SIZE = (64, 32)
WORLD_IMAGE_SUN_TEXELS = ((41, 25), (42, 25), (41, 26), (42, 26))
WORLD_IMAGE_ROTATION = (0.35, -0.2, 1.1)  # the Mapping node's XYZ Euler rotation, radians


def world_image_pixels():
    """(height, width, 4) RGBA float pixels of the WORLD_IMAGE sky, row 0 at the bottom."""
    width, height = WORLD_IMAGE_SIZE
    pixels = []
    for j in range(height):
        elevation = ((j + 0.5) / height - 0.5) * math.pi
        for i in range(width):
            if elevation < 0.0:
                rgb = (0.35, 0.2, 0.1)
            else:
                horizon = 1.0 - math.sin(elevation)
                rgb = (0.3 + 0.5 * horizon, 0.45 + 0.45 * horizon, 0.9 + 0.1 * horizon)
            if (i, j) in WORLD_IMAGE_SUN_TEXELS:
                rgb = (40.0, 36.0, 30.0)
            pixels.append((*rgb, 1.0))
    return pixels


def set_image_world(scene, strength=1.2):
    """A world lit by the WORLD_IMAGE sky: Texture Coordinate (Generated) -> Mapping (point,
    WORLD_IMAGE_ROTATION) -> Environment Texture (linear, equirectangular) -> Background."""
    world = cornell_box.set_black_world(scene, strength=strength)
    tree = world.node_tree
    width, height = WORLD_IMAGE_SIZE
    image = bpy.data.images.new("WorldSky", width, height, float_buffer=True)
    image.pixels.foreach_set([c for pixel in world_image_pixels() for c in pixel])
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    mapping.inputs["Rotation"].default_value = WORLD_IMAGE_ROTATION
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    texture.interpolation = "Linear"
    tree.links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    tree.links.new(texture.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    return world


def build_light_scene(kind, subdivisions=DEFAULT_SUBDIVISIONS, clear=True):
    """Build the receivers and the one light of `kind`; return {name: object}.

    The receivers (the objects to compare) are RECEIVERS, in that order.
    """
    if kind not in light_kinds():
        raise ValueError(f"unknown light kind {kind!r} in Blender {bpy.app.version_string}; "
                         f"expected one of {light_kinds()}")
    if clear:
        cornell_box.clear_scene()
    scene = bpy.context.scene
    collection = scene.collection
    material = cornell_box.diffuse_material("Receiver", RECEIVER_ALBEDO)
    cells = max(1, subdivisions)
    objects = {}
    vertices, faces = [], []
    cornell_box.grid_faces((-2, -2, 0), (4, 0, 0), (0, 4, 0), cells, cells, vertices, faces)
    objects["Floor"] = cornell_box.mesh_object("Floor", vertices, faces, material, collection)
    vertices, faces = [], []
    cornell_box.grid_faces((-2, 1, 0), (4, 0, 0), (0, 0, 2), cells, max(1, cells // 2), vertices, faces)
    objects["Wall"] = cornell_box.mesh_object("Wall", vertices, faces, material, collection)
    vertices, faces = [], []
    blocker_cells = max(1, cells // 5)
    cornell_box.grid_faces((-0.3, -0.3, 0), (0.6, 0, 0), (0, 0.6, 0), blocker_cells, blocker_cells, vertices, faces)
    blocker = cornell_box.mesh_object("Blocker", vertices, faces, material, collection)
    blocker.location = (0.1, 0.0, 0.6)
    objects["Blocker"] = blocker

    if kind == "WORLD":
        cornell_box.set_black_world(scene, color=(0.4, 0.5, 0.6), strength=1.5)
    elif kind == "WORLD_IMAGE":
        set_image_world(scene)
    else:
        cornell_box.set_black_world(scene)
        if kind == "EMISSIVE_MESH":
            objects["Emitter"] = _add_emissive_quad(collection)
        else:
            objects["Light"] = _add_light(kind, collection)

    camera = cornell_box.add_camera(scene, (0.0, -5.0, 2.5), (70.0, 0.0, 0.0), 50.0, collection)
    objects["Camera"] = camera
    cornell_box.configure_cycles_reference(scene)
    bpy.context.view_layer.update()  # new objects count as visible only after the view layer syncs
    return objects


def main():
    import argparse

    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description="Build a one-light scene and save it as a .blend file.")
    parser.add_argument("--kind", choices=LIGHT_KINDS, required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--subdivisions", type=int, default=DEFAULT_SUBDIVISIONS)
    arguments = parser.parse_args(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build_light_scene(arguments.kind, arguments.subdivisions)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(arguments.out))
    print(f"light_units: wrote {arguments.out} ({arguments.kind})")


if __name__ == "__main__":
    main()
