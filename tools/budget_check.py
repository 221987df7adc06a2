"""A 2-million-triangle room under a 256 MB memory budget, baked by every method: each bake
must be refused or coarsened with a message, never killed by the system. Prints, per method,
the outcome, the message or warnings, the seconds and the process' peak resident memory.

    /usr/bin/python3 tools/budget_check.py [--library build/libbakegi.so] [--triangles 2000000]
        [--budget 256]
"""

import argparse
import os
import resource
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))


def tessellated_box(triangles):
    """A closed 4 m x 4 m x 3 m room whose six walls are grids of about `triangles` in all."""
    n = max(2, int(np.sqrt(triangles / 12.0)))
    positions, indices = [], []
    size = np.array([4.0, 4.0, 3.0])
    for u, v, w in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        for side in (0.0, 1.0):
            j, i = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
            p = np.zeros(((n + 1) ** 2, 3))
            p[:, u], p[:, v], p[:, w] = i.ravel() / n, j.ravel() / n, side
            base = sum(len(x) for x in positions)
            positions.append(p * size)
            a = (np.arange(n)[None, :] + (n + 1) * np.arange(n)[:, None]).ravel() + base
            b, c = a + 1, a + n + 1
            d = c + 1
            quads = [a, b, d, a, d, c] if side == 0.0 else [a, d, b, a, c, d]
            indices.append(np.stack(quads, axis=1).reshape(-1))
    return (np.concatenate(positions).astype(np.float32),
            np.concatenate(indices).astype(np.uint32))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--library", default=os.path.join(ROOT, "build", "libbakegi.so"))
    parser.add_argument("--triangles", type=int, default=2_000_000)
    parser.add_argument("--budget", type=int, default=256)
    parser.add_argument("--methods", default="pathtrace,direct,antiradiance,meshless,splatting")
    args = parser.parse_args()
    from bakegi import native
    native.load_library(args.library)
    positions, indices = tessellated_box(args.triangles)
    scene = native.Scene()
    material = scene.add_material((0.6, 0.6, 0.6))
    scene.add_mesh(positions, indices, material=material)
    scene.add_light("POINT", position=(2.0, 2.0, 2.5), color=(50.0,) * 3)
    rng = np.random.default_rng(2)
    count = 10000
    floor = np.column_stack([rng.uniform(0.1, 3.9, (count, 2)), np.full(count, 1e-3)])
    points = native.Points(floor.astype(np.float32),
                           np.tile([0.0, 0.0, 1.0], (count, 1)).astype(np.float32),
                           np.zeros(count, np.uint32))
    print(f"{len(indices) // 3} triangles, {count} points, budget {args.budget} MB")
    for method in args.methods.split(","):
        start = time.perf_counter()
        outcome, detail = "baked", ""
        with native.Settings(method=method, samples=4, error_probes=0,
                             memory_budget_mb=args.budget) as settings:
            try:
                job = native.Job(scene, points, settings)
                try:
                    job.wait()
                    report = job.report()
                    detail = "; ".join(report.get("warnings", []))[:300]
                    if report.get("method_used", method) != method:
                        outcome = "handed to " + str(report.get("method_used"))
                finally:
                    job.close()
            except native.BakeGIError as error:
                outcome, detail = error.status, error.message[:300]
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        print(f"{method:13s} {outcome:32s} {time.perf_counter() - start:7.1f} s  "
              f"peak so far {peak:7.0f} MB  {detail}")


if __name__ == "__main__":
    main()
