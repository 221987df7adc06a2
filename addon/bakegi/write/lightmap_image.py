# SPDX-License-Identifier: GPL-3.0-or-later
"""The lightmap image of a LIGHTMAP bake: the atlas written as an OpenEXR file by the core
(atomically; on a worker thread, into a staging file the session renames over the lightmap's
file when it commits), loaded as the image "BakeGI_Lightmap_<scene>", and each target's tile
placed on its object (custom properties material_hook.LIGHTMAP_*)."""

import os
import time
import uuid

from ..native import BakeGIError
from .attributes import drop_lightmap, look_up_targets
from .file_names import baked_file_name
from .material_hook import ATTRIBUTE_NAME, LIGHTMAP_OFFSET, LIGHTMAP_SCALE, LIGHTMAP_WEIGHT


def lightmap_image_name(scene_name):
    return f"BakeGI_Lightmap_{scene_name}"


def lightmap_file_name(blend_path, scene_name, identity):
    """See file_names.baked_file_name: unique per .blend file and scene."""
    return baked_file_name("BakeGI_Lightmap", blend_path, scene_name, identity, ".exr")


STAGING_PREFIX = ".bakegi_pending_"
# A staging file this old is a leftover of a Blender that was killed before it committed.
STALE_STAGING_SECONDS = 600.0


def staging_path(folder):
    """A fresh staging file name in `folder` (hidden, unique per write)."""
    return os.path.join(folder, f"{STAGING_PREFIX}{os.getpid()}_{uuid.uuid4().hex[:8]}.exr")


def write_lightmap_file(exported, rgb, path, full_float=False):
    """Writes the atlas of a LIGHTMAP bake to `path` (absolute; atomically, by the core, which
    stops with BAKEGI_ERROR_CANCELLED when the lightmaps are cancelled). No bpy: runs on a
    worker thread. Removes staging files of killed sessions from the folder."""
    lightmaps = exported.lightmaps
    folder = os.path.dirname(path)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as error:
        raise BakeGIError("BAKEGI_ERROR_IO", f"cannot create the lightmap folder {folder}: "
                          f"{error.strerror}")
    _remove_stale_staging_files(folder)
    lightmaps.lightmaps.write_exr(0, rgb, path, padding=lightmaps.options.padding,
                                  full_float=full_float)


def _remove_stale_staging_files(folder):
    now = time.time()
    for entry in os.scandir(folder):
        if entry.name.startswith(STAGING_PREFIX) and entry.name.endswith(".exr"):
            try:
                if now - entry.stat().st_mtime > STALE_STAGING_SECONDS:
                    os.remove(entry.path)
            except OSError:
                pass


def place_lightmap(data, exported, path, scene_name, blend_path=""):
    """Loads the atlas at `path` as the scene's lightmap image and places every target's tile
    on it. Objects that had a tile in this scene's atlas from an earlier bake but are not in
    this one lose it (the atlas was rewritten without them). Returns (image, [names of objects
    dropped])."""
    import bpy

    resolved = look_up_targets(data, exported.targets)
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
            drop_lightmap(obj)
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
