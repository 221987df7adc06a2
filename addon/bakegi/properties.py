# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake settings stored on the scene: bpy.types.Scene.bakegi."""

import bpy
import os
import tempfile

from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

# The first item is the default: antiradiance reaches every error level of the Cornell chart
# 2-5x sooner than the path tracer (docs/methods/antiradiance.md).
METHOD_ITEMS = [
    ("antiradiance", "Antiradiance", "Dachsbacher et al. 2007: light exchanged between "
     "surface patches through directional bins, occlusion by antiradiance instead of "
     "visibility rays; fast and smooth, biased by patch size and bin count"),
    ("pathtrace", "Path Tracing", "Monte Carlo reference: converges to the exact indirect "
     "light; noise falls as samples grow"),
    ("meshless", "Meshless (Live)", "Lehtinen et al. 2008: precomputes how direct light "
     "becomes indirect light once, then relights in milliseconds; with Live Indirect the "
     "bake follows the lights as they move"),
]
# Debug only: bakes the DIRECT light (to check light units against Cycles), not indirect.
DEBUG_METHOD_ITEMS = METHOD_ITEMS + [
    ("direct", "Direct Light (debug)", "Bakes direct light instead of indirect light, to "
     "compare light units with Cycles"),
]

TARGET_ITEMS = [
    ("CORNER", "Face Corners", "One value per face corner: hard edges stay hard"),
    ("POINT", "Vertices", "One value per vertex: smooth across edges, fewer points"),
]

OBJECTS_ITEMS = [
    ("SELECTED", "Selected", "Bake the selected mesh objects"),
    ("VISIBLE", "All Visible", "Bake every visible mesh object"),
]


def _method_items(self, context):
    return DEBUG_METHOD_ITEMS if self.show_debug else METHOD_ITEMS


def _live_toggled(self, context):
    if not self.live_indirect:
        from . import live
        live.stop()


class BakeGISettings(bpy.types.PropertyGroup):
    show_debug: BoolProperty(
        name="Debug Methods", default=False,
        description="Offer methods meant for checking the add-on rather than for baking")
    method: EnumProperty(name="Method", items=_method_items,
                         description="How the indirect light is computed")
    samples: IntProperty(name="Samples", default=64, min=1, soft_max=4096,
                         description="Paths per bake point: more is slower and less noisy")
    bins: IntProperty(name="Bins", default=300, min=12, max=3072,
                      description="Antiradiance: directional bins per element; more bins "
                      "sharpen indirect shadows and cost memory and time")
    iterations: IntProperty(name="Iterations", default=32, min=1, soft_max=256,
                            description="Antiradiance: light bounces at most (stops early "
                            "once converged)")
    meshless_levels: IntProperty(
        name="Levels", default=0, min=0, max=8,
        description="Meshless: levels of the hierarchical basis; more resolve finer indirect "
        "detail and cost time and memory (0 = automatic, 4)")
    meshless_epsilon: FloatProperty(
        name="Link Threshold", default=0.01, min=0.0, soft_max=0.1, precision=3, step=0.1,
        description="Meshless: links that carry less than this are dropped; lower is more "
        "accurate and uses more memory (the paper used 0.025)")
    live_indirect: BoolProperty(
        name="Live Indirect", default=False, update=_live_toggled,
        description="Meshless: after a bake, relight BakeGI_Indirect whenever a light or the "
        "world changes (meshes and materials must stay as baked)")
    use_cache: BoolProperty(
        name="Cache Precomputation", default=True,
        description="Meshless: save the precomputed basis and transfer, so that baking the "
        "same geometry, materials and settings again (after reopening the file, too) skips "
        "the precompute; a changed scene is detected and computed again")
    cache_folder: StringProperty(
        name="Cache Folder", default="//bakegi_cache", subtype="DIR_PATH",
        description="Where the meshless cache is kept (// = next to the .blend; an unsaved "
        "file uses the system's temporary folder)")
    seed: IntProperty(name="Seed", default=0, min=0,
                      description="Random seed; a bake is repeatable for a seed")
    target: EnumProperty(name="Target", items=TARGET_ITEMS, default="CORNER",
                         description="Where the color attribute BakeGI_Indirect is stored")
    objects: EnumProperty(name="Objects", items=OBJECTS_ITEMS, default="SELECTED",
                          description="Which objects receive the bake (every visible object "
                          "always takes part in the light transport)")
    threads: IntProperty(name="Threads", default=0, min=0, max=1024,
                         description="Threads of the bake; 0 uses every core")
    hook_materials: BoolProperty(
        name="Show in Material Preview", default=True,
        description="Add nodes to the baked objects' materials so that Material Preview "
        "shows albedo x (direct + baked indirect); Remove Bake restores them")
    # Written by a successful bake (a cancelled or failed one leaves the scene untouched).
    last_result: StringProperty(name="Last Result", default="",
                                description="Summary of the last successful bake")
    last_report: StringProperty(name="Last Report", default="",
                                description="JSON report of the last successful bake")

    def resolved_method(self):
        if self.show_debug or self.method in {item[0] for item in METHOD_ITEMS}:
            return self.method
        return METHOD_ITEMS[0][0]

    def method_settings(self):
        """Core settings that only the resolved method reads."""
        method = self.resolved_method()
        if method == "antiradiance":
            return {"bins": self.bins, "iterations": self.iterations}
        if method == "meshless":
            settings = {"levels": self.meshless_levels, "epsilon": self.meshless_epsilon}
            if self.use_cache:
                settings["cache_dir"] = self.cache_directory()
            return settings
        return {}

    def cache_directory(self):
        """The cache folder as an absolute path."""
        folder = self.cache_folder or "//bakegi_cache"
        if folder.startswith("//") and not bpy.data.filepath:
            return os.path.join(tempfile.gettempdir(), "bakegi_cache")
        return os.path.abspath(bpy.path.abspath(folder))

    def live_requested(self):
        return self.live_indirect and self.resolved_method() == "meshless"


def register():
    bpy.utils.register_class(BakeGISettings)
    bpy.types.Scene.bakegi = bpy.props.PointerProperty(type=BakeGISettings)


def unregister():
    del bpy.types.Scene.bakegi
    bpy.utils.unregister_class(BakeGISettings)
