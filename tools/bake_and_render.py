"""Bakes the open .blend with bakegi, saves it, renders a PNG that shows the bake, and
prints time and size figures. Run inside Blender:
    blender -b scene.blend --python tools/bake_and_render.py -- [--method M --samples N] \
        --blend baked.blend --png baked.png --report report.json
Without --method it makes bakegi's default bake (bakegi.bake() with no method: the path
tracer to a 5% target error through its denoiser).
The PNG is a Cycles render with direct light only (max bounces 0) plus the emission that
the bakegi material hook adds (base color x baked indirect, camera rays only), i.e.
albedo x (direct + baked indirect): what Material Preview shows, rendered offline.
"""
import argparse
import json
import os
import sys
import time

import bpy


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--samples", type=int, default=None)
    parser.add_argument("--method", default=None)
    parser.add_argument("--blend", required=True)
    parser.add_argument("--png", required=True)
    parser.add_argument("--report", required=True)
    parser.add_argument("--render-samples", type=int, default=64)
    parser.add_argument("--resolution", type=int, default=512)
    return parser.parse_args(argv)


def render_png(path, samples, resolution):
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    cycles = scene.cycles
    cycles.device = 'CPU'
    cycles.samples = samples
    cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
    cycles.use_adaptive_sampling = False
    cycles.max_bounces = 0        # direct light only: the indirect comes from the bake
    scene.render.resolution_x = resolution
    scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = 'PNG'
    scene.render.filepath = os.path.abspath(path)
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return time.perf_counter() - start


def main():
    args = parse_args()
    import bakegi

    start = time.perf_counter()
    report = bakegi.bake(method=args.method, samples=args.samples, target='CORNER',
                         objects='VISIBLE')
    bake_wall = time.perf_counter() - start

    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.blend))
    render_seconds = render_png(args.png, args.render_samples, args.resolution)

    report["wall_seconds_in_blender"] = bake_wall
    report["render_seconds"] = render_seconds
    with open(args.report, "w") as f:
        json.dump(report, f, indent=2)

    seconds = report.get("seconds", {})
    settings = report.get("settings", {})
    if report.get("method") != "pathtrace":
        how = ""
    elif settings.get("target_error"):
        how = " to a %g%% target%s, %d paths," % (
            100 * settings["target_error"], " through the denoiser" if settings.get("denoise") else "",
            report.get("samples", 0))
    else:
        how = " %s samples per point," % settings.get("samples")
    print("bakegi bake: method %s,%s %d bake points, %d triangles"
          % (report.get("method"), how, report.get("bake_points", 0),
             report.get("triangles", 0)))
    for stage in sorted(seconds):
        print("  %-22s %8.3f s" % (stage, seconds[stage]))
    print("  %-22s %8.3f s" % ("bake (wall, Blender)", bake_wall))
    rays = report.get("rays", 0)
    solve = seconds.get("evaluate", 0.0) + seconds.get("solve", 0.0)
    if rays and solve > 0:
        print("  %-22s %8.2f Mrays/s (%d rays)" % ("ray throughput", rays / solve / 1e6, rays))
    print("  %-22s %8.1f MiB" % ("core memory", report.get("memory_bytes", 0) / 2**20))
    if report.get("estimated_error") is not None:
        print("  %-22s %8.2f %% (the bake's own check against the path tracer)"
              % ("estimated error", 100 * report["estimated_error"]))
    print("  %-22s %8.3f s (Cycles, direct + baked indirect)" % ("render", render_seconds))
    print("  %-22s %8.1f KiB  %s" % ("baked .blend", os.path.getsize(args.blend) / 1024, args.blend))
    print("  %-22s %8.1f KiB  %s" % ("PNG", os.path.getsize(args.png) / 1024, args.png))
    for warning in report.get("warnings", []):
        print("  warning: %s" % warning)


try:
    main()
except Exception as error:  # report and fail the process so the shell script stops
    print("bakegi error: %s" % error)
    sys.exit(1)
