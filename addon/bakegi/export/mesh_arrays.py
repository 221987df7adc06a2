# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender mesh data as numpy arrays: foreach_get, corner normals, world transforms of
positions and normals, and the check that refuses non-finite vertices."""

import numpy as np

from ..native import BakeGIError


def invalid_scene(message):
    return BakeGIError("BAKEGI_ERROR_INVALID_SCENE", message)


# ---- mesh arrays ------------------------------------------------------------------------


def get_array(collection, attr, count, dtype, width=1):
    out = np.empty(count * width, dtype)
    if count:
        collection.foreach_get(attr, out)
    return out.reshape(-1, width) if width > 1 else out


def corner_normals(mesh):
    """(loops, 3) normals as Blender shades each face corner (smooth/flat/custom)."""
    n = len(mesh.loops)
    if hasattr(mesh, "corner_normals"):  # Blender 4.1+: always up to date
        return get_array(mesh.corner_normals, "vector", n, np.float32, 3)
    mesh.calc_normals_split()  # Blender < 4.1 (the mesh here is a temporary one)
    return get_array(mesh.loops, "normal", n, np.float32, 3)


def matrix_array(m):
    return np.array([list(row) for row in m], dtype=np.float64)


def positions_to_world(matrix, positions):
    p = positions.astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
    return p.astype(np.float32)


def normals_to_world(matrix, normals):
    """Normals transform with the inverse transpose: n' = n^T M^-1, then renormalized."""
    m3 = matrix[:3, :3]
    try:
        normal_matrix = np.linalg.inv(m3)
    except np.linalg.LinAlgError:
        normal_matrix = m3
    n = normals.astype(np.float64) @ normal_matrix
    length = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.where(length > 0, n / np.maximum(length, 1e-30), 0.0)
    return n.astype(np.float32)


def check_finite(name, positions, what="vertex"):
    finite = np.isfinite(positions).all(axis=1)
    if not finite.all():
        i = int(np.argmin(finite))
        x, y, z = (float(v) for v in positions[i])
        raise invalid_scene(f"object '{name}': {what} {i} has a non-finite position "
                       f"({x:g}, {y:g}, {z:g}); fix the mesh (or its modifiers) and bake again")
