"""A maze lit only through a skylight: deep indirect light. A closed 6 x 6 x 2 m room whose
ceiling has one 1 x 1 m opening above the maze's first cell; a sun shines through it onto
that cell's floor and a sky fills it; every other cell lies one to nine cells along the
maze's corridors from it (a spanning tree of the 5 x 5 cells: one way to each, eight dead
ends), so most of the room is lit only after several bounces. A scene of the real-scene suite
(tools/real_scenes.py), built from code.

Run:
    blender -b --factory-startup --python scenes/maze.py -- --out maze.blend

The maze is a fixed 5 x 5 grid of 1.2 m cells (LAYOUT below); its walls are 0.1 m thick
solid boxes standing on the floor, 2 m tall up to the ceiling, each face a grid of at most
0.25 m cells so that corners carry the light's gradients.
"""

import argparse
import math
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import cornell_box  # noqa: E402  (grid faces, materials, camera)

CELL = 1.2
SIZE = 5  # cells per side: the maze spans [-3, 3]^2
HEIGHT = 2.0
THICKNESS = 0.1
MAX_FACE_CELL = 0.25
# Walls between cells: "h r c" a wall under row r (between rows r and r+1) across column c,
# "v r c" a wall right of column c (between columns c and c+1) along row r; row 0 is the
# north row (y = +3), column 0 the west one. A spanning tree of the grid (16 of its 40 inner
# walls), so every cell is reached from cell (0, 0), under the skylight, by exactly one path
# (cell_distances() below; the scene test checks it). Distances in cells from (0, 0):
#    0 9 8 7 8
#    1 2 3 6 7
#    8 5 4 5 8
#    7 6 9 6 7
#    8 7 8 7 8
LAYOUT = """
v 0 0, h 0 1, h 0 2, v 0 3, h 1 0, h 1 1, v 1 2, h 1 4, v 2 0, h 2 2, v 2 3, v 3 1, v 3 2,
h 3 4, v 4 0, v 4 2
"""
SUN_STRENGTH = 8.0  # W/m^2
SKY = ((0.45, 0.6, 1.0), 0.5)  # colour, strength


def _box(name, lo, hi, material, collection):
    """A closed box [lo, hi] facing outwards, each face a grid of at most MAX_FACE_CELL."""
    vertices, faces = [], []
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    sides = (  # origin, edge_u, edge_v with u x v outwards
        ((x0, y0, z0), (0, y1 - y0, 0), (x1 - x0, 0, 0)),  # bottom, -z
        ((x0, y0, z1), (x1 - x0, 0, 0), (0, y1 - y0, 0)),  # top, +z
        ((x0, y0, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0)),  # -y
        ((x0, y1, z0), (0, 0, z1 - z0), (x1 - x0, 0, 0)),  # +y
        ((x0, y0, z0), (0, 0, z1 - z0), (0, y1 - y0, 0)),  # -x
        ((x1, y0, z0), (0, y1 - y0, 0), (0, 0, z1 - z0)),  # +x
    )
    for origin, u, v in sides:
        lu, lv = math.sqrt(sum(c * c for c in u)), math.sqrt(sum(c * c for c in v))
        cornell_box.grid_faces(origin, u, v, max(1, math.ceil(lu / MAX_FACE_CELL - 1e-9)),
                               max(1, math.ceil(lv / MAX_FACE_CELL - 1e-9)), vertices, faces)
    # Weld the sides' shared edges: a closed 2-manifold solid (antiradiance's assumption).
    index, welded = {}, []
    remap = []
    for v in vertices:
        key = tuple(round(c, 6) for c in v)
        if key not in index:
            index[key] = len(welded)
            welded.append(v)
        remap.append(index[key])
    faces = [tuple(remap[i] for i in f) for f in faces]
    return cornell_box.mesh_object(name, welded, faces, material, collection)


def _layout_walls(layout):
    """(kind, row, column) per wall of the layout string."""
    for item in (w.split() for w in layout.replace("\n", " ").split(",") if w.strip()):
        yield item[0], int(item[1]), int(item[2])


def cell_distances(layout=LAYOUT):
    """{(row, column): cells from the skylight's cell (0, 0)} for the cells reachable from it
    (breadth first through the openings; pure Python, no Blender)."""
    walls = set(_layout_walls(layout))

    def neighbours(row, column):
        if column < SIZE - 1 and ("v", row, column) not in walls:
            yield row, column + 1
        if column > 0 and ("v", row, column - 1) not in walls:
            yield row, column - 1
        if row < SIZE - 1 and ("h", row, column) not in walls:
            yield row + 1, column
        if row > 0 and ("h", row - 1, column) not in walls:
            yield row - 1, column

    distance = {(0, 0): 0}
    frontier = [(0, 0)]
    while frontier:
        cell = frontier.pop(0)
        for other in neighbours(*cell):
            if other not in distance:
                distance[other] = distance[cell] + 1
                frontier.append(other)
    return distance


def _walls(layout):
    half = SIZE * CELL / 2
    t = THICKNESS / 2

    # No wall reaches through the room's shell into the sunlit outside: walls along the shell
    # stop 1 mm short of it, so their end faces look at the shell (dark), not out of the room.
    edge = half - 0.001

    def inside(lo, hi):
        return tuple(max(c, -edge) for c in lo[:2]) + lo[2:], tuple(min(c, edge) for c in hi[:2]) + hi[2:]

    for i, (kind, row, column) in enumerate(_layout_walls(layout)):
        if kind == "h":  # between rows row and row + 1, across column
            y = half - (row + 1) * CELL
            x0 = -half + column * CELL
            yield (f"Wall{i:02d}",) + inside((x0 - t, y - t, 0.0), (x0 + CELL + t, y + t, HEIGHT))
        else:  # right of column, along row
            x = -half + (column + 1) * CELL
            y1 = half - row * CELL
            yield (f"Wall{i:02d}",) + inside((x - t, y1 - CELL - t, 0.0), (x + t, y1 + t, HEIGHT))


def build_maze():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    collection = scene.collection
    white = cornell_box.diffuse_material("Plaster", (0.75, 0.73, 0.7))
    floor_material = cornell_box.diffuse_material("Stone", (0.5, 0.45, 0.4))
    half = SIZE * CELL / 2
    n = 16  # cells per 2 m of the shell (cornell_box.cells_for): 0.125 m
    objects = {
        "Floor": cornell_box.add_wall("Floor", (-half, -half, 0), (2 * half, 0, 0), (0, 2 * half, 0),
                                      floor_material, n, collection),
        "North": cornell_box.add_wall("North", (-half, half, 0), (2 * half, 0, 0), (0, 0, HEIGHT), white, n, collection),
        "South": cornell_box.add_wall("South", (-half, -half, 0), (0, 0, HEIGHT), (2 * half, 0, 0), white, n, collection),
        "West": cornell_box.add_wall("West", (-half, -half, 0), (0, 2 * half, 0), (0, 0, HEIGHT), white, n, collection),
        "East": cornell_box.add_wall("East", (half, -half, 0), (0, 0, HEIGHT), (0, 2 * half, 0), white, n, collection),
    }
    # The skylight: the ceiling's cells above the maze's first cell (row 0, column 0) left out.
    sky_lo, sky_hi = (-half + 0.1, half - CELL + 0.1), (-half + CELL - 0.1, half - 0.1)

    def skylight(centre):
        return sky_lo[0] < centre[0] < sky_hi[0] and sky_lo[1] < centre[1] < sky_hi[1]

    objects["Ceiling"] = cornell_box.add_wall("Ceiling", (-half, -half, HEIGHT), (0, 2 * half, 0), (2 * half, 0, 0),
                                              white, n, collection, hole=skylight)
    for name, lo, hi in _walls(LAYOUT):
        objects[name] = _box(name, lo, hi, white, collection)

    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = SUN_STRENGTH
    sun.angle = math.radians(0.53)
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = (math.radians(15.0), math.radians(-10.0), 0.0)
    collection.objects.link(sun_object)
    objects["Sun"] = sun_object
    cornell_box.set_black_world(scene, SKY[0], SKY[1])
    objects["Camera"] = cornell_box.add_camera(scene, (0.0, 0.0, HEIGHT - 0.05), (0.0, 0.0, 0.0), 100.0, collection)
    scene.render.resolution_x, scene.render.resolution_y = 512, 512
    bpy.context.view_layer.update()
    return objects


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="the .blend to write")
    args = parser.parse_args(argv)
    objects = build_maze()
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out))
    faces = sum(len(o.data.polygons) for o in objects.values() if o.type == "MESH")
    print(f"maze: {faces} faces, saved {args.out}")


if __name__ == "__main__":
    main()
