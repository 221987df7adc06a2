"""An office-scale interior lit by the sun through a window, built procedurally in Blender.

Run:
    blender -b --factory-startup --python scenes/office.py -- --out office.blend [--cell 0.25] [--sky R G B]

or import it from Blender's Python (``sys.path`` holding ``scenes/``) and call
``build_office()``.

The scene of the antiradiance targets (5-10k input triangles) and of its
convergence study (mean diffuse reflectance about 0.66), after the office of
the antiradiance paper (§5, Fig. 1): a room of 6 m x 5 m x 3 m (x in [0, 6],
y in [0, 5], z in [0, 3]) inside walls, floor and ceiling 0.2 m thick, with
a 3 m x 1.5 m window opening through the south wall (y = 0). A sun shines
through it onto the floor; everything else in the room is lit indirectly.

Everything is a solid, as the method assumes: the building is one closed
mesh (``Room_Shell``: the outside of the building, the inside of the room and
the four reveals of the window, welded into one surface), and every piece of
furniture is a closed box of its own (desks, chairs, a bookshelf, cabinets,
partitions: ``Desk1_Top``, ``Chair2_Seat`` and so on). Furniture floats 1 mm
above what it stands on, so no two faces coincide. Faces are grids of quads
(cells of at most ``cell`` metres inside the room, 1 m on the outside of the
building), flat shaded, Diffuse BSDF materials.

Reflectances: walls 0.80, ceiling 0.85, floor 0.50 (grey-brown), furniture in
wood, grey, blue, red and green. ``scene_statistics`` gives the area-weighted
mean reflectance (mean of R, G, B) over the surfaces facing the room (every
face but the building's outside, the Facade material): 0.66 at the default
cell size (0.66 over all surfaces too: the Facade is 0.66). The world is black
unless ``sky_color`` is given (a constant world radiance, which also lights the
room through the window).
"""

import math
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import box_solids  # noqa: E402
import cornell_box  # noqa: E402

ROOM = (6.0, 5.0, 3.0)  # interior extent; the room spans [0, ROOM[i]] along each axis
WALL = 0.2  # thickness of walls, floor and ceiling
WINDOW_X = (1.5, 4.5)  # the opening through the south wall (y in [-WALL, 0])
WINDOW_Z = (1.0, 2.5)

WALL_ALBEDO = (0.81, 0.80, 0.78)
CEILING_ALBEDO = (0.85, 0.85, 0.85)
FLOOR_ALBEDO = (0.52, 0.50, 0.47)
FACADE_ALBEDO = (0.68, 0.66, 0.64)  # the building's outside: not part of the mean
WOOD_ALBEDO = (0.70, 0.55, 0.40)
METAL_ALBEDO = (0.55, 0.56, 0.58)
BLUE_ALBEDO = (0.30, 0.40, 0.70)
RED_ALBEDO = (0.65, 0.12, 0.10)
GREEN_ALBEDO = (0.25, 0.50, 0.22)

# The sun comes from the south, a little from the east, 36 degrees above the horizon:
# its light travels north, west and down and lands on the floor 1.2-3.5 m into the room.
SUN_DIRECTION = (-0.3, 1.0, -0.75)  # direction the light travels
SUN_STRENGTH = 3.0  # irradiance in W/m^2 on a plane facing the sun
SUN_ANGLE_DEGREES = 0.526  # the sun's real angular diameter

CAMERA_LOCATION = (0.45, 4.75, 2.3)
CAMERA_TARGET = (4.2, 1.0, 0.5)
CAMERA_FOV_DEGREES = 75.0

DEFAULT_CELL = 0.25  # grid cells inside the room, metres: 8280 triangles
OUTSIDE_CELL = 1.0  # grid cells on the building's outside, which the room never sees
GAP = 0.001  # furniture floats this far above what it stands on: no coincident faces


def _room_ticks(cell):
    """Grid lines per axis of the building: the room's and the window's edges are breakpoints;
    the room and the window get `cell`, the outside beyond the room OUTSIDE_CELL."""
    breaks = [(0.0, ROOM[0], *WINDOW_X), (0.0, ROOM[1]), (0.0, ROOM[2], *WINDOW_Z)]
    inside = [box_solids.ticks(0.0, ROOM[i], cell, breaks[i]) for i in range(3)]

    def outside(i):
        # The outer surface needs the window's grid lines (its reveals weld to them); elsewhere coarse.
        fine = {0: WINDOW_X, 2: WINDOW_Z}.get(i)

        def cell_between(a, b):
            if fine is not None and a >= fine[0] - 1e-9 and b <= fine[1] + 1e-9:
                return cell
            return OUTSIDE_CELL

        return box_solids.ticks(-WALL, ROOM[i] + WALL, OUTSIDE_CELL, (0.0, ROOM[i], *breaks[i]), cell_between)

    return inside, [outside(i) for i in range(3)]


def _in_window(point):
    return WINDOW_X[0] < point[0] < WINDOW_X[1] and WINDOW_Z[0] < point[2] < WINDOW_Z[1]


def build_shell(cell, materials, collection):
    """The building as one closed solid: outside (facing out), room (facing in), window reveals."""
    wall, floor, ceiling, facade = 0, 1, 2, 3
    inside, outside = _room_ticks(cell)
    shell = box_solids.SolidMesh()
    south = lambda k, side, c: k == 1 and side == 0 and _in_window(c)  # noqa: E731
    shell.box((-WALL, -WALL, -WALL), (ROOM[0] + WALL, ROOM[1] + WALL, ROOM[2] + WALL), outside,
              materials={(k, s): facade for k in range(3) for s in (0, 1)}, skip=south)
    shell.box((0.0, 0.0, 0.0), ROOM, inside, inward=True, materials={(2, 0): floor, (2, 1): ceiling}, skip=south)
    # Reveals: the four sides of the opening, between y = -WALL and y = 0, facing into the opening.
    x_ticks = [x for x in inside[0] if WINDOW_X[0] - 1e-9 <= x <= WINDOW_X[1] + 1e-9]
    z_ticks = [z for z in inside[2] if WINDOW_Z[0] - 1e-9 <= z <= WINDOW_Z[1] + 1e-9]
    y_ticks = [-WALL, 0.0]
    shell.rectangle("z", WINDOW_Z[0], 1, x_ticks, y_ticks, wall)  # sill, facing up (axes x, y)
    shell.rectangle("z", WINDOW_Z[1], -1, x_ticks, y_ticks, wall)  # lintel, facing down
    shell.rectangle("x", WINDOW_X[0], 1, y_ticks, z_ticks, wall)  # jambs (axes y, z)
    shell.rectangle("x", WINDOW_X[1], -1, y_ticks, z_ticks, wall)
    return shell.to_object("Room_Shell", [materials[n] for n in ("Wall", "Floor", "Ceiling", "Facade")], collection)


def _box(objects, name, lo, hi, material, cell, collection):
    objects[name] = box_solids.solid_box(name, lo, hi, cell, material, collection)


def add_desk(objects, name, x, y, width, depth, material, legs_material, cell, collection, along_x=True):
    """A desk of width x depth (along x unless along_x is False) with its corner at (x, y):
    a 3 cm top at 0.75 m on four 5 cm legs."""
    sx, sy = (width, depth) if along_x else (depth, width)
    top_z = 0.75
    _box(objects, f"{name}_Top", (x, y, top_z - 0.03), (x + sx, y + sy, top_z), material, cell, collection)
    leg = 0.05
    for i, (lx, ly) in enumerate(((x, y), (x + sx - leg, y), (x, y + sy - leg), (x + sx - leg, y + sy - leg))):
        _box(objects, f"{name}_Leg{i + 1}", (lx, ly, GAP), (lx + leg, ly + leg, top_z - 0.03 - GAP), legs_material,
             cell, collection)


def add_chair(objects, name, x, y, facing, material, legs_material, cell, collection):
    """A chair centred at (x, y): 0.45 m seat at 0.45 m, four legs, a backrest on the side away
    from `facing` ('+x', '-x', '+y', '-y': where a sitting person looks)."""
    h = 0.225
    seat_z = 0.45
    _box(objects, f"{name}_Seat", (x - h, y - h, seat_z - 0.05), (x + h, y + h, seat_z), material, cell, collection)
    leg = 0.04
    corners = ((x - h, y - h), (x + h - leg, y - h), (x - h, y + h - leg), (x + h - leg, y + h - leg))
    for i, (lx, ly) in enumerate(corners):
        _box(objects, f"{name}_Leg{i + 1}", (lx, ly, GAP), (lx + leg, ly + leg, seat_z - 0.05 - GAP), legs_material,
             cell, collection)
    back = {"+x": ((x - h, y - h), (x - h + 0.05, y + h)), "-x": ((x + h - 0.05, y - h), (x + h, y + h)),
            "+y": ((x - h, y - h), (x + h, y - h + 0.05)), "-y": ((x - h, y + h - 0.05), (x + h, y + h))}[facing]
    (bx0, by0), (bx1, by1) = back
    _box(objects, f"{name}_Back", (bx0, by0, seat_z + GAP), (bx1, by1, seat_z + 0.45), material, cell, collection)


def add_bookshelf(objects, name, x0, y0, width, depth, height, shelves, material, cell, collection):
    """An open bookshelf with its back against a west wall at x0, spanning y0 to y0 + width, built
    from separate boards: two sides, a back panel, a bottom, a top and `shelves` shelves."""
    board = 0.03
    x1, y1 = x0 + depth, y0 + width
    _box(objects, f"{name}_SideL", (x0, y0, GAP), (x1, y0 + board, height), material, cell, collection)
    _box(objects, f"{name}_SideR", (x0, y1 - board, GAP), (x1, y1, height), material, cell, collection)
    _box(objects, f"{name}_Back", (x0, y0 + board + GAP, GAP), (x0 + board, y1 - board - GAP, height), material, cell,
         collection)
    levels = [GAP + (height - board - GAP) * i / (shelves + 1) for i in range(shelves + 2)]
    for i, z in enumerate(levels):
        _box(objects, f"{name}_Board{i + 1}", (x0 + board + GAP, y0 + board + GAP, z),
             (x1, y1 - board - GAP, z + board), material, cell, collection)


def build_office(cell=DEFAULT_CELL, sun_strength=SUN_STRENGTH, sky_color=None, clear=True, resolution=512):
    """Build the office into the current scene and return {name: object}.

    cell: largest grid cell inside the room, metres (0.25 gives 8280 triangles).
    sky_color: None for a black world, or an (r, g, b) constant world radiance.
    """
    if cell <= 0.0:
        raise ValueError("cell must be positive")
    if clear:
        cornell_box.clear_scene()
    scene = bpy.context.scene
    collection = scene.collection
    m = {name: cornell_box.diffuse_material(name, albedo) for name, albedo in (
        ("Wall", WALL_ALBEDO), ("Floor", FLOOR_ALBEDO), ("Ceiling", CEILING_ALBEDO), ("Facade", FACADE_ALBEDO),
        ("Wood", WOOD_ALBEDO), ("Metal", METAL_ALBEDO), ("Blue", BLUE_ALBEDO), ("Red", RED_ALBEDO),
        ("Green", GREEN_ALBEDO))}

    objects = {"Room_Shell": build_shell(cell, m, collection)}
    # Desks: two against the east wall facing it, one against the north wall (1 cm off the walls).
    add_desk(objects, "Desk1", ROOM[0] - 0.81, 0.6, 1.6, 0.8, m["Wood"], m["Metal"], cell, collection, along_x=False)
    add_desk(objects, "Desk2", ROOM[0] - 0.81, 2.4, 1.6, 0.8, m["Wood"], m["Metal"], cell, collection, along_x=False)
    add_desk(objects, "Desk3", 2.2, ROOM[1] - 0.81, 1.6, 0.8, m["Wood"], m["Metal"], cell, collection)
    add_chair(objects, "Chair1", ROOM[0] - 1.2, 1.4, "+x", m["Blue"], m["Metal"], cell, collection)
    add_chair(objects, "Chair2", ROOM[0] - 1.2, 3.2, "+x", m["Red"], m["Metal"], cell, collection)
    add_chair(objects, "Chair3", 3.0, ROOM[1] - 1.2, "+y", m["Blue"], m["Metal"], cell, collection)
    # A bookshelf against the west wall (its back to the wall), filing cabinets in the north-west corner.
    add_bookshelf(objects, "Shelf", 0.01, 1.8, 1.8, 0.4, 2.0, 3, m["Wood"], cell, collection)
    for i, x in enumerate((0.1, 0.65)):
        _box(objects, f"Cabinet{i + 1}", (x, ROOM[1] - 0.65, GAP), (x + 0.5, ROOM[1] - 0.05, 1.3), m["Green"], cell,
             collection)
    # Two partitions between the desks and the rest of the room, and a low red cabinet under the window.
    _box(objects, "Partition1", (ROOM[0] - 2.0, 2.0, GAP), (ROOM[0] - 1.95, 3.6, 1.5), m["Blue"], cell, collection)
    _box(objects, "Partition2", (4.1, 4.2, GAP), (5.1, 4.25, 1.5), m["Blue"], cell, collection)
    _box(objects, "LowCabinet", (0.2, 0.05, GAP), (1.2, 0.5, 0.8), m["Red"], cell, collection)

    sun_data = bpy.data.lights.new("Sun", "SUN")
    sun_data.energy = sun_strength
    sun_data.angle = math.radians(SUN_ANGLE_DEGREES)
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.location = (3.0, -4.0, 6.0)  # irrelevant for a sun; keeps it visible outside the window
    sun.rotation_euler = Vector(SUN_DIRECTION).to_track_quat("-Z", "Y").to_euler()  # a sun shines along local -Z
    collection.objects.link(sun)
    objects["Sun"] = sun

    direction = Vector(CAMERA_TARGET) - Vector(CAMERA_LOCATION)
    camera_rotation = [math.degrees(a) for a in direction.to_track_quat("-Z", "Y").to_euler()]
    objects["Camera"] = cornell_box.add_camera(scene, CAMERA_LOCATION, camera_rotation, CAMERA_FOV_DEGREES, collection)
    if sky_color is None:
        cornell_box.set_black_world(scene)
    else:
        cornell_box.set_black_world(scene, tuple(sky_color))
    cornell_box.configure_cycles_reference(scene)
    scene.render.resolution_x = resolution
    scene.render.resolution_y = resolution * 3 // 4
    scene.render.resolution_percentage = 100
    bpy.context.view_layer.update()  # new objects count as visible only after the view layer syncs
    return objects


def material_albedo(material):
    """The Diffuse BSDF colour of a material built by cornell_box.diffuse_material."""
    node = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfDiffuse")
    return tuple(node.inputs["Color"].default_value[:3])


def scene_statistics(objects):
    """Counts and the mean reflectance of a built office: triangles, mesh objects, bake points
    (face corners), the mean reflectance of the surfaces facing the room and of all surfaces."""
    meshes = [o for o in objects.values() if o.type == "MESH"]
    facade = bpy.data.materials.get("Facade")
    interior, interior_area = box_solids.mean_albedo(meshes, material_albedo, exclude_material=facade)
    everything, area = box_solids.mean_albedo(meshes, material_albedo)
    return {
        "triangles": box_solids.triangle_count(meshes),
        "mesh_objects": len(meshes),
        "face_corners": sum(len(o.data.loops) for o in meshes),
        "mean_albedo_interior": interior,
        "interior_area_m2": interior_area,
        "mean_albedo_all": everything,
        "area_m2": area,
    }


def parse_arguments(argv):
    import argparse

    parser = argparse.ArgumentParser(description="Build the office and save it as a .blend file.")
    parser.add_argument("--out", required=True, help="path of the .blend file to write")
    parser.add_argument("--cell", type=float, default=DEFAULT_CELL, help="largest grid cell inside the room, m")
    parser.add_argument("--sun-strength", type=float, default=SUN_STRENGTH, help="sun irradiance, W/m^2")
    parser.add_argument("--sky", type=float, nargs=3, metavar=("R", "G", "B"), help="constant world radiance")
    parser.add_argument("--resolution", type=int, default=512, help="render width (height is 3/4 of it)")
    return parser.parse_args(argv)


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    arguments = parse_arguments(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = build_office(arguments.cell, arguments.sun_strength, arguments.sky, resolution=arguments.resolution)
    stats = scene_statistics(objects)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(arguments.out))
    print(f"office: wrote {arguments.out}: {stats['triangles']} triangles, {stats['mesh_objects']} mesh objects, "
          f"{stats['face_corners']} face corners, mean albedo {stats['mean_albedo_interior']:.3f} "
          f"(surfaces facing the room, {stats['interior_area_m2']:.1f} m^2; all surfaces "
          f"{stats['mean_albedo_all']:.3f}), cell {arguments.cell} m")


if __name__ == "__main__":
    main()
