"""What window portals gain on a real scene: places portals where a scene's sky comes in, and
bakes the scene's reference subset with and without them at equal paths.

The scene (a folder of tools/real_scenes.py: scene.blend, corner/subset.bgs and the reference
chunks) has no portals of its own, so they are found from the light: Blender casts 64
cosine-distributed rays from each subset point, and the rays that leave the scene are followed
to the face of the scene's bounding box they cross; on each face named with --faces (0..5:
+x, -x, +y, -y, +z, -z) one rectangular portal covers where they crossed, facing in.
Then the path tracer bakes the subset without and with the portals (--paths per point, no
denoiser, seeds 1 and 2) and the errors against the scene's reference are printed.

    /usr/bin/python3 tools/portal_gain.py --scene /tmp/rs2/living_room [--faces 1,3] [--paths 64]

Without --faces it prints how many escaping rays cross each face, to choose them.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "tools"), os.path.join(ROOT, "blender_tests"),
                os.path.join(ROOT, "addon", "bakegi")]

import native  # noqa: E402  (bakegi's ctypes binding; never imports bpy)
from ivg_sweep import figures, reference_of  # noqa: E402

FACE_NAMES = ("+x", "-x", "+y", "-y", "+z", "-z")

# Run inside Blender: the escaping rays of the subset points, and the scene's bounds.
ESCAPES = r'''
import json, math, sys
import bpy, mathutils
import numpy
subset, out, library = sys.argv[sys.argv.index("--") + 1:]
sys.path.insert(0, library)
import native
_, points = native.Scene.read(subset)
positions, normals, _ = points.get()
scene = bpy.context.scene
graph = bpy.context.evaluated_depsgraph_get()
lo, hi = numpy.full(3, 1e30), numpy.full(3, -1e30)
for o in scene.objects:
    if o.type == "MESH" and not o.hide_render:
        corners = numpy.array([list(o.matrix_world @ mathutils.Vector(c)) for c in o.bound_box])
        lo, hi = numpy.minimum(lo, corners.min(0)), numpy.maximum(hi, corners.max(0))
random = numpy.random.default_rng(1)
escapes = []
for p, n in zip(positions, normals):
    n = n / numpy.linalg.norm(n)
    t = numpy.cross(n, [1, 0, 0] if abs(n[0]) < 0.9 else [0, 1, 0])
    t /= numpy.linalg.norm(t)
    b = numpy.cross(n, t)
    origin = mathutils.Vector(p + n * 1e-4)
    for _ in range(64):
        u1, u2 = random.random(2)
        r, phi = math.sqrt(u1), 2 * math.pi * u2
        d = t * r * math.cos(phi) + b * r * math.sin(phi) + n * math.sqrt(max(0.0, 1 - u1))
        if not scene.ray_cast(graph, origin, mathutils.Vector(d))[0]:
            escapes.append([float(v) for v in list(p) + list(d)])
json.dump({"lo": lo.tolist(), "hi": hi.tolist(), "rays": len(positions) * 64,
           "escapes": escapes}, open(out, "w"))
'''


def crossings(escapes, lo, hi):
    """Each escaping ray's exit face of the box [lo, hi] (FACE_NAMES order) and where."""
    origins, directions = escapes[:, :3], escapes[:, 3:]
    t = numpy.full(len(escapes), numpy.inf)
    face = numpy.zeros(len(escapes), int)
    for axis in range(3):
        for side, bound in ((1, hi[axis]), (-1, lo[axis])):
            leaving = directions[:, axis] * side > 1e-9
            safe = numpy.where(leaving, directions[:, axis], 1.0)
            distance = numpy.where(leaving, (bound - origins[:, axis]) / safe, numpy.inf)
            nearer = distance < t
            face[nearer] = 2 * axis + (side < 0)
            t = numpy.minimum(t, distance)
    return face, origins + directions * t[:, None]


def add_portals(scene, face, where, faces):
    for f in faces:
        at = where[face == f]
        if len(at) == 0:
            raise SystemExit(f"no escaping ray crosses face {FACE_NAMES[f]}")
        axis = f // 2
        across = [a for a in range(3) if a != axis]
        low, high = at.min(0), at.max(0)
        inward = [0.0, 0.0, 0.0]
        inward[axis] = -1.0 if f % 2 == 0 else 1.0
        axis_u = [0.0, 0.0, 0.0]
        axis_u[across[0]] = 1.0
        size = [float(high[a] - low[a]) for a in across]
        print(f"portal on face {FACE_NAMES[f]}: centre {numpy.round(0.5 * (low + high), 3)}, "
              f"{size[0]:.2f} x {size[1]:.2f} m, {len(at)} escaping rays")
        scene.add_portal(position=0.5 * (low + high), direction=inward, axis_u=axis_u,
                         shape="RECTANGLE", size_x=size[0], size_y=size[1])


def bake(cli, scene_file, paths, seed, out):
    start = time.perf_counter()
    subprocess.run([cli, "bake", scene_file, "--method", "pathtrace", "--samples", str(paths),
                    "--seed", str(seed), "--set", "error_probes=0", "--set", "denoise=0",
                    "--out", out], check=True, capture_output=True)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True, help="a real_scenes.py folder")
    parser.add_argument("--faces", default="", help="faces to put portals on, e.g. 1,3")
    parser.add_argument("--paths", type=int, default=64)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--blender", default="blender")
    args = parser.parse_args()
    os.environ.setdefault("BAKEGI_LIBRARY", os.path.join(args.build, "libbakegi.so"))
    folder = os.path.join(args.scene, "corner")
    subset = os.path.join(folder, "subset.bgs")
    with tempfile.TemporaryDirectory() as work:
        script, found = os.path.join(work, "escapes.py"), os.path.join(work, "escapes.json")
        with open(script, "w") as f:
            f.write(ESCAPES)
        subprocess.run([args.blender, "-b", "--factory-startup",
                        os.path.join(args.scene, "scene.blend"), "--python-exit-code", "1",
                        "--python", script, "--", subset, found,
                        os.path.join(ROOT, "addon", "bakegi")], check=True)
        with open(found) as f:
            data = json.load(f)
        escapes = numpy.array(data["escapes"], dtype=numpy.float64).reshape(-1, 6)
        face, where = crossings(escapes, numpy.array(data["lo"]), numpy.array(data["hi"]))
        print(f"{len(escapes)} of {data['rays']} rays leave the scene; by the face they cross: " +
              ", ".join(f"{FACE_NAMES[f]} {int((face == f).sum())}" for f in range(6)))
        if not args.faces:
            return
        scene, points = native.Scene.read(subset)
        add_portals(scene, face, where, [int(f) for f in args.faces.split(",")])
        with_portals = os.path.join(work, "portals.bgs")
        scene.write(with_portals, points)
        reference, noise = reference_of(folder)
        print(f"reference noise {100 * noise:.2f}% (NRMSE below has it removed)")
        cli = os.path.join(args.build, "bakegi")
        for label, scene_file in (("without portals", subset), ("with portals", with_portals)):
            for seed in (1, 2):
                out = os.path.join(work, f"{seed}.npy")
                seconds = bake(cli, scene_file, args.paths, seed, out)
                f = figures(numpy.load(out).astype(numpy.float64), reference, noise)
                print(f"{label}, seed {seed}: {seconds:.2f} s, NRMSE "
                      f"{100 * f['nrmse_without_reference_noise']:.2f}%, wRRMSE "
                      f"{100 * f['weighted_relative_rmse']:.2f}%, bias {100 * f['bias']:+.2f}%")


if __name__ == "__main__":
    main()
