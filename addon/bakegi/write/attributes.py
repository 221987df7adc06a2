# SPDX-License-Identifier: GPL-3.0-or-later
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes a finished bake into the meshes' color attributes, and removes a bake again.

The result of each target becomes a FLOAT_COLOR attribute "BakeGI_Indirect" on its
original mesh (domain CORNER or POINT, alpha 1), made the active color attribute so that
the viewport's Attribute color shows it. A LIGHTMAP bake becomes one OpenEXR atlas (written
by the core, loaded as the image "BakeGI_Lightmap_<scene>") and, on each target object, the
custom properties that place its tile in the atlas (material_hook.LIGHTMAP_*). An object holds
one bake: writing one kind removes the other from it. Nothing is written before every
target has been checked: a bake whose meshes changed while it ran is refused as a whole.
"""

import numpy as np

from ..native import BakeGIError
from . import material_hook
from .material_hook import ATTRIBUTE_NAME, LIGHTMAP_OFFSET, LIGHTMAP_SCALE, LIGHTMAP_WEIGHT


LIGHTMAP_PROPERTIES = (LIGHTMAP_SCALE, LIGHTMAP_OFFSET, LIGHTMAP_WEIGHT)


def look_up_targets(data, targets):
    """[(target, original mesh)] looked up by name; raises BakeGIError if a target's mesh
    can no longer take its slice of the result (object deleted, mesh replaced or edited
    into another topology, Edit Mode)."""
    resolved = []
    for t in targets:
        obj = data.objects.get(t.object_name)
        if obj is None or obj.type != "MESH":
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"'{t.object_name}' was deleted during the bake; nothing was "
                              "written")
        mesh = obj.data
        if mesh.name_full != t.mesh_name:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"'{t.object_name}': its mesh was replaced during the bake; "
                              "nothing was written")
        if getattr(mesh, "is_editmode", False):
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"'{t.object_name}' is in Edit Mode; leave it to write the bake")
        if t.domain == "LIGHTMAP":  # texels on the UV map: any topology still takes them
            resolved.append((t, obj, mesh))
            continue
        # Both targets are baked at corners; a vertex target also writes per vertex.
        counts = [("corners", t.count, len(mesh.loops))]
        if t.domain == "POINT":
            counts.append(("vertices", t.vertex_count, len(mesh.vertices)))
        for what, then, now in counts:
            if then != now:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  f"'{t.object_name}': its mesh changed during the bake ({then} "
                                  f"{what} then, {now} now); nothing was written")
        resolved.append((t, obj, mesh))
    return resolved


def vertex_means(values, vertex_of_point, vertex_count):
    """Each vertex's mean of its points' values (0 for a vertex of no face), as Cycles
    writes a vertex colour from the face corners it bakes."""
    sums = np.stack([np.bincount(vertex_of_point, weights=values[:, c], minlength=vertex_count)
                     for c in range(3)], axis=1)
    counts = np.bincount(vertex_of_point, minlength=vertex_count)[:, None]
    return (sums / np.maximum(counts, 1)).astype(np.float32)


def target_values(t, rgb):
    """A target's values on its domain: its slice of the bake, per vertex for 'POINT'."""
    values = rgb[t.start:t.start + t.count]
    if t.domain == "POINT":
        values = vertex_means(values, t.vertex_of_point, t.vertex_count)
    return values


def write_results(data, targets, rgb):
    """rgb: (points, 3) float32 in the order of the targets' slices. All targets are
    checked before anything is written."""
    resolved = look_up_targets(data, targets)
    rgb = np.asarray(rgb, np.float32).reshape(-1, 3)
    for t, obj, mesh in resolved:
        drop_lightmap(obj)
        values = target_values(t, rgb)
        rgba = np.ones((len(values), 4), np.float32)
        rgba[:, :3] = values
        attributes = mesh.color_attributes
        existing = attributes.get(ATTRIBUTE_NAME)
        if existing is not None and (existing.domain != t.domain or
                                     existing.data_type != "FLOAT_COLOR"):
            attributes.remove(existing)
            existing = None
        attribute = existing or attributes.new(ATTRIBUTE_NAME, "FLOAT_COLOR", t.domain)
        attribute.data.foreach_set("color", rgba.reshape(-1))
        attributes.active_color = attribute
        mesh.update()


def drop_lightmap(obj):
    for key in LIGHTMAP_PROPERTIES + ("bakegi_lightmap_image",):
        if key in obj.keys():
            del obj[key]


def _has_lightmap(obj):
    return obj.get(LIGHTMAP_WEIGHT) is not None


def _mesh_objects(data, objects):
    if objects is None:
        return [o for o in data.objects if o.type == "MESH"]
    out = []
    for item in objects:
        obj = data.objects.get(item) if isinstance(item, str) else item
        if obj is None:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"no object named {item!r}")
        if obj.type == "MESH":
            out.append(obj)
    return out


def _has_bake(obj):
    return obj.data.color_attributes.get(ATTRIBUTE_NAME) is not None or _has_lightmap(obj)


def remove_bake(data, objects=None):
    """Removes BakeGI_Indirect from the objects' meshes (all meshes if objects is None) and
    their lightmap tiles, and unhooks their materials, except materials still used by
    another baked object. The lightmap files and UV maps stay (they are the user's now).
    Returns {"objects": [...], "materials": [...]} of what was changed."""
    cleared = []
    for obj in _mesh_objects(data, objects):
        mesh = obj.data
        attribute = mesh.color_attributes.get(ATTRIBUTE_NAME)
        changed = False
        if attribute is not None and mesh.library is None:
            mesh.color_attributes.remove(attribute)
            mesh.update()
            changed = True
        if _has_lightmap(obj):
            drop_lightmap(obj)
            obj.update_tag()
            changed = True
        if changed:
            cleared.append(obj.name)
    still_baked = set()
    for obj in data.objects:
        if obj.type == "MESH" and _has_bake(obj):
            for slot in obj.material_slots:
                if slot.material is not None:
                    still_baked.add(slot.material.name_full)
    unhooked = []
    for material in data.materials:
        if material_hook.is_hooked(material) and material.name_full not in still_baked:
            if material_hook.unhook(material):
                unhooked.append(material.name)
    return {"objects": cleared, "materials": unhooked}
