# SPDX-License-Identifier: GPL-3.0-or-later
"""bakegi: bakes indirect global illumination into color attributes.

In Blender (the add-on enabled, e.g. `blender -b file.blend --addons bakegi`):

    import bakegi
    report = bakegi.bake(method="pathtrace", samples=64, target="CORNER")

Public API: bake, apply_grid, export_scene_file, remove_bake, live_update, live_stop,
BakeGIError; operators bpy.ops.bakegi.bake_indirect, remove_bake, add_grid_box and
apply_grid; settings scene.bakegi (scene.bakegi.grid_follow: objects lit by apply_grid are
lit again when they move; bakegi.grid_follow.update() does it at once in scripts).

Without Blender (plain Python) only the bpy-free modules are importable:
bakegi.light_units and bakegi.native.
"""

bl_info = {
    "name": "BakeGI",
    "author": "bakegi developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > BakeGI Indirect Light",
    "description": "Bakes indirect global illumination into color attributes",
    "category": "Render",
}

import sys

from .native import BakeGIError  # noqa: E402  (bpy-free)

try:
    import bpy  # noqa: F401
except ImportError:  # plain Python: tests of the bpy-free modules
    bpy = None

__all__ = ["BakeGIError"]
if bpy is not None:
    from .api import (apply_grid, bake, export_scene_file, export_web, live_stop,  # noqa: E402
                      live_update, remove_bake, simplify_copy, subdivide_copy)

    __all__ += ["apply_grid", "bake", "export_scene_file", "export_web", "live_stop",
                "live_update", "remove_bake", "simplify_copy", "subdivide_copy"]

_MODULES = ("ui.preferences", "ui.properties", "ui.operators", "ui.panels", "live",
            "grid_follow", "preview")


def register():
    import importlib

    for name in _MODULES:
        importlib.import_module(f".{name}", __name__).register()
    # Installed as a Blender 4.2+ extension the package is bl_ext.<repository>.bakegi;
    # make `import bakegi` work there too.
    if __name__ != "bakegi" and "bakegi" not in sys.modules:
        sys.modules["bakegi"] = sys.modules[__name__]


def unregister():
    import importlib

    for name in reversed(_MODULES):
        importlib.import_module(f".{name}", __name__).unregister()
    if __name__ != "bakegi" and sys.modules.get("bakegi") is sys.modules[__name__]:
        del sys.modules["bakegi"]
