# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake points of a target: one per face corner of the ORIGINAL mesh (where the
attribute is written), from the evaluated mesh when it has the original's element counts
(deforming modifiers), else from the original in world space (with a warning); points nudged
into their faces, normals repaired, and the display probes inside faces that the error
estimate adds.

A vertex ('POINT') target is baked at its face corners too, and each vertex gets the mean of
its corners (write/attributes.py), as Cycles bakes a vertex colour: a vertex between faces
of different normals (every corner of a flat-shaded box) has no single normal to bake with,
and one point at the vertex with the faces' mean normal sat inside the solid, 0 on every
corner of a box. Where the corners share the vertex's normal (smooth shading) point sharing
bakes them once."""

from dataclasses import dataclass

import numpy as np

from . import point_sharing
from .mesh_arrays import (check_finite, corner_normals, get_array, matrix_array,
                          normals_to_world, positions_to_world)


# ---- bake points --------------------------------------------------------------------------


def _original_corner_normals(mesh):
    """Corner normals of an original mesh read without changing it (custom normals are not
    read): the vertex normal on smooth faces, the face normal on flat ones."""
    loops = len(mesh.loops)
    vertex_normals = get_array(mesh.vertices, "normal", len(mesh.vertices), np.float32, 3)
    loop_vertex = get_array(mesh.loops, "vertex_index", loops, np.int32)
    polys = len(mesh.polygons)
    face_normals = get_array(mesh.polygons, "normal", polys, np.float32, 3)
    smooth = get_array(mesh.polygons, "use_smooth", polys, bool)
    totals = get_array(mesh.polygons, "loop_total", polys, np.int32)
    loop_face = np.repeat(np.arange(polys), totals)
    return np.where(smooth[loop_face][:, None], vertex_normals[loop_vertex],
                    face_normals[loop_face])


# How far a bake point moves from its vertex towards the centre of its face(s), as a fraction
# of that distance. A corner on a concave junction (a floor corner at the foot of a wall) lies
# exactly in the plane of the neighbouring surface; rays leaving it then hit or miss that
# surface by float rounding, and the value came out 36% dark there against Cycles. Moved this
# little into its own face, the point gives the limit from inside the face, which is what
# Cycles' bake returns there, and the value moves by a negligible 0.2% of a face's size.
INWARD_FRACTION = 2e-3


def nudge_into_faces(positions, inward_targets):
    """Moves each bake point INWARD_FRACTION of the way towards its target point."""
    return positions + INWARD_FRACTION * (inward_targets - positions)


# Display probes (points inside faces where the bake checks what a viewer sees between bake
# points, interpolation included): this many per target object, fewer when there are many
# targets, so that the check costs about the same on any scene.
DISPLAY_PROBES_PER_OBJECT = 16
DISPLAY_PROBES_MIN_PER_OBJECT = 8
DISPLAY_PROBES_TOTAL = 2048


def display_probes_per_object(target_count):
    if target_count <= 0:
        return 0
    return max(DISPLAY_PROBES_MIN_PER_OBJECT,
               min(DISPLAY_PROBES_PER_OBJECT, DISPLAY_PROBES_TOTAL // target_count))


@dataclass
class DisplayProbes:
    """Probes of one target in object space: positions, normals, and per probe the target's
    three bake points (of the face corner triangle it lies in) with barycentric weights."""
    positions: np.ndarray  # (k, 3)
    normals: np.ndarray  # (k, 3)
    points: np.ndarray  # (k, 3) bake point indices within the target
    weights: np.ndarray  # (k, 3)


def _display_probes(source, normals, count, rng):
    """`count` points spread uniformly over the area of `source`'s faces (loop triangles),
    each with the corner bake points and weights that interpolate the color attribute there,
    as the viewport does (for a vertex target the viewport interpolates the corners' means:
    the probes check the corners, not the mean)."""
    source.calc_loop_triangles()
    tris = len(source.loop_triangles)
    if count <= 0 or tris == 0:
        return None
    tri_loops = get_array(source.loop_triangles, "loops", tris, np.int32, 3)
    loop_vertex = get_array(source.loops, "vertex_index", len(source.loops), np.int32)
    vertices = get_array(source.vertices, "co", len(source.vertices), np.float32, 3).astype(np.float64)
    corners = vertices[loop_vertex[tri_loops]]  # (T, 3, 3)
    areas = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                          corners[:, 2] - corners[:, 0]), axis=1)
    total = areas.sum()
    if not (total > 0.0):
        return None
    chosen = rng.choice(tris, size=count, p=areas / total)
    # Uniform barycentrics (Osada et al.): sqrt folds the square onto the triangle.
    r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
    weights = np.stack([1.0 - r1, r1 * (1.0 - r2), r1 * r2], axis=1)
    positions = np.einsum("kj,kjc->kc", weights, corners[chosen])
    points = tri_loops[chosen]
    corner_normals = normals[points].astype(np.float64)
    probe_normals = np.einsum("kj,kjc->kc", weights, corner_normals)
    return DisplayProbes(positions.astype(np.float32), probe_normals.astype(np.float32),
                         points.astype(np.uint32), weights.astype(np.float32))


def repair_normals(normals, fallback, name, warnings):
    """Bake points need a direction: a zero or non-finite normal (imported meshes carry them
    on degenerate faces and in broken custom normals) takes its face's normal (`fallback`, the
    summed face normals for vertices), and where that is zero too, +z, with a warning."""
    normals = np.asarray(normals, np.float32)
    length = np.linalg.norm(normals, axis=1)
    bad = ~(np.isfinite(length) & (length > 1e-12))
    if not bad.any():
        return normals
    repaired = normals.copy()
    replacement = np.nan_to_num(np.asarray(fallback, np.float64)[bad], nan=0.0, posinf=0.0,
                                neginf=0.0)
    replacement_length = np.linalg.norm(replacement, axis=1)
    arbitrary = ~(replacement_length > 1e-12)
    replacement[arbitrary] = (0.0, 0.0, 1.0)
    replacement_length[arbitrary] = 1.0
    repaired[bad] = (replacement / replacement_length[:, None]).astype(np.float32)
    if arbitrary.any():
        warnings.append(f"'{name}': {int(arbitrary.sum())} bake points lie on faces without "
                        "area (no normal); they are baked facing +z (merge or delete the "
                        "degenerate faces)")
    return repaired


@dataclass
class TargetPoints:
    """One target's bake points, one per face corner, in world space."""
    positions: np.ndarray  # (corners, 3)
    normals: np.ndarray  # (corners, 3)
    probes: object  # DisplayProbes or None
    share_candidates: np.ndarray  # (corners,) point_sharing.share_candidates
    # A vertex ('POINT') target: the vertex of each corner, and the vertex count; None, 0 for
    # 'CORNER'.
    vertex_of_point: object = None
    vertex_count: int = 0


def target_points(obj, depsgraph, domain, warnings, probe_count=0, seed=0, first_index=0):
    """TargetPoints of one target on its original mesh ('CORNER' or 'POINT': corners either
    way), and `probe_count` display probes inside its faces (positions and normals in world
    space, bake point indices within the target). The target's points are numbered from
    first_index (point_sharing.py)."""
    original = obj.data
    obj_eval = obj.evaluated_get(depsgraph)
    matrix = matrix_array(obj_eval.matrix_world)
    mesh = obj_eval.to_mesh()
    try:
        same = (mesh is not None and len(mesh.vertices) == len(original.vertices) and
                len(mesh.loops) == len(original.loops))
        source = mesh if same else original
        if not same:
            warnings.append(f"'{obj.name}': modifiers change its topology; the bake is made on "
                            "the mesh without them (placed in world space)")
        vertices = get_array(source.vertices, "co", len(source.vertices), np.float32, 3)
        loop_vertex = get_array(source.loops, "vertex_index", len(source.loops), np.int32)
        polys = len(source.polygons)
        face_centers = get_array(source.polygons, "center", polys, np.float32, 3)
        loop_face = np.repeat(np.arange(polys),
                              get_array(source.polygons, "loop_total", polys, np.int32))
        face_normals = get_array(source.polygons, "normal", polys, np.float32, 3)
        positions = vertices[loop_vertex]
        normals = corner_normals(source) if same else _original_corner_normals(source)
        normals = repair_normals(normals, face_normals[loop_face], obj.name, warnings)
        candidates = point_sharing.share_candidates(positions, normals, first_index)
        positions = nudge_into_faces(positions, face_centers[loop_face])
        probes = _display_probes(source, normals, probe_count,
                                 np.random.default_rng(seed)) if probe_count else None
    finally:
        obj_eval.to_mesh_clear()
    check_finite(obj.name, positions, "vertex" if domain == "POINT" else "face corner")
    if probes is not None:
        probes.positions = positions_to_world(matrix, probes.positions)
        probes.normals = normals_to_world(matrix, probes.normals)
    vertex_point = domain == "POINT"
    return TargetPoints(positions_to_world(matrix, positions), normals_to_world(matrix, normals),
                        probes, candidates, loop_vertex if vertex_point else None,
                        len(original.vertices) if vertex_point else 0)


def mesh_facts(mesh):
    """What the error check says about a target (error_check.ObjectFacts): its vertex count
    and the share of its edges that bound a single face (open, sheet-like geometry)."""
    from ..error_check import ObjectFacts
    edges = len(mesh.edges)
    if edges == 0:
        return ObjectFacts(vertices=len(mesh.vertices))
    loop_edges = get_array(mesh.loops, "edge_index", len(mesh.loops), np.int32)
    faces_per_edge = np.bincount(loop_edges, minlength=edges)
    return ObjectFacts(vertices=len(mesh.vertices),
                       open_edge_share=float(np.count_nonzero(faces_per_edge == 1)) / edges)
