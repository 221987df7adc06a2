# SPDX-License-Identifier: GPL-3.0-or-later
"""The precomputation cache folder as the panel shows it: how many cache files (*.bgcache)
it holds and their size, and clearing them. The core keeps the folder under its size cap
itself (setting cache_max_mb: the least recently used files go after each save); this is
for the user who wants the space back now. No bpy: tested without Blender."""

import os

CACHE_SUFFIX = ".bgcache"


def _cache_files(folder):
    try:
        with os.scandir(folder) as entries:
            return [e for e in entries if e.name.endswith(CACHE_SUFFIX) and e.is_file()]
    except OSError:  # missing or unreadable: nothing cached
        return []


def usage(folder):
    """(number of cache files, their bytes) in `folder`."""
    files = _cache_files(folder)
    total = 0
    for entry in files:
        try:
            total += entry.stat().st_size
        except OSError:  # deleted meanwhile (another Blender's eviction)
            pass
    return len(files), total


def clear(folder):
    """Deletes the cache files of `folder` (nothing else); returns how many went."""
    removed = 0
    for entry in _cache_files(folder):
        try:
            os.remove(entry.path)
            removed += 1
        except OSError:
            pass
    return removed


def describe(folder):
    """'3 files, 45.2 MB' or 'empty'."""
    count, total = usage(folder)
    if count == 0:
        return "empty"
    return f"{count} file{'s' if count != 1 else ''}, {total / 1e6:.1f} MB"
