"""Measures the splatting method (issue 17) on the real-scene suite's rooms and writes
docs/splatting.json and the pictures of docs/methods/splatting.md (docs/images/splatting_*):

    /usr/bin/python3 tools/splatting_bench.py [--build build] [--work /tmp/bakegi_splatting]
        [--scenes cornell_box,office,sponza,living_room,bunny_dragon,two_rooms]
        [--pictures cornell_box,office,sponza] [--bake-scenes cornell_box,office]
        [--json docs/splatting.json]

Sections not run (--bake-scenes '' skips the bakes; --scenes names the preview scenes) keep
their numbers from the JSON. With cornell_box among --pictures it also renders the glossy
receivers' picture (docs/images/splatting_glossy.png).

Preview (bakegi preview, 640x480, 256 VPLs, the scene's camera): multiresolution against
full-resolution splatting of the same VPLs (error and time), the discontinuity tests and
neighbour rules of the paper, subsplat counts per level against VPL count and finest
resolution (the shape of its Tables 1-2), the per-VPL refinement of §3.3.1, the upsampling
artifacts of Fig. 7, and frame times (first frame, and with the G-buffer kept as when only
lights move). Bake (bakegi bake): method splatting against the path tracer limited to one
bounce (its own noise from two halves), over VPL count, visibility rays and the near-field
split. Leak: the two-rooms scene, light in room B over light in room A.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep_cornell import ROOT, addon_environment, log  # noqa: E402

LUMINANCE = numpy.array([0.2126, 0.7152, 0.0722])
WIDTH, HEIGHT = 640, 480


def metrics(values, reference):
    """NRMSE and the luminance-weighted relative RMSE (points where r > 1% of mean(r))."""
    y = values[..., :3] @ LUMINANCE
    r = reference[..., :3] @ LUMINANCE
    y, r = y.ravel(), r.ravel()
    mean = r.mean()
    nrmse = float(numpy.sqrt(numpy.mean((y - r) ** 2)) / mean)
    keep = r > 0.01 * mean
    weighted = float(numpy.sqrt(numpy.sum((y[keep] - r[keep]) ** 2 / r[keep]) / numpy.sum(r[keep])))
    return {"nrmse": nrmse, "weighted_relative_rmse": weighted}


def export(work, build, scene):
    bgs = os.path.join(work, scene + ".bgs")
    if not os.path.exists(bgs):
        subprocess.run([sys.executable, os.path.join(ROOT, "tools", "export_scene.py"), "--scene",
                        scene, "--out", bgs, "--build", build], check=True,
                       stdout=subprocess.DEVNULL)
    return bgs


CAMERA_SCRIPT = """
import bpy, json, sys
from bakegi.preview.camera import scene_camera_values
print("CAMERA" + json.dumps(scene_camera_values(bpy.context.scene.camera, %d, %d)))
""" % (WIDTH, HEIGHT)


def scene_camera(work, build, scene):
    blend = os.path.join(work, scene + ".blend")
    script = os.path.join(work, "camera.py")
    with open(script, "w") as f:
        f.write(CAMERA_SCRIPT)
    env = addon_environment(work, build)
    out = subprocess.run(["blender", "-b", blend, "--python-expr",
                          "import addon_utils; addon_utils.enable('bakegi')", "--python", script],
                         check=True, capture_output=True, text=True, env=env).stdout
    line = next(li for li in out.splitlines() if li.startswith("CAMERA"))
    return json.loads(line[len("CAMERA"):])


class Previewer:
    def __init__(self, cli, bgs, camera, work):
        self.cli, self.bgs, self.work = cli, bgs, work
        self.camera = ",".join(f"{v:.7g}" for v in camera)

    def frame(self, settings, repeat=11, layers=("indirect",)):
        """(reports of each frame, arrays by layer) of `repeat` frames with these settings."""
        args = [self.cli, "preview", self.bgs, "--camera", self.camera, "--width", str(WIDTH),
                "--height", str(HEIGHT), "--repeat", str(repeat)]
        paths = {}
        for layer in layers:
            paths[layer] = os.path.join(self.work, f"frame_{layer}.npy")
            args += ["--" + ("out" if layer == "rgba" else layer), paths[layer]]
        for key, value in settings.items():
            args += ["--set", f"{key}={value}"]
        out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
        reports = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
        return reports, {layer: numpy.load(path) for layer, path in paths.items()}


def splat_seconds(report):
    s = report["seconds"]
    return s["mipmap"] + s["refine"] + s["render"] + s["upsample"]


def fastest(reports, key=splat_seconds):
    return min(key(r) for r in reports[1:] or reports)  # the first frame traces the G-buffer


def preview_scene(cli, work, build, scene, images):
    log(f"preview {scene}")
    bgs = export(work, build, scene)
    previewer = Previewer(cli, bgs, scene_camera(work, build, scene), work)
    base = {"direct_samples": 0}
    full_reports, full = previewer.frame(dict(base, refinement="none"))
    reference = full["indirect"]
    result = {"full_resolution": {"subsplats": full_reports[-1]["subsplats"],
                                  "splat_seconds": fastest(full_reports),
                                  "render_seconds": fastest(full_reports,
                                                            lambda r: r["seconds"]["render"])}}
    variants = {
        "default (range, curvature, no neighbours, light)": {},
        "components, diagonal (the bake's)": {"normal_test": "components",
                                              "normal_threshold": 0.5,
                                              "refine_neighbours": "diagonal"},
        "diagonal neighbours": {"refine_neighbours": "diagonal"},
        "all neighbours": {"refine_neighbours": "all"},
        "no light test": {"light_threshold": 0},
        "depth derivative": {"depth_test": "derivative", "depth_threshold": 0.02},
        "depth threshold 0.1": {"depth_threshold": 0.1},
        "upsampling nearest": {"upsampling": "nearest"},
        "upsampling bilinear": {"upsampling": "bilinear"},
        "per-VPL illumination refinement (3.3.1)": {"refinement": "illumination"},
    }
    rows = {}
    for name, settings in variants.items():
        reports, arrays = previewer.frame(dict(base, **settings), layers=("indirect", "levels"))
        seconds = fastest(reports)
        # Relit frames keep the mipmap; a moved camera rebuilds it (the first frame's).
        rebuilt = seconds + reports[0]["seconds"]["mipmap"]
        rows[name] = dict(metrics(arrays["indirect"], reference),
                          subsplats=reports[-1]["subsplats"],
                          subsplats_per_level=reports[-1]["subsplats_per_level"],
                          splat_seconds=seconds,
                          speedup=result["full_resolution"]["splat_seconds"] / seconds,
                          speedup_mipmap_rebuilt=result["full_resolution"]["splat_seconds"] /
                          rebuilt)
        if name.startswith("default"):
            images["levels"] = arrays["levels"]
            images["indirect"] = arrays["indirect"]
        if name.startswith("upsampling"):
            images[name] = arrays["indirect"]
    images["full"] = reference
    result["variants"] = rows

    # Tables 1-2: subsplats and time over VPL count and finest resolution.
    table = []
    for vpls in (64, 256, 1024):
        for finest in (128, 256, 512, 0):
            reports, _ = previewer.frame(dict(base, vpl_count=vpls, max_resolution=finest),
                                         repeat=2)
            table.append({"vpls": reports[-1]["vpls"], "max_resolution": finest or WIDTH,
                          "subsplats": reports[-1]["subsplats"],
                          "splat_seconds": fastest(reports)})
    result["counts"] = table

    # Frames as the user sees them: direct light and the bounce, first frame and relit ones.
    reports, arrays = previewer.frame({}, repeat=6, layers=("rgba",))
    images["frame"] = arrays["rgba"]
    relit = sorted(r["seconds"]["total"] for r in reports[1:])
    result["frame"] = {"first_seconds": reports[0]["seconds"]["total"],
                       "relit_median_seconds": relit[len(relit) // 2],
                       "relit_steps": reports[-1]["seconds"], "vpls": reports[-1]["vpls"]}
    reports, _ = previewer.frame({"visibility_clusters": 16}, repeat=4, layers=("rgba",))
    relit = sorted(r["seconds"]["total"] for r in reports[1:])
    result["frame_visibility_16"] = {"relit_median_seconds": relit[len(relit) // 2]}
    return result


METAL_SCRIPT = """
import sys, bpy
sys.path.insert(0, %r)
import cornell_box
bpy.ops.wm.read_factory_settings(use_empty=True)
cornell_box.build_cornell_box(cornell_box.DEFAULT_SUBDIVISIONS, cornell_box.LIGHT_POWER,
                              surface="PRINCIPLED_METAL")
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1])
""" % os.path.join(ROOT, "scenes")


def glossy_preview(cli, work, build, folder):
    """Glossy receivers: the Cornell box with Principled BSDFs (their coats fold into the
    albedo) and the tall box a rough metal (its lobe gathered at every pixel it covers),
    against the box of Diffuse BSDFs, from the same camera; frame times as in the frame rows."""
    log("glossy preview")
    blend = os.path.join(work, "cornell_metal.blend")
    bgs = os.path.join(work, "cornell_metal.bgs")
    if not os.path.exists(bgs):
        script = os.path.join(work, "cornell_metal.py")
        with open(script, "w") as f:
            f.write(METAL_SCRIPT)
        subprocess.run(["blender", "-b", "--factory-startup", "--python", script, "--", blend],
                       check=True, stdout=subprocess.DEVNULL)
        expression = (f"import bakegi; bakegi.export_scene_file({bgs!r}, target='CORNER', "
                      "objects='VISIBLE')")
        subprocess.run(["blender", "-b", blend, "--addons", "bakegi", "--python-exit-code", "1",
                        "--python-expr", expression], check=True, stdout=subprocess.DEVNULL,
                       env=addon_environment(work, build))
    camera = scene_camera(work, build, "cornell_box")
    result, frames = {}, {}
    for name, scene_file in (("diffuse", export(work, build, "cornell_box")), ("metal", bgs)):
        reports, arrays = Previewer(cli, scene_file, camera, work).frame({}, repeat=6,
                                                                         layers=("rgba",))
        relit = sorted(r["seconds"]["total"] for r in reports[1:])
        result[name] = {"relit_median_seconds": relit[len(relit) // 2],
                        "glossy_pixels": reports[-1]["glossy_pixels"],
                        "glossy_seconds": sorted(r["seconds"]["glossy"]
                                                 for r in reports[1:])[len(relit) // 2]}
        frames[name] = arrays["rgba"]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scale = numpy.percentile(frames["diffuse"][..., :3], 99.5)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    titles = {"diffuse": "Diffuse BSDFs",
              "metal": "Principled BSDFs, the tall box a rough metal (lobe per pixel)"}
    for axis, (name, frame) in zip(axes, frames.items()):
        axis.imshow(numpy.clip((frame[..., :3] / scale) ** (1 / 2.2), 0, 1))
        axis.set_title(f"{titles[name]}: {1000 * result[name]['relit_median_seconds']:.0f} ms")
        axis.axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "splatting_glossy.png"), dpi=60, bbox_inches="tight")
    plt.close(fig)
    return result


def bake(cli, bgs, out, arguments):
    start = time.perf_counter()
    completed = subprocess.run([cli, "bake", bgs, "--out", out] + arguments, check=True,
                               capture_output=True, text=True)
    seconds = time.perf_counter() - start
    return json.loads(completed.stdout), seconds, numpy.load(out)


def bake_scene(cli, work, build, scene, samples):
    log(f"bake {scene}")
    bgs = export(work, build, scene)
    halves = []
    for seed in (0, 1):
        _, seconds, values = bake(cli, bgs, os.path.join(work, f"ref{seed}.npy"),
                                  ["--method", "pathtrace", "--samples", str(samples // 2),
                                   "--seed", str(seed), "--set", "max_bounces=1",
                                   "--set", "error_probes=0"])
        halves.append(values)
    reference = (halves[0] + halves[1]) / 2
    noise = metrics(halves[0], halves[1])
    noise = {k: v / 2 for k, v in noise.items()}  # of the mean of the two halves
    rows = []
    for vpls in (256, 1024, 4096):
        for clusters in (0, 16, 64):
            for gather in (0, 32):
                arguments = ["--method", "splatting", "--set", f"vpl_count={vpls}", "--set",
                             f"visibility_clusters={clusters}", "--set",
                             f"gather_rays={gather}", "--set", "error_probes=0"]
                report, seconds, values = bake(cli, bgs, os.path.join(work, "splat.npy"),
                                               arguments)
                rows.append(dict(metrics(values, reference), vpls=vpls,
                                 visibility_clusters=clusters, gather_rays=gather,
                                 process_seconds=seconds,
                                 core_seconds=report["seconds"]["total"],
                                 steps=report["seconds"]))
    # The one-bounce path tracer's own curve, for the chart.
    traced = []
    for spp in (1, 4, 16, 64):
        report, seconds, values = bake(cli, bgs, os.path.join(work, "traced.npy"),
                                       ["--method", "pathtrace", "--samples", str(spp), "--seed",
                                        "7", "--set", "max_bounces=1", "--set", "error_probes=0"])
        traced.append(dict(metrics(values, reference), samples=spp,
                           core_seconds=report["seconds"]["total"]))
    return {"reference": {"method": "pathtrace", "max_bounces": 1, "samples": samples,
                          "noise": noise}, "runs": rows, "pathtrace_one_bounce": traced}


def save_bake_chart(bakes, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(bakes), figsize=(6 * len(bakes), 4.5), squeeze=False)
    for axis, (scene, result) in zip(axes[0], bakes.items()):
        traced = result["pathtrace_one_bounce"]
        axis.plot([t["core_seconds"] for t in traced], [t["weighted_relative_rmse"] for t in traced],
                  "o-", color="black", label="path tracer, 1 bounce (1-64 spp)")
        for clusters, colour in ((0, "tab:red"), (16, "tab:orange"), (64, "tab:green")):
            for gather, marker in ((0, "o"), (32, "^")):
                runs = [r for r in result["runs"]
                        if r["visibility_clusters"] == clusters and r["gather_rays"] == gather]
                axis.scatter([r["core_seconds"] for r in runs],
                             [r["weighted_relative_rmse"] for r in runs], color=colour,
                             marker=marker,
                             label=f"splatting, {clusters} visibility, {gather} gather rays")
        noise = result["reference"]["noise"]["weighted_relative_rmse"]
        axis.axhline(noise, color="grey", linestyle=":", label="reference noise")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("core seconds (2 cores)")
        axis.set_ylabel("weighted relative RMSE vs 1-bounce reference")
        axis.set_title(scene)
        axis.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=70)
    plt.close(fig)


def leak(cli, work, build):
    log("two rooms")
    bgs = export(work, build, "two_rooms")
    with open(os.path.join(work, "two_rooms_objects.json")) as f:
        objects = json.load(f)["objects"]
    names = numpy.concatenate([[o["name"]] * o["corners"] for o in objects]).astype(str)
    room_a, room_b = numpy.char.startswith(names, "RoomA_"), numpy.char.startswith(names, "RoomB_")
    rows = []
    for clusters in (0, 16, 64):
        report, _, values = bake(cli, bgs, os.path.join(work, "leak.npy"),
                                  ["--method", "splatting", "--set",
                                   f"visibility_clusters={clusters}", "--set", "error_probes=0"])
        y = values @ LUMINANCE
        rows.append({"visibility_clusters": clusters,
                     "leakage": float(y[room_b].mean() / y[room_a].mean()),
                     "core_seconds": report["seconds"]["total"]})
    return rows


def save_pictures(scene, images, folder):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def tone(x):
        y = x[..., :3]
        return numpy.clip((y / max(numpy.percentile(y, 99.5), 1e-12)) ** (1 / 2.2), 0, 1)

    levels = images["levels"].astype(float)
    levels[levels == 255] = numpy.nan
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.2))
    axes[0].imshow(tone(images["frame"]))
    axes[0].set_title("BakeGI Preview: direct + splatted bounce")
    shown = axes[1].imshow(levels, cmap="viridis")
    axes[1].set_title("subsplat level (texels of 2^level px)")
    fig.colorbar(shown, ax=axes[1], fraction=0.035)
    axes[2].imshow(tone(images["indirect"]))
    axes[2].set_title("indirect, multiresolution")
    axes[3].imshow(tone(images["full"]))
    axes[3].set_title("indirect, full resolution")
    for a in axes:
        a.axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, f"splatting_{scene}_refinement.png"), dpi=60)
    plt.close(fig)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    for a, name in zip(axes, ("upsampling nearest", "upsampling bilinear", "indirect")):
        a.imshow(tone(images[name]))
        a.set_title({"indirect": "the paper's upsampling (3.5)"}.get(name, name + " (Fig. 7)"))
        a.axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, f"splatting_{scene}_upsampling.png"), dpi=60)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--work", default="/tmp/bakegi_splatting")
    parser.add_argument("--scenes",
                        default="cornell_box,office,sponza,living_room,bunny_dragon,two_rooms")
    parser.add_argument("--pictures", default="cornell_box,office,sponza")
    parser.add_argument("--bake-scenes", default="cornell_box,office")
    parser.add_argument("--samples", type=int, default=1024)
    parser.add_argument("--json", default=os.path.join(ROOT, "docs", "splatting.json"))
    args = parser.parse_args()
    build = os.path.abspath(args.build)
    cli = os.path.join(build, "bakegi")
    os.makedirs(args.work, exist_ok=True)
    images_folder = os.path.join(ROOT, "docs", "images")
    results = {"preview": {}, "bake": {}}
    if os.path.exists(args.json):
        with open(args.json) as f:
            results = json.load(f)
    results["command"] = "/usr/bin/python3 tools/splatting_bench.py " + " ".join(sys.argv[1:])
    results["machine"] = "2 cores"
    results.setdefault("preview", {})  # the scenes run replace their own entries
    pictures = set(filter(None, args.pictures.split(",")))
    for scene in filter(None, args.scenes.split(",")):
        images = {}
        results["preview"][scene] = preview_scene(cli, args.work, build, scene, images)
        if scene in pictures:
            save_pictures(scene, images, images_folder)
    if "cornell_box" in pictures:
        results["glossy"] = glossy_preview(cli, args.work, build, images_folder)
    baked = list(filter(None, args.bake_scenes.split(",")))
    for scene in baked:
        results["bake"][scene] = bake_scene(cli, args.work, build, scene, args.samples)
    if baked:
        save_bake_chart(results["bake"], os.path.join(ROOT, "docs", "splatting_bake.png"))
    results["leak"] = leak(cli, args.work, build)
    with open(args.json, "w") as f:
        json.dump(results, f, indent=1)
    log(f"wrote {args.json}")


if __name__ == "__main__":
    main()
