"""Cycles' side of the Cornell sweep, run inside Blender by tools/sweep_cornell.py:

    blender -b cornell.blend --python tools/sweep_cycles.py -- \
        --samples 1,4,16,64,256 [--seed 0] [--noise-seed 1] [--repeat R] [--objects A,B,...] \
        --out-dir DIR

Bakes Cycles' indirect light (tools/cycles_bake.py: Diffuse bake Direct+Indirect minus
Direct, same seed and samples) at each sample count and writes, into DIR:
  cycles_<samples>.npy       values (n, 3) float32, objects in the given order, face
                             corners in loop order (the order of the .bgs export)
  cycles_<samples>_seed<S>.npy  one more bake at the largest count with --noise-seed, so
                             that Cycles' own noise at that count can be measured
  corner_positions.npy       world position of each corner, (n, 3), to check that the
                             order matches the bake points of the .bgs file
  cycles_runs.json           per bake: samples, seed, seconds (wall time of both bakes,
                             scene sync and BVH included; the fastest of --repeat runs),
                             points

A 1-sample bake runs first and is not recorded: Cycles loads its kernels and builds caches
on the first bake of a session, a one-time cost that would otherwise be charged to
whichever sample count came first.
"""

import json
import os
import sys

import bpy
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_bake  # noqa: E402  (tools/ is put on sys.path just above)


def corner_positions(objects):
    """World-space position of every face corner, objects in order, loops in order."""
    arrays = []
    for obj in objects:
        mesh = obj.data
        vertices = numpy.empty(len(mesh.vertices) * 3, dtype=numpy.float64)
        mesh.vertices.foreach_get("co", vertices)
        loop_vertices = numpy.empty(len(mesh.loops), dtype=numpy.int64)
        mesh.loops.foreach_get("vertex_index", loop_vertices)
        local = vertices.reshape(-1, 3)[loop_vertices]
        matrix = numpy.array(obj.matrix_world, dtype=numpy.float64)
        arrays.append(local @ matrix[:3, :3].T + matrix[:3, 3])
    return numpy.concatenate(arrays).astype(numpy.float32)


def main():
    import argparse

    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description="Cycles indirect bakes at several sample counts.")
    parser.add_argument("--samples", required=True, help="comma-separated sample counts")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--noise-seed", type=int, default=1, help="seed of the extra bake at the largest count; -1: none")
    parser.add_argument("--repeat", type=int, default=1, help="bake each setting R times, keep the fastest time")
    parser.add_argument("--objects", default="", help="comma-separated mesh names in export order; default: scene order")
    parser.add_argument("--out-dir", required=True)
    arguments = parser.parse_args(argv)

    objects = cycles_bake.mesh_objects([n for n in arguments.objects.split(",") if n])
    os.makedirs(arguments.out_dir, exist_ok=True)
    numpy.save(os.path.join(arguments.out_dir, "corner_positions.npy"), corner_positions(objects))

    counts = [int(s) for s in arguments.samples.split(",")]
    bakes = [(n, arguments.seed, f"cycles_{n}.npy") for n in counts]
    if arguments.noise_seed >= 0:
        top = max(counts)
        bakes.append((top, arguments.noise_seed, f"cycles_{top}_seed{arguments.noise_seed}.npy"))
    cycles_bake.cycles_indirect(objects, 1, seed=arguments.seed, domain="CORNER")  # warm-up
    runs = []
    for samples, seed, name in bakes:
        all_seconds = []
        for _ in range(max(1, arguments.repeat)):
            # Same seed and samples: the values are identical, only the time varies.
            values, seconds = cycles_bake.cycles_indirect(objects, samples, seed=seed, domain="CORNER")
            all_seconds.append(seconds)
        numpy.save(os.path.join(arguments.out_dir, name), values)
        runs.append({"samples": samples, "seed": seed, "seconds": min(all_seconds), "seconds_all": all_seconds,
                     "points": int(values.shape[0]), "file": name})
        print(f"sweep_cycles: {samples} samples (seed {seed}): {min(all_seconds):.2f} s", flush=True)

    with open(os.path.join(arguments.out_dir, "cycles_runs.json"), "w") as f:
        json.dump({"objects": [o.name for o in objects], "blender": bpy.app.version_string,
                   "bounces": cycles_bake.REFERENCE_BOUNCES, "runs": runs}, f, indent=1)


if __name__ == "__main__":
    main()
