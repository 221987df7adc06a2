#!/usr/bin/python3
"""Leakage of the meshless method through a shared wall (issue 4), per setting.

Same scenes, masks and metrics as tools/two_rooms_leakage.py (whose functions this imports):
leakage = mean luminance of room B's baked face corners / mean luminance of room A's (room B's
exact indirect light is 0), and room A's relative RMSE against a 256-spp path tracer bake.

    /usr/bin/python3 tools/meshless_two_rooms.py --build build \\
        [--configs ";levels=4 coarse_spacing=0.3 epsilon=0.01"] [--visibility 1,0] \\
        [--work /tmp/bakegi_scenes] [--json out.json]

--configs: ';'-separated lists of space-separated key=value meshless settings ("" = defaults).
The path tracer references (<work>/<scene>_pathtrace.npy) are reused when present.
"""

import argparse
import json
import os
import sys

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from two_rooms_leakage import LUMINANCE, ROOT, VARIANTS, bake, relative_rmse, room_masks, scene_file  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--cli", help="bakegi binary (default <build>/bakegi)")
    parser.add_argument("--configs", default=";levels=4 coarse_spacing=0.3 epsilon=0.01")
    parser.add_argument("--visibility", default="1,0")
    parser.add_argument("--work", default="/tmp/bakegi_scenes")
    parser.add_argument("--json", help="write the results here too")
    arguments = parser.parse_args()
    build = os.path.abspath(arguments.build)
    cli = arguments.cli or os.path.join(build, "bakegi")

    results = {"command": "/usr/bin/python3 tools/meshless_two_rooms.py " + " ".join(sys.argv[1:]), "rows": []}
    print("| wall | settings | visibility | points | links | leakage (B / A) | room A error vs path tracer "
          "| room A mean / PT | precompute s | total s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for variant, (name, extra) in VARIANTS.items():
        bgs, objects = scene_file(arguments.work, build, name, extra)
        room_a, room_b = room_masks(objects)
        reference_path = os.path.join(arguments.work, name + "_pathtrace.npy")
        if not os.path.exists(reference_path):
            bake(cli, bgs, reference_path, ["--method", "pathtrace", "--samples", "256"])
        reference = numpy.load(reference_path)
        reference_a = float((reference[room_a] @ LUMINANCE).mean())
        for config in arguments.configs.split(";"):
            for visibility in arguments.visibility.split(","):
                settings = config.split() + [f"visibility={visibility}"]
                out = os.path.join(arguments.work, f"{name}_meshless_{'_'.join(settings)}.npy")
                set_arguments = [a for s in settings for a in ("--set", s)]
                report = bake(cli, bgs, out, ["--method", "meshless"] + set_arguments)
                values = numpy.load(out)
                a = float((values[room_a] @ LUMINANCE).mean())
                b = float((values[room_b] @ LUMINANCE).mean())
                seconds = report["seconds"]
                precompute = sum(seconds.get(k, 0.0) for k in
                                 ("meshless_placement", "meshless_basis", "meshless_refinement", "meshless_bounces"))
                row = {"wall": variant, "settings": config or "defaults", "visibility": int(visibility),
                       "points": report.get("meshless_points"), "links": report.get("meshless_links"),
                       "coarse_spacing": report.get("meshless_coarse_spacing"),
                       "room_a_mean": a, "room_b_mean": b, "leakage": b / a if a > 0 else None,
                       "room_a_error": relative_rmse(values[room_a], reference[room_a]),
                       "room_a_over_pathtrace": a / reference_a, "precompute_seconds": precompute,
                       "seconds": seconds["total"], "warnings": report.get("warnings", [])}
                results["rows"].append(row)
                leak = f"{row['leakage'] * 100:.2f}%" if row["leakage"] is not None else "n/a"
                print(f"| {variant} | {row['settings']} | {visibility} | {row['points']:,} | {row['links']:,} "
                      f"| {leak} | {row['room_a_error'] * 100:.1f}% | {row['room_a_over_pathtrace']:.3f} "
                      f"| {precompute:.1f} | {row['seconds']:.1f} |", flush=True)
    if arguments.json:
        with open(arguments.json, "w") as f:
            json.dump(results, f, indent=1)
        print(f"wrote {arguments.json}")


if __name__ == "__main__":
    main()
