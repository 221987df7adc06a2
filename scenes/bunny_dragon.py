"""The Stanford bunny and dragon on the floor of a closed room: detailed scanned objects
(69,451 + 100,000 triangles) in a simple closed room, lit by a ceiling area light. A scene of the real-scene suite (tools/real_scenes.py); the scans are read
from ../shared/scenes/stanford-bunny and stanford-dragon (see their SOURCE.md).

Run:
    blender -b --factory-startup --python scenes/bunny_dragon.py -- --out bunny_dragon.blend

The room is 4 x 4 x 3 m of inward grid walls (0.25 m cells); the bunny (scaled to 0.8 m
tall) and the dragon (1.4 m long) stand on the floor, near enough to each other and to a
wall to shadow and colour each other.
"""

import argparse
import math
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import cornell_box  # noqa: E402  (grid walls, materials, camera)

SHARED = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "scenes"))
BUNNY = os.path.join(SHARED, "stanford-bunny", "bun_zipper.ply")
DRAGON = os.path.join(SHARED, "stanford-dragon", "dragon_100k.ply")

ROOM = (4.0, 4.0, 3.0)  # x in [-2, 2], y in [-2, 2], z in [0, 3]
CELLS_PER_2M = 8  # grid cells per 2 m of wall (cornell_box.cells_for): 0.25 m cells
LIGHT_POWER = 400.0  # W, the ceiling area light
LIGHT_SIZE = 1.0


def _import_ply(path, name, height=None, length=None, location=(0.0, 0.0), rotation_z=0.0):
    """Imports a scan, stands it up (+Y up in the file), scales it to `height` (z extent) or
    `length` (largest horizontal extent) and sets it on the floor at `location`."""
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path} not found (the shared scenes folder)")
    bpy.ops.import_mesh.ply(filepath=path)
    obj = bpy.context.selected_objects[0]
    obj.name = name
    obj.rotation_euler = (math.radians(90.0), 0.0, math.radians(rotation_z))
    bpy.context.view_layer.update()
    corners = [obj.matrix_world @ v.co for v in obj.data.vertices]
    lo = [min(c[k] for c in corners) for k in range(3)]
    hi = [max(c[k] for c in corners) for k in range(3)]
    scale = height / (hi[2] - lo[2]) if height else length / max(hi[0] - lo[0], hi[1] - lo[1])
    obj.scale = (scale, scale, scale)
    bpy.context.view_layer.update()
    corners = [obj.matrix_world @ v.co for v in obj.data.vertices]
    lo = [min(c[k] for c in corners) for k in range(3)]
    hi = [max(c[k] for c in corners) for k in range(3)]
    obj.location.x += location[0] - 0.5 * (lo[0] + hi[0])
    obj.location.y += location[1] - 0.5 * (lo[1] + hi[1])
    obj.location.z -= lo[2]
    for polygon in obj.data.polygons:
        polygon.use_smooth = True
    return obj


def build_bunny_dragon():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    collection = scene.collection
    white = cornell_box.diffuse_material("Walls", (0.7, 0.7, 0.68))
    floor_material = cornell_box.diffuse_material("Floor", (0.45, 0.35, 0.25))
    blue = cornell_box.diffuse_material("BlueWall", (0.2, 0.3, 0.6))
    x, y, z = ROOM[0] / 2, ROOM[1] / 2, ROOM[2]
    n = CELLS_PER_2M
    objects = {
        "Floor": cornell_box.add_wall("Floor", (-x, -y, 0), (2 * x, 0, 0), (0, 2 * y, 0), floor_material, n, collection),
        "Ceiling": cornell_box.add_wall("Ceiling", (-x, -y, z), (0, 2 * y, 0), (2 * x, 0, 0), white, n, collection),
        "BackWall": cornell_box.add_wall("BackWall", (-x, y, 0), (2 * x, 0, 0), (0, 0, z), white, n, collection),
        "FrontWall": cornell_box.add_wall("FrontWall", (-x, -y, 0), (0, 0, z), (2 * x, 0, 0), white, n, collection),
        "LeftWall": cornell_box.add_wall("LeftWall", (-x, -y, 0), (0, 2 * y, 0), (0, 0, z), blue, n, collection),
        "RightWall": cornell_box.add_wall("RightWall", (x, -y, 0), (0, 0, z), (0, 2 * y, 0), white, n, collection),
    }
    bunny = _import_ply(BUNNY, "Bunny", height=0.8, location=(-0.6, 0.4), rotation_z=30.0)
    bunny.data.materials.append(cornell_box.diffuse_material("BunnyClay", (0.75, 0.72, 0.68)))
    dragon = _import_ply(DRAGON, "Dragon", length=1.4, location=(0.7, -0.2), rotation_z=-20.0)
    dragon.data.materials.append(cornell_box.diffuse_material("DragonJade", (0.25, 0.55, 0.35)))
    objects["Bunny"], objects["Dragon"] = bunny, dragon

    light = bpy.data.lights.new("CeilingLight", "AREA")
    light.shape = "SQUARE"
    light.size = LIGHT_SIZE
    light.energy = LIGHT_POWER
    lamp = bpy.data.objects.new("CeilingLight", light)
    lamp.location = (0.3, 0.5, z - 0.02)
    collection.objects.link(lamp)
    objects["CeilingLight"] = lamp
    objects["Camera"] = cornell_box.add_camera(scene, (0.0, -1.9, 1.3), (78.0, 0.0, 0.0), 60.0, collection)
    cornell_box.set_black_world(scene)
    scene.render.resolution_x, scene.render.resolution_y = 512, 384
    bpy.context.view_layer.update()
    return objects


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="the .blend to write")
    args = parser.parse_args(argv)
    objects = build_bunny_dragon()
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out))
    triangles = sum(len(o.data.polygons) for o in objects.values() if o.type == "MESH")
    print(f"bunny_dragon: {triangles} faces, saved {args.out}")


if __name__ == "__main__":
    main()
