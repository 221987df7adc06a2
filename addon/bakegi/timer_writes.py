# SPDX-License-Identifier: GPL-3.0-or-later
"""What a timer that writes into the scene needs (live indirect, Follow Moves): its write as
an undo step of its own, so that Ctrl+Z steps back over it like over the change that caused
it instead of folding it into whatever the user does next, and a redraw of the panels and
viewports that show it."""

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
