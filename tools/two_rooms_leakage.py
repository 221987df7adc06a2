#!/usr/bin/python3
"""Leakage of indirect light through a shared wall (Antiradiance Fig. 13), per bin count.

Two closed rooms share one wall and a light hangs in room A only (scenes/two_rooms.py), so
room B's exact indirect light is 0. Leakage = mean luminance of room B's baked face corners
/ mean luminance of room A's. Both variants of the scene: a 0.1 m thick wall (closed solids)
and a zero-thickness wall (one plane, open room meshes).

    /usr/bin/python3 tools/two_rooms_leakage.py --build build [--bins 48,108,192,432,768] \\
        [--work /tmp/bakegi_scenes] [--json docs/two_rooms_leakage.json]

Also bakes both variants with the path tracer (256 samples per corner) for room A's level:
the error of antiradiance's room A against it is reported next to the leakage.
"""

import argparse
import json
import os
import subprocess
import sys

import numpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LUMINANCE = numpy.array([0.2126, 0.7152, 0.0722])
VARIANTS = {"thick wall": ("two_rooms", []), "zero-thickness wall": ("two_rooms_zero", ["--zero-thickness"])}


def scene_file(work, build, name, extra):
    bgs = os.path.join(work, name + ".bgs")
    if not os.path.exists(bgs):
        subprocess.run([sys.executable, os.path.join(ROOT, "tools", "export_scene.py"), "--scene", "two_rooms",
                        "--out", bgs, "--build", build, "--"] + extra, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(work, name + "_objects.json")) as f:
        objects = json.load(f)["objects"]
    return bgs, objects


def room_masks(objects):
    """Boolean masks over the bake points of room A's and room B's receivers."""
    names = numpy.concatenate([[o["name"]] * o["corners"] for o in objects])
    return (numpy.char.startswith(names.astype(str), "RoomA_"),
            numpy.char.startswith(names.astype(str), "RoomB_"))


def bake(cli, bgs, out, arguments):
    completed = subprocess.run([cli, "bake", bgs, "--out", out] + arguments, check=True, capture_output=True, text=True)
    return json.loads(completed.stdout)


def relative_rmse(values, reference):
    v, r = values @ LUMINANCE, reference @ LUMINANCE
    return float(numpy.sqrt(((v - r) ** 2).sum() / (r ** 2).sum()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--bins", default="48,108,192,432,768")
    parser.add_argument("--work", default="/tmp/bakegi_scenes")
    parser.add_argument("--json", help="write the results here too")
    arguments = parser.parse_args()
    build = os.path.abspath(arguments.build)
    cli = os.path.join(build, "bakegi")
    os.makedirs(arguments.work, exist_ok=True)

    results = {"command": "/usr/bin/python3 tools/two_rooms_leakage.py " + " ".join(sys.argv[1:]), "variants": {}}
    print("| wall | method | bins | leakage (B / A) | room A error vs path tracer | seconds | warnings |")
    print("|---|---|---:|---:|---:|---:|---|")
    for variant, (name, extra) in VARIANTS.items():
        bgs, objects = scene_file(arguments.work, build, name, extra)
        room_a, room_b = room_masks(objects)
        reference_path = os.path.join(arguments.work, name + "_pathtrace.npy")
        report = bake(cli, bgs, reference_path, ["--method", "pathtrace", "--samples", "256"])
        reference = numpy.load(reference_path)
        rows = []

        def record(method, bins, values, report):
            a = float((values[room_a] @ LUMINANCE).mean())
            b = float((values[room_b] @ LUMINANCE).mean())
            row = {"method": method, "bins": bins, "room_a_mean": a, "room_b_mean": b,
                   "leakage": b / a if a > 0 else None,
                   "room_a_error": relative_rmse(values[room_a], reference[room_a]),
                   "seconds": report["seconds"]["total"], "warnings": report.get("warnings", [])}
            rows.append(row)
            leak = f"{row['leakage'] * 100:.2f}%" if row["leakage"] is not None else "n/a"
            print(f"| {variant} | {method} | {bins or ''} | {leak} | {row['room_a_error'] * 100:.1f}% "
                  f"| {row['seconds']:.2f} | {len(row['warnings'])} |", flush=True)

        record("pathtrace 256 spp", None, reference, report)
        for bins in [int(b) for b in arguments.bins.split(",")]:
            out = os.path.join(arguments.work, f"{name}_antiradiance_{bins}.npy")
            report = bake(cli, bgs, out, ["--method", "antiradiance", "--set", f"bins={bins}"])
            record("antiradiance", bins, numpy.load(out), report)
        results["variants"][variant] = rows
    if arguments.json:
        with open(arguments.json, "w") as f:
            json.dump(results, f, indent=1)
        print(f"wrote {arguments.json}")


if __name__ == "__main__":
    main()
