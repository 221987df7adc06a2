"""The real-scene suite: every method at its defaults on every scene of the suite, for both
targets (face corners, lightmap texels), against a converged path-traced reference.

    /usr/bin/python3 tools/real_scenes.py [--scenes a,b] [--targets CORNER,LIGHTMAP]
        [--methods antiradiance,meshless,pathtrace] [--work /tmp/bakegi_real_scenes]
        [--build build] [--reuse] [--docs]

Per scene and target:
 1. builds the scene with its script in scenes/ and exports it with the add-on
    (`bakegi.export_scene_file`: the bake points are the targets' corners, or their lightmap
    texels at the scene's texel density);
 2. draws a fixed random subset of the bake points (`bakegi subset`, seed 1, 2,000 points);
 3. bakes the reference on the subset with the path tracer in chunks of 512 paths (seeds
    1, 2, ...) until its own noise, NRMSE(mean of the odd chunks, mean of the even ones) / 2,
    is at most 2% (or 64 chunks); both halves are kept, so the noise is stated, not assumed;
 4. bakes the whole scene with every method at its defaults (the CLI: the core's report gives
    seconds, memory and the bake's own error estimate; the process's peak RSS is measured);
 5. compares the method's values at the subset with the reference (real_scene_metrics.py).
Results go to WORK/<scene>/<target>/results.json; with --docs, to docs/real_scenes/ and the
table and charts of docs/real_scenes.md (tools/real_scenes_report.py). Scenes whose data is
missing (../shared/scenes) are skipped with a message. Long: about an hour on 2 cores.
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import time

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_scene_metrics import compare_at_subset, nrmse  # noqa: E402
from sweep_cornell import ROOT, addon_environment  # noqa: E402

# name: (script in scenes/, its arguments, bake target domain for CORNER ("CORNER" or
# "POINT": Sponza's 786k corners would make the methods' runs long; its 81k vertices are what
# docs/methods/meshless.md measured), lightmap texels per metre)
SCENES = {
    "cornell_area": ("cornell_box", [], "CORNER", 40.0),
    "cornell_emissive": ("cornell_box", ["--light", "emissive"], "CORNER", 40.0),
    "two_rooms": ("two_rooms", [], "CORNER", 20.0),
    "office": ("office", [], "CORNER", 20.0),
    "maze": ("maze", [], "CORNER", 16.0),
    "bunny_dragon": ("bunny_dragon", [], "CORNER", 16.0),
    "living_room": ("living_room", [], "CORNER", 12.0),
    "sponza_spot": ("sponza", ["--light", "spot"], "POINT", 2.0),
    "sponza_sun": ("sponza", ["--light", "sun"], "POINT", 2.0),
}
METHODS = ("antiradiance", "meshless", "pathtrace")
SUBSET = 2000
CHUNK_SAMPLES = 512
MAX_CHUNKS = 64
TARGET_NOISE = 0.02


def log(message):
    print(f"[real_scenes {time.strftime('%H:%M:%S')}] {message}", flush=True)


def run(command, env=None, check=True):
    completed = subprocess.run(command, env=env, capture_output=True, text=True)
    if check and completed.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({completed.returncode}):\n"
                           f"{completed.stdout[-2000:]}\n{completed.stderr[-2000:]}")
    return completed


def run_measured(command, folder):
    """(returncode, stdout, stderr, peak resident memory in bytes) of one child process, its
    own peak (wait4), not the largest of all children so far."""
    out_path, err_path = os.path.join(folder, "stdout.txt"), os.path.join(folder, "stderr.txt")
    with open(out_path, "w") as out, open(err_path, "w") as err:
        process = subprocess.Popen(command, stdout=out, stderr=err)
        _, status, usage = os.wait4(process.pid, 0)
    with open(out_path) as out, open(err_path) as err:
        return os.waitstatus_to_exitcode(status), out.read(), err.read(), usage.ru_maxrss * 1024


def export(scene, target, folder, build):
    """Builds the scene and exports `target`; returns the export's info dict (targets with
    their slices of the bake points, warnings) or None when the scene's data is missing."""
    script, arguments, domain, texels_per_meter = SCENES[scene]
    bgs = os.path.join(folder, "scene.bgs")
    info_path = os.path.join(folder, "export.json")
    blend = os.path.join(os.path.dirname(folder), "scene.blend")
    if not os.path.exists(blend):
        completed = run(["blender", "-b", "--factory-startup", "--python", os.path.join(ROOT, "scenes", script + ".py"),
                         "--", "--out", blend] + arguments, check=False)
        if "FileNotFoundError" in completed.stdout + completed.stderr or not os.path.exists(blend):
            log(f"{scene}: skipped, its scene could not be built:\n{(completed.stdout + completed.stderr)[-600:]}")
            return None
    kind = domain if target == "CORNER" else "LIGHTMAP"
    expression = (
        "import bakegi, json; "
        f"r = bakegi.export_scene_file({bgs!r}, target={kind!r}, objects='VISIBLE', "
        f"texels_per_meter={texels_per_meter!r}, lightmap_max_size=1024); "
        f"json.dump(r, open({info_path!r}, 'w'), default=str)")
    run(["blender", "-b", blend, "--addons", "bakegi", "--python-exit-code", "1", "--python-expr", expression],
        env=addon_environment(folder, build))
    with open(info_path) as f:
        return json.load(f)


def object_names_at(info, indices):
    """The target object's name for each bake point index."""
    names = numpy.empty(len(indices), dtype=object)
    for t in info["targets"]:
        inside = (indices >= t["start"]) & (indices < t["start"] + t["count"])
        names[inside] = t["object"]
    return names


def suite_scene(cli, work, scene, target="CORNER"):
    """An exported suite scene for studies that bake it whole and compare at its subset:
    (scene.bgs, subset indices, reference, its noise, its paths per point, object names at
    the subset). Exits with a message when tools/real_scenes.py has not set it up."""
    folder = os.path.join(work, scene, target.lower())
    bgs = os.path.join(folder, "scene.bgs")
    if not os.path.exists(bgs):
        sys.exit("%s: no export in %s: run tools/real_scenes.py for it first" % (scene, folder))
    with open(os.path.join(folder, "export.json")) as f:
        info = json.load(f)
    indices = numpy.load(os.path.join(folder, "subset_indices.npy")).astype(numpy.int64)
    ref, ref_noise, ref_samples = reference(cli, os.path.join(folder, "subset.bgs"), folder)
    return bgs, indices, ref, ref_noise, ref_samples, object_names_at(info, indices)


def reference(cli, subset_bgs, folder):
    """(reference (k, 3), noise, samples) on the subset: chunks until the noise of the mean of
    two interleaved halves is at most TARGET_NOISE."""
    chunks = []
    noise = float("inf")
    while len(chunks) < MAX_CHUNKS:
        for _ in range(2):
            seed = len(chunks) + 1
            path = os.path.join(folder, f"reference_chunk_{seed}.npy")
            if not os.path.exists(path):
                run([cli, "bake", subset_bgs, "--method", "pathtrace", "--samples", str(CHUNK_SAMPLES),
                     "--seed", str(seed), "--out", path])
            chunks.append(numpy.load(path).astype(numpy.float64))
        odd, even = numpy.mean(chunks[0::2], axis=0), numpy.mean(chunks[1::2], axis=0)
        noise = nrmse(odd, even) / 2.0
        if noise <= TARGET_NOISE:
            break
    return numpy.mean(chunks, axis=0), noise, len(chunks) * CHUNK_SAMPLES


def bake_method(cli, bgs, method, folder):
    """The method's values and report on the whole scene, or an error record."""
    out = os.path.join(folder, f"{method}.npy")
    report_path = os.path.join(folder, f"{method}_report.json")
    started = time.perf_counter()
    code, stdout, stderr, peak = run_measured([cli, "bake", bgs, "--method", method, "--out", out,
                                               "--report", report_path], folder)
    wall = time.perf_counter() - started
    if code != 0:
        message = stderr.strip().splitlines()[-1] if stderr.strip() else f"exit code {code}"
        return None, {"method": method, "failed": message, "wall_seconds": wall}
    with open(report_path) as f:
        report = json.load(f)
    return numpy.load(out).astype(numpy.float64), {
        "method": method, "method_used": report.get("method_used", method), "wall_seconds": wall,
        "peak_rss_bytes": peak,
        "seconds": report.get("seconds", {}).get("total"), "memory_bytes": report.get("memory_bytes"),
        "estimated_error": report.get("estimated_error"),
        "estimated_error_interval": report.get("estimated_error_interval"),
        "rays": report.get("rays"), "bake_points": report.get("bake_points"),
        "warnings": report.get("warnings", [])[:8],
    }


def refresh_methods(results, methods, folder, build, results_path):
    """Bakes `methods` again on a scene whose export and reference are kept (after a change
    to those methods), replacing their rows."""
    cli = os.path.join(build, "bakegi")
    indices = numpy.load(os.path.join(folder, "subset_indices.npy")).astype(numpy.int64)
    with open(os.path.join(folder, "export.json")) as f:
        info = json.load(f)
    chunks = sorted(glob.glob(os.path.join(folder, "reference_chunk_*.npy")))
    ref = numpy.mean([numpy.load(c).astype(numpy.float64) for c in chunks], axis=0)
    names = object_names_at(info, indices)
    rows = {row["method"]: row for row in results["methods"]}
    for method in methods:
        values, row = bake_method(cli, os.path.join(folder, "scene.bgs"), method, folder)
        if values is not None:
            row.update(compare_at_subset(values[indices], ref, results["reference_noise"], names))
            estimate, true = row.get("estimated_error"), row["nrmse_without_reference_noise"]
            row["estimate_over_true"] = estimate / true if estimate and true > 0 else None
        rows[method] = row
        log(f"{results['scene']} {results['target']} {method}: refreshed")
    results["methods"] = [rows[m] for m in METHODS if m in rows]
    results["refreshed"] = time.strftime("%Y-%m-%d") + ": " + ",".join(methods)
    with open(results_path, "w") as f:
        json.dump(results, f, indent=1, default=str)
    return results


def run_scene_target(scene, target, work, build, methods, reuse, refresh=()):
    cli = os.path.join(build, "bakegi")
    folder = os.path.join(work, scene, target.lower())
    os.makedirs(folder, exist_ok=True)
    results_path = os.path.join(folder, "results.json")
    if reuse and os.path.exists(results_path):
        with open(results_path) as f:
            kept = json.load(f)
        if not refresh:
            return kept
        return refresh_methods(kept, refresh, folder, build, results_path)
    started = time.perf_counter()
    info = export(scene, target, folder, build)
    if info is None:
        return None
    bgs = os.path.join(folder, "scene.bgs")
    subset_bgs = os.path.join(folder, "subset.bgs")
    indices_path = os.path.join(folder, "subset_indices.npy")
    run([cli, "subset", bgs, "--count", str(SUBSET), "--seed", "1", "--out", subset_bgs, "--indices", indices_path])
    indices = numpy.load(indices_path).astype(numpy.int64)
    log(f"{scene} {target}: {info['counts']} exported; reference on {len(indices)} points")
    ref, ref_noise, ref_samples = reference(cli, subset_bgs, folder)
    log(f"{scene} {target}: reference {ref_samples} paths per point, its noise {100 * ref_noise:.2f}%")
    names = object_names_at(info, indices)
    rows = []
    for method in methods:
        values, row = bake_method(cli, bgs, method, folder)
        if values is not None:
            row.update(compare_at_subset(values[indices], ref, ref_noise, names))
            estimate = row.get("estimated_error")
            true = row["nrmse_without_reference_noise"]
            row["estimate_over_true"] = estimate / true if estimate and true > 0 else None
            log(f"{scene} {target} {method}: {row['seconds']:.1f} s, NRMSE {100 * row['nrmse']:.1f}% "
                f"(estimated {100 * estimate:.1f}%), bias {100 * row['bias']:+.1f}%")
        else:
            log(f"{scene} {target} {method}: FAILED: {row['failed']}")
        rows.append(row)
    results = {
        "scene": scene, "target": target, "script": SCENES[scene][0], "script_arguments": SCENES[scene][1],
        "domain": SCENES[scene][2] if target == "CORNER" else "LIGHTMAP",
        "texels_per_meter": SCENES[scene][3] if target == "LIGHTMAP" else None,
        "counts": info["counts"], "bake_points": next((r["bake_points"] for r in rows if r.get("bake_points")), None),
        "subset": len(indices), "reference_samples": ref_samples, "reference_noise": ref_noise,
        "methods": rows, "export_warnings": info.get("warnings", [])[:12],
        "minutes": (time.perf_counter() - started) / 60.0,
        "date": time.strftime("%Y-%m-%d"), "load_average": os.getloadavg(),
    }
    with open(results_path, "w") as f:
        json.dump(results, f, indent=1, default=str)
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", default=",".join(SCENES), help="comma-separated scene names")
    parser.add_argument("--targets", default="CORNER,LIGHTMAP")
    parser.add_argument("--methods", default=",".join(METHODS))
    parser.add_argument("--work", default="/tmp/bakegi_real_scenes")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--reuse", action="store_true", help="keep results already in --work")
    parser.add_argument("--refresh", default="", help="with --reuse: bake these methods again on kept scenes")
    parser.add_argument("--docs", action="store_true", help="write docs/real_scenes/ and docs/real_scenes.md")
    arguments = parser.parse_args()
    build = os.path.abspath(arguments.build)
    work = os.path.abspath(arguments.work)
    all_results = []
    for scene in [s for s in arguments.scenes.split(",") if s]:
        if scene not in SCENES:
            raise SystemExit(f"unknown scene {scene!r}; the suite has {', '.join(SCENES)}")
        for target in [t for t in arguments.targets.split(",") if t]:
            try:
                results = run_scene_target(scene, target, work, build, arguments.methods.split(","), arguments.reuse,
                                           [m for m in arguments.refresh.split(",") if m])
            except RuntimeError as error:
                log(f"{scene} {target}: FAILED: {error}")
                continue
            if results is not None:
                all_results.append(results)
    if arguments.docs:
        import real_scenes_report

        real_scenes_report.write(all_results, " ".join(sys.argv[1:]))


if __name__ == "__main__":
    main()
