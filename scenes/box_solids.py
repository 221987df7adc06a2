"""Closed, grid-subdivided box solids for scenes that need solids (the antiradiance scenes).

A ``SolidMesh`` collects axis-aligned rectangles, each a grid of quads, and welds
vertices that coincide, so that rectangles sharing an edge with the same grid
lines along it form one 2-manifold surface. Boxes built from six such
rectangles are closed: every edge belongs to exactly two faces, used once in
each direction. A box can face outwards (a solid block) or inwards (a cavity:
the air of a room inside a thicker solid), and a box face can leave out the
grid cells of a rectangular opening (a window), to be closed by the reveal
rectangles of the opening.

Grid lines come from ``ticks``: a span split at given breakpoints, each
segment divided into equal cells no longer than a maximum. Faces that meet
along an edge must use the same ticks along it; scenes do that by building
every face of one surface from the same per-axis tick lists.

``open_edge_count`` and ``signed_volume`` check a Blender mesh: a closed
surface has no open edges, a solid encloses a positive volume and a cavity a
negative one.
"""

import math
from collections import Counter

import bpy

AXES = "xyz"
WELD_DIGITS = 6  # vertices closer than a micrometre are one vertex


def ticks(lo, hi, max_cell, breakpoints=(), max_cell_between=None):
    """Sorted coordinates from lo to hi: the breakpoints inside (lo, hi), every segment cut
    into equal cells of at most max_cell. max_cell_between(a, b), when given, chooses the
    cell size per segment (it overrides max_cell)."""
    stops = sorted({lo, hi, *(b for b in breakpoints if lo < b < hi)})
    out = [lo]
    for a, b in zip(stops, stops[1:]):
        cell = max_cell_between(a, b) if max_cell_between else max_cell
        cells = max(1, math.ceil((b - a) / cell - 1e-9))
        out.extend(a + (b - a) * (i + 1) / cells for i in range(cells))
    out[-1] = hi
    return out


class SolidMesh:
    """Vertices (welded), quads and their material slots, ready for a Blender mesh."""

    def __init__(self):
        self.vertices = []
        self.faces = []
        self.face_materials = []
        self._index = {}

    def vertex(self, position):
        key = tuple(round(c, WELD_DIGITS) for c in position)
        index = self._index.get(key)
        if index is None:
            index = self._index[key] = len(self.vertices)
            self.vertices.append(tuple(float(c) for c in position))
        return index

    def rectangle(self, axis, value, normal_sign, ticks_a, ticks_b, material=0, skip=None):
        """Quads on the plane <axis> = value spanning ticks_a x ticks_b along the two other axes
        (in cyclic order after `axis`), facing +axis (normal_sign 1) or -axis (-1).
        skip(center) -> True leaves a cell out (an opening)."""
        k = AXES.index(axis) if isinstance(axis, str) else axis
        a, b = (k + 1) % 3, (k + 2) % 3

        def point(u, v):
            p = [0.0, 0.0, 0.0]
            p[k], p[a], p[b] = value, u, v
            return p

        for j in range(len(ticks_b) - 1):
            for i in range(len(ticks_a) - 1):
                u0, u1, v0, v1 = ticks_a[i], ticks_a[i + 1], ticks_b[j], ticks_b[j + 1]
                if skip is not None and skip(point(0.5 * (u0 + u1), 0.5 * (v0 + v1))):
                    continue
                quad = [self.vertex(point(u0, v0)), self.vertex(point(u1, v0)), self.vertex(point(u1, v1)),
                        self.vertex(point(u0, v1))]
                if normal_sign < 0:
                    quad.reverse()  # e_a x e_b = +e_axis for cyclic (a, b, axis)
                self.faces.append(tuple(quad))
                self.face_materials.append(material)

    def box(self, lo, hi, axis_ticks, inward=False, materials=None, skip=None):
        """The six faces of the box [lo, hi]. axis_ticks[i] are the grid lines along axis i
        (from lo[i] to hi[i]). inward: normals point into the box (a cavity).
        materials: {(axis, side): slot} with side 0 for the lo face, 1 for the hi face
        (default slot 0). skip(axis, side, center) -> True leaves a cell out."""
        materials = materials or {}
        for k in range(3):
            a, b = (k + 1) % 3, (k + 2) % 3
            for side, value in ((0, lo[k]), (1, hi[k])):
                outward = 1 if side == 1 else -1
                skip_cell = None
                if skip is not None:
                    skip_cell = (lambda k_, s_: (lambda c: skip(k_, s_, c)))(k, side)
                self.rectangle(k, value, -outward if inward else outward, axis_ticks[a], axis_ticks[b],
                               materials.get((k, side), 0), skip_cell)

    def to_object(self, name, materials, collection):
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata(self.vertices, [], self.faces)
        mesh.update()
        for material in materials:
            mesh.materials.append(material)
        mesh.polygons.foreach_set("material_index", self.face_materials)
        mesh.polygons.foreach_set("use_smooth", [False] * len(self.faces))  # flat: corners share the face normal
        mesh.update()
        obj = bpy.data.objects.new(name, mesh)
        collection.objects.link(obj)
        return obj


def box_ticks(lo, hi, max_cell):
    """Per-axis grid lines of a box with cells of at most max_cell."""
    return [ticks(lo[i], hi[i], max_cell) for i in range(3)]


def solid_box(name, lo, hi, max_cell, material, collection):
    """A closed box object [lo, hi] facing outwards, one material."""
    solid = SolidMesh()
    solid.box(lo, hi, box_ticks(lo, hi, max_cell))
    return solid.to_object(name, [material], collection)


def open_edge_count(mesh):
    """Edges not used exactly once in each direction by the faces (0 for a closed, consistently
    oriented 2-manifold surface)."""
    directed = Counter()
    for polygon in mesh.polygons:
        vertices = list(polygon.vertices)
        for i, v in enumerate(vertices):
            directed[(v, vertices[(i + 1) % len(vertices)])] += 1
    bad = 0
    for (u, v), count in directed.items():
        if count != 1 or directed.get((v, u), 0) != 1:
            bad += 1
    return bad


def signed_volume(obj):
    """Volume enclosed by a mesh object's faces in world space (divergence theorem over its
    triangles): positive for an outward-facing closed surface, negative for a cavity."""
    matrix = obj.matrix_world
    positions = [matrix @ v.co for v in obj.data.vertices]
    total = 0.0
    for polygon in obj.data.polygons:
        vs = [positions[i] for i in polygon.vertices]
        for i in range(1, len(vs) - 1):
            total += vs[0].dot(vs[i].cross(vs[i + 1])) / 6.0
    return total


def triangle_count(objects):
    """Triangles of the mesh objects after triangulation (a quad is two, an n-gon n - 2)."""
    return sum(len(p.vertices) - 2 for o in objects if o.type == "MESH" for p in o.data.polygons)


def mean_albedo(objects, albedo_of_material, exclude_material=None):
    """Area-weighted mean diffuse reflectance (mean of R, G, B) over the mesh objects' faces in
    world space. albedo_of_material(material) -> (r, g, b); faces whose material is
    exclude_material are left out. Returns (mean, area)."""
    weighted, total = 0.0, 0.0
    for obj in objects:
        if obj.type != "MESH":
            continue
        matrix = obj.matrix_world
        positions = [matrix @ v.co for v in obj.data.vertices]
        slots = list(obj.data.materials)
        for polygon in obj.data.polygons:
            material = slots[polygon.material_index]
            if exclude_material is not None and material == exclude_material:
                continue
            vs = [positions[i] for i in polygon.vertices]
            area = sum(((vs[i] - vs[0]).cross(vs[i + 1] - vs[0])).length / 2.0 for i in range(1, len(vs) - 1))
            weighted += area * sum(albedo_of_material(material)) / 3.0
            total += area
    return weighted / total, total
