"""Cycles' diffuse light at face corners or vertices, as references for bakegi.

Import it inside Blender (``sys.path`` holding ``tools/``) or run it:

    blender -b scene.blend --python tools/cycles_bake.py -- \
        --light indirect --samples 1024 [--seed 0] [--sample-offset 0] \
        [--domain CORNER|POINT] [--objects Floor,Ceiling] --out values.npy

What it computes (CYCLES_FACTS.md): a Cycles Diffuse bake without the Color
pass, i.e. the diffuse light over the diffuse colour (E / pi), written into a
FLOAT_COLOR attribute and read back.

- ``cycles_direct``: pass filter {DIRECT}.
- ``cycles_indirect``: {DIRECT, INDIRECT} minus {DIRECT}, same seed, samples
  and sample offset. A bake with only INDIRECT is wrong in Blender 3.4 (next
  event estimation is switched off on the whole path); with the same seed the
  direct estimates of the two bakes are identical and cancel exactly.

Settings for references: no denoising (in this build a denoised bake is
black), no clamping, no adaptive sampling, light threshold 0, and
REFERENCE_BOUNCES bounces (see the constant). ``sample_offset`` shifts the
sample sequence, so bakes of S samples at offsets 0, S, 2S, ... average to one
bake of their total samples: references are made in chunks.

Values come back as one float32 array of shape (n, 3): the objects in the
order given, each contributing its face corners (domain CORNER, in loop
order) or vertices (domain POINT, in vertex order).
"""

import sys
import time

import bpy
import numpy

# Path length cap for references. Cycles ends paths by Russian roulette long
# before this in a scene of albedo <= 0.73, so a high cap costs nothing
# measurable. Mean luminance of the small Cornell box's indirect light, 4096
# samples, same seed (blender_tests/make_references.py --bounce-study): 4
# bounces (Cycles' default) -7.3 %, 8 bounces -0.6 %, 16 bounces -0.008 %,
# 32 to 1024 bounces identical to 6 digits.
REFERENCE_BOUNCES = 128

BAKE_ATTRIBUTE = "CyclesBakeReference"
DOMAINS = ("CORNER", "POINT")


def configure_reference(scene, samples, seed=0, sample_offset=0, bounces=REFERENCE_BOUNCES):
    """Put Cycles in the reference configuration; return the previous values to restore."""
    cycles = scene.cycles
    settings = {
        "samples": samples,
        "seed": seed,
        "sample_offset": sample_offset,
        "use_animated_seed": False,
        "use_denoising": False,
        "use_adaptive_sampling": False,
        "sample_clamp_direct": 0.0,
        "sample_clamp_indirect": 0.0,
        "light_sampling_threshold": 0.0,
        "max_bounces": bounces,
        "diffuse_bounces": bounces,
        "glossy_bounces": bounces,
        "transmission_bounces": bounces,
        "transparent_max_bounces": bounces,
        "device": "CPU",
    }
    if hasattr(cycles, "use_guiding"):
        settings["use_guiding"] = False
    previous = {"engine": scene.render.engine}
    scene.render.engine = "CYCLES"
    for name, value in settings.items():
        previous[name] = getattr(cycles, name)
        setattr(cycles, name, value)
    return previous


def restore_settings(scene, previous):
    scene.render.engine = previous.pop("engine")
    for name, value in previous.items():
        setattr(scene.cycles, name, value)


def _count(mesh, domain):
    return len(mesh.loops) if domain == "CORNER" else len(mesh.vertices)


def _check_targets(objects, domain):
    if domain not in DOMAINS:
        raise ValueError(f"domain must be one of {DOMAINS}, not {domain!r}")
    if not objects:
        raise ValueError("no objects to bake")
    meshes = set()
    for obj in objects:
        if obj.type != "MESH":
            raise ValueError(f"{obj.name} is not a mesh")
        if obj.data.name in meshes:
            raise ValueError(f"{obj.name} shares its mesh with another target; the bake would overwrite it")
        meshes.add(obj.data.name)


def bake_diffuse(objects, pass_filter, samples, seed=0, domain="CORNER", sample_offset=0, bounces=REFERENCE_BOUNCES):
    """One Cycles Diffuse bake (Color off) of `objects` into a float attribute.

    Returns (values (n, 3) float32, wall seconds of the bake operator, scene
    sync and BVH build included). The scene is left as it was: the temporary
    attribute is removed, active attributes, selection and settings restored.
    """
    _check_targets(objects, domain)
    context = bpy.context
    scene = context.scene
    view_layer = context.view_layer
    previous_settings = configure_reference(scene, samples, seed, sample_offset, bounces)
    previous_active = view_layer.objects.active
    previous_selection = [o for o in view_layer.objects if o.select_get()]
    previous_colors = {}
    try:
        for obj in objects:
            mesh = obj.data
            colors = mesh.color_attributes
            previous_colors[obj.name] = (colors.active_color_name, colors.render_color_index)
            if BAKE_ATTRIBUTE in colors:
                colors.remove(colors[BAKE_ATTRIBUTE])
            attribute = colors.new(BAKE_ATTRIBUTE, "FLOAT_COLOR", domain)
            colors.active_color = attribute  # the bake writes into the active colour attribute
        for obj in view_layer.objects:
            obj.select_set(False)
        for obj in objects:
            obj.select_set(True)
        view_layer.objects.active = objects[0]

        start = time.perf_counter()
        result = bpy.ops.object.bake(
            type="DIFFUSE",
            pass_filter=set(pass_filter),
            target="VERTEX_COLORS",
            use_selected_to_active=False,
            use_clear=True,
            margin=0,
        )
        seconds = time.perf_counter() - start
        if result != {"FINISHED"}:
            raise RuntimeError(f"Cycles bake returned {result}")

        arrays = []
        for obj in objects:
            mesh = obj.data
            count = _count(mesh, domain)
            rgba = numpy.empty(count * 4, dtype=numpy.float32)
            mesh.color_attributes[BAKE_ATTRIBUTE].data.foreach_get("color", rgba)
            arrays.append(rgba.reshape(count, 4)[:, :3])
        return numpy.concatenate(arrays).astype(numpy.float32), seconds
    finally:
        for obj in objects:
            colors = obj.data.color_attributes
            if BAKE_ATTRIBUTE in colors:
                colors.remove(colors[BAKE_ATTRIBUTE])
            if obj.name in previous_colors:
                active_name, render_index = previous_colors[obj.name]
                if active_name and active_name in colors:
                    colors.active_color = colors[active_name]
                if 0 <= render_index < len(colors):
                    colors.render_color_index = render_index
        for obj in view_layer.objects:
            obj.select_set(obj in previous_selection)
        view_layer.objects.active = previous_active
        restore_settings(scene, previous_settings)


def cycles_direct(objects, samples, seed=0, domain="CORNER", sample_offset=0, bounces=REFERENCE_BOUNCES):
    """Cycles' direct diffuse light (E_direct / pi): returns (values (n, 3), seconds)."""
    return bake_diffuse(objects, {"DIRECT"}, samples, seed, domain, sample_offset, bounces)


def cycles_indirect(objects, samples, seed=0, domain="CORNER", sample_offset=0, bounces=REFERENCE_BOUNCES):
    """Cycles' indirect diffuse light, bakegi's output quantity: returns (values (n, 3), seconds).

    {DIRECT, INDIRECT} minus {DIRECT} with the same seed, samples and offset;
    seconds is the wall time of both bakes.
    """
    total, total_seconds = bake_diffuse(objects, {"DIRECT", "INDIRECT"}, samples, seed, domain, sample_offset, bounces)
    direct, direct_seconds = bake_diffuse(objects, {"DIRECT"}, samples, seed, domain, sample_offset, bounces)
    return total - direct, total_seconds + direct_seconds


def cycles_chunked(function, objects, samples, chunk_samples, seed=0, domain="CORNER", progress=None, **kwargs):
    """Average `function` (cycles_direct or cycles_indirect) over independent chunks.

    Each chunk gets its own sample offset and its own seed (seed + chunk index): Cycles 4.5
    and 5.0 ignore the sample offset in a bake (chunks at different offsets came out
    identical), so the offset alone would repeat one chunk. Returns
    (values, seconds, chunk values list).
    """
    chunks = []
    seconds = 0.0
    offset = 0
    while offset < samples:
        count = min(chunk_samples, samples - offset)
        values, chunk_seconds = function(objects, count, seed + len(chunks), domain, offset, **kwargs)
        chunks.append((values.astype(numpy.float64), count))
        seconds += chunk_seconds
        offset += count
        if progress:
            progress(offset, samples, seconds)
    mean = sum(v * n for v, n in chunks) / samples
    return mean.astype(numpy.float32), seconds, chunks


def mesh_objects(names=None, scene=None):
    """Mesh objects of the scene by name (all renderable meshes in scene order when names is None)."""
    scene = scene or bpy.context.scene
    if names:
        return [scene.objects[name] for name in names]
    return [o for o in scene.objects if o.type == "MESH" and not o.hide_render]


def main():
    import argparse
    import json

    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description="Bake Cycles' diffuse light per face corner or vertex.")
    parser.add_argument("--light", choices=("direct", "indirect"), default="indirect")
    parser.add_argument("--samples", type=int, default=256)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--sample-offset", type=int, default=0)
    parser.add_argument("--bounces", type=int, default=REFERENCE_BOUNCES)
    parser.add_argument("--domain", choices=DOMAINS, default="CORNER")
    parser.add_argument("--objects", default="", help="comma-separated names; default: all renderable meshes")
    parser.add_argument("--out", required=True, help=".npy file; a .json sidecar is written next to it")
    arguments = parser.parse_args(argv)

    objects = mesh_objects([n for n in arguments.objects.split(",") if n])
    function = cycles_indirect if arguments.light == "indirect" else cycles_direct
    values, seconds = function(
        objects, arguments.samples, arguments.seed, arguments.domain, arguments.sample_offset, bounces=arguments.bounces
    )
    numpy.save(arguments.out, values)
    sidecar = {
        "light": arguments.light,
        "samples": arguments.samples,
        "seed": arguments.seed,
        "sample_offset": arguments.sample_offset,
        "bounces": arguments.bounces,
        "domain": arguments.domain,
        "objects": [[o.name, _count(o.data, arguments.domain)] for o in objects],
        "seconds": seconds,
        "blender": bpy.app.version_string,
        "file": bpy.data.filepath,
    }
    with open(arguments.out.rsplit(".", 1)[0] + ".json", "w") as f:
        json.dump(sidecar, f, indent=1)
    print(f"cycles_bake: {arguments.light} {values.shape[0]} points, {arguments.samples} samples, {seconds:.2f} s")


if __name__ == "__main__":
    main()
