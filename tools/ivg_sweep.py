#!/usr/bin/env python3
"""The Irradiance Vector Grid measured against the real-scene suite's references (issue 16;
docs/ivg.md): for each scene and grid resolution, bake a grid through the core (the path
tracer's paths, or another method's field), light the reference subset's points from it
(trilinear and tricubic, float and quantized) and compare.

    BAKEGI_LIBRARY=build/libbakegi.so python3 tools/ivg_sweep.py --work /tmp/rs \\
        --scenes cornell_area --cells 8,16,32,48 --rays 64 --out docs/ivg_sweep.json

Needs the suite's exports and references (tools/real_scenes.py --work /tmp/rs ...): per
scene <work>/<scene>/corner/{scene.bgs, subset.bgs, reference_chunk_*.npy}.

Figures per run: the project's two metrics over every subset point, and over the points the
reference sees lit (r > 1% of the mean: a grid cannot know that a face lies buried under
another object, e.g. the floor under the Cornell boxes, which the reference sees black);
the reference's own noise; the bake's seconds and rays; the file bytes of both encodings;
the quantized grid's difference from the float one in CIELAB (mean Delta E 1976 of the
lit points' colours, white = the brightest float value, as a percentage of L's range 100:
the paper's measure, 0.008% on its scene) and in NRMSE; Apply Grid's time on the full
scene's bake points and on 100,000 random points; and the figures again with the points
inside or under geometry at 0 (bakegi.apply_grid's darken_buried), and as Apply Grid reads
it by default: each point from the grid vertices it sees (grid_visibility.h).
"""

import argparse
import glob
import json
import os
import sys
import tempfile
import time

import numpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "addon"))

import real_scene_metrics as metrics  # noqa: E402
from bakegi import native  # noqa: E402


def reference_of(folder):
    """(reference, its noise): the chunks' mean; noise = NRMSE(odd mean, even mean) / 2."""
    chunks = [numpy.load(p).astype(numpy.float64)
              for p in sorted(glob.glob(os.path.join(folder, "reference_chunk_*.npy")),
                              key=lambda p: int(p.rsplit("_", 1)[1].split(".")[0]))]
    if len(chunks) < 2:
        raise SystemExit(f"{folder}: needs at least two reference chunks")
    odd, even = numpy.mean(chunks[0::2], axis=0), numpy.mean(chunks[1::2], axis=0)
    return numpy.mean(chunks, axis=0), metrics.nrmse(odd, even) / 2.0


def srgb_linear_to_lab(rgb, white):
    """CIELAB (D65) of linear Rec. 709 colours scaled so that `white` is Y = 1."""
    m = numpy.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722],
                     [0.0193, 0.1192, 0.9505]])
    xyz = (numpy.asarray(rgb, numpy.float64) / white) @ m.T
    xyz /= numpy.array([0.95047, 1.0, 1.08883])
    f = numpy.where(xyz > (6 / 29) ** 3, numpy.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return numpy.stack([116 * f[:, 1] - 16, 500 * (f[:, 0] - f[:, 1]),
                        200 * (f[:, 1] - f[:, 2])], axis=1)


def lab_difference_percent(values, reference):
    white = float(numpy.max(metrics.luminance(reference)))
    if not white > 0.0:
        return 0.0
    delta = srgb_linear_to_lab(values, white) - srgb_linear_to_lab(reference, white)
    return float(numpy.mean(numpy.linalg.norm(delta, axis=1)))  # of 100: already a percentage


def figures(values, reference, noise):
    lit = metrics.luminance(reference) > 0.01 * numpy.mean(metrics.luminance(reference))
    return {"nrmse": metrics.nrmse(values, reference),
            "nrmse_without_reference_noise": metrics.without_noise(
                metrics.nrmse(values, reference), noise),
            "weighted_relative_rmse": metrics.weighted_relative_rmse(values, reference),
            "nrmse_lit": metrics.nrmse(values[lit], reference[lit]),
            "lit_points": int(lit.sum()), "points": int(len(lit)),
            "bias": float(metrics.luminance(values).mean() /
                          metrics.luminance(reference).mean() - 1.0)}


def bake_grid(scene, bounds, cells, rays, method, threads, pad=0.0):
    """A grid of `cells` cells on the box's longest axis, the box widened by `pad` cells on
    every side (0: the scene's bounds, as the default bake)."""
    cell = max(h - l for l, h in zip(*bounds)) / cells
    lo = [l - pad * cell for l in bounds[0]]
    hi = [h + pad * cell for h in bounds[1]]
    with native.Grid.create(lo, hi, cell, 1 << 26) as layout, \
            native.Settings(method=method, threads=threads) as settings:
        start = time.perf_counter()
        job = native.GridJob(scene, layout, settings, rays)
        job.wait()
        seconds = time.perf_counter() - start
        report = job.report()
        grid = job.grid()
        job.close()
    return grid, seconds, report


def apply_seconds(grid, positions, normals, repeat=5):
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        grid.evaluate(positions, normals)
        best = min(best, time.perf_counter() - start)
    return best


def run_scene(work, name, cells_list, rays, method, threads, pad=0.0):
    folder = os.path.join(work, name, "corner")
    scene, all_points = native.Scene.read(os.path.join(folder, "scene.bgs"))
    _, subset = native.Scene.read(os.path.join(folder, "subset.bgs"))
    reference, noise = reference_of(folder)
    positions, normals, _ = subset.get()
    buried = subset.flag_inside(scene)
    full_positions, full_normals, _ = all_points.get()
    bounds = scene.bounds()
    rng = numpy.random.default_rng(0)
    random_positions = rng.uniform(bounds[0], bounds[1], (100_000, 3)).astype(numpy.float32)
    random_normals = rng.normal(size=(100_000, 3)).astype(numpy.float32)
    rows = []
    for cells in cells_list:
        grid, seconds, report = bake_grid(scene, bounds, cells, rays, method, threads, pad)
        row = {"scene": name, "method": method, "cells_on_longest_axis": cells, "pad_cells": pad,
               "rays_per_hemisphere": rays, "seconds": seconds, "rays": report.get("rays"),
               "grid": grid.info(), "reference_noise": noise}
        for interpolation in ("TRILINEAR", "TRICUBIC"):
            values = grid.evaluate(positions, normals, interpolation).astype(numpy.float64)
            row[interpolation.lower()] = figures(values, reference, noise)
            # As Apply Grid's darken_buried leaves them: points inside geometry at 0.
            values[buried] = 0.0
            row[interpolation.lower() + "_buried_dark"] = figures(values, reference, noise)
        row["buried_points"] = int(buried.sum())
        # The |n| directional weights instead of the paper's n^2 (grid_interpolation.h).
        values = grid.evaluate(positions, normals, "TRILINEAR", "ABSOLUTE").astype(numpy.float64)
        row["trilinear_absolute"] = figures(values, reference, noise)
        values[buried] = 0.0
        row["trilinear_absolute_buried_dark"] = figures(values, reference, noise)
        # Where the scene is known (Apply Grid's default): each point reads the vertices it
        # sees, buried points 0 (grid_visibility.h).
        for directional in ("SQUARED", "ABSOLUTE"):
            start = time.perf_counter()
            values, codes = grid.evaluate_in_scene(scene, positions, normals, "TRILINEAR",
                                                   directional)
            key = "visibility" + ("_absolute" if directional == "ABSOLUTE" else "")
            row[key] = figures(values.astype(numpy.float64), reference, noise)
            row[key]["unsure_points"] = int(numpy.count_nonzero(codes == 1))
            row[key]["seconds"] = time.perf_counter() - start
        # As the web page reads it: the visibility volume of the web export instead of rays
        # from each point (grid_visibility_volume.h), buried points not darkened.
        start = time.perf_counter()
        values, codes = grid.evaluate_in_scene(scene, positions, normals, page_visibility=True)
        row["page_visibility"] = figures(values.astype(numpy.float64), reference, noise)
        row["page_visibility"]["unsure_points"] = int(numpy.count_nonzero(codes == 1))
        row["page_visibility"]["seconds"] = time.perf_counter() - start
        f_values = grid.evaluate(positions, normals).astype(numpy.float64)
        lit = metrics.luminance(reference) > 0.01 * numpy.mean(metrics.luminance(reference))
        row["file_bytes"] = {}
        encoded = {}
        with tempfile.TemporaryDirectory() as tmp:
            for encoding in ("FLOAT", "FACTORED", "QUANTIZED"):
                path = os.path.join(tmp, f"{encoding}.bgivg")
                grid.write(path, encoding=encoding)
                row["file_bytes"][encoding.lower()] = os.path.getsize(path)
                with native.Grid.read(path) as read:
                    encoded[encoding] = read.evaluate(positions, normals).astype(numpy.float64)
        # The paper's compression in two steps: the factorization (FACTORED against the exact
        # matrices), then the quantization (QUANTIZED against FACTORED); and both.
        for step, values, base in (("factored", encoded["FACTORED"], f_values),
                                   ("quantized_against_factored", encoded["QUANTIZED"],
                                    encoded["FACTORED"]),
                                   ("quantized", encoded["QUANTIZED"], f_values)):
            row[step] = {"lab_difference_percent": lab_difference_percent(values[lit], base[lit]),
                         "nrmse_against_base": metrics.nrmse(values, base),
                         "against_reference": figures(values, reference, noise)}
        row["apply_seconds"] = {
            "scene_points": int(len(full_positions)),
            "scene": apply_seconds(grid, full_positions, full_normals),
            "random_100k": apply_seconds(grid, random_positions, random_normals)}
        grid.close()
        print(json.dumps({k: row[k] for k in ("scene", "cells_on_longest_axis", "seconds")}),
              "trilinear", json.dumps(row["trilinear"]), flush=True)
        rows.append(row)
    scene.close()
    return rows


def direct_without_lamps(folder, points, samples, seed):
    """(n, 3): the direct light of the world and emitters at the points (the "direct" method
    on the scene with its lamps removed)."""
    scene, _ = native.Scene.read(os.path.join(folder, "scene.bgs"))
    scene.clear_lights()
    try:
        with native.Settings(method="direct", samples=samples, seed=seed,
                             error_probes=0) as settings:
            job = native.Job(scene, points, settings)
            job.wait()
            values = job.result().astype(numpy.float64)
            job.close()
    except native.BakeGIError as error:
        if "light" not in str(error):
            raise
        values = numpy.zeros((len(points), 3))  # lamps alone light the scene
    scene.close()
    return values


def run_page_light(work, name, cells_list, rays, method, threads, samples, pad=0.0,
                   normal_offsets=()):
    """What the web page draws besides its lamps, against the truth: the reference's indirect
    light plus the direct light of the world and emitters (the "direct" method without the
    lamps, two seeds, their difference giving its noise), read as the page reads the grid
    (trilinear, n^2 weights, no visibility): the bounced light alone (the page before the
    grid carried the emitted light) and with the emitted light (now)."""
    folder = os.path.join(work, name, "corner")
    scene, _ = native.Scene.read(os.path.join(folder, "scene.bgs"))
    _, subset = native.Scene.read(os.path.join(folder, "subset.bgs"))
    reference, noise = reference_of(folder)
    positions, normals, _ = subset.get()
    start = time.perf_counter()
    first, second = (direct_without_lamps(folder, subset, samples, seed) for seed in (1, 2))
    direct_seconds = time.perf_counter() - start
    direct = (first + second) / 2.0
    truth = reference + direct
    direct_mean = float(metrics.luminance(direct).mean())
    # Noise of the sum: the indirect reference's and the direct estimate's, in quadrature,
    # each relative to the sum's mean.
    direct_noise = (metrics.nrmse(first, second) / 2.0 * direct_mean
                    if direct_mean > 0.0 else 0.0)
    truth_mean = float(metrics.luminance(truth).mean())
    truth_noise = float(numpy.hypot(noise * metrics.luminance(reference).mean(),
                                    direct_noise) / truth_mean)
    rows = []
    for cells in cells_list:
        grid, seconds, _ = bake_grid(scene, tuple(scene.bounds()), cells, rays, method, threads,
                                     pad)
        page_grid, has_emitted = grid.with_emitted_light()
        bounced = grid.evaluate(positions, normals).astype(numpy.float64)
        page = page_grid.evaluate(positions, normals).astype(numpy.float64)
        row = {"scene": name, "kind": "page_light", "method": method,
               "cells_on_longest_axis": cells, "rays_per_hemisphere": rays, "seconds": seconds,
               "pad_cells": pad, "grid": grid.info(), "has_emitted": has_emitted,
               "direct_samples": samples, "direct_seconds": direct_seconds,
               "direct_share": direct_mean / truth_mean if truth_mean > 0 else 0.0,
               "reference_noise": truth_noise,
               "bounced_only": figures(bounced, truth, truth_noise),
               "with_emitted": figures(page, truth, truth_noise),
               # The page since it reads the visibility volume of the web export.
               "with_emitted_visibility": figures(
                   page_grid.evaluate_in_scene(scene, positions, normals,
                                               page_visibility=True)[0].astype(numpy.float64),
                   truth, truth_noise),
               "emitted_against_direct": (
                   figures(page - bounced, direct, direct_noise / direct_mean)
                   if direct_mean > 0 else None)}
        # The page's reading moved along the normal by a fraction of a cell (away from the
        # vertices behind the surface): against the bounced reference and the page's truth.
        cell = max(h - l for l, h in zip(*scene.bounds())) / cells
        row["normal_offsets"] = {}
        for offset in normal_offsets:
            moved = positions + offset * cell * normals
            row["normal_offsets"][str(offset)] = {
                "bounced_only": figures(grid.evaluate(moved, normals).astype(numpy.float64),
                                        reference, noise),
                "with_emitted": figures(page_grid.evaluate(moved, normals).astype(numpy.float64),
                                        truth, truth_noise)}
        grid.close()
        page_grid.close()
        print(json.dumps({k: row[k] for k in ("scene", "cells_on_longest_axis", "direct_share",
                                                "reference_noise")}),
              "bounced only", json.dumps(row["bounced_only"]),
              "with emitted", json.dumps(row["with_emitted"]), flush=True)
        rows.append(row)
    scene.close()
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default="/tmp/rs")
    parser.add_argument("--scenes", default="cornell_area")
    parser.add_argument("--cells", default="8,16,32")
    parser.add_argument("--rays", type=int, default=64)
    parser.add_argument("--method", default="pathtrace")
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--page-light", action="store_true",
                        help="measure what the web page draws besides its lamps instead")
    parser.add_argument("--direct-samples", type=int, default=4096)
    parser.add_argument("--normal-offsets", default="",
                        help="--page-light: also read the grid this many cells along the "
                        "normal (comma-separated)")
    parser.add_argument("--pad-cells", type=float, default=0.0,
                        help="widen the grid's box by this many cells on every side")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    rows = []
    for name in args.scenes.split(","):
        cells = [int(c) for c in args.cells.split(",")]
        if args.page_light:
            rows += run_page_light(args.work, name, cells, args.rays, args.method, args.threads,
                                   args.direct_samples, args.pad_cells,
                                   [float(o) for o in args.normal_offsets.split(",") if o])
        else:
            rows += run_scene(args.work, name, cells, args.rays, args.method, args.threads,
                              args.pad_cells)
    previous = []
    if os.path.exists(args.out):
        with open(args.out) as f:
            previous = json.load(f).get("runs", [])
    def key(r):
        return (r["scene"], r.get("kind", ""), r["method"], r["cells_on_longest_axis"],
                r["rays_per_hemisphere"], r.get("pad_cells", 0.0))
    keep = [r for r in previous if key(r) not in {key(r) for r in rows}]
    with open(args.out, "w") as f:
        json.dump({"command": " ".join(sys.argv), "runs": keep + rows}, f, indent=1)


if __name__ == "__main__":
    main()
