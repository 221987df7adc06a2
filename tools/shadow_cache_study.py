#!/usr/bin/env python3
"""The lamp shadow cache (setting `shadow_cache`, native/src/lights/lamp_shadow_cache.h) on
the real-scene suite: the default bake (the path tracer to a 5% target through the denoiser)
with the cache off and on, in alternating rounds so that both see the same machine, against
the suite's references at the 2,000-point subsets.

    /usr/bin/python3 tools/shadow_cache_study.py --scenes cornell_area,two_rooms,office,maze \
        [--rounds 2] [--work /tmp/rs] [--json docs/shadow_cache.json]

Needs the exports and references of tools/real_scenes.py in --work. Prints per scene and
setting: seconds (the core's), paths, rays per path, the pilot's seconds and rays, NRMSE with
the reference's noise removed, and the weighted relative RMSE.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_scene_metrics import compare_at_subset, row_metrics  # noqa: E402
from real_scenes import suite_scene  # noqa: E402
from suite_targets import write_rows  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def default_bake(cli, bgs, shadow_cache, folder):
    out = os.path.join(folder, "values.npy")
    report_path = os.path.join(folder, "report.json")
    subprocess.run([cli, "bake", bgs, "--method", "pathtrace", "--samples", "65536",
                    "--set", "target_error=0.05", "--set", "denoise=1",
                    "--set", "shadow_cache=%d" % shadow_cache, "--set", "error_probes=0",
                    "--seed", "0", "--out", out, "--report", report_path],
                   check=True, stdout=subprocess.DEVNULL)
    with open(report_path) as f:
        return numpy.load(out).astype(numpy.float64), json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", required=True)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--work", default="/tmp/bakegi_real_scenes")
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "bakegi"))
    parser.add_argument("--json")
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for scene in args.scenes.split(","):
            bgs, indices, ref, ref_noise, ref_samples, names = suite_scene(args.cli, args.work,
                                                                          scene)
            for round_index in range(args.rounds):
                for shadow_cache in (0, 1):
                    values, report = default_bake(args.cli, bgs, shadow_cache, folder)
                    metrics = compare_at_subset(values[indices], ref, ref_noise, names)
                    seconds = report["seconds"]
                    row = {"scene": scene, "round": round_index, "shadow_cache": shadow_cache,
                           "seconds": seconds["total"], "samples": report["samples"],
                           "rays": report["rays"],
                           "rays_per_path": report["rays"] / max(report["samples"], 1),
                           "pilot_seconds": seconds.get("shadow_cache", 0.0),
                           "pilot_rays": report.get("shadow_cache_rays", 0),
                           "predicted": report.get("sampling_predicted_error"),
                           **row_metrics(metrics, ref_samples, ref_noise)}
                    rows.append(row)
                    print("%s round %d shadow_cache %d: %.2f s, %d paths, %.2f rays a path, "
                          "pilot %.2f s / %d rays; NRMSE %.2f%% (reference noise %.2f%% "
                          "removed), wRRMSE %.2f%%" % (
                              scene, round_index, shadow_cache, row["seconds"], row["samples"],
                              row["rays_per_path"], row["pilot_seconds"], row["pilot_rays"],
                              100 * row["nrmse_without_reference_noise"], 100 * ref_noise,
                              100 * row["weighted_relative_rmse"]), flush=True)
    if args.json:
        write_rows(args.json, rows)


if __name__ == "__main__":
    main()
