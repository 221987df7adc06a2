"""See-through surfaces on a real scene: what they change in a bake, and what they cost.

    blender -b SCENE.blend --python tools/see_through_study.py -- --variant V \\
        [--samples 16] [--seed 1] [--target CORNER|POINT] [--out values.npy] [--json F]

Variants (one per run, so that each bake's time is its own process's):
  as_built  the scene as its script saved it;
  glass     the objects hidden because of their glass (scenes/living_room.py) shown;
  opaque    the same as `glass`, with every see-through surface read as opaque (no share of
            light passes, the reflectances as read), which is what bakegi did before it let
            light through surfaces.
Bakes the path tracer at a fixed number of paths (no target, no denoiser, no error check) on
every mesh object that is neither hidden nor glass, so all variants bake the same points (face
corners, or vertices with --target POINT); writes their values (--out) and seconds, mean and
the see-through materials the export found (--json). Compare variants with numpy: the means
are over ~10^5 points, so their noise is far below the differences.
"""

import argparse
import json
import sys
import time

import bpy
import numpy


def args_after_dashes():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--variant", choices=("as_built", "glass", "opaque"), required=True)
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--target", choices=("CORNER", "POINT"), default="CORNER")
    parser.add_argument("--out", default="")
    parser.add_argument("--json", default="")
    return parser.parse_args(argv)


def main():
    args = args_after_dashes()
    import addon_utils
    addon_utils.enable("bakegi", default_set=True)
    import bakegi
    from bakegi.export import materials

    scene = bpy.context.scene
    glass = [o for o in scene.objects if o.type == "MESH" and o.hide_render]
    if args.variant in ("glass", "opaque"):
        for obj in glass:
            obj.hide_render = False
            obj.hide_set(False)
    passing = sorted(m.name for m in bpy.data.materials
                     if m.users and materials.read_material(m).lets_light_pass())
    if args.variant == "opaque":
        materials.MaterialInfo.lets_light_pass = lambda self: False
    targets = [o for o in scene.objects
               if o.type == "MESH" and not o.hide_render and o not in glass]
    start = time.perf_counter()
    report = bakegi.bake(method="pathtrace", samples=args.samples, seed=args.seed,
                         target=args.target, objects=targets, estimate_error=False,
                         hook_materials=False)
    seconds = time.perf_counter() - start
    values = []
    for obj in targets:
        attribute = obj.data.color_attributes.get("BakeGI_Indirect")
        flat = numpy.empty(len(attribute.data) * 4, numpy.float32)
        attribute.data.foreach_get("color", flat)
        values.append(flat.reshape(-1, 4)[:, :3])
    values = numpy.concatenate(values)
    luminance = values @ numpy.array([0.2126, 0.7152, 0.0722], numpy.float32)
    result = {"variant": args.variant, "samples": args.samples, "seconds": seconds,
              "core_seconds": report.get("seconds", {}), "corners": int(len(values)),
              "mean_luminance": float(luminance.mean()), "glass_objects": len(glass),
              "target_objects": len(targets), "see_through_materials": passing,
              "rays": report.get("counts", {}).get("rays")}
    print(json.dumps(result))
    if args.out:
        numpy.save(args.out, values)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)


main()
