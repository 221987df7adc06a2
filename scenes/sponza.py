"""Crytek Sponza (262,087 triangles) lit by one spot light (or, --light sun, a sun and a sky): the large scene of the meshless
benchmark (issue 4; the meshless paper's Sponza, §5, Fig. 8), imported from
../shared/scenes/crytek-sponza (not copied into the project; see its SOURCE.md).

Run:
    blender -b --factory-startup --python scenes/sponza.py -- --out sponza.blend
        [--sponza /path/to/crytek-sponza] [--spot-power 30000]

The glTF is imported as is (170 mesh objects, 26 materials with base-colour textures).
A spot light hangs in the atrium and points down and sideways onto the floor and the lower
arcade, so most of the building is lit only indirectly, as in the paper's figure. The
world is black; CameraMain is the scene camera (a valid viewpoint for the meshless
method's importance particles, §2.3).

Scale: the model is about 51 x 21 x 31 units (SOURCE.md: 1.7x the Khronos Sponza); the
floor is at z = 2.28. The spot power is chosen for a mid-grey exposure only; the benchmark
compares relative errors.
"""

import argparse
import math
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import cornell_box  # noqa: E402  (shared helpers)
DEFAULT_SPONZA = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "scenes", "crytek-sponza"))

SPOT_LOCATION = (4.0, 0.8, 17.0)
SPOT_TARGET = (-6.0, 0.8, 2.3)  # the floor of the atrium's west half
SPOT_SIZE_DEGREES = 50.0
SPOT_BLEND = 0.15
SPOT_RADIUS = 0.25
SPOT_POWER = 30000.0  # W, Blender's spot power

# The sun variant: a sun 30 degrees off the zenith across the atrium's long axis, so a strip
# of the floor and the lower arcade of one side is sunlit, and a blue sky of a tenth of its
# strength's order (W/m^2 irradiance of a sun vs radiance of a sky: the usual outdoor ratio).
SUN_STRENGTH = 5.0  # W/m^2, Blender's sun strength
SUN_ANGLE_DEGREES = 0.53
SUN_ELEVATION_TILT_DEGREES = 30.0  # rotation about x: 0 is straight down
SUN_AZIMUTH_DEGREES = 20.0
SKY_COLOR = (0.45, 0.6, 1.0)
SKY_STRENGTH = 0.3


def sponza_path(folder=None):
    return os.path.join(folder or os.environ.get("BAKEGI_SPONZA", DEFAULT_SPONZA), "Sponza.gltf")


def build_sponza(folder=None, spot_power=SPOT_POWER, light="SPOT"):
    """Imports Sponza into an empty file and adds the light: "SPOT" (the spot in the atrium,
    black world) or "SUN" (a sun through the open roof onto the floor and the lower arcade
    plus a blue sky as the world colour). Returns the light object.
    Raises FileNotFoundError (with the path) when the scene data is absent."""
    path = sponza_path(folder)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"Crytek Sponza not found at {path} (set BAKEGI_SPONZA)")
    import numpy

    if not hasattr(numpy, "bool"):
        numpy.bool = bool  # Blender 3.4's glTF importer uses np.bool, gone in numpy 1.24
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    scene = bpy.context.scene
    camera = bpy.data.objects.get("CameraMain")
    if camera is not None:
        scene.camera = camera

    world = bpy.data.worlds.new("Black")
    cornell_box.use_nodes(world)
    background = world.node_tree.nodes.get("Background")
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    scene.world = world
    if light == "SUN":
        background.inputs["Color"].default_value = (*SKY_COLOR, 1.0)
        background.inputs["Strength"].default_value = SKY_STRENGTH
        data = bpy.data.lights.new("Sun", "SUN")
        data.energy = SUN_STRENGTH
        data.angle = math.radians(SUN_ANGLE_DEGREES)
        sun = bpy.data.objects.new("Sun", data)
        sun.rotation_euler = (math.radians(SUN_ELEVATION_TILT_DEGREES), 0.0, math.radians(SUN_AZIMUTH_DEGREES))
        scene.collection.objects.link(sun)
        return sun
    if light != "SPOT":
        raise ValueError(f"light must be SPOT or SUN, not {light!r}")

    data = bpy.data.lights.new("Spot", "SPOT")
    data.energy = spot_power
    data.spot_size = math.radians(SPOT_SIZE_DEGREES)
    data.spot_blend = SPOT_BLEND
    data.shadow_soft_size = SPOT_RADIUS
    spot = bpy.data.objects.new("Spot", data)
    spot.location = SPOT_LOCATION
    direction = [t - s for t, s in zip(SPOT_TARGET, SPOT_LOCATION)]
    # A spot shines along its local -Z: rotate -Z onto the direction.
    from mathutils import Vector

    spot.rotation_euler = Vector(direction).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(spot)
    return spot


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="the .blend to write")
    parser.add_argument("--sponza", default=None, help="folder holding Sponza.gltf")
    parser.add_argument("--spot-power", type=float, default=SPOT_POWER)
    parser.add_argument("--light", choices=("spot", "sun"), default="spot",
                        help="the spot in the atrium (black world), or a sun and a blue sky")
    args = parser.parse_args(argv)
    build_sponza(args.sponza, args.spot_power, args.light.upper())
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out))
    triangles = 0
    for obj in bpy.context.scene.objects:
        if obj.type == "MESH":
            obj.data.calc_loop_triangles()
            triangles += len(obj.data.loop_triangles)
    print(f"sponza: {triangles} triangles, saved {args.out}")


if __name__ == "__main__":
    main()
