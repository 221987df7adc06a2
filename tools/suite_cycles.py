"""Cycles against bakegi's default bake on scenes of the real-scene suite: the time each needs
for the same error.

    /usr/bin/python3 tools/real_scenes.py --scenes two_rooms,office --targets CORNER --methods pathtrace
    /usr/bin/python3 tools/suite_targets.py --scenes two_rooms,office --targets 0.05 --denoise 1
    /usr/bin/python3 tools/suite_cycles.py --scenes two_rooms,office [--samples 256] \\
        [--scene-samples office=64] [--work /tmp/bakegi_real_scenes] [--blender blender] \\
        [--json docs/suite_cycles.json]

For every scene set up by tools/real_scenes.py (its .blend, export, 2,000-point subset and
path-traced reference) and baked by tools/suite_targets.py at the default settings (5%
target through the denoiser, kept in the scene's folder):

1. Cycles bakes the indirect light of every face corner of the .blend (tools/sweep_cycles.py:
   Diffuse bake Direct+Indirect minus Direct, all cores) at N/4 and N = `--samples` samples
   with seed 0, and at N again with seed 1; its seconds include scene sync and BVH, after a
   warm-up bake, and the two counts split them into a fixed part and a part per sample;
2. its values at the subset are compared with the reference (NRMSE, weighted relative RMSE,
   bias; the reference's noise removed in quadrature), and its own noise is measured from the
   two seeds (NRMSE of their difference / sqrt 2);
3. Cycles' error falls as 1/sqrt(samples) where it is noise (measured on the Cornell box:
   exponent -0.51) and its time is fixed + per_sample * samples, so for an error e it needs
   N * (err(N) / e)^2 samples, err(N) the noise-removed NRMSE at N samples. Where err(N)
   exceeds Cycles' own noise (a difference in how the two model the scene, which no number
   of samples removes, or rare bright paths that two seeds happen to miss) that law
   overrates Cycles' time, so its time is also given from its own noise, and
4. ratio = the smaller of the two times at the default bake's true error / the default
   bake's seconds.
"""

import argparse
import json
import os
import subprocess
import sys

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_scene_metrics import compare_at_subset, luminance, nrmse  # noqa: E402
from real_scenes import object_names_at, reference  # noqa: E402
from suite_targets import write_rows  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_BAKE = "target_0.05_denoise_1"  # suite_targets.py's name for the default settings


def cycles(blender, blend, objects, samples, out_dir):
    """Cycles' values at N samples, seeds 0 and 1, its time model (fixed seconds, seconds per
    sample) from the seed-0 bakes at N/4 and N, and the Blender version (cached in out_dir)."""
    runs_path = os.path.join(out_dir, "cycles_runs.json")
    low = max(1, samples // 4)
    if not os.path.exists(runs_path):
        subprocess.run([blender, "-b", blend, "--python", os.path.join(ROOT, "tools", "sweep_cycles.py"),
                        "--", "--samples", f"{low},{samples}", "--seed", "0", "--noise-seed", "1",
                        "--objects", ",".join(objects), "--out-dir", out_dir],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(runs_path) as f:
        runs = json.load(f)
    first = numpy.load(os.path.join(out_dir, f"cycles_{samples}.npy")).astype(numpy.float64)
    second = numpy.load(os.path.join(out_dir, f"cycles_{samples}_seed1.npy")).astype(numpy.float64)
    seconds = {r["samples"]: r["seconds"] for r in runs["runs"] if r["seed"] == 0}
    per_sample = (seconds[samples] - seconds[low]) / (samples - low)
    fixed = max(0.0, seconds[samples] - per_sample * samples)
    return first, second, seconds[samples], fixed, per_sample, runs["blender"]


def own_noise(first, second):
    """Both metrics of one bake's noise, from two bakes with different seeds."""
    y1, y2 = luminance(first), luminance(second)
    r = 0.5 * (y1 + y2)
    keep = r > 0.01 * numpy.mean(r)
    weighted = numpy.sqrt(numpy.sum((y1 - y2)[keep] ** 2 / r[keep]) / numpy.sum(r[keep]) / 2.0)
    return nrmse(first, second) / numpy.sqrt(2.0), float(weighted)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", required=True, help="comma-separated suite scene names")
    parser.add_argument("--samples", type=int, default=256, help="Cycles samples per corner")
    parser.add_argument("--scene-samples", default="",
                        help="per scene instead, e.g. two_rooms=512,living_room=64")
    parser.add_argument("--work", default="/tmp/bakegi_real_scenes")
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "bakegi"))
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    scene_samples = dict(item.split("=") for item in args.scene_samples.split(",") if item)
    rows = []
    for scene in args.scenes.split(","):
        samples = int(scene_samples.get(scene, args.samples))
        folder = os.path.join(args.work, scene, "corner")
        with open(os.path.join(folder, "export.json")) as f:
            info = json.load(f)
        if any(t["domain"] != "CORNER" for t in info["targets"]):
            print(f"{scene}: skipped, Cycles is compared on face corners only")
            continue
        indices = numpy.load(os.path.join(folder, "subset_indices.npy")).astype(numpy.int64)
        ref, ref_noise, ref_samples = reference(args.cli, os.path.join(folder, "subset.bgs"), folder)
        names = object_names_at(info, indices)
        default_path = os.path.join(folder, DEFAULT_BAKE + ".npy")
        if not os.path.exists(default_path):
            sys.exit(f"{scene}: no default bake in {folder}: run tools/suite_targets.py "
                     "--targets 0.05 --denoise 1 for it first")
        with open(os.path.join(folder, DEFAULT_BAKE + "_report.json")) as f:
            bakegi_report = json.load(f)
        bakegi = compare_at_subset(numpy.load(default_path).astype(numpy.float64)[indices], ref,
                                   ref_noise, names)
        objects = [t["object"] for t in info["targets"]]
        first, second, seconds, fixed, per_sample, blender = cycles(args.blender, os.path.join(args.work, scene, "scene.blend"),
                                                 objects, samples, os.path.join(folder, f"cycles_{samples}"))
        if first.shape[0] != info["counts"]["bake_points"]:
            sys.exit(f"{scene}: Cycles baked {first.shape[0]} corners, the export has "
                     f"{info['counts']['bake_points']}")
        at_subset = compare_at_subset(first[indices], ref, ref_noise, names)
        noise, weighted_noise = own_noise(first[indices], second[indices])
        cycles_error = at_subset["nrmse_without_reference_noise"]
        bakegi_error = bakegi["nrmse_without_reference_noise"]
        def cycles_seconds_at(error):
            return fixed + per_sample * samples * (cycles_error / error) ** 2

        cycles_seconds_at_bakegi = cycles_seconds_at(bakegi_error)
        # The same law through Cycles' own noise instead of its error against the reference.
        noise_seconds_at_bakegi = fixed + per_sample * samples * (noise / bakegi_error) ** 2
        row = {
            "scene": scene, "bake_points": info["counts"]["bake_points"],
            "reference_samples": ref_samples, "reference_noise": ref_noise,
            "cycles": {"blender": blender, "samples": samples, "seconds": seconds,
                       "fixed_seconds": fixed, "seconds_per_sample": per_sample,
                       "nrmse": at_subset["nrmse"], "nrmse_without_reference_noise": cycles_error,
                       "weighted_relative_rmse": at_subset["weighted_relative_rmse"],
                       "bias": at_subset["bias"], "own_noise": noise,
                       "own_weighted_noise": weighted_noise,
                       "seconds_at_5_percent": cycles_seconds_at(0.05)},
            "bakegi": {"settings": "default (path tracer, 5% target, denoised)",
                       "seconds": bakegi_report["seconds"]["total"],
                       "nrmse": bakegi["nrmse"], "nrmse_without_reference_noise": bakegi_error,
                       "weighted_relative_rmse": bakegi["weighted_relative_rmse"],
                       "bias": bakegi["bias"]},
            "cycles_seconds_at_bakegi_error": cycles_seconds_at_bakegi,
            "cycles_seconds_at_bakegi_error_by_own_noise": noise_seconds_at_bakegi,
            "ratio": min(cycles_seconds_at_bakegi, noise_seconds_at_bakegi) /
                     bakegi_report["seconds"]["total"],
        }
        rows.append(row)
        c, b = row["cycles"], row["bakegi"]
        print(f"{scene}: Cycles {samples} samples {c['seconds']:.1f} s, NRMSE "
              f"{100 * c['nrmse_without_reference_noise']:.2f}% (own noise {100 * c['own_noise']:.2f}%), "
              f"wRRMSE {100 * c['weighted_relative_rmse']:.2f}%, bias {100 * c['bias']:+.1f}%; bakegi "
              f"{b['seconds']:.2f} s, {100 * b['nrmse_without_reference_noise']:.2f}%; Cycles at that "
              f"error {cycles_seconds_at_bakegi:.0f} s ({noise_seconds_at_bakegi:.0f} s by its own noise): "
              f"{row['ratio']:.0f}x", flush=True)
    if args.json:
        write_rows(args.json, rows)


if __name__ == "__main__":
    main()
