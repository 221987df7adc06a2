# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes a finished bake into the meshes, and removes it again.

The result of each target becomes a FLOAT_COLOR attribute "BakeGI_Indirect" on its
original mesh (domain CORNER or POINT, alpha 1), made the active color attribute so that
the viewport's Attribute color shows it. A LIGHTMAP bake becomes one OpenEXR atlas (written
by the core, loaded as the image "BakeGI_Lightmap_<scene>") and, on each target object, the
custom properties that place its tile in the atlas (materials.LIGHTMAP_*). An object holds
one bake: writing one kind removes the other from it. Nothing is written before every
target has been checked: a bake whose meshes changed while it ran is refused as a whole.
"""

import os

import numpy as np

from . import materials
from .materials import ATTRIBUTE_NAME, LIGHTMAP_OFFSET, LIGHTMAP_SCALE, LIGHTMAP_WEIGHT
from .native import BakeGIError

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
    resolved = look_up_targets(data, targets)
    rgb = np.asarray(rgb, np.float32).reshape(-1, 3)
    for t, obj, mesh in resolved:
        _drop_lightmap(obj)
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


def lightmap_image_name(scene_name):
    return f"BakeGI_Lightmap_{scene_name}"


def lightmap_file_name(scene_name):
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in scene_name) or "scene"
    return f"BakeGI_Lightmap_{safe}.exr"


def write_lightmap(data, exported, rgb, path, scene_name, full_float=False, blend_path=""):
    """Writes the atlas of a LIGHTMAP bake to `path` (absolute; atomically, by the core),
    loads it as the scene's lightmap image and places every target's tile on it. Objects
    that had a tile in this scene's atlas from an earlier bake but are not in this one lose
    it (the atlas was rewritten without them). Returns (image, [names of objects dropped])."""
    import bpy

    resolved = look_up_targets(data, exported.targets)
    lightmaps = exported.lightmaps
    folder = os.path.dirname(path)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as error:
        raise BakeGIError("BAKEGI_ERROR_IO", f"cannot create the lightmap folder {folder}: "
                          f"{error.strerror}")
    lightmaps.lightmaps.write_exr(0, rgb, path, padding=lightmaps.options.padding,
                                  full_float=full_float)
    name = lightmap_image_name(scene_name)
    image = data.images.get(name)
    stored_path = bpy.path.relpath(path) if blend_path else path
    if image is None or image.source != "FILE":
        image = data.images.load(path, check_existing=False)
        image.name = name
    image.filepath = stored_path
    image.reload()
    baked = {t.object_name for t, _, _ in resolved}
    dropped = []
    for obj in data.objects:
        if obj.name not in baked and obj.get(LIGHTMAP_WEIGHT) is not None and \
                obj.get("bakegi_lightmap_image") == name:
            _drop_lightmap(obj)
            dropped.append(obj.name)
    for t, obj, mesh in resolved:
        su, sv, ou, ov = t.atlas_scale_offset
        obj[LIGHTMAP_SCALE] = [float(su), float(sv), 1.0]
        obj[LIGHTMAP_OFFSET] = [float(ou), float(ov), 0.0]
        obj[LIGHTMAP_WEIGHT] = 1.0
        obj["bakegi_lightmap_image"] = name
        attribute = mesh.color_attributes.get(ATTRIBUTE_NAME)
        if attribute is not None:
            mesh.color_attributes.remove(attribute)
            mesh.update()
        obj.update_tag()
    return image, dropped


def _drop_lightmap(obj):
    for key in LIGHTMAP_PROPERTIES + ("bakegi_lightmap_image",):
        if key in obj.keys():
            del obj[key]


def _has_lightmap(obj):
    return obj.get(LIGHTMAP_WEIGHT) is not None


def hook_materials(data, material_infos, targets, lightmap_image=None, uv_map="BakeGI"):
    """Hooks the materials (name_full -> MaterialInfo) used by the targets (and points hooked
    ones at lightmap_image, if given); returns the names of the materials hooked now."""
    used = set()
    for t, obj, mesh in look_up_targets(data, targets):
        for m in list(mesh.materials) + [s.material for s in obj.material_slots]:
            if m is not None:
                used.add(m.name_full)
    hooked = []
    for material in data.materials:
        info = material_infos.get(material.name_full)
        if info is None or material.name_full not in used:
            continue
        if materials.hook(material, info, lightmap_image, uv_map):
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
            _drop_lightmap(obj)
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
        if materials.is_hooked(material) and material.name_full not in still_baked:
            if materials.unhook(material):
                unhooked.append(material.name)
    return {"objects": cleared, "materials": unhooked}
