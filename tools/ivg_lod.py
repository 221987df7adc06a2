#!/usr/bin/env python3
"""Grid lighting per level of detail (issue 16, item 4; docs/ivg.md): bake an Irradiance
Vector Grid once on a scene, make levels of detail of every mesh with the core's simplifier
(bakegi.simplify_copy: meshoptimizer, 100% down to 1% of the triangles), light each level's
face corners from the grid as Apply Grid does, and compare with a converged path-traced
reference baked on that same level.

    BAKEGI_LIBRARY=build/libbakegi.so /usr/bin/python3 tools/ivg_lod.py --work /tmp/ivg_lod \\
        --scene cornell_box --ratios 1,0.5,0.25,0.1,0.05,0.01 --cells 16,32 \\
        --out docs/ivg_lod.json

Per level: Blender (the system's) builds the scene with its script in scenes/, replaces every
mesh with its level of detail and exports the face corners (bakegi.export_scene_file); the
CLI draws 2,000 of them (seed 1) and bakes the reference on them in chunks of 512 paths
until its own noise, NRMSE(odd chunks' mean, even chunks' mean) / 2, is at most 2%; the grid
(baked on the full-detail scene, 64 rays per hemisphere) lights the same points with the
level's geometry for visibility (bakegi_grid_evaluate_in_scene). For scale, a direct bake
of the same points with the path tracer at its defaults is compared too. Both metrics of the
project come with the reference's noise. tools/plot_ivg_lod.py draws docs/ivg_lod.png.
"""

import argparse
import json
import os
import sys
import time

import numpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "addon"))

from ivg_sweep import bake_grid, figures  # noqa: E402
from real_scenes import reference, run  # noqa: E402  (the suite's reference loop)
from sweep_cornell import addon_environment  # noqa: E402
from bakegi import native  # noqa: E402

SUBSET = 2000

# Runs inside Blender: every visible mesh replaced by its level of detail, then exported.
EXPORT_LEVEL = """
import bpy, bakegi, json
ratio = {ratio!r}
levels = []
if ratio < 1.0:
    for obj in [o for o in bpy.context.scene.objects if o.type == 'MESH' and o.visible_get()]:
        copy, info = bakegi.simplify_copy(obj, ratio)
        info["object"] = obj.name
        levels.append(info)
result = bakegi.export_scene_file({bgs!r}, target='CORNER', objects='VISIBLE')
result["levels"] = levels
json.dump(result, open({info!r}, 'w'), default=str)
"""


def log(message):
    print(f"[ivg_lod {time.strftime('%H:%M:%S')}] {message}", flush=True)


def export_level(blend, ratio, folder, build):
    bgs, info = os.path.join(folder, "scene.bgs"), os.path.join(folder, "export.json")
    if not os.path.exists(info):
        expression = EXPORT_LEVEL.format(ratio=ratio, bgs=bgs, info=info)
        run(["blender", "-b", blend, "--addons", "bakegi", "--python-exit-code", "1",
             "--python-expr", expression], env=addon_environment(folder, build))
    with open(info) as f:
        return bgs, json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default="/tmp/ivg_lod")
    parser.add_argument("--scene", default="cornell_box", help="a script in scenes/")
    parser.add_argument("--scene-args", default="", help="its arguments, comma-separated")
    parser.add_argument("--ratios", default="1,0.5,0.25,0.1,0.05,0.01")
    parser.add_argument("--cells", default="16,32")
    parser.add_argument("--rays", type=int, default=64)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    cli = os.path.join(args.build, "bakegi")
    blend = os.path.join(args.work, "scene.blend")
    if not os.path.exists(blend):
        log(f"building {args.scene}")
        extra = [a for a in args.scene_args.split(",") if a]
        run(["blender", "-b", "--factory-startup", "--python",
             os.path.join(ROOT, "scenes", args.scene + ".py"), "--", "--out", blend] + extra)

    ratios = [float(r) for r in args.ratios.split(",")]
    if 1.0 not in ratios:
        ratios.insert(0, 1.0)
    levels = {}
    for ratio in ratios:
        folder = os.path.join(args.work, f"lod_{ratio:g}")
        os.makedirs(folder, exist_ok=True)
        bgs, info = export_level(blend, ratio, folder, args.build)
        subset = os.path.join(folder, "subset.bgs")
        if not os.path.exists(subset):
            run([cli, "subset", bgs, "--count", str(SUBSET), "--seed", "1", "--out", subset])
        ref, noise, samples = reference(cli, subset, folder)
        # A direct bake of the same points at the path tracer's defaults, for scale.
        baked_path = os.path.join(folder, "direct_bake.npy")
        if not os.path.exists(baked_path):
            run([cli, "bake", subset, "--method", "pathtrace", "--seed", "1000",
                 "--out", baked_path])
        info["direct_bake"] = figures(numpy.load(baked_path).astype(numpy.float64), ref, noise)
        levels[ratio] = (bgs, subset, info, ref, noise, samples)
        triangles = sum(level["lod_triangles"] for level in info["levels"]) or None
        log(f"level {ratio:g}: {info['counts']}, reference noise {noise:.2%} ({samples} paths)"
            + (f", {triangles} triangles" if triangles else ""))

    full_scene, _ = native.Scene.read(levels[1.0][0])
    bounds = full_scene.bounds()
    rows = []
    for cells in [int(c) for c in args.cells.split(",")]:
        grid, seconds, _ = bake_grid(full_scene, bounds, cells, args.rays, "pathtrace",
                                     args.threads)
        for ratio in ratios:
            bgs, subset_bgs, info, ref, noise, samples = levels[ratio]
            scene, _ = native.Scene.read(bgs)
            _, subset = native.Scene.read(subset_bgs)
            positions, normals, _ = subset.get()
            values, codes = grid.evaluate_in_scene(scene, positions, normals, "TRILINEAR",
                                                   "ABSOLUTE")
            triangles = scene.triangle_count
            row = {"cells_on_longest_axis": cells, "ratio": ratio, "triangles": triangles,
                   "grid_seconds": seconds, "reference_noise": noise,
                   "reference_samples": samples, "points": int(len(positions)),
                   "deviation": max([lv["deviation"] for lv in info["levels"]] or [0.0]),
                   "apply_grid": figures(values.astype(numpy.float64), ref, noise),
                   "direct_bake_at_defaults": info["direct_bake"],
                   "unsure_points": int(numpy.count_nonzero(codes == 1)),
                   "buried_points": int(numpy.count_nonzero(codes == 2))}
            rows.append(row)
            log(f"{cells}^3 at {ratio:g} ({triangles} triangles): NRMSE "
                f"{row['apply_grid']['nrmse']:.2%}, weighted relative "
                f"{row['apply_grid']['weighted_relative_rmse']:.2%} (reference noise "
                f"{noise:.2%})")
            scene.close()
            subset.close()
        grid.close()
    full_scene.close()
    result = {"command": " ".join(["tools/ivg_lod.py"] + sys.argv[1:]), "scene": args.scene,
              "scene_args": args.scene_args, "rays_per_hemisphere": args.rays, "rows": rows}
    if args.out:
        with open(args.out, "w") as f:
            json.dump(result, f, indent=1)
        log(f"wrote {args.out}")


if __name__ == "__main__":
    main()
