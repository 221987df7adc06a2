# SPDX-License-Identifier: GPL-3.0-or-later
"""Which bake points may share one value: face corners (or vertices) of a target that lie
on the same vertex position with the same normal get the same indirect light wherever the
light is continuous across the vertex. A grid mesh has 4 to 6 corners per vertex, so
baking each corner alone does the same work 4 to 6 times.

The add-on only names the candidates (each point: the first point of its group); the core
checks each with a ray between the two points (each moved into its own face), so that a
wall standing on the vertex, which leaves the corners on its two sides in two different
lights, keeps them apart (native/src/bake/point_sharing.h).
"""

import numpy as np

# Positions agree when they round alike at this fraction of the target's size.
POSITION_QUANTUM = 1e-6
# Normals agree when every component rounds alike at this step (0.06 degrees): coplanar
# flat faces whose normals differ by rounding share, a crease of any visible angle does not.
NORMAL_QUANTUM = 1e-3


def share_candidates(positions, normals, first_index=0):
    """Per element, the index (offset by first_index) of the first element with the same
    position and normal; its own index where it is the first. positions, normals: (n, 3)."""
    n = len(positions)
    if n == 0:
        return np.zeros(0, np.uint32)
    positions = positions.astype(np.float64)
    size = float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0)))
    quantum = max(size, 1e-6) * POSITION_QUANTUM
    keys = np.column_stack([np.floor(positions / quantum),
                            np.rint(normals.astype(np.float64) / NORMAL_QUANTUM)])
    _, first, group = np.unique(keys.astype(np.int64), axis=0, return_index=True,
                                return_inverse=True)
    return (first[group.reshape(-1)] + first_index).astype(np.uint32)
