"""A picture of each real-scene bake from its scene camera: the scene as the suite built it
(WORK/<scene>/scene.blend, tools/real_scenes.py), baked in Blender with the default method
(antiradiance; the path tracer where it falls back) and rendered by tools/bake_and_render.py
(Cycles, direct light + the baked indirect, what Material Preview shows) into
docs/real_scenes/<scene>.jpg.

    /usr/bin/python3 tools/real_scene_pictures.py [--scenes a,b] [--work /tmp/bakegi_real_scenes]
        [--method antiradiance] [--resolution 320] [--render-samples 16]
"""

import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from real_scenes import SCENES  # noqa: E402
from sweep_cornell import ROOT, addon_environment  # noqa: E402

FOLDER = os.path.join(ROOT, "docs", "real_scenes")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--work", default="/tmp/bakegi_real_scenes")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--method", default="antiradiance")
    parser.add_argument("--resolution", type=int, default=320)
    parser.add_argument("--render-samples", type=int, default=16)
    arguments = parser.parse_args()
    os.makedirs(FOLDER, exist_ok=True)
    for scene in [s for s in arguments.scenes.split(",") if s]:
        folder = os.path.join(arguments.work, scene)
        blend = os.path.join(folder, "scene.blend")
        if not os.path.exists(blend):
            print(f"{scene}: no {blend} (run tools/real_scenes.py first); skipped")
            continue
        png = os.path.join(folder, "picture.png")
        report = os.path.join(folder, "picture_report.json")
        completed = subprocess.run(
            ["blender", "-b", blend, "--addons", "bakegi", "--python", os.path.join(ROOT, "tools", "bake_and_render.py"),
             "--", "--method", arguments.method, "--samples", "64", "--blend", os.path.join(folder, "picture.blend"),
             "--png", png, "--report", report, "--render-samples", str(arguments.render_samples),
             "--resolution", str(arguments.resolution)],
            env=addon_environment(folder, os.path.abspath(arguments.build)), capture_output=True, text=True)
        if completed.returncode != 0 or not os.path.exists(png):
            print(f"{scene}: failed\n{(completed.stdout + completed.stderr)[-800:]}")
            continue
        jpg = os.path.join(FOLDER, f"{scene}.jpg")
        # JPEG keeps the docs small; Blender's own image writer converts.
        subprocess.run(["blender", "-b", "--factory-startup", "--python-expr",
                        f"import bpy; i = bpy.data.images.load({png!r}); s = bpy.context.scene; "
                        f"s.render.image_settings.file_format = 'JPEG'; s.render.image_settings.quality = 85; "
                        f"i.save_render({jpg!r}, scene=s)"], capture_output=True, text=True)
        with open(report) as f:
            used = json.load(f).get("method_used", arguments.method)
        print(f"{scene}: {jpg} (baked by {used})")


if __name__ == "__main__":
    main()
