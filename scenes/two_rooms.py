"""Two closed rooms sharing one wall, a light in one: the leakage test scene.

Run:
    blender -b --factory-startup --python scenes/two_rooms.py -- --out two_rooms.blend \
        [--wall 0.1] [--zero-thickness] [--cell 0.25]

or import it from Blender's Python (``sys.path`` holding ``scenes/``) and call
``build_two_rooms()``.

Room A spans x in [0, 3], room B x in [3 + wall, 6 + wall], both y in [0, 3]
and z in [0, 2.5]; a point light hangs in room A only, so room B receives no
light at all: the exact answer there is 0, and any light a solver puts there
has leaked through the shared wall.

Default (thick) variant: everything is a closed solid. The building is a
block with two cavities; its outside is ``Building_Exterior`` (facing out,
0.2 m beyond the rooms), each cavity a closed inward-facing surface
(``RoomA_Shell``, ``RoomB_Shell``), and the material between the cavities is
the shared wall, ``wall`` metres thick (0.1 m by default). A cube stands in
each room (``RoomA_Box``, ``RoomB_Box``, 1 mm above the floor).

Zero-thickness variant (``zero_thickness=True``, the "open meshes and
zero-thickness planes" case): the two rooms are one cavity divided by a single
plane, ``SharedWall`` (one-sided geometry; its faces look into room A).
``RoomA_Shell`` and ``RoomB_Shell`` then lack the face where the plane stands,
so they and the plane are open meshes; together they still close each room.

The receivers of room B are the objects whose names start with ``RoomB_``
(``ROOM_B_PREFIX``); of room A, ``RoomA_``. Faces are grids of cells of at
most ``cell`` metres (the outside of the building 1 m), flat shaded, Diffuse
BSDF materials; the world is black.
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import box_solids  # noqa: E402
import cornell_box  # noqa: E402

ROOM = (3.0, 3.0, 2.5)  # each room's interior extent
OUTER_WALL = 0.2  # walls, floor and ceiling around the two rooms
DEFAULT_SHARED_WALL = 0.1
DEFAULT_CELL = 0.25
OUTSIDE_CELL = 1.0
GAP = 0.001  # the cubes float this far above the floor: no coincident faces

ROOM_A_PREFIX = "RoomA_"
ROOM_B_PREFIX = "RoomB_"

WALL_ALBEDO = (0.75, 0.75, 0.75)
FLOOR_ALBEDO = (0.5, 0.5, 0.5)
EXTERIOR_ALBEDO = (0.6, 0.6, 0.6)
BOX_A_ALBEDO = (0.7, 0.3, 0.2)
BOX_B_ALBEDO = (0.2, 0.4, 0.7)
BOX_SIDE = 0.6

LIGHT_POWER = 100.0  # W
LIGHT_RADIUS = 0.05  # m: a small sphere well inside room A
LIGHT_HEIGHT = 1.9


def room_bounds(wall=DEFAULT_SHARED_WALL, zero_thickness=False):
    """((lo, hi) of room A, (lo, hi) of room B) for a shared wall of this thickness."""
    wall = 0.0 if zero_thickness else wall
    a = ((0.0, 0.0, 0.0), ROOM)
    b = ((ROOM[0] + wall, 0.0, 0.0), (2.0 * ROOM[0] + wall, ROOM[1], ROOM[2]))
    return a, b


def _cavity(name, lo, hi, cell, materials, collection, open_side=None):
    """An inward-facing box surface; open_side (axis, side) leaves that face out."""
    surface = box_solids.SolidMesh()
    skip = None
    if open_side is not None:
        skip = lambda k, side, c: (k, side) == open_side  # noqa: E731
    surface.box(lo, hi, box_solids.box_ticks(lo, hi, cell), inward=True, materials={(2, 0): 1}, skip=skip)
    return surface.to_object(name, [materials["Wall"], materials["Floor"]], collection)


def build_two_rooms(wall=DEFAULT_SHARED_WALL, zero_thickness=False, cell=DEFAULT_CELL, light_power=LIGHT_POWER,
                    clear=True, resolution=512):
    """Build the two rooms into the current scene and return {name: object}.

    wall: thickness of the shared wall in metres (ignored when zero_thickness).
    zero_thickness: divide the rooms by a single plane instead of a solid wall.
    cell: largest grid cell inside the rooms, metres.
    """
    if cell <= 0.0:
        raise ValueError("cell must be positive")
    if not zero_thickness and wall <= 0.0:
        raise ValueError("a solid shared wall needs a positive thickness (or zero_thickness=True)")
    if clear:
        cornell_box.clear_scene()
    scene = bpy.context.scene
    collection = scene.collection
    m = {name: cornell_box.diffuse_material(name, albedo) for name, albedo in (
        ("Wall", WALL_ALBEDO), ("Floor", FLOOR_ALBEDO), ("Exterior", EXTERIOR_ALBEDO),
        ("BoxA", BOX_A_ALBEDO), ("BoxB", BOX_B_ALBEDO))}
    (a_lo, a_hi), (b_lo, b_hi) = room_bounds(wall, zero_thickness)
    objects = {}

    t = OUTER_WALL
    outer_lo, outer_hi = (-t, -t, -t), (b_hi[0] + t, b_hi[1] + t, b_hi[2] + t)
    exterior = box_solids.SolidMesh()
    exterior.box(outer_lo, outer_hi, box_solids.box_ticks(outer_lo, outer_hi, OUTSIDE_CELL))
    objects["Building_Exterior"] = exterior.to_object("Building_Exterior", [m["Exterior"]], collection)

    if zero_thickness:
        objects[ROOM_A_PREFIX + "Shell"] = _cavity(ROOM_A_PREFIX + "Shell", a_lo, a_hi, cell, m, collection, (0, 1))
        objects[ROOM_B_PREFIX + "Shell"] = _cavity(ROOM_B_PREFIX + "Shell", b_lo, b_hi, cell, m, collection, (0, 0))
        plane = box_solids.SolidMesh()
        y_ticks = box_solids.ticks(0.0, ROOM[1], cell)
        z_ticks = box_solids.ticks(0.0, ROOM[2], cell)
        plane.rectangle("x", a_hi[0], -1, y_ticks, z_ticks)
        objects["SharedWall"] = plane.to_object("SharedWall", [m["Wall"]], collection)
    else:
        objects[ROOM_A_PREFIX + "Shell"] = _cavity(ROOM_A_PREFIX + "Shell", a_lo, a_hi, cell, m, collection)
        objects[ROOM_B_PREFIX + "Shell"] = _cavity(ROOM_B_PREFIX + "Shell", b_lo, b_hi, cell, m, collection)

    # A cube in each room, off centre towards the outer wall, so the shared wall is in plain view.
    for prefix, lo, material in ((ROOM_A_PREFIX, a_lo, m["BoxA"]), (ROOM_B_PREFIX, b_lo, m["BoxB"])):
        x = lo[0] + (0.6 if prefix == ROOM_A_PREFIX else ROOM[0] - 0.6 - BOX_SIDE)
        name = prefix + "Box"
        objects[name] = box_solids.solid_box(name, (x, 1.2, GAP), (x + BOX_SIDE, 1.2 + BOX_SIDE, GAP + BOX_SIDE),
                                             cell, material, collection)

    light_data = bpy.data.lights.new("LightA", "POINT")
    light_data.energy = light_power
    light_data.shadow_soft_size = LIGHT_RADIUS
    light = bpy.data.objects.new("LightA", light_data)
    light.location = (0.5 * ROOM[0], 0.5 * ROOM[1], LIGHT_HEIGHT)
    collection.objects.link(light)
    objects["LightA"] = light

    # The camera stands in room A's far corner and looks at the shared wall (room B is behind it).
    objects["Camera"] = cornell_box.add_camera(scene, (0.2, 0.2, 1.6), (80.0, 0.0, -60.0), 75.0, collection)
    cornell_box.set_black_world(scene)
    cornell_box.configure_cycles_reference(scene)
    scene.render.resolution_x = resolution
    scene.render.resolution_y = resolution * 3 // 4
    scene.render.resolution_percentage = 100
    bpy.context.view_layer.update()  # new objects count as visible only after the view layer syncs
    return objects


def receivers(objects, prefix):
    """The mesh objects of one room (names starting with prefix), sorted by name."""
    return [objects[n] for n in sorted(objects) if n.startswith(prefix) and objects[n].type == "MESH"]


def scene_statistics(objects):
    meshes = [o for o in objects.values() if o.type == "MESH"]
    return {
        "triangles": box_solids.triangle_count(meshes),
        "mesh_objects": len(meshes),
        "face_corners": sum(len(o.data.loops) for o in meshes),
        "room_b_face_corners": sum(len(o.data.loops) for o in receivers(objects, ROOM_B_PREFIX)),
        "open_meshes": sorted(o.name for o in meshes if box_solids.open_edge_count(o.data)),
    }


def parse_arguments(argv):
    import argparse

    parser = argparse.ArgumentParser(description="Build the two-rooms scene and save it as a .blend file.")
    parser.add_argument("--out", required=True, help="path of the .blend file to write")
    parser.add_argument("--wall", type=float, default=DEFAULT_SHARED_WALL, help="shared wall thickness, m")
    parser.add_argument("--zero-thickness", action="store_true", help="a single plane between the rooms")
    parser.add_argument("--cell", type=float, default=DEFAULT_CELL, help="largest grid cell inside the rooms, m")
    parser.add_argument("--light-power", type=float, default=LIGHT_POWER, help="point light power in room A, W")
    return parser.parse_args(argv)


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    arguments = parse_arguments(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = build_two_rooms(arguments.wall, arguments.zero_thickness, arguments.cell, arguments.light_power)
    stats = scene_statistics(objects)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(arguments.out))
    variant = "zero-thickness plane" if arguments.zero_thickness else f"shared wall {arguments.wall} m"
    print(f"two_rooms: wrote {arguments.out}: {variant}, {stats['triangles']} triangles, {stats['mesh_objects']} "
          f"mesh objects, {stats['face_corners']} face corners ({stats['room_b_face_corners']} in room B), "
          f"open meshes: {', '.join(stats['open_meshes']) or 'none'}")


if __name__ == "__main__":
    main()
