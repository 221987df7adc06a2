# SPDX-License-Identifier: GPL-3.0-or-later
"""The part of a file or folder name that comes from a Blender name (a scene's): letters,
digits, '-', '_' and '.' kept, anything else '_', so that every system can hold it."""


def safe_name(name, fallback="scene"):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name) or fallback
