# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's preferences (Edit > Preferences > Add-ons > BakeGI): what belongs to the
machine rather than to a .blend file: threads, the memory budget, the meshless cache folder.

`current()` returns them (or their defaults where the add-on is not registered, e.g. when
only its modules are imported)."""

import os
from dataclasses import dataclass

import bpy
from bpy.props import IntProperty, StringProperty

from .. import compat

# "bakegi" as a legacy add-on, "bl_ext.<repository>.bakegi" as an extension (4.2+): the
# package above this ui/ folder.
PACKAGE = __package__.rpartition(".")[0]


class BakeGIPreferences(bpy.types.AddonPreferences):
    bl_idname = PACKAGE

    threads: IntProperty(
        name="Threads", default=0, min=0, max=1024,
        description="Threads of a bake; 0 uses every core")
    memory_budget_mb: IntProperty(
        name="Memory Budget (MB)", default=0, min=0, max=1 << 20,
        description="Most memory a bake may use; a method that needs more coarsens or hands "
        "the scene to the path tracer, and a lightmap that needs more is refused before it "
        "is made. 0 = automatic (the core's default)")
    cache_folder: StringProperty(
        name="Meshless Cache Folder", default="", subtype="DIR_PATH",
        description="Where meshless precomputations are kept for reuse. Empty: a "
        "bakegi_cache folder next to the .blend file, or, for a file never saved, in the "
        "add-on's own user folder")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "threads")
        layout.prop(self, "memory_budget_mb")
        layout.prop(self, "cache_folder")
        layout.label(text="Unsaved files keep caches and lightmaps in " + compat.user_folder(""),
                     icon="INFO")


@dataclass
class Preferences:
    threads: int = 0
    memory_budget_mb: int = 0
    cache_folder: str = ""


def current(context=None):
    """The preferences as plain values (defaults when the add-on is not registered)."""
    context = context or bpy.context
    addon = context.preferences.addons.get(PACKAGE)
    prefs = getattr(addon, "preferences", None)
    if prefs is None:
        return Preferences()
    return Preferences(threads=prefs.threads, memory_budget_mb=prefs.memory_budget_mb,
                       cache_folder=os.path.abspath(bpy.path.abspath(prefs.cache_folder))
                       if prefs.cache_folder else "")


def register():
    bpy.utils.register_class(BakeGIPreferences)


def unregister():
    bpy.utils.unregister_class(BakeGIPreferences)
