"""Builds one of the scenes in scenes/ and exports it, with its face corners (or vertices,
--target POINT) as bake points,
to a .bgs scene file for the CLI (benchmarks, convergence studies, leakage tables).

    /usr/bin/python3 tools/export_scene.py --scene office --out /tmp/office.bgs [--build build]
        [--target CORNER|POINT|LIGHTMAP] [--texels-per-meter T] [-- extra arguments for the scene script, e.g. --zero-thickness]

Writes next to the .bgs: <name>.blend (the built scene) and <name>_objects.json (the baked
objects' names in export order, and the corner count of each, so CLI results can be split
per object).
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_cornell import ROOT, addon_environment, run  # noqa: E402


def main():
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True, help="a script name in scenes/ (without .py)")
    parser.add_argument("--out", required=True, help="the .bgs file to write")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"), help="build directory with libbakegi.so")
    parser.add_argument("--target", default="CORNER", choices=("CORNER", "POINT", "LIGHTMAP"),
                        help="bake points: face corners (default), vertices, or lightmap texels "
                             "(also writes the layout, <out without .bgs>.bgl)")
    parser.add_argument("--texels-per-meter", type=float, default=40.0,
                        help="lightmap density for --target LIGHTMAP")
    args = parser.parse_args(argv)

    out = os.path.abspath(args.out)
    work = os.path.dirname(out)
    os.makedirs(work, exist_ok=True)
    stem = os.path.splitext(out)[0]
    blend = stem + ".blend"
    script = os.path.join(ROOT, "scenes", args.scene + ".py")
    if not os.path.isfile(script):
        sys.exit(f"no scene script {script}")
    run(["blender", "-b", "--factory-startup", "--python", script, "--", "--out", blend] + extra)

    info = stem + "_objects.json"
    expression = (
        "import bpy, bakegi, json; from bakegi.export import targets as export; "
        f"r = bakegi.export_scene_file({out!r}, target={args.target!r}, objects='VISIBLE', "
        f"texels_per_meter={args.texels_per_meter!r}); "
        "objs = export.resolve_targets(bpy.context, 'VISIBLE')[0]; "
        f"info = [{{'name': o.name, 'corners': len(o.data.loops), 'vertices': len(o.data.vertices)}} for o in objs]; "
        f"json.dump({{'objects': info, 'export': r}}, open({info!r}, 'w'), default=str)"
    )
    run(["blender", "-b", blend, "--addons", "bakegi", "--python-exit-code", "1", "--python-expr", expression],
        env=addon_environment(work, os.path.abspath(args.build)))
    print(f"wrote {out} and {info}")


if __name__ == "__main__":
    main()
