"""Time against error of the path tracer with and without the point denoiser (setting
"denoise", native/src/bake/point_denoiser.h) on one exported scene (.bgs, tools/export_scene.py),
against a path-traced reference made of two independent halves (their mean is the reference;
its own noise, NRMSE(a, b) / 2, is printed next to every figure).

    /usr/bin/python3 tools/denoise_study.py --scene /tmp/cornell.bgs --reference-samples 32768 \
        --samples 16 64 128 256 1024 [--targets 0.1 0.05 0.03] [--cli build/bakegi] \
        [--work /tmp/denoise_study] [--json docs/denoise_cornell.json]

--targets also bakes to each target error (adaptive sampling, at most 65,536 paths per point)
with and without the denoiser, which the sampler then aims through.

The halves are cached in --work (named after the scene and the sample count) and reused.
--json keeps the rows for tools/plot_denoise_study.py.
"""

import argparse
import json
import os
import subprocess
import sys

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_scene_metrics import nrmse, weighted_relative_rmse  # noqa: E402


def bake(cli, scene, out, samples, seed, extra=()):
    report = out[:-4] + ".json"
    subprocess.run([cli, "bake", scene, "--method", "pathtrace", "--samples", str(samples),
                    "--seed", str(seed), "--set", "error_probes=0", *extra, "--out", out,
                    "--report", report], check=True, stdout=subprocess.DEVNULL)
    with open(report) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True)
    parser.add_argument("--reference-samples", type=int, required=True,
                        help="paths per point of each reference half")
    parser.add_argument("--samples", type=int, nargs="+", default=[16, 64, 256])
    parser.add_argument("--targets", type=float, nargs="*", default=[])
    parser.add_argument("--cli", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                      "bakegi"))
    parser.add_argument("--work", default="/tmp/denoise_study")
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    name = os.path.splitext(os.path.basename(args.scene))[0]

    halves = []
    for half in range(2):
        path = os.path.join(args.work, "%s_ref%d_%d.npy" % (name, args.reference_samples, half))
        if not os.path.exists(path):
            # Seed 1, other samples than the bakes below (seed 0).
            bake(args.cli, args.scene, path, args.reference_samples, 1,
                 ["--set", "sample_offset=%d" % (half * args.reference_samples)])
        halves.append(numpy.load(path))
    reference = 0.5 * (halves[0] + halves[1])
    noise = 0.5 * nrmse(halves[0], halves[1])
    print("%s: reference %d paths per point, its noise (NRMSE) %.2f%%"
          % (name, 2 * args.reference_samples, 100 * noise))
    rows = []
    print("| samples | denoise | seconds | NRMSE | weighted rel. RMSE | predicted noise |")
    print("|---:|---|---:|---:|---:|---:|")
    for samples in args.samples:
        for denoise in (0, 1):
            out = os.path.join(args.work, "%s_%d_%d.npy" % (name, samples, denoise))
            report = bake(args.cli, args.scene, out, samples, 0, ["--set", "denoise=%d" % denoise])
            values = numpy.load(out)
            predicted = report.get("denoise_noise_after") if denoise else None
            rows.append({"samples": samples, "denoise": bool(denoise),
                         "seconds": report["seconds"]["total"],
                         "nrmse": nrmse(values, reference),
                         "weighted_relative_rmse": weighted_relative_rmse(values, reference),
                         "predicted_noise": predicted})
            print("| %d | %s | %.2f | %.2f%% | %.2f%% | %s |" % (
                samples, "on" if denoise else "off", report["seconds"]["total"],
                100 * nrmse(values, reference), 100 * weighted_relative_rmse(values, reference),
                "%.2f%%" % (100 * predicted) if predicted is not None else ""))
    target_rows = []
    if args.targets:
        print("\n| target | denoise | seconds | paths | predicted | NRMSE | weighted rel. RMSE |")
        print("|---:|---|---:|---:|---:|---:|---:|")
    for target in args.targets:
        for denoise in (0, 1):
            out = os.path.join(args.work, "%s_target%g_%d.npy" % (name, target, denoise))
            report = bake(args.cli, args.scene, out, 65536, 0,
                          ["--set", "denoise=%d" % denoise, "--set", "target_error=%g" % target])
            values = numpy.load(out)
            row = {"target_error": target, "denoise": bool(denoise),
                   "seconds": report["seconds"]["total"], "paths": report["samples"],
                   "predicted": report["sampling_predicted_error"],
                   "noise_left_by_filter": report.get("sampling_noise_left_by_filter"),
                   "mean_shift": report.get("denoise_mean_shift"),
                   "nrmse": nrmse(values, reference),
                   "weighted_relative_rmse": weighted_relative_rmse(values, reference)}
            target_rows.append(row)
            print("| %g%% | %s | %.2f | %d | %.2f%% | %.2f%% | %.2f%% |" % (
                100 * target, "on" if denoise else "off", row["seconds"], row["paths"],
                100 * row["predicted"], 100 * row["nrmse"], 100 * row["weighted_relative_rmse"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"scene": name, "points": report.get("evaluated_points"),
                       "reference_paths": 2 * args.reference_samples,
                       "reference_noise": noise, "rows": rows, "target_rows": target_rows},
                      f, indent=1)


if __name__ == "__main__":
    main()
