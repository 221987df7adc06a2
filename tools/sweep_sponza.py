#!/usr/bin/python3
"""Speed versus accuracy on Crytek Sponza (262,087 triangles, one spot light): bakegi's path
tracer and the meshless method's two curves (precompute + first solve, relight alone), against
a converged path-traced reference. Issue 4's Sponza benchmark.

    /usr/bin/python3 tools/sweep_sponza.py --build build [--work /tmp/bakegi_sponza] [--docs]

Needs ../shared/scenes/crytek-sponza (or $BAKEGI_SPONZA), Blender on PATH, the built CLI.
Not part of the test suite: about 25 minutes on 2 cores, most of it the reference. Steps, all
in --work:
 1. scenes/sponza.py builds sponza.blend; the add-on exports it with its 80,957 vertices as bake
    points (tools/export_scene.py --target POINT);
 2. the reference: two independent halves of --reference-samples / 2 paths per vertex; its
    own noise is half the error between the halves (as tools/sweep_cornell.py);
 3. `bakegi sweep` of the path tracer;
 4. meshless at each --meshless-settings configuration with the importance particles leaving
    the scene camera (CameraMain, the paper's valid viewpoint): `bakegi relight --move 0,0,0`
    gives the full bake's and the relight's times and the result;
 5. writes sponza_sweep.json and sponza_speed_accuracy.png (docs/ with --docs).
"""

import argparse
import datetime
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_cornell import (DOCS, ROOT, compare, log, machine, make_reference, meshless_sweep,  # noqa: E402
                           parse_setting_list, pathtrace_sweep, run)

# CameraMain's position in scenes/sponza.py's import (Blender Z-up).
CAMERA_MAIN = "15.465,-0.452,4.388"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--work", default="/tmp/bakegi_sponza")
    parser.add_argument("--reference-samples", type=int, default=2048)
    parser.add_argument("--reference-chunk", type=int, default=1024)
    parser.add_argument("--pathtrace-samples", default="1,4,16,64,256")
    parser.add_argument("--meshless-settings", default="levels=3;levels=4",
                        help="meshless configurations (';' between runs, ',' between key=value)")
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--docs", action="store_true", help="write into docs/")
    arguments = parser.parse_args()

    build = os.path.abspath(arguments.build)
    work = os.path.abspath(arguments.work)
    cli = os.path.join(build, "bakegi")
    os.makedirs(work, exist_ok=True)
    started = time.perf_counter()
    bgs = os.path.join(work, "sponza.bgs")
    if not os.path.exists(bgs):
        run([sys.executable, os.path.join(ROOT, "tools", "export_scene.py"), "--scene", "sponza", "--out", bgs,
             "--build", build, "--target", "POINT"])
    reference = os.path.join(work, "reference.npy")
    reference_info_path = os.path.join(work, "reference.json")
    if os.path.exists(reference) and os.path.exists(reference_info_path):
        log("reusing the reference")
        with open(reference_info_path) as f:
            reference_info = json.load(f)
    else:
        reference, reference_info = make_reference(cli, bgs, work, arguments.reference_samples,
                                                   arguments.reference_chunk, arguments.threads)
        with open(reference_info_path, "w") as f:
            json.dump(reference_info, f, indent=1)

    load_before = os.getloadavg()
    pathtrace = pathtrace_sweep(cli, bgs, reference, work, [int(s) for s in arguments.pathtrace_samples.split(",")],
                                arguments.threads, arguments.repeat)
    meshless, relit = meshless_sweep(cli, bgs, reference, work, parse_setting_list(arguments.meshless_settings),
                                     arguments.threads, arguments.repeat, {"viewpoint": CAMERA_MAIN})
    sweep = {
        "title": "Crytek Sponza (262k triangles, spot light, 80,957 vertices): time vs error",
        "subtitle": f"reference {reference_info['samples']} paths per vertex, its noise ≈ {reference_info['noise']:.3f}; "
                    "meshless points from CameraMain",
        "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "machine": machine(),
        "load_average_before": load_before,
        "load_average_after": os.getloadavg(),
        "command": "/usr/bin/python3 tools/sweep_sponza.py " + " ".join(sys.argv[1:]),
        "reference": reference_info,
        "reference_noise": reference_info["noise"],
        "methods": {"pathtrace": pathtrace, "meshless": meshless, "meshless_relight": relit},
    }
    folder = DOCS if arguments.docs else work
    sweep_json = os.path.join(folder, "sponza_sweep.json")
    chart = os.path.join(folder, "sponza_speed_accuracy.png")
    with open(sweep_json, "w") as f:
        json.dump(sweep, f, indent=1)
    subprocess.run([sys.executable, os.path.join(ROOT, "tools", "plot_sweep.py"), sweep_json, "--out", chart],
                   check=True)
    for r in pathtrace:
        print(f"pathtrace {r['settings']['samples']:>5} samples: {r['seconds']:8.2f} s  error {r['error']:.4f}")
    for r in meshless:
        print(f"meshless {r['label']:>10}: full {r['seconds']:8.2f} s, relight {r['relight_seconds'] * 1000:7.1f} ms "
              f"(core {r['relight_solve_seconds'] * 1000:.1f} ms)  error {r['error']:.4f}")
    log(f"wrote {sweep_json} and {chart} in {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
