# SPDX-License-Identifier: GPL-3.0-or-later
"""File names made from Blender names, and the names of the files a bake writes.

safe_name: the part of a file or folder name that comes from a Blender name (a scene's):
letters, digits, '-', '_' and '.' kept, anything else '_', so that every system can hold it
(and "../../x" cannot leave the folder the user chose).

baked_file_name: a lightmap or grid file is named by the .blend file, the scene and an
identifier the scene keeps (FILE_ID_PROPERTY, made on its first such bake and saved with the
.blend), so that two .blend files baking into one folder, or two unsaved files sharing the
temporary folder, never overwrite each other's files; the same scene of the same file
replaces its own file on every bake."""

import os
import uuid

FILE_ID_PROPERTY = "bakegi_file_id"


def safe_name(name, fallback="scene"):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name) or fallback


def file_identity(scene):
    """The scene's identifier for its baked files (8 hex digits), made on first use."""
    identity = scene.get(FILE_ID_PROPERTY)
    if not isinstance(identity, str) or len(identity) != 8:
        identity = uuid.uuid4().hex[:8]
        scene[FILE_ID_PROPERTY] = identity
    return identity


def baked_file_name(prefix, blend_path, scene_name, identity, extension):
    """"<prefix>_<.blend name>_<scene>_<identity><extension>"; an unsaved file is "untitled"."""
    stem = os.path.splitext(os.path.basename(blend_path))[0] if blend_path else "untitled"
    return (f"{prefix}_{safe_name(stem, 'untitled')}_{safe_name(scene_name)}_"
            f"{safe_name(identity, 'x')}{extension}")
