"""Draws docs/images/architecture.png: the rooms of bakegi and the flow of one bake.

    /usr/bin/python3 tools/architecture_diagram.py [--out docs/images/architecture.png]

Left column: the add-on (Python, in Blender); middle: the C API and the bake job; right: the
core's rooms that a job uses. Arrows follow one bake from the user's click to the written
result. The boxes name the folders and files, so the picture is checked against the tree:
every path drawn must exist (the script fails otherwise).
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (key, x, y, width, height, title, paths shown (relative to the repository), colour)
ADDON = "#dbe9f6"
BOUNDARY = "#fde2c7"
CORE = "#e3f1de"
SHARED = "#eeeeee"
BOXES = [
    ("ui", 0.2, 8.6, 3.6, 1.1, "UI: Bake Indirect, panel, scripting",
     ["addon/bakegi/ui/", "addon/bakegi/api.py"], ADDON),
    ("export", 0.2, 6.9, 3.6, 1.4, "export: targets, scene, materials, lights",
     ["addon/bakegi/export/", "addon/bakegi/light_units.py"],
     ADDON),
    ("session", 0.2, 5.4, 3.6, 1.2, "session: one bake, progress, Esc",
     ["addon/bakegi/session.py", "addon/bakegi/native.py"], ADDON),
    ("write", 0.2, 3.6, 3.6, 1.5, "write back: attributes, lightmap image, hook",
     ["addon/bakegi/write/"],
     ADDON),
    ("capi", 4.6, 6.9, 3.4, 1.4, "C API (never throws)",
     ["native/include/bakegi/bakegi.h", "native/src/api/"], BOUNDARY),
    ("job", 4.6, 4.6, 3.4, 2.0, "bake job: check settings, build\nthe scene and BVH, solve (or hand\nto the path tracer), estimate its\nown error, report",
     ["native/src/bake/"], BOUNDARY),
    ("cli", 4.6, 2.8, 3.4, 1.3, "command line: calls bakegi.h\nas the add-on does",
     ["native/cli/", "native/common/"], SHARED),
    ("settings", 8.8, 8.6, 3.9, 1.1, "settings: one schema per method",
     ["native/src/settings/", "docs/settings.md"], CORE),
    ("scene", 8.8, 7.1, 3.9, 1.2, "scene: meshes, materials, bake points, ray tracer",
     ["native/src/scene/"], CORE),
    ("lights", 8.8, 5.9, 3.9, 0.9, "lights: direct light of every light type",
     ["native/src/lights/"], CORE),
    ("solvers", 8.8, 3.9, 3.9, 1.7, "solvers -> an indirect field",
     ["native/src/solvers/method_registry.cpp", "native/src/solvers/pathtrace/",
      "native/src/solvers/antiradiance/", "native/src/solvers/meshless/"], CORE),
    ("lightmap", 8.8, 2.3, 3.9, 1.3, "lightmap: texels, rejection, seams, padding, EXR",
     ["native/src/lightmap/"], CORE),
]

# (from, to, label) in the order of one bake
ARROWS = [
    ("ui", "export", "1 targets"),
    ("export", "session", "2 scene + points"),
    ("session", "capi", "3 ctypes"),
    ("capi", "job", "4 start"),
    ("job", "settings", "5 check"),
    ("job", "scene", "6 build + BVH"),
    ("job", "lights", "7 direct light"),
    ("job", "solvers", "8 solve"),
    ("job", "lightmap", "texels"),
    ("job", "session", "9 result, report"),
    ("session", "write", "10 write"),
]


def check_paths():
    missing = [p for *_, paths, _ in BOXES for p in paths if not os.path.exists(os.path.join(ROOT, p))]
    if missing:
        sys.exit("architecture_diagram: paths drawn but not in the tree: " + ", ".join(missing))


def draw(out):
    check_paths()
    fig, ax = plt.subplots(figsize=(13, 8.2))
    ax.set_xlim(0, 12.9)
    ax.set_ylim(2.0, 10.0)
    ax.axis("off")
    centres = {}
    for key, x, y, w, h, title, paths, colour in BOXES:
        ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.04", fc=colour, ec="#555555"))
        ax.text(x + 0.1, y + h - 0.12, title, va="top", fontsize=9.5, weight="bold", wrap=True)
        for i, p in enumerate(paths):
            ax.text(x + 0.12, y + h - 0.22 - 0.26 * (title.count("\n") + 1) - 0.26 * i, p, va="top", fontsize=8, family="monospace",
                    color="#333333")
        centres[key] = (x, y, w, h)

    def anchor(key, towards):
        x, y, w, h = centres[key]
        tx, ty, tw, th = centres[towards]
        cx, cy, tcx, tcy = x + w / 2, y + h / 2, tx + tw / 2, ty + th / 2
        if abs(tcx - cx) > (w + tw) / 2:  # side by side: leave from the facing side
            return (x + w if tcx > cx else x, min(max(tcy, y + 0.15), y + h - 0.15))
        return (cx, y if tcy < cy else y + h)

    for a, b, label in ARROWS:
        start, end = anchor(a, b), anchor(b, a)
        ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=12, color="#335577",
                                     lw=1.3, connectionstyle="arc3,rad=0.0"))
        if label:
            ax.text((start[0] + end[0]) / 2, (start[1] + end[1]) / 2 + 0.08, label, fontsize=8,
                    color="#224466", ha="center", bbox=dict(fc="white", ec="none", pad=0.5, alpha=0.85))
    ax.text(0.2, 9.9, "add-on (Python, in Blender)", fontsize=11, weight="bold", color="#2a5d8a")
    ax.text(4.6, 9.9, "boundary and job", fontsize=11, weight="bold", color="#a0571c")
    ax.text(8.8, 9.9, "core rooms (C++, native/src)", fontsize=11, weight="bold", color="#3c7a2a")
    fig.tight_layout()
    os.makedirs(os.path.dirname(out), exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"architecture_diagram: wrote {out}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "images", "architecture.png"))
    draw(parser.parse_args().out)


if __name__ == "__main__":
    main()
