"""What each error in reading a world image costs, against Cycles: bakes the WORLD_IMAGE scene
of scenes/light_units.py (an HDR sky with a sun, turned by a Mapping node) with bakegi's
direct light as exported, with the Mapping rotation ignored, with it inverted, and with the
image replaced by its mean colour (what the add-on did before it read world images), and
prints each one's relative RMSE against the stored Cycles reference of this Blender version
(blender_tests/data/<version>/light_WORLD_IMAGE.npy).

    BAKEGI_LIBRARY=build/libbakegi.so BLENDER_USER_SCRIPTS=<folder with addons/bakegi> \\
        blender -b --factory-startup --python tools/world_image_costs.py
"""

import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "blender_tests"), os.path.join(ROOT, "scenes"),
                os.path.join(ROOT, "tools")]

import common  # noqa: E402
import light_units  # noqa: E402
import metrics  # noqa: E402

bakegi = common.enable_addon()
from bakegi.export import world  # noqa: E402

SAMPLES = 4096


def bake(label, reference, subdivisions):
    common.new_empty_scene()
    built = light_units.build_light_scene("WORLD_IMAGE", subdivisions)
    receivers = [built[name] for name in light_units.RECEIVERS]
    bakegi.bake(method="direct", samples=SAMPLES, seed=0, target="CORNER", objects=receivers)
    values = common.read_color_attribute(receivers, domain="CORNER")
    ratio = metrics.luminance(values).sum() / metrics.luminance(reference).sum()
    print(f"{label}: relative RMSE {100 * metrics.relative_rmse(values, reference):.2f}%, "
          f"total ratio bakegi/Cycles {ratio:.4f}")


def main():
    reference, sidecar = common.load_reference("light_WORLD_IMAGE")
    subdivisions = sidecar["scene"]["subdivisions"]
    bake("as exported", reference, subdivisions)
    rotation, environment = world._mapping_rotation, world._environment_light
    try:
        world._mapping_rotation = lambda *arguments: None
        bake("Mapping rotation ignored", reference, subdivisions)
        turned = world._euler_xyz_matrix(light_units.WORLD_IMAGE_ROTATION)
        world._mapping_rotation = lambda *arguments: [list(row) for row in zip(*turned)]
        bake("Mapping rotation inverted", reference, subdivisions)
        world._mapping_rotation = rotation
        world._environment_light = lambda *arguments: world.WorldLight(
            environment(*arguments).radiance)
        bake("image replaced by its mean colour", reference, subdivisions)
    finally:
        world._mapping_rotation, world._environment_light = rotation, environment


main()
