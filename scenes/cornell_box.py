"""The Cornell box, built procedurally in Blender.

Run:
    blender -b --factory-startup --python scenes/cornell_box.py -- --out cornell.blend [--subdivisions N]

or import it from Blender's Python (``sys.path`` holding ``scenes/``) and call
``build_cornell_box()``.

Geometry follows the published Cornell box (as in the CornellBox-Original
model of McGuire's archive, converted to Blender's Z-up axes): a 2 m room,
open at the front (y = -1), red left wall, green right wall, white floor,
ceiling and back wall, a short box (0.6 m) front right and a tall box (1.2 m)
back left, each a 0.6 m square rotated as in the classic box. Reflectances
are the published diffuse colours. Every wall and box is its own mesh object
with a Diffuse BSDF, and every face is a grid of quads so that a per-corner
colour attribute has resolution. The light is a one-sided rectangular area
light (0.47 m x 0.38 m) just below the ceiling, pointing down, with the warm
colour of the classic emitter (Ke 17, 12, 4). The world is black.

The boxes carry their placement in the object transform (location and Z
rotation) rather than in the mesh, so exporters are exercised on world
transforms.
"""

import math
import sys

import bpy

# Published diffuse reflectances of the Cornell box (CornellBox-Original .mtl).
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)
WHITE = (0.725, 0.71, 0.68)

ROOM_HALF_WIDTH = 1.0  # x in [-1, 1]
ROOM_HALF_DEPTH = 1.0  # y in [-1, 1]; the front (y = -1) is open
ROOM_HEIGHT = 2.0  # z in [0, 2]

LIGHT_SIZE_X = 0.47
LIGHT_SIZE_Y = 0.38
LIGHT_HEIGHT = 1.98  # 2 cm below the ceiling, so the ceiling does not clip it
# Warm colour of the classic emitter, Ke = (17, 12, 4) normalised to its maximum.
LIGHT_COLOR = (1.0, 12.0 / 17.0, 4.0 / 17.0)
# Cycles' area light radiance is P / (4 A) (CYCLES_FACTS.md). This power gives
# the red channel the classic radiance of 17 W/(m^2 sr):
# P = 4 * 0.47 * 0.38 * 17 = 12.1 W.
LIGHT_POWER = 4.0 * LIGHT_SIZE_X * LIGHT_SIZE_Y * 17.0

BOX_SIDE = 0.6
# (name, centre x, centre y, height, rotation about Z in degrees): centroids and
# edge directions of the two boxes of the classic model.
BOXES = (
    ("ShortBox", 0.3275, -0.3725, 0.6, -16.6),
    ("TallBox", -0.335, 0.29, 1.2, 17.5),
)

TALL_BOX_METAL_ROUGHNESS = 0.4  # surface="PRINCIPLED_METAL" only

CAMERA_LOCATION = (0.0, -3.9, 1.0)
CAMERA_FOV_DEGREES = 39.3  # frames the open front of the box exactly

DEFAULT_SUBDIVISIONS = 32  # about 26k face corners in total
TEST_SUBDIVISIONS = 8  # about 1.7k face corners: the small version used by tests


def clear_scene():
    """Remove every object and every data-block the scene builders create."""
    for collection in (
        bpy.data.objects,
        bpy.data.meshes,
        bpy.data.materials,
        bpy.data.lights,
        bpy.data.cameras,
        bpy.data.worlds,
    ):
        for block in list(collection):
            collection.remove(block)


def use_nodes(block):
    """Shade a material or world by its node tree (always so from Blender 5.0, where setting
    use_nodes is deprecated)."""
    if bpy.app.version < (5, 0, 0):
        block.use_nodes = True


def uses_nodes(block):
    return block.node_tree is not None and (bpy.app.version >= (5, 0, 0) or block.use_nodes)


def bsdf_material(name, color, node_type):
    """A material whose surface is one BSDF node of `node_type` (returned with the material)
    wired to the output; `color` is also the solid-mode viewport colour."""
    material = bpy.data.materials.new(name)
    use_nodes(material)
    nodes = material.node_tree.nodes
    nodes.clear()
    bsdf = nodes.new(node_type)
    output = nodes.new("ShaderNodeOutputMaterial")
    output.location = (300, 0)
    material.node_tree.links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    material.diffuse_color = (*color, 1.0)
    return material, bsdf


def diffuse_material(name, color):
    """A material whose surface is a single Diffuse BSDF of the given colour."""
    material, diffuse = bsdf_material(name, color, "ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*color, 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0
    return material


def principled_material(name, color, roughness=0.5, metallic=0.0):
    """A material whose surface is a Principled BSDF of the given base colour with a dielectric
    coat of F0 = 0.04 in every version (3.x: Specular 0.5; 4.x: IOR 1.5, Specular IOR Level
    0.5), which Cycles 3.x adds on top of the diffuse base and 4.x's Principled v2 layers over
    it (the base then loses what the coat reflects)."""
    material, principled = bsdf_material(name, color, "ShaderNodeBsdfPrincipled")
    principled.inputs["Base Color"].default_value = (*color, 1.0)
    principled.inputs["Roughness"].default_value = roughness
    principled.inputs["Metallic"].default_value = metallic
    if "Specular IOR Level" in principled.inputs:
        principled.inputs["IOR"].default_value = 1.5
        principled.inputs["Specular IOR Level"].default_value = 0.5
    else:
        principled.inputs["Specular"].default_value = 0.5
    return material


def emission_material(name, color, strength):
    material = bpy.data.materials.new(name)
    use_nodes(material)
    nodes = material.node_tree.nodes
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*color, 1.0)
    emission.inputs["Strength"].default_value = strength
    output = nodes.new("ShaderNodeOutputMaterial")
    output.location = (300, 0)
    material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


def grid_faces(origin, edge_u, edge_v, cells_u, cells_v, vertices, faces):
    """Append a grid of quads spanning origin + s*edge_u + t*edge_v, s, t in [0, 1].

    The quads wind so that their normal is edge_u x edge_v.
    """
    first = len(vertices)
    for j in range(cells_v + 1):
        t = j / cells_v
        for i in range(cells_u + 1):
            s = i / cells_u
            vertices.append(tuple(origin[k] + s * edge_u[k] + t * edge_v[k] for k in range(3)))
    row = cells_u + 1
    for j in range(cells_v):
        for i in range(cells_u):
            a = first + j * row + i
            faces.append((a, a + 1, a + 1 + row, a + row))


def cells_for(length, subdivisions):
    """Grid cells along an edge: `subdivisions` cells per 2 m (the room's width), at least 1."""
    return max(1, round(subdivisions * length / (2.0 * ROOM_HALF_WIDTH)))


def mesh_object(name, vertices, faces, material, collection):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.update()
    for polygon in mesh.polygons:
        polygon.use_smooth = False  # flat: the corners of a face share its normal
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    collection.objects.link(obj)
    return obj


def hole_extent(length, light_size, subdivisions):
    """(lo, hi) of the grid cells across a centred edge of `length` whose centres lie within
    the light's half size: the hole the emissive panel fills."""
    cells = cells_for(length, subdivisions)
    size = length / cells
    centres = [-length / 2 + (i + 0.5) * size for i in range(cells)]
    inside = [c for c in centres if abs(c) < light_size / 2]
    if not inside:
        raise ValueError(f"{subdivisions} subdivisions leave no ceiling cell under the light")
    return min(inside) - size / 2, max(inside) + size / 2


def without_faces(vertices, faces, drop):
    """The faces for which drop(face centre) is false, and only the vertices they use."""
    kept = [f for f in faces if not drop([sum(vertices[i][k] for i in f) / len(f) for k in range(3)])]
    used = sorted({i for f in kept for i in f})
    index = {old: new for new, old in enumerate(used)}
    return [vertices[i] for i in used], [tuple(index[i] for i in f) for f in kept]


def add_wall(name, origin, edge_u, edge_v, material, subdivisions, collection, hole=None):
    """A grid-subdivided wall; `hole(centre)` true leaves that cell out."""
    vertices, faces = [], []
    length_u = math.sqrt(sum(c * c for c in edge_u))
    length_v = math.sqrt(sum(c * c for c in edge_v))
    grid_faces(
        origin,
        edge_u,
        edge_v,
        cells_for(length_u, subdivisions),
        cells_for(length_v, subdivisions),
        vertices,
        faces,
    )
    if hole is not None:
        vertices, faces = without_faces(vertices, faces, hole)
    return mesh_object(name, vertices, faces, material, collection)


def add_box(name, center_x, center_y, height, rotation_degrees, material, subdivisions, collection):
    """A box without a bottom face (it stands on the floor), faces pointing outwards."""
    h = BOX_SIDE / 2.0
    side_cells = cells_for(BOX_SIDE, subdivisions)
    height_cells = cells_for(height, subdivisions)
    vertices, faces = [], []
    # Top, normal +z.
    grid_faces((-h, -h, height), (BOX_SIDE, 0, 0), (0, BOX_SIDE, 0), side_cells, side_cells, vertices, faces)
    up = (0, 0, height)
    # Four sides: (corner, edge along the side) with edge x up pointing outwards.
    sides = (
        ((-h, -h, 0), (BOX_SIDE, 0, 0)),  # -y
        ((h, -h, 0), (0, BOX_SIDE, 0)),  # +x
        ((h, h, 0), (-BOX_SIDE, 0, 0)),  # +y
        ((-h, h, 0), (0, -BOX_SIDE, 0)),  # -x
    )
    for corner, edge in sides:
        grid_faces(corner, edge, up, side_cells, height_cells, vertices, faces)
    obj = mesh_object(name, vertices, faces, material, collection)
    obj.location = (center_x, center_y, 0.0)
    obj.rotation_euler = (0.0, 0.0, math.radians(rotation_degrees))
    return obj


def set_black_world(scene, color=(0.0, 0.0, 0.0), strength=1.0):
    world = bpy.data.worlds.new("World")
    use_nodes(world)
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = strength
    world.color = color
    scene.world = world
    return world


def configure_cycles_reference(scene, samples=1024):
    """Cycles settings for reference renders and bakes (see CYCLES_FACTS.md)."""
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_denoising = False  # this build has no OIDN: denoised bakes come back black
    cycles.use_adaptive_sampling = False
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.max_bounces = 64
    cycles.diffuse_bounces = 64
    cycles.glossy_bounces = 64
    cycles.transmission_bounces = 64
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.blur_glossy = 0.0
    cycles.seed = 0
    cycles.use_animated_seed = False
    if hasattr(cycles, "use_guiding"):
        cycles.use_guiding = False
    scene.render.bake.target = "VERTEX_COLORS"
    scene.render.bake.margin = 0
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 1.0  # one stop up: the classic emitter radiance reads dim otherwise
    scene.view_settings.gamma = 1.0


def add_camera(scene, location, rotation_degrees, fov_degrees, collection):
    camera_data = bpy.data.cameras.new("Camera")
    camera_data.sensor_fit = "AUTO"
    camera_data.angle = math.radians(fov_degrees)
    camera = bpy.data.objects.new("Camera", camera_data)
    camera.location = location
    camera.rotation_euler = tuple(math.radians(a) for a in rotation_degrees)
    collection.objects.link(camera)
    scene.camera = camera
    return camera


def build_cornell_box(subdivisions=DEFAULT_SUBDIVISIONS, light_power=LIGHT_POWER, clear=True, resolution=512,
                      light="AREA", surface="DIFFUSE"):
    """Build the Cornell box into the current scene and return {name: object}.

    subdivisions: grid cells along a 2 m edge of a wall; box faces get cells in
    proportion to their size (32 gives about 26k face corners, 8 about 1.7k).
    light: "AREA" (a rectangle area light) or "EMISSIVE" (a mesh quad of the same size and
    place with an Emission shader of the same radiance, the way most Blender scenes are lit;
    mesh emission is two-sided in Cycles 3.4, so its back lights the ceiling 2 cm above too).
    surface: "DIFFUSE" (Diffuse BSDFs, the classic box), "PRINCIPLED" (Principled BSDFs of the
    same base colours, roughness 0.5, a dielectric coat of F0 = 0.04: each version's Principled
    BSDF) or "PRINCIPLED_METAL" (the same with the tall box a rough metal of the white colour,
    roughness 0.4; Cycles' Diffuse bake of a metal is black, it has no diffuse part).
    """
    if subdivisions < 1:
        raise ValueError("subdivisions must be at least 1")
    if clear:
        clear_scene()
    scene = bpy.context.scene
    collection = scene.collection
    if surface == "DIFFUSE":
        red, green, white = (diffuse_material(n, c) for n, c in (("Red", RED), ("Green", GREEN), ("White", WHITE)))
        metal = white
    elif surface in ("PRINCIPLED", "PRINCIPLED_METAL"):
        red, green, white = (principled_material(n, c) for n, c in (("Red", RED), ("Green", GREEN), ("White", WHITE)))
        metal = white
        if surface == "PRINCIPLED_METAL":
            metal = principled_material("Metal", WHITE, roughness=TALL_BOX_METAL_ROUGHNESS, metallic=1.0)
    else:
        raise ValueError(f"surface must be DIFFUSE, PRINCIPLED or PRINCIPLED_METAL, not {surface!r}")

    w, d, top = ROOM_HALF_WIDTH, ROOM_HALF_DEPTH, ROOM_HEIGHT
    objects = {}
    # Each wall: origin, edge_u, edge_v with edge_u x edge_v pointing into the room.
    objects["Floor"] = add_wall("Floor", (-w, -d, 0), (2 * w, 0, 0), (0, 2 * d, 0), white, subdivisions, collection)
    def under_the_light(centre):
        return abs(centre[0]) < LIGHT_SIZE_X / 2 and abs(centre[1]) < LIGHT_SIZE_Y / 2

    hole = under_the_light if light == "EMISSIVE" else None
    objects["Ceiling"] = add_wall("Ceiling", (-w, -d, top), (0, 2 * d, 0), (2 * w, 0, 0), white, subdivisions,
                                  collection, hole)
    objects["BackWall"] = add_wall("BackWall", (-w, d, 0), (2 * w, 0, 0), (0, 0, top), white, subdivisions, collection)
    objects["LeftWall"] = add_wall("LeftWall", (-w, -d, 0), (0, 2 * d, 0), (0, 0, top), red, subdivisions, collection)
    objects["RightWall"] = add_wall("RightWall", (w, -d, 0), (0, 0, top), (0, 2 * d, 0), green, subdivisions, collection)
    for name, x, y, height, rotation in BOXES:
        objects[name] = add_box(name, x, y, height, rotation, metal if name == "TallBox" else white, subdivisions,
                                collection)

    if light == "EMISSIVE":
        # The panel fills the ceiling's hole (the grid cells whose centres lie under the area
        # light's rectangle) flush with the ceiling, its back to the black world above.
        radiance = light_power / (4.0 * LIGHT_SIZE_X * LIGHT_SIZE_Y)  # the area light's, CYCLES_FACTS.md
        panel_material = emission_material("CeilingPanelEmission", LIGHT_COLOR, radiance)
        (x0, x1), (y0, y1) = (hole_extent(2 * w, LIGHT_SIZE_X, subdivisions),
                              hole_extent(2 * d, LIGHT_SIZE_Y, subdivisions))
        # Wound clockwise seen from above: the face normal points down into the room.
        vertices = [(x0, y0, top), (x0, y1, top), (x1, y1, top), (x1, y0, top)]
        objects["CeilingPanel"] = mesh_object("CeilingPanel", vertices, [(0, 1, 2, 3)], panel_material, collection)
        return _finish(scene, objects, collection, resolution)
    if light != "AREA":
        raise ValueError(f"light must be AREA or EMISSIVE, not {light!r}")
    light_data = bpy.data.lights.new("CeilingLight", "AREA")
    light_data.shape = "RECTANGLE"
    light_data.size = LIGHT_SIZE_X
    light_data.size_y = LIGHT_SIZE_Y
    light_data.energy = light_power
    light_data.color = LIGHT_COLOR
    light = bpy.data.objects.new("CeilingLight", light_data)
    light.location = (0.0, 0.0, LIGHT_HEIGHT)  # an area light emits along its local -Z: down
    collection.objects.link(light)
    objects["CeilingLight"] = light
    return _finish(scene, objects, collection, resolution)


def _finish(scene, objects, collection, resolution):
    """Camera, world and render settings common to both lights."""
    objects["Camera"] = add_camera(scene, CAMERA_LOCATION, (90.0, 0.0, 0.0), CAMERA_FOV_DEGREES, collection)
    set_black_world(scene)
    configure_cycles_reference(scene)
    scene.render.resolution_x = resolution
    scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    bpy.context.view_layer.update()  # new objects count as visible only after the view layer syncs
    return objects


def scene_parameters(subdivisions, light_power=LIGHT_POWER):
    """The parameters that define a built box, for sidecar files next to references."""
    return {
        "subdivisions": subdivisions,
        "room": {"x": [-ROOM_HALF_WIDTH, ROOM_HALF_WIDTH], "y": [-ROOM_HALF_DEPTH, ROOM_HALF_DEPTH], "z": [0.0, ROOM_HEIGHT]},
        "albedo": {"red": RED, "green": GREEN, "white": WHITE},
        "light": {
            "type": "AREA",
            "shape": "RECTANGLE",
            "size": [LIGHT_SIZE_X, LIGHT_SIZE_Y],
            "height": LIGHT_HEIGHT,
            "power_w": light_power,
            "color": LIGHT_COLOR,
        },
        "boxes": [
            {"name": n, "center": [x, y], "side": BOX_SIDE, "height": h, "rotation_z_deg": r} for n, x, y, h, r in BOXES
        ],
        "camera": {"location": CAMERA_LOCATION, "fov_deg": CAMERA_FOV_DEGREES},
    }


def parse_arguments(argv):
    import argparse

    parser = argparse.ArgumentParser(description="Build the Cornell box and save it as a .blend file.")
    parser.add_argument("--out", required=True, help="path of the .blend file to write")
    parser.add_argument("--subdivisions", type=int, default=DEFAULT_SUBDIVISIONS, help="grid cells per 2 m edge")
    parser.add_argument("--light-power", type=float, default=LIGHT_POWER, help="area light power in W")
    parser.add_argument("--resolution", type=int, default=512, help="render resolution (square)")
    parser.add_argument("--light", choices=("area", "emissive"), default="area",
                        help="an area light, or an emissive mesh quad of the same radiance in its place")
    return parser.parse_args(argv)


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    arguments = parse_arguments(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = build_cornell_box(arguments.subdivisions, arguments.light_power, resolution=arguments.resolution,
                                light=arguments.light.upper())
    corners = sum(len(o.data.loops) for o in objects.values() if o.type == "MESH")
    import os

    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(arguments.out))
    print(f"cornell_box: wrote {arguments.out}: {corners} face corners, subdivisions {arguments.subdivisions}")


if __name__ == "__main__":
    main()
