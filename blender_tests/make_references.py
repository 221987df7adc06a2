"""Make the Cycles references that the in-Blender tests compare bakegi against.

    blender -b --factory-startup --python blender_tests/make_references.py -- \
        [--only cornell|principled|lights|textured] [--kinds WORLD_IMAGE ...] \
        [--cornell-samples 65536] \
        [--principled-samples 16384] [--light-samples 16384] \
        [--textured-samples 8192] [--chunk 8192]
    blender -b --factory-startup --python blender_tests/make_references.py -- --bounce-study
    <python with bpy> blender_tests/bpy_boot.py blender_tests/make_references.py -- [...]

Writes into blender_tests/data/<Blender major.minor>/ (each version's tests compare with its
own Cycles; --data elsewhere):
- cornell_indirect.npy: Cycles' indirect light (tools/cycles_bake.py,
  cycles_indirect) per face corner of the small Cornell box
  (scenes/cornell_box.py, TEST_SUBDIVISIONS), float32 (n, 3);
- cornell_principled_indirect.npy: the same with Principled BSDFs
  (build_cornell_box(surface="PRINCIPLED"): each version's own Principled, v1 in 3.x, v2 in 4.x);
- light_<KIND>.npy: Cycles' direct light per face corner of the receivers of
  each one-light scene of scenes/light_units.py;
- light_EMISSIVE_TEXTURED.npy: the same for the emissive quad with an image
  texture on its emission colour (blender_tests/textured_emitter.py);
and a .json sidecar for each: samples, seed, bounces, Blender version, bake
seconds, object order with point counts, scene parameters and the noise of
the reference itself, estimated from two independent halves of its samples
(relative RMSE of the halves / 2, metrics.noise_from_halves).
"""

import json
import os
import sys
import time

import bpy
import numpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path[:0] = [HERE, os.path.join(ROOT, "scenes"), os.path.join(ROOT, "tools")]

import cornell_box  # noqa: E402
import cycles_bake  # noqa: E402
import light_units  # noqa: E402
import metrics  # noqa: E402
import textured_emitter  # noqa: E402

import common  # noqa: E402

DATA = common.reference_folder()
CORNELL_OBJECTS = ("Floor", "Ceiling", "BackWall", "LeftWall", "RightWall", "ShortBox", "TallBox")


def log(message):
    print(f"make_references: {message}", flush=True)


def chunked_with_halves(function, objects, samples, chunk, seed):
    """Chunked bake; returns (mean, seconds, noise of the mean from two halves of the chunks)."""

    def progress(done, total, seconds):
        log(f"  {done}/{total} samples, {seconds:.1f} s")

    if samples < 2 * chunk or samples % (2 * chunk):
        raise ValueError("samples must be an even multiple of chunk")
    mean, seconds, chunks = cycles_bake.cycles_chunked(function, objects, samples, chunk, seed, progress=progress)
    half = len(chunks) // 2
    half_a = sum(v for v, _ in chunks[:half]) / half
    half_b = sum(v for v, _ in chunks[half:]) / (len(chunks) - half)
    return mean, seconds, metrics.noise_from_halves(half_a, half_b)


def save(name, values, sidecar):
    os.makedirs(DATA, exist_ok=True)
    numpy.save(os.path.join(DATA, name + ".npy"), values.astype(numpy.float32))
    with open(os.path.join(DATA, name + ".json"), "w") as f:
        json.dump(sidecar, f, indent=1)
    log(f"wrote {name}.npy ({values.shape[0]} points) and {name}.json")


def common_sidecar(objects, samples, chunk, seed, seconds, noise):
    return {
        "samples": samples,
        "chunk_samples": chunk,
        "seed": seed,
        "bounces": cycles_bake.REFERENCE_BOUNCES,
        "domain": "CORNER",
        "objects": [[o.name, len(o.data.loops)] for o in objects],
        "seconds": round(seconds, 2),
        "noise_relative_rmse": noise,
        "blender": bpy.app.version_string,
        "made_by": "blender_tests/make_references.py with tools/cycles_bake.py",
    }


def make_cornell(samples, chunk, seed, surface="DIFFUSE"):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    built = cornell_box.build_cornell_box(cornell_box.TEST_SUBDIVISIONS, surface=surface)
    objects = [built[name] for name in CORNELL_OBJECTS]
    log(f"Cornell box ({surface}), {sum(len(o.data.loops) for o in objects)} corners, {samples} samples")
    values, seconds, noise = chunked_with_halves(cycles_bake.cycles_indirect, objects, samples, chunk, seed)
    sidecar = common_sidecar(objects, samples, chunk, seed, seconds, noise)
    sidecar["light"] = "indirect"
    sidecar["scene"] = {"builder": "scenes/cornell_box.py build_cornell_box", "surface": surface,
                        **cornell_box.scene_parameters(cornell_box.TEST_SUBDIVISIONS)}
    name = "cornell_indirect" if surface == "DIFFUSE" else f"cornell_{surface.lower()}_indirect"
    save(name, values, sidecar)
    log(f"Cornell {surface} indirect: {seconds:.1f} s, noise {100 * noise:.3f}%")


def make_lights(samples, chunk, seed, kinds=None):
    for kind in light_units.light_kinds():
        if kinds and kind not in kinds:
            continue
        bpy.ops.wm.read_factory_settings(use_empty=True)
        built = light_units.build_light_scene(kind)
        objects = [built[name] for name in light_units.RECEIVERS]
        values, seconds, noise = chunked_with_halves(cycles_bake.cycles_direct, objects, samples, chunk, seed)
        sidecar = common_sidecar(objects, samples, chunk, seed, seconds, noise)
        sidecar["light"] = "direct"
        sidecar["scene"] = {
            "builder": "scenes/light_units.py build_light_scene",
            "kind": kind,
            "subdivisions": light_units.DEFAULT_SUBDIVISIONS,
        }
        save(f"light_{kind}", values, sidecar)
        log(f"{kind} direct: {seconds:.1f} s, noise {100 * noise:.3f}%")


def make_textured_emitter(samples, chunk, seed):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    built = textured_emitter.build_textured_emitter_scene("EMISSION")
    objects = [built[name] for name in light_units.RECEIVERS]
    values, seconds, noise = chunked_with_halves(cycles_bake.cycles_direct, objects, samples, chunk, seed)
    sidecar = common_sidecar(objects, samples, chunk, seed, seconds, noise)
    sidecar["light"] = "direct"
    sidecar["scene"] = textured_emitter.scene_parameters()
    save(f"light_{textured_emitter.KIND}", values, sidecar)
    log(f"{textured_emitter.KIND} direct: {seconds:.1f} s, noise {100 * noise:.3f}%")


def bounce_study(samples=4096):
    """Mean luminance of the Cornell indirect against the bounce cap (same seed, so differences are the cap's)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    built = cornell_box.build_cornell_box(cornell_box.TEST_SUBDIVISIONS)
    objects = [built[name] for name in CORNELL_OBJECTS]
    for bounces in (4, 8, 16, 32, 64, 128, 1024):
        values, seconds = cycles_bake.cycles_indirect(objects, samples, bounces=bounces)
        log(f"bounces {bounces:5d}: mean luminance {metrics.luminance(values).mean():.6f}, {seconds:.2f} s")


def main():
    import argparse

    global DATA

    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--only", choices=("cornell", "principled", "lights", "textured"))
    parser.add_argument("--cornell-samples", type=int, default=65536)
    parser.add_argument("--principled-samples", type=int, default=16384)
    parser.add_argument("--light-samples", type=int, default=16384)
    parser.add_argument("--textured-samples", type=int, default=8192)
    parser.add_argument("--chunk", type=int, default=8192)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--kinds", nargs="+", help="with --only lights: only these light kinds")
    parser.add_argument("--bounce-study", action="store_true")
    parser.add_argument("--data", help=f"output folder (default {os.path.relpath(DATA, ROOT)})")
    arguments = parser.parse_args(argv)
    if arguments.data:
        DATA = os.path.abspath(arguments.data)
    start = time.perf_counter()
    if arguments.bounce_study:
        bounce_study()
        return
    if arguments.only in (None, "lights"):
        make_lights(arguments.light_samples, min(arguments.chunk, arguments.light_samples // 2),
                    arguments.seed, arguments.kinds)
    if arguments.only in (None, "textured"):
        make_textured_emitter(arguments.textured_samples,
                              min(arguments.chunk, arguments.textured_samples // 2), arguments.seed)
    if arguments.only in (None, "cornell"):
        make_cornell(arguments.cornell_samples, arguments.chunk, arguments.seed)
    if arguments.only in (None, "principled"):
        make_cornell(arguments.principled_samples, min(arguments.chunk, arguments.principled_samples // 4),
                     arguments.seed, surface="PRINCIPLED")
    log(f"done in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
