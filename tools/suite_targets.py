"""The path tracer with the denoiser against the issue's targets on scenes of the real-scene
suite: for every scene already set up by tools/real_scenes.py (its export, 2,000-point subset
and path-traced reference, reused here), bakes the whole scene with `--method pathtrace` at
each target error, with and without `denoise`, and compares the values at the subset with the
reference (tools/real_scene_metrics.py; the reference's own noise is stated and removed in
quadrature).

    /usr/bin/python3 tools/real_scenes.py --scenes sponza_spot --targets CORNER --methods pathtrace
    /usr/bin/python3 tools/suite_targets.py --scenes sponza_spot --targets 0.1 0.05 0.03 \\
        [--work /tmp/bakegi_real_scenes] [--cli build/bakegi] [--json docs/suite_targets.json]

Seconds are the core's (`report["seconds"]["total"]`: validation, BVH, tracing, denoising),
error probes off (they measure, they do not change the result).
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_scene_metrics import compare_at_subset, row_metrics  # noqa: E402
from real_scenes import suite_scene  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def bake(cli, bgs, folder, target, denoise, kept_only):
    """(values, report) of the bake, or None with kept_only when it was not made before."""
    name = "target_%g_denoise_%d" % (target, denoise)
    out = os.path.join(folder, name + ".npy")
    report_path = os.path.join(folder, name + "_report.json")
    if os.path.exists(out) and os.path.exists(report_path):  # deterministic: keep it
        with open(report_path) as f:
            return numpy.load(out).astype(numpy.float64), json.load(f)
    if kept_only:
        return None
    subprocess.run([cli, "bake", bgs, "--method", "pathtrace", "--samples", "65536",
                    "--set", "target_error=%g" % target, "--set", "denoise=%d" % denoise,
                    "--set", "error_probes=0", "--seed", "0", "--out", out,
                    "--report", report_path], check=True, stdout=subprocess.DEVNULL)
    with open(report_path) as f:
        return numpy.load(out).astype(numpy.float64), json.load(f)


def write_rows(path, rows):
    """The rows as JSON, with the command that made them, when, and the machine's load."""
    with open(path, "w") as f:
        json.dump({"command": " ".join(sys.argv), "date": time.strftime("%Y-%m-%d %H:%M"),
                   "load_average": os.getloadavg(), "rows": rows}, f, indent=1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", required=True, help="comma-separated suite scene names")
    parser.add_argument("--targets", type=float, nargs="+", default=[0.1, 0.05])
    parser.add_argument("--denoise", type=int, nargs="+", default=[1, 0])
    parser.add_argument("--work", default="/tmp/bakegi_real_scenes")
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "bakegi"))
    parser.add_argument("--json", help="write the rows here")
    parser.add_argument("--kept-only", action="store_true",
                        help="bake nothing: report the bakes kept in --work (a bake is kept "
                        "and reused whenever its files exist)")
    args = parser.parse_args()
    rows = []
    for scene in args.scenes.split(","):
        bgs, indices, ref, ref_noise, ref_samples, names = suite_scene(args.cli, args.work, scene)
        folder = os.path.dirname(bgs)
        print("%s: reference %d paths per point, its noise %.2f%%" % (scene, ref_samples, 100 * ref_noise))
        for target in args.targets:
            for denoise in args.denoise:
                baked = bake(args.cli, bgs, folder, target, denoise, args.kept_only)
                if baked is None:
                    continue
                values, report = baked
                metrics = compare_at_subset(values[indices], ref, ref_noise, names)
                row = {
                    "scene": scene, "target_error": target, "denoise": denoise,
                    "seconds": report["seconds"]["total"], "samples": report.get("samples"),
                    "bake_points": report.get("bake_points"),
                    "evaluated_points": report.get("evaluated_points"),
                    "predicted": report.get("sampling_predicted_error"),
                    "noise_left_by_filter": report.get("sampling_noise_left_by_filter"),
                    "denoise_mean_shift": report.get("denoise_mean_shift"),
                    "denoise_local_bias": report.get("denoise_local_bias"),
                    "denoise_applied": report.get("denoise_applied"),
                        **row_metrics(metrics, ref_samples, ref_noise),
                }
                rows.append(row)
                print("%s target %g denoise %d: %.1f s, %s paths, predicted %.2f%%, NRMSE %.2f%% "
                      "(%.2f%% without the reference's noise), wRRMSE %.2f%%, bias %+.1f%%"
                      % (scene, target, denoise, row["seconds"], row["samples"], 100 * row["predicted"],
                         100 * row["nrmse"], 100 * row["nrmse_without_reference_noise"],
                         100 * row["weighted_relative_rmse"], 100 * row["bias"]), flush=True)
    if args.json:
        write_rows(args.json, rows)


if __name__ == "__main__":
    main()
