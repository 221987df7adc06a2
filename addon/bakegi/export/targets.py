# SPDX-License-Identifier: GPL-3.0-or-later
"""Which objects a bake reads and writes: the targets (selected, visible or named mesh
objects; the reasons others are skipped), linked duplicates and Make Single User."""

import re
from dataclasses import dataclass

import numpy as np

from ..native import BakeGIError


MESH_LIKE = {"MESH", "CURVE", "SURFACE", "META", "FONT"}
# Where a bake goes: a color attribute on face corners or vertices, or lightmap textures.


@dataclass
class BakeTarget:
    """One object whose mesh receives the bake, and its slice of the bake points."""

    # Names, not references: the result is written after the bake, and references do not
    # survive an undo (or a deletion) in between.
    object_name: str
    mesh_name: str  # name_full of the original mesh, where the attribute goes
    domain: str
    start: int
    count: int  # bake points: face corners for 'CORNER' and 'POINT', texels for 'LIGHTMAP'
    # LIGHTMAP only: (scale_u, scale_v, offset_u, offset_v) of its tile in the atlas, and the
    # tile's side in texels.
    atlas_scale_offset: tuple = ()
    tile_side: int = 0
    # 'POINT' only: the vertex of each of its points (corners), whose mean the vertex gets,
    # and the mesh's vertex count.
    vertex_of_point: object = None
    vertex_count: int = 0


def _by_index(names, kind):
    """A re.sub replacement: "<kind> 3" -> "<kind> '<names[3]>'" (left as it is past the end)."""
    def name(match):
        i = int(match.group(1))
        return f"{kind} '{names[i]}'" if i < len(names) else match.group(0)
    return name


def name_objects(message, object_names):
    """Puts Blender object names into a core message: "(object 3)" -> "(object 'Cube')"."""
    return re.sub(r"\bobject (\d+)", _by_index(object_names, "object"), message)


def name_elements(message, object_names, material_names=(), light_names=(), targets=()):
    """name_objects, and the core's other numbers for Blender's names: "material 1" ->
    "material 'Glass'", "light 0" -> "light 'Area'" (by the core's ids), "bake point 600" ->
    "bake point 600 (object 'Cube')" (by the targets' slices)."""
    message = name_objects(message, object_names)
    message = re.sub(r"\bmaterial (\d+)", _by_index(material_names, "material"), message)
    message = re.sub(r"\blight (\d+)", _by_index(light_names, "light"), message)

    def point(match):
        i = int(match.group(1))
        owner = next((t.object_name for t in targets if t.start <= i < t.start + t.count), None)
        return match.group(0) + (f" (object '{owner}')" if owner is not None else "")
    return re.sub(r"\bbake point (\d+)", point, message)


def with_surface(targets, skipped):
    """The targets whose transform keeps a surface: one scaled to 0 along an axis (a common
    way to hide an object in an animation) has no area and no normals to bake with; it is
    named in `skipped` (a list of reasons) and still takes part in the scene (as nothing)."""
    kept = []
    for obj in targets:
        m3 = np.array(obj.matrix_world, np.float64)[:3, :3]
        scale = max(float(np.abs(m3).max()), 1e-300)
        if abs(float(np.linalg.det(m3))) <= 1e-12 * scale ** 3:
            skipped.append(f"'{obj.name}' not baked: its scale is 0 along an axis, so it has no "
                           "surface to bake")
        else:
            kept.append(obj)
    return kept


def some_names(names, shown=5):
    """The first `shown` of `names` in order, joined for a report line ("A, B, C ...")."""
    names = sorted(names)
    return ", ".join(names[:shown]) + (" ..." if len(names) > shown else "")


# ---- which objects ----------------------------------------------------------------------


def resolve_targets(context, objects, shared_meshes=False):
    """objects: 'SELECTED', 'VISIBLE' or a list of objects or names. shared_meshes: objects
    that share a mesh are all baked (lightmaps: each object has its own tile); otherwise
    only the first of them (a color attribute lives on the mesh).
    Returns (mesh objects to bake, [reasons for skipped objects])."""
    view_layer = context.view_layer
    if objects == "SELECTED":
        candidates = list(context.selected_objects)
    elif objects == "VISIBLE":
        # (None entries: objects removed since the view layer was last updated)
        candidates = [o for o in view_layer.objects
                      if o is not None and o.visible_get(view_layer=view_layer)]
    elif isinstance(objects, str):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"objects must be 'SELECTED', 'VISIBLE' or a list, not {objects!r}")
    else:
        candidates = []
        data_objects = context.blend_data.objects
        for item in objects:
            obj = data_objects.get(item) if isinstance(item, str) else item
            if obj is None:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"no object named {item!r}")
            candidates.append(obj)
    targets, skipped, meshes = [], [], {}
    for obj in candidates:
        if obj.type != "MESH":
            if objects != "VISIBLE":
                skipped.append(f"'{obj.name}' skipped: a {obj.type.lower()}, not a mesh")
            continue
        if view_layer.objects.get(obj.name) is None or not obj.visible_get(
                view_layer=view_layer):
            skipped.append(f"'{obj.name}' skipped: not visible in the view layer")
            continue
        mesh = obj.data
        if mesh.library is not None or getattr(mesh, "override_library", None) is not None:
            skipped.append(f"'{obj.name}' skipped: its mesh is linked from a library")
            continue
        if len(mesh.polygons) == 0:
            skipped.append(f"'{obj.name}' skipped: its mesh has no faces")
            continue
        if mesh.name_full in meshes and not shared_meshes:
            skipped.append(f"'{obj.name}' not baked: it shares mesh '{mesh.name}' with "
                           f"'{meshes[mesh.name_full]}' and shows that object's light (Linked "
                           f"Duplicates: Make Single User bakes each)")
            continue
        meshes[mesh.name_full] = obj.name
        targets.append(obj)
    return targets, skipped


# What an attribute bake does with linked duplicates (objects sharing one mesh, which holds
# one color attribute for all of them).


def linked_duplicates(context, objects):
    """Target objects that share their mesh with an earlier target: [(object, the target it
    shares with)]. An attribute bake bakes only the first of each group."""
    targets, _ = resolve_targets(context, objects, shared_meshes=True)
    first, shared = {}, []
    for obj in targets:
        key = obj.data.name_full
        if key in first:
            shared.append((obj, first[key]))
        else:
            first[key] = obj
    return shared


def make_single_users(context, objects):
    """Gives every linked duplicate among the targets its own copy of the mesh (Blender's
    Make Single User), so that each is baked with its own light. Returns [(object, shared
    mesh, copy)] for undo_single_users."""
    made = []
    for obj, _ in linked_duplicates(context, objects):
        shared = obj.data
        copy = shared.copy()
        obj.data = copy
        made.append((obj, shared, copy))
    return made


def undo_single_users(data, made):
    """Puts the shared meshes back and deletes the copies (a bake that failed or was
    cancelled leaves the scene as it was)."""
    for obj, shared, copy in reversed(made):
        try:
            obj.data = shared
            if copy.users == 0:
                data.meshes.remove(copy)
        except ReferenceError:  # the object or mesh was deleted meanwhile
            pass
