# SPDX-License-Identifier: GPL-3.0-or-later
"""Subdivide a Copy: a finer copy of a mesh object whose vertices are too few for the light
on it (the bake's error check says which: error_check.py), so that a color attribute can
hold that light. The copy replaces the original in the viewport and the render; the original
is hidden, not changed, so it stays one click away.

Edges are split in halves, only where longer than the target length, until none is or the
vertex budget is reached: a large floor gets many vertices, a detailed chair next to none.
"""

import math

import bmesh
import bpy

# Enough for indirect light across a room-sized surface (4,000 vertices: a 5 m floor gets a
# vertex every 8 cm) without making a large scene unwieldy.
DEFAULT_VERTICES = 4000
MAX_VERTICES = 200_000
MAX_ROUNDS = 12  # each halves the longest edges: 4096x finer at most
SUFFIX = "_BakeGI"


def world_area(obj, mesh):
    matrix = obj.matrix_world
    area = 0.0
    for polygon in mesh.polygons:
        points = [matrix @ mesh.vertices[v].co for v in polygon.vertices]
        for i in range(1, len(points) - 1):
            area += (points[i] - points[0]).cross(points[i + 1] - points[0]).length / 2.0
    return area


def subdivide_copy(obj, vertices=DEFAULT_VERTICES):
    """Makes '<name>_BakeGI', a copy of `obj` whose edges are split until they are no longer
    than the edge of a square holding one of `vertices` vertices over the object's world
    area (or the next round would pass MAX_VERTICES), hides `obj` in the viewport and the render, and
    selects the copy. Returns the copy."""
    if obj is None or obj.type != "MESH" or obj.data is None:
        raise ValueError("Subdivide a Copy needs a mesh object")
    vertices = max(int(vertices), 1)
    area = world_area(obj, obj.data)
    if not area > 0.0:
        raise ValueError(f"'{obj.name}' has no faces to subdivide")
    scale = obj.matrix_world.to_scale()
    stretch = max(abs(scale.x), abs(scale.y), abs(scale.z), 1e-12)
    target = math.sqrt(area / vertices) / stretch  # in the mesh's own units

    mesh = obj.data.copy()
    mesh.name = obj.data.name + SUFFIX
    bm = bmesh.new()
    try:
        bm.from_mesh(mesh)
        for _ in range(MAX_ROUNDS):
            long_edges = [e for e in bm.edges if e.calc_length() > target]
            # A split edge adds a vertex (grid fill adds one per split face more).
            if not long_edges or len(bm.verts) + 2 * len(long_edges) > MAX_VERTICES:
                break
            bmesh.ops.subdivide_edges(bm, edges=long_edges, cuts=1, use_grid_fill=True)
        bm.to_mesh(mesh)
    finally:
        bm.free()

    return replace_with_copy(obj, mesh, obj.name + SUFFIX)


def replace_with_copy(obj, mesh, name, clear_modifiers=False):
    """Links '<name>', a copy of `obj` with `mesh`, into obj's collections, hides `obj` in
    the viewport and the render (not changed: one click brings it back) and selects the copy
    alone. clear_modifiers: `mesh` is already evaluated. Returns the copy."""
    copy = obj.copy()
    if clear_modifiers:
        copy.modifiers.clear()
    copy.data = mesh
    copy.name = name
    for collection in obj.users_collection:
        collection.objects.link(copy)
    obj.hide_set(True)
    obj.hide_render = True
    for other in bpy.context.selected_objects:
        other.select_set(False)
    copy.select_set(True)
    bpy.context.view_layer.objects.active = copy
    return copy
