#!/usr/bin/python3
"""Speed versus accuracy on the Cornell box: bakegi's path tracer against Cycles.

    /usr/bin/python3 tools/sweep_cornell.py --build build [--work /tmp/bakegi_cornell_sweep]

Needs the built `bakegi` CLI and libbakegi.so in --build, Blender on PATH, and
/usr/bin/python3 (numpy, matplotlib). Not part of the test suite: it takes about
15-20 minutes on 2 cores. Steps, all in --work:

 1. builds the Cornell box (scenes/cornell_box.py) into cornell.blend;
 2. exports the scene and its face corners as bake points into cornell.bgs with the
    add-on (bakegi.export_scene_file, target CORNER, visible objects);
 3. makes the converged reference with the CLI: two independent halves (different
    seeds), each the mean of chunks; the reference is their mean, and its own noise is
    half the error between the halves (the halves' noise is independent and equal);
 4. `bakegi sweep` of the path tracer over sample counts against that reference;
 5. Cycles' indirect light (tools/sweep_cycles.py in Blender, Diffuse bake
    Direct+Indirect minus Direct) at several sample counts, timed, plus one more bake at
    the largest count with another seed to measure Cycles' own noise; checks that
    Cycles' corners come in the order of the .bgs bake points (positions must agree);
 6. Cycles' error against the same reference with `bakegi compare` (the one metric);
 7. writes docs/cornell_sweep.json, docs/cornell_speed_accuracy.png (tools/plot_sweep.py)
    and the table between the markers of docs/benchmarks.md.

Timings are wall times on this machine; the load average is recorded with them.
"""

import argparse
import datetime
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time

import numpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(ROOT, "docs")
TABLE_BEGIN = "<!-- cornell-table:begin (written by tools/sweep_cornell.py) -->"
TABLE_END = "<!-- cornell-table:end -->"


def log(message):
    print(f"[sweep_cornell {time.strftime('%H:%M:%S')}] {message}", flush=True)


def run(command, env=None, quiet=False):
    """Runs a command; on failure prints its output and stops."""
    log("$ " + " ".join(command))
    result = subprocess.run(command, env=env, capture_output=True, text=True)
    if result.returncode != 0:
        sys.stdout.write(result.stdout[-6000:])
        sys.stderr.write(result.stderr[-6000:])
        raise SystemExit(f"sweep_cornell: command failed with exit code {result.returncode}")
    if not quiet:
        for line in result.stdout.splitlines():
            # Blender prints a lot; keep what our scripts print.
            if not line.startswith(("Blender ", "Read blend", "Info:", "Fra:", "\x1b")):
                print("    " + line)
    return result.stdout


def machine():
    model = ""
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return {"cpu": model, "cores": os.cpu_count(), "system": platform.platform()}


def addon_environment(work, build):
    """Blender environment with the repository's add-on importable and the built library."""
    scripts = os.path.join(work, "blender_scripts")
    addons = os.path.join(scripts, "addons")
    os.makedirs(addons, exist_ok=True)
    link = os.path.join(addons, "bakegi")
    if not os.path.islink(link):
        if os.path.exists(link):
            shutil.rmtree(link)
        os.symlink(os.path.join(ROOT, "addon", "bakegi"), link)
    env = dict(os.environ)
    env["BLENDER_USER_SCRIPTS"] = scripts
    env["BAKEGI_LIBRARY"] = os.path.join(build, "libbakegi.so")
    return env


def build_scene(work, subdivisions, light="area"):
    blend = os.path.join(work, "cornell.blend")
    run(["blender", "-b", "--factory-startup", "--python", os.path.join(ROOT, "scenes", "cornell_box.py"),
         "--", "--out", blend, "--subdivisions", str(subdivisions), "--light", light])
    return blend


def export_scene(work, build, blend):
    """Exports the .bgs with the add-on; returns its path and the baked objects' names in
    export order (the add-on's own resolve_targets, which the export uses)."""
    bgs = os.path.join(work, "cornell.bgs")
    order = os.path.join(work, "export_objects.json")
    expression = (
        "import bpy, bakegi, json; from bakegi.export import targets as export; "
        f"r = bakegi.export_scene_file({bgs!r}, target='CORNER', objects='VISIBLE'); "
        "names = [o.name for o in export.resolve_targets(bpy.context, 'VISIBLE')[0]]; "
        f"json.dump({{'objects': names, 'export_seconds': r.get('seconds')}}, open({order!r}, 'w'))"
    )
    run(["blender", "-b", blend, "--addons", "bakegi", "--python-exit-code", "1", "--python-expr", expression],
        env=addon_environment(work, build))
    return bgs, read_export_info(order)


def read_export_info(path):
    """{'objects': names in export order, 'export_seconds': the add-on's export time}."""
    with open(path) as f:
        return json.load(f)


def bake_chunks(cli, bgs, samples, chunk, first_seed, out, threads):
    """Mean of bakes of `chunk` samples with seeds first_seed, first_seed + 1, ...: one
    estimate of `samples` samples (independent chunks, so the mean is unbiased)."""
    total = None
    done = 0
    seed = first_seed
    seconds = 0.0
    while done < samples:
        count = min(chunk, samples - done)
        path = out + f".chunk{seed}.npy"
        start = time.perf_counter()
        run([cli, "bake", bgs, "--method", "pathtrace", "--samples", str(count), "--seed", str(seed),
             "--threads", str(threads), "--out", path], quiet=True)
        seconds += time.perf_counter() - start
        values = numpy.load(path).astype(numpy.float64)
        os.remove(path)
        total = values * count if total is None else total + values * count
        done += count
        seed += 1
    mean = (total / samples).astype(numpy.float32)
    numpy.save(out, mean)
    return seconds


def compare(cli, values, reference):
    """The older relative RMSE (`bakegi compare`'s "relative_rmse"), the metric `bakegi sweep`
    reports as "error", so that both sides of the chart use one."""
    return float(json.loads(run([cli, "compare", values, reference], quiet=True))["relative_rmse"])


def make_reference(cli, bgs, work, samples, chunk, threads):
    half = samples // 2
    a = os.path.join(work, "reference_half_a.npy")
    b = os.path.join(work, "reference_half_b.npy")
    log(f"reference: 2 x {half} samples per corner")
    seconds = bake_chunks(cli, bgs, half, chunk, 1000, a, threads)
    seconds += bake_chunks(cli, bgs, half, chunk, 2000, b, threads)
    reference = os.path.join(work, "reference.npy")
    numpy.save(reference, ((numpy.load(a).astype(numpy.float64) + numpy.load(b)) / 2).astype(numpy.float32))
    halves_error = compare(cli, a, b)
    info = {
        "samples": 2 * half,
        "seconds": seconds,
        "halves_error": halves_error,
        # Each half is truth + independent noise of equal size: the error between halves is
        # sqrt(2) times one half's noise, and the mean of two halves has 1/sqrt(2) of it.
        "noise": halves_error / 2.0,
        "seeds": "1000+ (half a), 2000+ (half b), chunks of %d" % chunk,
    }
    log(f"reference noise: halves differ by {halves_error:.5f}, reference noise ~ {info['noise']:.5f}")
    return reference, info


def pathtrace_sweep(cli, bgs, reference, work, samples, threads, repeat):
    out = os.path.join(work, "pathtrace_sweep.json")
    run([cli, "sweep", bgs, "--method", "pathtrace", "--samples", ",".join(map(str, samples)), "--seed", "0",
         "--threads", str(threads), "--repeat", str(repeat), "--reference", reference, "--out", out])
    with open(out) as f:
        sweep = json.load(f)
    runs = []
    for r in sweep["runs"]:
        r = dict(r)
        r.pop("report", None)
        runs.append(r)
    return runs


def fastest_bake(cli, bgs, arguments, values, report_path, repeat):
    """Bakes `repeat` times with `arguments` (method, settings, threads) and returns the
    report of the fastest run (core job seconds); the values of the last run are in `values`."""
    best = None
    for _ in range(repeat):
        run([cli, "bake", bgs] + arguments + ["--out", values, "--report", report_path], quiet=True)
        with open(report_path) as f:
            report = json.load(f)
        if best is None or report["seconds"]["total"] < best["seconds"]["total"]:
            best = report
    return best


def antiradiance_sweep(cli, bgs, reference, work, bins_list, threads, repeat):
    """One antiradiance bake per bin count (other settings at their defaults), each timed
    `repeat` times keeping the fastest; seconds are the core's job time, as for the path
    tracer's sweep."""
    runs = []
    for bins in bins_list:
        values = os.path.join(work, f"antiradiance_{bins}.npy")
        report_path = os.path.join(work, f"antiradiance_{bins}.json")
        best = fastest_bake(cli, bgs, ["--method", "antiradiance", "--set", f"bins={bins}", "--threads",
                                       str(threads)], values, report_path, repeat)
        entry = {"method": "antiradiance", "settings": {"bins": bins}, "label": f"{bins} bins",
                 "seconds": best["seconds"]["total"], "error": compare(cli, values, reference),
                 "bake_points": best["bake_points"], "memory_bytes": best.get("memory_bytes"),
                 "links": best.get("antiradiance_links"), "elements": best.get("antiradiance_elements"),
                 "iterations": best.get("antiradiance_iterations"),
                 "stage_seconds": {k: v for k, v in best["seconds"].items() if k.startswith("antiradiance_")}}
        log(f"antiradiance {bins} bins: {entry['seconds']:.3f} s, error {entry['error']:.4f}")
        runs.append(entry)
    return runs


def parse_setting_list(text):
    """"levels=3;levels=4,epsilon=0.005" -> [{"levels": "3"}, {"levels": "4", "epsilon": "0.005"}]."""
    configurations = []
    for entry in text.split(";"):
        entry = entry.strip()
        if not entry:
            continue
        configurations.append(dict(item.split("=", 1) for item in entry.split(",")))
    return configurations


def meshless_sweep(cli, bgs, reference, work, configurations, threads, repeat, common_settings=None):
    """Meshless at each configuration, two curves (issue 4): the full bake (precompute and
    first solve) and the relight alone (same lights: `bakegi relight --move 0,0,0`, whose
    result equals the full bake's, so both curves share the error)."""
    runs = []
    for index, configuration in enumerate(configurations):
        values = os.path.join(work, f"meshless_{index}.npy")
        settings = []
        for key, value in list(configuration.items()) + list((common_settings or {}).items()):
            settings += ["--set", f"{key}={value}"]
        output = run([cli, "relight", bgs, "--method", "meshless", "--move", "0,0,0", "--scale", "1",
                      "--repeat", str(max(repeat, 3)), "--threads", str(threads), "--out", values] + settings,
                     quiet=True)
        timing = json.loads(output[output.index("{"):])
        label = ", ".join(f"{k}={v}" for k, v in configuration.items()) or "defaults"
        entry = {"method": "meshless", "settings": dict(configuration), "label": label,
                 "seconds": timing["full_seconds"], "relight_seconds": timing["relight_seconds"],
                 "relight_solve_seconds": timing["relight_solve_seconds"],
                 "error": compare(cli, values, reference), "bake_points": timing["points"]}
        log(f"meshless {label}: full {entry['seconds']:.2f} s, relight {entry['relight_seconds'] * 1000:.1f} ms, "
            f"error {entry['error']:.4f}")
        runs.append(entry)
    relit = [dict(r, method="meshless_relight", seconds=r["relight_seconds"]) for r in runs]
    return runs, relit


def splatting_sweep(cli, bgs, reference, work, vpl_counts, threads, repeat):
    """The splatting draft (issue 17) at each VPL count, its other settings at the bake's
    defaults: one bounce only, so its error against the full reference is the light it leaves
    out. Timed without the error probes (they would double a 0.1 s bake; the bake reports its
    one-bounce shortfall through them when they run), each `repeat` times keeping the
    fastest."""
    runs = []
    for vpls in vpl_counts:
        values = os.path.join(work, f"splatting_{vpls}.npy")
        report_path = os.path.join(work, f"splatting_{vpls}.json")
        best = fastest_bake(cli, bgs, ["--method", "splatting", "--set", f"vpl_count={vpls}", "--set",
                                       "error_probes=0", "--threads", str(threads)], values, report_path, repeat)
        entry = {"method": "splatting", "settings": {"vpls": vpls}, "label": f"{vpls} VPLs",
                 "seconds": best["seconds"]["total"], "error": compare(cli, values, reference),
                 "bake_points": best["bake_points"]}
        log(f"splatting {vpls} VPLs: {entry['seconds']:.3f} s, error {entry['error']:.4f}")
        runs.append(entry)
    return runs


def cycles_sweep(work, build, blend, samples, objects, cli, reference, positions, repeat):
    out_dir = os.path.join(work, "cycles")
    command = ["blender", "-b", blend, "--python-exit-code", "1", "--python", os.path.join(ROOT, "tools", "sweep_cycles.py"),
               "--", "--samples", ",".join(map(str, samples)), "--seed", "0", "--noise-seed", "1", "--repeat", str(repeat), "--out-dir", out_dir]
    if objects:
        command += ["--objects", ",".join(objects)]
    run(command, env=addon_environment(work, build))
    with open(os.path.join(out_dir, "cycles_runs.json")) as f:
        result = json.load(f)

    # The Cycles values must be in the order of the bake points: compare positions.
    ours = numpy.load(positions)
    theirs = numpy.load(os.path.join(out_dir, "corner_positions.npy"))
    if ours.shape != theirs.shape:
        raise SystemExit(f"sweep_cornell: Cycles baked {theirs.shape[0]} corners, the .bgs holds {ours.shape[0]}")
    mismatch = float(numpy.abs(ours - theirs).max())
    # The add-on moves bake points 0.2% of the way into their face (export/points.py, INWARD_FRACTION):
    # under 1 mm here, while a corner out of order is off by a whole grid cell (>= 6 cm).
    if mismatch > POSITION_TOLERANCE:
        raise SystemExit(f"sweep_cornell: corner order differs from the .bgs export (max position difference {mismatch})")
    log(f"corner order matches the .bgs export (max position difference {mismatch:.2e} m)")

    runs, extra = [], None
    for r in result["runs"]:
        path = os.path.join(out_dir, r["file"])
        entry = {"method": "cycles", "settings": {"samples": r["samples"], "seed": r["seed"]},
                 "seconds": r["seconds"], "seconds_all": r.get("seconds_all"),
                 "error": compare(cli, path, reference), "bake_points": r["points"],
                 "file": path}
        if r["seed"] == 0:
            runs.append(entry)
        else:
            extra = entry
    return runs, extra, result


# Metres: above the add-on's inward nudge of bake points, far below one grid cell.
POSITION_TOLERANCE = 1e-3

# The plane each room surface lies in: (axis, coordinate) in the scene of scenes/cornell_box.py.
ROOM_PLANES = {"Floor": (2, 0.0), "Ceiling": (2, 2.0), "BackWall": (1, 1.0), "LeftWall": (0, -1.0), "RightWall": (0, 1.0)}


def contact_points(positions, object_ids, objects):
    """Face corners that lie on another object's surface: where two walls meet, and the
    bottom corners of the boxes, which stand on the floor. A corner there sees the other
    surface at grazing incidence from its very position, the hardest case for ray offsets."""
    own = numpy.array([ROOM_PLANES.get(objects[int(i)], (-1, 0.0))[0] for i in object_ids])
    own_value = numpy.array([ROOM_PLANES.get(objects[int(i)], (-1, 0.0))[1] for i in object_ids])
    contact = numpy.zeros(len(positions), dtype=bool)
    for axis, value in ROOM_PLANES.values():
        on_plane = numpy.abs(positions[:, axis] - value) < POSITION_TOLERANCE
        own_plane = (own == axis) & (own_value == value)
        contact |= on_plane & ~own_plane
    return contact


def agreement_by_region(cli, work, values_path, reference_path, positions, object_ids, objects):
    """Cycles against the reference on the contact corners and on all the others (the error
    of each subset through `bakegi compare`, the one implementation of the metric)."""
    values, reference = numpy.load(values_path), numpy.load(reference_path)
    contact = contact_points(positions, object_ids, objects)
    result = {}
    for name, mask in (("contact_corners", contact), ("other_corners", ~contact)):
        v, r = os.path.join(work, f"subset_{name}_values.npy"), os.path.join(work, f"subset_{name}_reference.npy")
        numpy.save(v, values[mask])
        numpy.save(r, reference[mask])
        luminance = numpy.array([0.2126, 0.7152, 0.0722])
        result[name] = {"points": int(mask.sum()), "error": compare(cli, v, r),
                        "mean_ratio": float((values[mask] @ luminance).mean() / (reference[mask] @ luminance).mean())}
    return result


def interpolate_time_at_error(curve, error):
    """Time a method needs for `error`, log-log interpolated on its (seconds, error) runs;
    None outside the curve's error range."""
    points = sorted((r["error"], r["seconds"]) for r in curve if r.get("error"))
    for (e0, t0), (e1, t1) in zip(points, points[1:]):
        if e0 <= error <= e1:
            if e1 == e0:
                return t0
            f = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    return None


def antiradiance_table(sweep):
    """Antiradiance runs with the time pathtrace and Cycles need for the same error."""
    comparable_above = 1.5 * sweep["agreement"]["bias_estimate"]
    lines = ["| antiradiance bins | seconds | error | links | pathtrace time at equal error / antiradiance time "
             "| Cycles time at equal error / antiradiance time |",
             "|---:|---:|---:|---:|---:|---:|"]
    for r in sweep["methods"].get("antiradiance", []):
        ratios = []
        for other in ("pathtrace", "cycles"):
            t = interpolate_time_at_error(sweep["methods"][other], r["error"])
            if other == "cycles" and r["error"] < comparable_above:
                ratios.append("— (below 1.5 × Cycles' bias)")
            else:
                ratios.append(f"{t / r['seconds']:.1f}x" if t else "outside its range")
        lines.append(f"| {r['settings']['bins']} | {r['seconds']:.3f} | {r['error']:.4f} | {r.get('links') or ''} "
                     f"| {ratios[0]} | {ratios[1]} |")
    return "\n".join(lines)


def markdown_table(sweep):
    cycles = sweep["methods"]["cycles"]
    # Where Cycles' curve flattens onto its disagreement with the reference (the bias
    # estimate), its time for an error says nothing about speed: compare only well above it.
    comparable_above = 1.5 * sweep["agreement"]["bias_estimate"]
    lines = ["| method | samples | seconds | error | Cycles time at equal error / bakegi time |",
             "|---|---:|---:|---:|---:|"]
    for method in ("pathtrace", "cycles"):
        for r in sweep["methods"][method]:
            ratio = ""
            if method == "pathtrace":
                t = interpolate_time_at_error(cycles, r["error"])
                if r["error"] < comparable_above:
                    ratio = "— (below 1.5 × Cycles' bias)"
                else:
                    ratio = f"{t / r['seconds']:.1f}x" if t else "outside Cycles' range"
            lines.append(f"| {'bakegi pathtrace' if method == 'pathtrace' else 'Cycles'} | {r['settings']['samples']} "
                         f"| {r['seconds']:.3f} | {r['error']:.4f} | {ratio} |")
    table = "\n".join(lines)
    if sweep["methods"].get("antiradiance"):
        table += "\n\n" + antiradiance_table(sweep)
    if sweep["methods"].get("meshless"):
        table += "\n\n" + meshless_table(sweep)
    if sweep["methods"].get("splatting"):
        table += "\n\n" + splatting_table(sweep)
    return table


def splatting_table(sweep):
    """Splatting runs (one bounce) with the time pathtrace needs for the same error."""
    lines = ["| splatting VPLs (one bounce) | seconds | error | pathtrace time at equal error / splatting time |",
             "|---:|---:|---:|---:|"]
    for r in sweep["methods"]["splatting"]:
        t = interpolate_time_at_error(sweep["methods"]["pathtrace"], r["error"])
        ratio = f"{t / r['seconds']:.1f}x" if t else "outside its range"
        lines.append(f"| {r['settings']['vpls']} | {r['seconds']:.3f} | {r['error']:.4f} | {ratio} |")
    return "\n".join(lines)


def meshless_table(sweep):
    """Meshless runs: full bake and relight, with the time pathtrace needs for the same error."""
    lines = ["| meshless settings | full bake (s) | relight (ms) | error | pathtrace time at equal error / full bake "
             "| pathtrace time at equal error / relight |",
             "|---|---:|---:|---:|---:|---:|"]
    for r in sweep["methods"]["meshless"]:
        t = interpolate_time_at_error(sweep["methods"]["pathtrace"], r["error"])
        full = f"{t / r['seconds']:.2f}x" if t else "outside its range"
        relit = f"{t / r['relight_seconds']:.0f}x" if t else "outside its range"
        lines.append(f"| {r['label']} | {r['seconds']:.2f} | {r['relight_seconds'] * 1000:.1f} | {r['error']:.4f} "
                     f"| {full} | {relit} |")
    return "\n".join(lines)


def update_benchmarks_page(table, sweep):
    page = os.path.join(DOCS, "benchmarks.md")
    if not os.path.exists(page):
        log(f"{page} does not exist; table not written there")
        return
    with open(page) as f:
        text = f.read()
    if TABLE_BEGIN not in text or TABLE_END not in text:
        log("docs/benchmarks.md has no table markers; table not written there")
        return
    agreement = sweep["agreement"]
    regions = agreement["by_region"]
    block = (f"{TABLE_BEGIN}\n"
             f"Measured {sweep['date']} on {sweep['machine']['cpu']} ({sweep['machine']['cores']} cores), "
             f"load average {sweep['load_average_before'][0]:.2f} before / {sweep['load_average_after'][0]:.2f} after; "
             f"{sweep['bake_points']} face corners; reference {sweep['reference']['samples']} samples per corner "
             f"(noise ≈ {sweep['reference']['noise']:.4f}).\n\n{table}\n\n"
             f"Agreement at Cycles' largest sample count ({agreement['cycles_samples']}): error of Cycles against "
             f"bakegi's reference {agreement['cycles_error']:.4f}; Cycles' own noise there "
             f"{agreement['cycles_noise']:.4f} (two seeds); reference noise {agreement['reference_noise']:.4f}; "
             f"what noise does not explain (bias estimate): {agreement['bias_estimate']:.4f}. "
             f"On the {regions['contact_corners']['points']} face corners that lie on another surface "
             f"(wall junctions, box bottoms) the error is {regions['contact_corners']['error']:.4f} "
             f"(Cycles' mean / bakegi's mean = {regions['contact_corners']['mean_ratio']:.3f}); on the other "
             f"{regions['other_corners']['points']} it is {regions['other_corners']['error']:.4f} "
             f"(mean ratio {regions['other_corners']['mean_ratio']:.3f}).\n"
             f"{TABLE_END}")
    start = text.index(TABLE_BEGIN)
    end = text.index(TABLE_END) + len(TABLE_END)
    with open(page, "w") as f:
        f.write(text[:start] + block + text[end:])
    log("updated the table in docs/benchmarks.md")


def main():
    parser = argparse.ArgumentParser(description="Cornell box: bakegi pathtrace vs Cycles, time vs error.")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder with bakegi and libbakegi.so")
    parser.add_argument("--work", default="/tmp/bakegi_cornell_sweep", help="folder for scene, reference and raw results")
    parser.add_argument("--subdivisions", type=int, default=16, help="Cornell box grid cells per 2 m edge")
    parser.add_argument("--light", choices=("area", "emissive"), default="area",
                        help="the area light, or an emissive quad filling a hole in the ceiling (writes "
                             "cornell_emissive_* files, leaves the benchmarks table alone)")
    parser.add_argument("--reference-samples", type=int, default=32768, help="samples per corner of the reference")
    parser.add_argument("--reference-chunk", type=int, default=4096, help="samples per CLI run while making the reference")
    parser.add_argument("--pathtrace-samples", default="1,2,4,8,16,32,64,128,256,512,1024")
    parser.add_argument("--cycles-samples", default="1,4,16,64,256,1024")
    parser.add_argument("--antiradiance-bins", default="48,108,192,432,768",
                        help="bin counts of the antiradiance curve (empty: no antiradiance curve)")
    parser.add_argument("--only-antiradiance", action="store_true",
                        help="keep the pathtrace and Cycles runs of the existing sweep JSON (docs/ with --docs, else "
                             "--work) and run only the antiradiance curve; implies --reuse")
    parser.add_argument("--meshless-settings", default="levels=3;levels=4;levels=5",
                        help="meshless configurations, ';' between runs, ',' between key=value settings "
                             "(empty: no meshless curves)")
    parser.add_argument("--only-meshless", action="store_true",
                        help="like --only-antiradiance, for the two meshless curves")
    parser.add_argument("--splatting-vpls", default="256,1024,4096",
                        help="VPL counts of the splatting curve (empty: no splatting curve)")
    parser.add_argument("--only-splatting", action="store_true",
                        help="like --only-antiradiance, for the splatting curve")
    parser.add_argument("--threads", type=int, default=0, help="path tracer threads (0 = all cores, as Cycles)")
    parser.add_argument("--repeat", type=int, default=2, help="time each setting R times (both methods), keep the fastest")
    parser.add_argument("--reuse", action="store_true", help="reuse scene, export and reference already in --work")
    parser.add_argument("--docs", action="store_true", help="write docs/cornell_sweep.json, the chart and the table")
    arguments = parser.parse_args()

    build = os.path.abspath(arguments.build)
    work = os.path.abspath(arguments.work)
    cli = os.path.join(build, "bakegi")
    for needed in (cli, os.path.join(build, "libbakegi.so")):
        if not os.path.exists(needed):
            raise SystemExit(f"sweep_cornell: {needed} is missing; build first (cmake --build {build})")
    os.makedirs(work, exist_ok=True)
    started = time.perf_counter()

    blend = os.path.join(work, "cornell.blend")
    bgs = os.path.join(work, "cornell.bgs")
    reference = os.path.join(work, "reference.npy")
    reference_info_path = os.path.join(work, "reference.json")
    export_path = os.path.join(work, "export_objects.json")
    if arguments.only_antiradiance or arguments.only_meshless or arguments.only_splatting:
        arguments.reuse = True
    if arguments.reuse and all(os.path.exists(p) for p in (blend, bgs, reference, reference_info_path, export_path)):
        log("reusing scene, export and reference")
        with open(reference_info_path) as f:
            reference_info = json.load(f)
        export_info = read_export_info(export_path)
    else:
        build_scene(work, arguments.subdivisions, arguments.light)
        bgs, export_info = export_scene(work, build, blend)
        reference, reference_info = make_reference(cli, bgs, work, arguments.reference_samples,
                                                   arguments.reference_chunk, arguments.threads)
        with open(reference_info_path, "w") as f:
            json.dump(reference_info, f, indent=1)
    objects = export_info["objects"]
    run([cli, "info", bgs])
    positions = os.path.join(work, "bake_positions.npy")
    object_ids_path = os.path.join(work, "bake_object_ids.npy")
    run([cli, "points", bgs, "--positions", positions, "--object-ids", object_ids_path], quiet=True)

    stem = "cornell" if arguments.light == "area" else "cornell_emissive"
    sweep_json = os.path.join(DOCS if arguments.docs else work, f"{stem}_sweep.json")
    bins_list = [int(b) for b in arguments.antiradiance_bins.split(",") if b.strip()]
    meshless_configurations = parse_setting_list(arguments.meshless_settings)
    splatting_vpls = [int(v) for v in arguments.splatting_vpls.split(",") if v.strip()]
    if arguments.only_splatting:
        with open(sweep_json) as f:
            sweep = json.load(f)
        load_before = os.getloadavg()
        sweep["methods"]["splatting"] = splatting_sweep(cli, bgs, reference, work, splatting_vpls,
                                                        arguments.threads, arguments.repeat)
        sweep["splatting_date"] = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
        sweep["splatting_load_average"] = [load_before, os.getloadavg()]
        sweep["splatting_command"] = "/usr/bin/python3 tools/sweep_cornell.py " + " ".join(sys.argv[1:])
        write_results(sweep, sweep_json, work, arguments.docs, started)
        return
    if arguments.only_meshless:
        with open(sweep_json) as f:
            sweep = json.load(f)
        load_before = os.getloadavg()
        sweep["methods"]["meshless"], sweep["methods"]["meshless_relight"] = meshless_sweep(
            cli, bgs, reference, work, meshless_configurations, arguments.threads, arguments.repeat)
        sweep["meshless_date"] = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
        sweep["meshless_load_average"] = [load_before, os.getloadavg()]
        sweep["meshless_command"] = "/usr/bin/python3 tools/sweep_cornell.py " + " ".join(sys.argv[1:])
        write_results(sweep, sweep_json, work, arguments.docs, started)
        return
    if arguments.only_antiradiance:
        with open(sweep_json) as f:
            sweep = json.load(f)
        load_before = os.getloadavg()
        sweep["methods"]["antiradiance"] = antiradiance_sweep(cli, bgs, reference, work, bins_list, arguments.threads,
                                                              arguments.repeat)
        sweep["antiradiance_date"] = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
        sweep["antiradiance_load_average"] = [load_before, os.getloadavg()]
        sweep["antiradiance_command"] = "/usr/bin/python3 tools/sweep_cornell.py " + " ".join(sys.argv[1:])
        write_results(sweep, sweep_json, work, arguments.docs, started)
        return

    load_before = os.getloadavg()
    pathtrace_runs = pathtrace_sweep(cli, bgs, reference, work, [int(s) for s in arguments.pathtrace_samples.split(",")],
                                     arguments.threads, arguments.repeat)
    antiradiance_runs = antiradiance_sweep(cli, bgs, reference, work, bins_list, arguments.threads, arguments.repeat)
    meshless_runs, meshless_relit = meshless_sweep(cli, bgs, reference, work, meshless_configurations,
                                                   arguments.threads, arguments.repeat)
    splatting_runs = splatting_sweep(cli, bgs, reference, work, splatting_vpls, arguments.threads,
                                     arguments.repeat)
    cycles_runs, cycles_extra, cycles_result = cycles_sweep(
        work, build, blend, [int(s) for s in arguments.cycles_samples.split(",")], objects, cli, reference, positions, arguments.repeat)
    load_after = os.getloadavg()

    top = max(cycles_runs, key=lambda r: r["settings"]["samples"])
    # Two Cycles bakes with different seeds: their difference is sqrt(2) x one bake's noise.
    cycles_noise = compare(cli, cycles_extra["file"], top["file"]) / math.sqrt(2.0) if cycles_extra else None
    unexplained = top["error"] ** 2 - (cycles_noise or 0.0) ** 2 - reference_info["noise"] ** 2
    agreement = {
        "cycles_samples": top["settings"]["samples"],
        "cycles_error": top["error"],
        "cycles_noise": cycles_noise,
        "reference_noise": reference_info["noise"],
        "bias_estimate": math.sqrt(max(0.0, unexplained)),
        "by_region": agreement_by_region(cli, work, top["file"], reference, numpy.load(positions),
                                         numpy.load(object_ids_path), objects),
    }
    log("agreement: " + json.dumps(agreement))

    sweep = {
        "title": f"Cornell box, indirect light at {pathtrace_runs[0]['bake_points']} face corners (2 cores)",
        "subtitle": "error: relative RMSE, luminance-weighted, against bakegi pathtrace at "
                    f"{reference_info['samples']} samples; time: wall seconds of the bake",
        "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "machine": machine(),
        "load_average_before": load_before,
        "load_average_after": load_after,
        "bake_points": pathtrace_runs[0]["bake_points"],
        "scene": {"subdivisions": arguments.subdivisions, "objects": objects,
                  "bakegi_export_seconds": export_info["export_seconds"]},
        "reference": reference_info,
        "reference_noise": reference_info["noise"],
        "blender": cycles_result.get("blender"),
        "cycles_bounces": cycles_result.get("bounces"),
        "methods": {"pathtrace": pathtrace_runs,
                    "cycles": [{k: v for k, v in r.items() if k != "file"} for r in cycles_runs],
                    "antiradiance": antiradiance_runs, "meshless": meshless_runs,
                    "meshless_relight": meshless_relit, "splatting": splatting_runs},
        "agreement": agreement,
        "command": "/usr/bin/python3 tools/sweep_cornell.py " + " ".join(sys.argv[1:]),
    }
    write_results(sweep, sweep_json, work, arguments.docs, started)


def write_results(sweep, sweep_json, work, docs, started):
    """The sweep JSON, the chart next to it, and (with --docs, for the area light) the table in
    benchmarks.md."""
    table = markdown_table(sweep)
    print(table)
    emissive = os.path.basename(sweep_json).startswith("cornell_emissive")
    chart = os.path.join(DOCS if docs else work,
                         "cornell_emissive_speed_accuracy.png" if emissive else "cornell_speed_accuracy.png")
    with open(sweep_json, "w") as f:
        json.dump(sweep, f, indent=1)
    run([sys.executable, os.path.join(ROOT, "tools", "plot_sweep.py"), sweep_json, "--out", chart])
    if docs and not emissive:
        update_benchmarks_page(table, sweep)
    log(f"wrote {sweep_json} and {chart} in {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
