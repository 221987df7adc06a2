"""Cancel at every stage of every method (tools/cancel_latency.py on a small closed box):
each bake cancelled where its progress text first shows a stage must end CANCELLED, never
finish or fail otherwise. The latencies are printed (run pytest -s to see them); they are
measured on real rooms in docs/reliability.md, not asserted here."""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "tools"))
import cancel_latency  # noqa: E402

# Enough work per stage that a bake is still running when its stage shows; small enough for
# the test suite (the whole test takes seconds).
QUICK = {
    "pathtrace": {"samples": 256, "error_probes": 16},
    "direct": {"samples": 512},
    "antiradiance": {"bins": 48, "near_field_rays": 64, "error_probes": 16},
    "meshless": {"gather_rays": 64, "error_probes": 16},
    "splatting": {"vpl_count": 1024, "gather_rays": 64, "error_probes": 16},
}


def closed_box_arrays():
    """A 1 m closed box (6 * 2 * 144 triangles facing inwards), a point light's position and
    2000 points on its floor: (positions, indices, light, points, normals)."""
    n = 12  # cells per side
    positions, indices = [], []
    for u, v, w in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        for side in (0.0, 1.0):
            base = len(positions)
            for j in range(n + 1):
                for i in range(n + 1):
                    p = [0.0, 0.0, 0.0]
                    p[u], p[v], p[w] = i / n, j / n, side
                    positions.append(p)
            for j in range(n):
                for i in range(n):
                    a, b = base + j * (n + 1) + i, base + j * (n + 1) + i + 1
                    c, d = a + n + 1, b + n + 1
                    # Faces point into the box: wound by the side.
                    indices += [a, b, d, a, d, c] if side == 0.0 else [a, d, b, a, c, d]
    rng = np.random.default_rng(1)
    count = 2000
    floor = np.column_stack([rng.uniform(0.05, 0.95, (count, 2)), np.full(count, 1e-3)])
    normals = np.tile([0.0, 0.0, 1.0], (count, 1)).astype(np.float32)
    return (np.array(positions, np.float32), np.array(indices, np.uint32), (0.5, 0.5, 0.8),
            floor, normals)


def closed_box(native):
    """closed_box_arrays as a core scene with a 5 W/sr point light, and its points."""
    positions, indices, light, floor, normals = closed_box_arrays()
    scene = native.Scene()
    material = scene.add_material((0.6, 0.6, 0.6))
    scene.add_mesh(positions, indices, material=material)
    scene.add_light("POINT", position=light, color=(5.0, 5.0, 5.0))
    return scene, native.Points(floor.astype(np.float32), normals,
                                np.zeros(len(floor), np.uint32))


def test_every_stage_of_every_method_cancels(native, capsys):
    scene, points = closed_box(native)
    results = cancel_latency.measure(native, scene, points, QUICK, repeat=1, timeout=120.0)
    with capsys.disabled():
        print("\n" + cancel_latency.markdown(results))
    for method, rows in results.items():
        caught = [row for row in rows if row["latencies"]]
        assert caught, f"{method}: no stage was caught running"
        for row in rows:
            for status in row["statuses"]:
                assert status in ("BAKEGI_ERROR_CANCELLED", "missed"), (method, row)
