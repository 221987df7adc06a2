# SPDX-License-Identifier: GPL-3.0-or-later
"""Simplify a Copy: a level of detail of a mesh object made with the core's simplifier
(meshoptimizer's edge collapses, bakegi_mesh_simplify), to light from a grid without a
re-bake and to measure how grid lighting holds up as a mesh coarsens (docs/ivg.md). Like
Subdivide a Copy, the copy replaces the original, which is hidden, not changed.

Faces take the material of the original face nearest to them; the copy has no UV maps (a
lightmap of a level of detail needs its own unwrap)."""

import bpy
import mathutils.kdtree
import numpy

from . import native
from .subdivision import replace_with_copy

SUFFIX = "_LOD"


def mesh_triangles(mesh):
    """(positions (v, 3), triangles (t, 3), material index per triangle, smooth per
    triangle) of a mesh in its own space."""
    mesh.calc_loop_triangles()
    positions = numpy.zeros(len(mesh.vertices) * 3, numpy.float32)
    mesh.vertices.foreach_get("co", positions)
    count = len(mesh.loop_triangles)
    triangles = numpy.zeros(count * 3, numpy.int32)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    materials = numpy.zeros(count, numpy.int32)
    mesh.loop_triangles.foreach_get("material_index", materials)
    smooth = numpy.zeros(count, bool)
    mesh.loop_triangles.foreach_get("use_smooth", smooth)
    return positions.reshape(-1, 3), triangles.reshape(-1, 3), materials, smooth


def nearest_faces(centroids, queries):
    """Per query point, the index of the nearest of `centroids` (Blender's k-d tree)."""
    tree = mathutils.kdtree.KDTree(len(centroids))
    for index, point in enumerate(centroids):
        tree.insert(point, index)
    tree.balance()
    return numpy.array([tree.find(point)[1] for point in queries], numpy.int64)


def simplified_mesh(mesh, ratio, name, materials):
    """A new mesh datablock: `mesh`'s triangles reduced towards `ratio` of them, with
    `materials` (original datablocks: an evaluated mesh's are the depsgraph's copies, which
    must not be linked into the file). The whole mesh is simplified at once (a material's
    faces alone can be all border, which nothing may collapse); each new face takes the
    material and smoothing of the original face nearest to its centre. Returns (mesh,
    triangles before, triangles after, deviation over the extent)."""
    positions, triangles, material_of, smooth = mesh_triangles(mesh)
    if len(triangles) == 0:
        raise ValueError(f"'{mesh.name}' has no faces to simplify")
    lod, deviation = native.simplify_mesh(positions, triangles, ratio)
    if len(lod) == 0:
        raise ValueError(f"'{mesh.name}' simplifies to nothing")
    nearest = nearest_faces(positions[triangles].mean(axis=1), positions[lod].mean(axis=1))
    used, compact = numpy.unique(lod, return_inverse=True)
    compact = compact.reshape(-1, 3)

    result = bpy.data.meshes.new(name)
    result.from_pydata(positions[used].tolist(), [], compact.tolist())
    for material in materials:
        result.materials.append(material)
    result.polygons.foreach_set("material_index", material_of[nearest])
    result.polygons.foreach_set("use_smooth", smooth[nearest])
    result.update()
    return result, len(triangles), len(lod), (deviation if deviation == deviation else 0.0)


def simplify_copy(obj, ratio):
    """Makes '<name>_LOD<percent>', a copy of `obj` with about `ratio` (0, 1] of its
    triangles (modifiers applied: the evaluated mesh), hides `obj` in the viewport and the
    render, and selects the copy. Returns (copy, {"triangles": before, "lod_triangles":
    after, "deviation": over the extent})."""
    if obj is None or obj.type != "MESH" or obj.data is None:
        raise ValueError("Simplify a Copy needs a mesh object")
    ratio = float(ratio)
    if not 0.0 < ratio <= 1.0:
        raise ValueError(f"the ratio must lie in (0, 1], not {ratio}")
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    source = evaluated.to_mesh()
    try:
        name = f"{obj.name}{SUFFIX}{round(ratio * 100):g}"
        mesh, before, after, deviation = simplified_mesh(source, ratio, name,
                                                         list(obj.data.materials))
    finally:
        evaluated.to_mesh_clear()

    copy = replace_with_copy(obj, mesh, name, clear_modifiers=True)
    return copy, {"triangles": before, "lod_triangles": after, "deviation": deviation}
