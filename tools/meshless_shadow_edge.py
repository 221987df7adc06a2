#!/usr/bin/python3
"""Issue 4, "sharp shadow boundaries ring" (Lehtinen et al. 2008, §5.2): the Cornell box lit by
a sharp-edged spot light, its indirect light baked by meshless and by the path tracer, drawn
along a line across the edge of the spot's pool on the floor, with the error near the edge
and away from it.

    /usr/bin/python3 tools/meshless_shadow_edge.py --build build [--work /tmp/bakegi_edge] [--docs]

The basis smooths what it represents, so a sharp edge projected into it would ring (the
paper shows it for direct light). bakegi projects only the DIRECT light at the sender points
(e = P† E) and bakes only the INDIRECT light: the sharp edge of the direct light is drawn by
the renderer, never by the basis, and the indirect light it causes is smooth. The figure
shows both: the direct light (sharp, from the renderer) and the baked indirect light against
the path tracer. Writes meshless_shadow_edge.png/.json (docs/ with --docs). About 2 minutes.
"""

import argparse
import json
import os
import sys

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_cornell import DOCS, ROOT, addon_environment, compare, log, run  # noqa: E402

SPOT_HEIGHT = 1.9
SPOT_SIZE_DEGREES = 40.0  # pool radius 1.9 tan 20° = 0.69 m on the floor
SUBDIVISIONS = 32  # 6.25 cm cells: 65 floor corners along the line


def build_and_export(work, build):
    bgs = os.path.join(work, "cornell_spot.bgs")
    expression = (
        "import sys, math, bpy; sys.path.insert(0, %r); import cornell_box, bakegi; "
        "o = cornell_box.build_cornell_box(%d); bpy.data.objects.remove(o['CeilingLight']); "
        "d = bpy.data.lights.new('Spot', 'SPOT'); d.energy = 40.0; d.spot_size = math.radians(%f); "
        "d.spot_blend = 0.0; d.shadow_soft_size = 0.0; s = bpy.data.objects.new('Spot', d); "
        "s.location = (0.0, 0.0, %f); bpy.context.scene.collection.objects.link(s); "
        "bakegi.export_scene_file(%r, target='CORNER', objects='VISIBLE')"
        % (os.path.join(ROOT, "scenes"), SUBDIVISIONS, SPOT_SIZE_DEGREES, SPOT_HEIGHT, bgs))
    run(["blender", "-b", "--factory-startup", "--addons", "bakegi", "--python-exit-code", "1",
         "--python-expr", expression], env=addon_environment(work, build))
    return bgs


def relative_rmse(values, reference):
    w = numpy.array([0.2126, 0.7152, 0.0722])
    return float(numpy.sqrt((((values - reference) ** 2) @ w).sum() / ((reference ** 2) @ w).sum()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--work", default="/tmp/bakegi_edge")
    parser.add_argument("--reference-samples", type=int, default=2048)
    parser.add_argument("--docs", action="store_true")
    arguments = parser.parse_args()
    build, work = os.path.abspath(arguments.build), os.path.abspath(arguments.work)
    cli = os.path.join(build, "bakegi")
    os.makedirs(work, exist_ok=True)

    bgs = build_and_export(work, build)
    paths = {name: os.path.join(work, name + ".npy") for name in ("direct", "pathtrace", "meshless")}
    run([cli, "bake", bgs, "--method", "direct", "--samples", "16", "--out", paths["direct"]], quiet=True)
    run([cli, "bake", bgs, "--method", "pathtrace", "--samples", str(arguments.reference_samples), "--seed", "7",
         "--out", paths["pathtrace"]], quiet=True)
    run([cli, "bake", bgs, "--method", "meshless", "--out", paths["meshless"]], quiet=True)
    positions = os.path.join(work, "positions.npy")
    normals = os.path.join(work, "normals.npy")
    run([cli, "points", bgs, "--positions", positions, "--normals", normals], quiet=True)
    p, n = numpy.load(positions), numpy.load(normals)
    values = {k: numpy.load(v).astype(numpy.float64) for k, v in paths.items()}

    floor = (numpy.abs(p[:, 2]) < 1e-3) & (n[:, 2] > 0.9)
    radius = SPOT_HEIGHT * numpy.tan(numpy.radians(SPOT_SIZE_DEGREES / 2))
    r = numpy.hypot(p[:, 0], p[:, 1])
    near_edge = floor & (numpy.abs(r - radius) < 0.15)
    elsewhere = ~near_edge
    errors = {"all": relative_rmse(values["meshless"], values["pathtrace"]),
              "floor_near_edge": relative_rmse(values["meshless"][near_edge], values["pathtrace"][near_edge]),
              "elsewhere": relative_rmse(values["meshless"][elsewhere], values["pathtrace"][elsewhere]),
              "floor_near_edge_points": int(near_edge.sum())}
    errors["all_compare"] = compare(cli, paths["meshless"], paths["pathtrace"])
    log(f"meshless against the {arguments.reference_samples}-path tracer: {errors}")

    # The line y ~ -0.3 (in front of the boxes), x across the pool and its edges.
    line = floor & (numpy.abs(p[:, 1] + 0.3) < 0.04)
    order = numpy.argsort(p[line, 0])
    x = p[line, 0][order]
    w = numpy.array([0.2126, 0.7152, 0.0722])
    curves = {k: (v[line] @ w)[order] for k, v in values.items()}

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, left = plt.subplots(figsize=(7.5, 4.2), dpi=120)
    right = left.twinx()
    right.plot(x, curves["direct"], color="gray", linewidth=1.0, label="direct (drawn by the renderer)")
    right.set_ylabel("direct E/π (gray)")
    left.plot(x, curves["pathtrace"], "o", color="tab:blue", markersize=3,
              label=f"indirect, path tracer {arguments.reference_samples} paths")
    left.plot(x, curves["meshless"], "-", color="tab:purple", linewidth=1.6, label="indirect, meshless bake")
    for edge in (-1, 1):
        edge_x = edge * numpy.sqrt(max(radius ** 2 - 0.3 ** 2, 0.0))
        left.axvline(edge_x, color="black", linestyle=":", linewidth=0.8)
    left.set_xlabel("x on the floor at y = -0.3 m (dotted: the spot's edge)")
    left.set_ylabel("indirect E/π, luminance")
    left.set_ylim(bottom=0.0)
    lines = left.get_legend_handles_labels()
    more = right.get_legend_handles_labels()
    left.legend(lines[0] + more[0], lines[1] + more[1], fontsize=8, loc="upper left")
    left.set_title(f"Cornell box under a sharp spot: meshless error {100 * errors['floor_near_edge']:.1f}% within "
                   f"15 cm of the edge, {100 * errors['elsewhere']:.1f}% elsewhere", fontsize=9)
    figure.tight_layout()
    folder = DOCS if arguments.docs else work
    chart = os.path.join(folder, "meshless_shadow_edge.png")
    figure.savefig(chart)
    with open(os.path.join(folder, "meshless_shadow_edge.json"), "w") as f:
        json.dump({"command": "/usr/bin/python3 tools/meshless_shadow_edge.py " + " ".join(sys.argv[1:]),
                   "spot": {"height_m": SPOT_HEIGHT, "cone_degrees": SPOT_SIZE_DEGREES, "blend": 0.0,
                            "radius_m": 0.0},
                   "errors": errors}, f, indent=1)
    log(f"wrote {chart}")


if __name__ == "__main__":
    main()
