"""Bakes lightmaps into a saved scene in a real Blender window and screenshots Material
Preview through the scene camera: the pictures and numbers of docs/lightmaps.md.

    blender -b --factory-startup --python scenes/cornell_box.py -- --out /tmp/cornell.blend
    xvfb-run -a -s "-screen 0 1280x900x24" blender --factory-startup -p 0 0 1200 860 \\
        /tmp/cornell.blend --python tools/lightmap_screenshot.py -- \\
        --texels-per-meter 40 --png docs/images/lightmap_cornell.png \\
        --atlas-png docs/images/lightmap_cornell_atlas.png --json docs/lightmap_cornell.json

The add-on must be importable (BLENDER_USER_SCRIPTS, as tools/bake_cornell.sh sets it) and
BAKEGI_LIBRARY must point at libbakegi.so. Writes the JSON report of the bake (atlas size,
texels baked and rejected, seconds per stage) and quits Blender.
"""

import argparse
import json
import os
import sys
import time
import traceback

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--texels-per-meter", type=float, default=40.0)
    parser.add_argument("--max-size", type=int, default=1024)
    parser.add_argument("--method", default="antiradiance")
    parser.add_argument("--samples", type=int, default=64, help="pathtrace: paths per texel sample")
    parser.add_argument("--uv-method", default="SMART")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a core setting of the method, e.g. bins=108")
    parser.add_argument("--exposure", type=float, default=None, help="view exposure (stops)")
    parser.add_argument("--target", default="LIGHTMAP", choices=("LIGHTMAP", "CORNER"),
                        help="CORNER: the color attribute instead, for comparison")
    parser.add_argument("--png", required=True, help="the viewport screenshot")
    parser.add_argument("--atlas-png", default=None, help="the atlas, tone-mapped, as PNG")
    parser.add_argument("--json", required=True)
    return parser.parse_args(argv)


def method_settings(pairs):
    settings = {}
    for pair in pairs:
        key, value = pair.split("=", 1)
        for kind in (int, float):
            try:
                settings[key] = kind(value)
                break
            except ValueError:
                continue
        else:
            settings[key] = value
    return settings


class Screenshot:
    def __init__(self, args):
        self.args = args
        self.steps = self.run()

    def tick(self):
        try:
            return next(self.steps)
        except StopIteration:
            pass
        except Exception:
            traceback.print_exc()
            sys.stdout.flush()
            os._exit(1)
        sys.stdout.flush()
        os._exit(0)

    def viewport(self):
        window = bpy.context.window_manager.windows[0]
        area = max((a for a in window.screen.areas if a.type == "VIEW_3D"),
                   key=lambda a: a.width * a.height)
        return window, area, next(r for r in area.regions if r.type == "WINDOW")

    def screenshot(self, path):
        with bpy.context.temp_override(window=self.window, area=self.area):
            bpy.ops.screen.screenshot_area(filepath=path)

    def wait_for_shaders(self):
        for _ in range(900):
            yield 1.0
            if not bpy.app.is_job_running("SHADER_COMPILATION"):
                break
        yield 3.0  # EEVEE's temporal samples

    def run(self):
        import addon_utils
        addon_utils.enable("bakegi", default_set=True)
        import bakegi

        args = self.args
        scene = bpy.context.scene
        if args.exposure is not None:
            scene.view_settings.exposure = args.exposure
        yield 0.5
        start = time.perf_counter()
        report = bakegi.bake(method=args.method, samples=args.samples, target=args.target,
                             objects="VISIBLE",
                             texels_per_meter=args.texels_per_meter,
                             lightmap_max_size=args.max_size, lightmap_uv_method=args.uv_method,
                             method_settings=method_settings(args.set))
        wall = time.perf_counter() - start
        lm = report.get("lightmap") or {"width": 0, "height": 0, "covered_texels": 0,
                                        "rejected_samples": 0, "image": "", "uv_maps_created": []}
        print(f"lightmap: {lm['width']} x {lm['height']} atlas, {lm['covered_texels']:,} texels "
              f"baked, {report['bake_points']:,} samples, {lm['rejected_samples']:,} rejected; "
              f"bake call {wall:.1f} s")

        self.window, self.area, self.region = self.viewport()
        space = self.area.spaces.active
        space.shading.type = "MATERIAL"
        space.shading.use_scene_lights = True
        space.shading.use_scene_world = True
        space.overlay.show_overlays = False
        space.show_gizmo = False
        for region in ("toolbar", "header", "ui", "tool_header"):
            setattr(space, f"show_region_{region}", False)
        if scene.camera is not None:
            space.region_3d.view_perspective = "CAMERA"
            with bpy.context.temp_override(window=self.window, area=self.area,
                                           region=self.region):
                bpy.ops.view3d.view_center_camera()
        scene.eevee.taa_samples = 16
        yield from self.wait_for_shaders()
        os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
        self.screenshot(os.path.abspath(args.png))
        if args.atlas_png and lm["image"]:
            save_atlas_png(bpy.data.images[lm["image"]], os.path.abspath(args.atlas_png))

        record = {
            "command": " ".join(sys.argv),
            "blend": bpy.data.filepath,
            "method": args.method,
            "method_settings": method_settings(args.set),
            "texels_per_meter": args.texels_per_meter,
            "objects": len(report["objects"]),
            "triangles": report["counts"].get("triangles"),
            "bake_call_seconds": round(wall, 3),
            "seconds": {k: round(v, 3) for k, v in report["seconds"].items()
                        if isinstance(v, (int, float))},
            "samples": report["bake_points"],
            "lightmap": {k: v for k, v in lm.items() if k not in ("path", "uv_maps_created")},
            "uv_maps_created": len(lm["uv_maps_created"]),
            "warnings": report["warnings"][:20],
        }
        with open(args.json, "w") as f:
            json.dump(record, f, indent=1)
        print(json.dumps(record["seconds"]))


def save_atlas_png(image, path):
    """The atlas tone-mapped for a picture: x / (1 + x) after scaling its 99th percentile
    to 1, so that the layout and the light in it are both visible."""
    import numpy
    width, height = image.size
    pixels = numpy.empty(width * height * 4, numpy.float32)
    image.pixels.foreach_get(pixels)
    rgb = pixels.reshape(-1, 4)[:, :3]
    lit = rgb[rgb.max(axis=1) > 0]
    scale = 1.0 / max(float(numpy.percentile(lit, 99)) if lit.size else 1.0, 1e-6)
    mapped = rgb * scale
    mapped = (mapped / (1.0 + mapped)) * 2.0
    out = bpy.data.images.new("BakeGI_atlas_preview", width, height, alpha=False)
    rgba = numpy.ones((width * height, 4), numpy.float32)
    rgba[:, :3] = numpy.clip(mapped, 0.0, 1.0) ** (1.0 / 2.2)
    out.pixels.foreach_set(rgba.reshape(-1))
    out.filepath_raw = path
    out.file_format = "PNG"
    out.save()


job = Screenshot(arguments())
bpy.app.timers.register(job.tick, first_interval=1.0)
