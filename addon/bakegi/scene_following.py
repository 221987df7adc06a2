# SPDX-License-Identifier: GPL-3.0-or-later
"""What live indirect (live.py) and Follow Moves (grid_follow.py) share: following the scene
with a depsgraph update handler and forgetting it when a file loads, and writing from a timer:
the write as an undo step of its own, so that Ctrl+Z steps back over it like over the change
that caused it instead of folding it into whatever the user does next, and a redraw of the
panels and viewports that show it."""

import bpy


def push_undo_step(message):
    wm = getattr(bpy.context, "window_manager", None)
    if wm is None or not wm.windows:
        return
    window = wm.windows[0]
    override = {"window": window, "screen": window.screen}
    try:
        if hasattr(bpy.context, "temp_override"):
            with bpy.context.temp_override(**override):
                bpy.ops.ed.undo_push(message=message)
        else:
            bpy.ops.ed.undo_push(override, message=message)
    except RuntimeError:  # no undo here (background, or an operator running): no step
        pass


def redraw():
    wm = getattr(bpy.context, "window_manager", None)
    if wm is None:
        return
    for window in wm.windows:
        for area in window.screen.areas:
            if area.type in {"PROPERTIES", "VIEW_3D"}:
                area.tag_redraw()


def add_handlers(on_depsgraph_update, on_load_pre):
    if on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(on_depsgraph_update)
    if on_load_pre not in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.append(on_load_pre)


def remove_handlers(on_depsgraph_update, on_load_pre, timer):
    if on_depsgraph_update in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(on_depsgraph_update)
    if on_load_pre in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(on_load_pre)
    if bpy.app.timers.is_registered(timer):
        bpy.app.timers.unregister(timer)
