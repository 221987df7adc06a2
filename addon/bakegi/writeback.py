# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes a finished bake into the meshes, and removes it again.

The result of each target becomes a FLOAT_COLOR attribute "BakeGI_Indirect" on its
original mesh (domain CORNER or POINT, alpha 1), made the active color attribute so that
the viewport's Attribute color shows it. Nothing is written before every target has been
checked: a bake whose meshes changed while it ran is refused as a whole.
"""

import numpy as np

from . import materials
from .materials import ATTRIBUTE_NAME
from .native import BakeGIError


def resolve_targets(data, targets):
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
        count = len(mesh.loops) if t.domain == "CORNER" else len(mesh.vertices)
        if count != t.count:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"'{t.object_name}': its mesh changed during the bake ({t.count} "
                              f"{'corners' if t.domain == 'CORNER' else 'vertices'} then, "
                              f"{count} now); nothing was written")
        resolved.append((t, obj, mesh))
    return resolved


def write_results(data, targets, rgb):
    """rgb: (points, 3) float32 in the order of the targets' slices. All targets are
    checked before anything is written."""
    resolved = resolve_targets(data, targets)
    rgb = np.asarray(rgb, np.float32).reshape(-1, 3)
    for t, _, mesh in resolved:
        rgba = np.ones((t.count, 4), np.float32)
        rgba[:, :3] = rgb[t.start:t.start + t.count]
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


def hook_materials(data, material_infos, targets):
    """Hooks the materials (name_full -> MaterialInfo) used by the targets; returns the
    names of the materials hooked."""
    used = set()
    for t, obj, mesh in resolve_targets(data, targets):
        for m in list(mesh.materials) + [s.material for s in obj.material_slots]:
            if m is not None:
                used.add(m.name_full)
    hooked = []
    for material in data.materials:
        info = material_infos.get(material.name_full)
        if info is not None and material.name_full in used and materials.hook(material, info):
            hooked.append(material.name)
    return hooked


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


def _has_bake(mesh):
    return mesh.color_attributes.get(ATTRIBUTE_NAME) is not None


def remove_bake(data, objects=None):
    """Removes BakeGI_Indirect from the objects' meshes (all meshes if objects is None) and
    unhooks their materials, except materials still used by another baked mesh.
    Returns {"objects": [...], "materials": [...]} of what was changed."""
    cleared = []
    for obj in _mesh_objects(data, objects):
        mesh = obj.data
        attribute = mesh.color_attributes.get(ATTRIBUTE_NAME)
        if attribute is not None and mesh.library is None:
            mesh.color_attributes.remove(attribute)
            mesh.update()
            cleared.append(obj.name)
    still_baked = set()
    for obj in data.objects:
        if obj.type == "MESH" and _has_bake(obj.data):
            for slot in obj.material_slots:
                if slot.material is not None:
                    still_baked.add(slot.material.name_full)
    unhooked = []
    for material in data.materials:
        if materials.is_hooked(material) and material.name_full not in still_baked:
            if materials.unhook(material):
                unhooked.append(material.name)
    return {"objects": cleared, "materials": unhooked}
