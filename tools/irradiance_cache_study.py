"""The irradiance cache (`--set irradiance_cache=a`) against the plain path tracer on scenes
of the real-scene suite: for every scene already set up by tools/real_scenes.py (its export,
2,000-point subset and reference, reused here), bakes the whole scene with each accuracy a and
paths per record, and the plain path tracer at each count of paths per point, and compares
the values at the subset with the reference (tools/real_scene_metrics.py; the reference's
own noise is stated and removed in quadrature).

    /usr/bin/python3 tools/irradiance_cache_study.py --scenes cornell_area,bunny_dragon \\
        --accuracy 0.1 0.2 0.3 --record-samples 256 1024 --plain-samples 64 256 1024 \\
        [--target CORNER|LIGHTMAP] [--work /tmp/bakegi_real_scenes] [--cli build/bakegi] \\
        [--json docs/irradiance_cache.json]

Seconds are the core's (`report["seconds"]["total"]`), error probes off.
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


def bake(cli, bgs, folder, name, settings, samples):
    """(values, report) of one bake, kept in `folder` under `name` and reused."""
    out = os.path.join(folder, name + ".npy")
    report_path = os.path.join(folder, name + "_report.json")
    if not (os.path.exists(out) and os.path.exists(report_path)):
        command = [cli, "bake", bgs, "--method", "pathtrace", "--samples", str(samples),
                   "--set", "error_probes=0", "--seed", "0", "--out", out, "--report", report_path]
        for key, value in settings.items():
            command += ["--set", "%s=%s" % (key, value)]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    with open(report_path) as f:
        return numpy.load(out).astype(numpy.float64), json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", required=True, help="comma-separated suite scene names")
    parser.add_argument("--accuracy", type=float, nargs="+", default=[0.1, 0.2, 0.3])
    parser.add_argument("--record-samples", type=int, nargs="*", default=[256, 1024])
    parser.add_argument("--plain-samples", type=int, nargs="+", default=[16, 64, 256])
    parser.add_argument("--denoised-targets", type=float, nargs="*", default=[],
                        help="also the default bake (target_error and denoise) at these targets")
    parser.add_argument("--cache-targets", type=float, nargs="*", default=[],
                        help="also the cache at each accuracy aiming at these target errors "
                        "(records sampled in rounds; at most 65,536 paths a record)")
    parser.add_argument("--target", default="CORNER", choices=("CORNER", "LIGHTMAP"),
                        help="which of the scene's exports: face corners or lightmap texels")
    parser.add_argument("--work", default="/tmp/bakegi_real_scenes")
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "bakegi"))
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    rows = []
    for scene in args.scenes.split(","):
        bgs, indices, ref, ref_noise, ref_samples, names = suite_scene(
            args.cli, args.work, scene, args.target)
        folder = os.path.dirname(bgs)
        print("%s: reference %d paths per point, its noise %.2f%%"
              % (scene, ref_samples, 100 * ref_noise), flush=True)
        runs = [("plain_%d" % n, {}, n, 0.0) for n in args.plain_samples]
        runs += [("denoised_%g" % t, {"target_error": t, "denoise": 1}, 65536, 0.0)
                 for t in args.denoised_targets]
        runs += [("cache_%g_%d" % (a, n), {"irradiance_cache": a}, n, a)
                 for a in args.accuracy for n in args.record_samples]
        runs += [("cache_%g_target_%g" % (a, t), {"irradiance_cache": a, "target_error": t},
                  65536, a) for a in args.accuracy for t in args.cache_targets]
        for name, settings, samples, accuracy in runs:
            values, report = bake(args.cli, bgs, folder, "ic_" + name, settings, samples)
            metrics = compare_at_subset(values[indices], ref, ref_noise, names)
            row = {
                "scene": scene, "target": args.target, "accuracy": accuracy, "samples": samples,
                "denoised_target": settings.get("target_error") if not accuracy else None,
                "cache_target": settings.get("target_error") if accuracy else None,
                "predicted": report.get("sampling_predicted_error"),
                "seconds": report["seconds"]["total"], "paths": report.get("samples"),
                "rays": report.get("rays"), "evaluated_points": report.get("evaluated_points"),
                "records": report.get("irradiance_cache_records"),
                "declined": bool(report.get("irradiance_cache_declined")),
                "record_fraction": report.get("irradiance_cache_record_fraction"),
                "rounds": report.get("irradiance_cache_rounds"),
                "predicted_interpolation_error": report.get("irradiance_cache_interpolation_error"),
                **row_metrics(metrics, ref_samples, ref_noise),
            }
            rows.append(row)
            print("%s %s: %.2f s, %s records of %s points, NRMSE %.2f%% (%.2f%% without the "
                  "reference's noise), wRRMSE %.2f%%, bias %+.1f%%, predicted interpolation %s"
                  % (scene, name, row["seconds"], row["records"], row["evaluated_points"],
                     100 * row["nrmse"], 100 * row["nrmse_without_reference_noise"],
                     100 * row["weighted_relative_rmse"], 100 * row["bias"],
                     "%.2f%%" % (100 * row["predicted_interpolation_error"])
                     if row["predicted_interpolation_error"] is not None else "-"), flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"command": " ".join(sys.argv), "date": time.strftime("%Y-%m-%d %H:%M"),
                       "load_average": os.getloadavg(), "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
