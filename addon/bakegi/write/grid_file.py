# SPDX-License-Identifier: GPL-3.0-or-later
"""The Irradiance Vector Grid in Blender (docs/ivg.md): where a GRID bake writes its .bgivg
file, the box a grid object spans, and Apply Grid: BakeGI_Indirect on any meshes from a
baked grid, without baking them."""

import os
import time

import numpy as np

from .. import native
from ..export import materials, points as export_points
from ..export.targets import BakeTarget, with_surface
from . import attributes, material_hook
from .file_names import baked_file_name

# The custom property of the scene that names its newest grid file (what apply_grid reads
# when no path is given); set by every successful GRID bake.
GRID_PATH_PROPERTY = "bakegi_grid_path"


def grid_file_name(blend_path, scene_name, identity):
    """See file_names.baked_file_name: unique per .blend file and scene."""
    return baked_file_name("BakeGI_Grid", blend_path, scene_name, identity, ".bgivg")


def object_bounds(obj):
    """The world-space axis-aligned box of a grid object: an Empty's display cube
    (empty_display_size around its origin, through its transform) or any object's bound box."""
    if obj.type == "EMPTY":
        size = float(obj.empty_display_size)
        local = np.array([[x, y, z] for x in (-size, size) for y in (-size, size)
                          for z in (-size, size)], np.float64)
    else:
        local = np.array([tuple(corner) for corner in obj.bound_box], np.float64)
    matrix = np.array(obj.matrix_world, np.float64)
    world = local @ matrix[:3, :3].T + matrix[:3, 3]
    return tuple(world.min(axis=0).tolist()), tuple(world.max(axis=0).tolist())


def describe(info):
    """'32 x 32 x 32 cells (32,768 vertices), 2.00 x 2.00 x 2.00 m, cell 6.3 cm'."""
    res = info["resolution"]
    size = [hi - lo for lo, hi in zip(info["bounds_min"], info["bounds_max"])]
    cell = max(s / r for s, r in zip(size, res))
    cell_text = f"{cell * 100:.1f} cm" if cell < 1.0 else f"{cell:.2f} m"
    return (f"{res[0]} x {res[1]} x {res[2]} cells ({info['vertex_count']:,} vertices), "
            f"{size[0]:.2f} x {size[1]:.2f} x {size[2]:.2f} m, cell {cell_text}")


def apply_grid(data, depsgraph, objects, path, interpolation="TRILINEAR", domain="CORNER",
               hook_materials=True, scene=None, directional="ABSOLUTE", visibility=True,
               darken_buried=True):
    """Writes BakeGI_Indirect on `objects` (mesh objects) from the grid file at `path`: the
    grid's light at each face corner (or vertex), in world space as the objects stand now.
    Everything is read and evaluated before anything is written; hook_materials: their
    materials show it in Material Preview as after a bake. scene (a native.Scene of the
    visible objects as they stand): each point reads only the grid vertices it sees
    (visibility: no light through walls thinner than a cell), and points buried inside or
    under geometry (a floor under a box) read 0 (darken_buried), as a bake sees them; None:
    the grid's light as the paper reads it. Returns a report dict."""
    start = time.perf_counter()
    with native.Grid.read(path) as grid:
        info = grid.info()
        warnings, targets, positions, normals = [], [], [], []
        offset = 0
        for obj in with_surface(objects, warnings):
            points_of = export_points.target_points(obj, depsgraph, domain, warnings)
            count = len(points_of.positions)
            targets.append(BakeTarget(obj.name, obj.data.name_full, domain, offset, count,
                                      vertex_of_point=points_of.vertex_of_point,
                                      vertex_count=points_of.vertex_count))
            positions.append(points_of.positions)
            normals.append(points_of.normals)
            offset += count
        read = time.perf_counter()
        codes = np.zeros(offset, np.uint8)
        if not offset:
            rgb = np.zeros((0, 3), np.float32)
        elif scene is not None and (visibility or darken_buried):
            rgb, codes = grid.evaluate_in_scene(scene, np.concatenate(positions),
                                                np.concatenate(normals), interpolation,
                                                directional, visibility, darken_buried)
        else:
            rgb = grid.evaluate(np.concatenate(positions), np.concatenate(normals),
                                interpolation, directional)
        evaluated = time.perf_counter()
    attributes.write_results(data, targets, rgb)
    hooked = material_hook.hook_materials(data, _material_infos(objects), targets) \
        if hook_materials else []
    done = time.perf_counter()
    unsure = int(np.count_nonzero(codes == 1))
    if unsure:
        warnings.append(f"{unsure:,} of {offset:,} points see none of the grid vertices around "
                        "them and read them anyway: their light is unsure (a finer grid, or a "
                        "bake, holds it)")
    outside = _points_outside(np.concatenate(positions) if offset else np.zeros((0, 3)), info)
    if outside:
        warnings.append(f"{outside:,} of {offset:,} points lie outside the grid's box and take "
                        "the nearest grid vertices' light; bake a grid that covers them")
    return {"path": os.fspath(path), "objects": [t.object_name for t in targets],
            "points": offset, "interpolation": interpolation, "directional": directional,
            "grid": info,
            "warnings": warnings, "hooked_materials": hooked,
            "buried_points": int(np.count_nonzero(codes == 2)),
            "unsure_points": int(np.count_nonzero(codes == 1)),
            "seconds": {"read": read - start, "evaluate": evaluated - read,
                        "write": done - evaluated, "total": done - start}}


def _material_infos(objects):
    """What the material hook needs of the objects' materials (name_full -> MaterialInfo)."""
    infos = {}
    for obj in objects:
        for slot in obj.material_slots:
            material = slot.material
            if material is not None and material.name_full not in infos:
                infos[material.name_full] = materials.read_material(material)
    return infos


def _points_outside(positions, info):
    lo = np.asarray(info["bounds_min"], np.float32)
    hi = np.asarray(info["bounds_max"], np.float32)
    margin = 1e-4 * float(np.max(hi - lo))
    return int(np.count_nonzero(np.any((positions < lo - margin) | (positions > hi + margin),
                                       axis=1)))
