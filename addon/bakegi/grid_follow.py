# SPDX-License-Identifier: GPL-3.0-or-later
"""Follow Moves: objects lit from a grid by Apply Grid are lit from it again when they move
or change shape.

    bakegi.apply_grid(["Chair"])        # remembered, with its options, for the scene
    scene.bakegi.grid_follow = True     # the panel's Follow Moves (off by default)
    ... move the chair ...              # the UI: re-applied after 50 ms without a move
    bakegi.grid_follow.update()         # scripts and background mode: at once

A depsgraph update handler compares each remembered object's world matrix with the one it was
lit at, so a move by hand, by a parent, a constraint or an animation is caught alike. Where
the depsgraph says an object's geometry changed, it also compares a fingerprint of its
evaluated mesh (face count and vertex positions, modifiers applied) with the one it was lit
at: an edit, a modifier or a shape key is caught, and the add-on's own writes (a colour
attribute: neither matrix nor positions change) are not. An object in Edit Mode waits until
it leaves it (the edit mesh, not the object's data, holds its shape until then). A timer
re-applies the grid to the changed objects with the options of the last Apply Grid; its
writes are undo steps of their own, and what undo or redo brings back is taken as lit (its
attribute comes back with it).

The state lives in this module (not in the .blend); loading a file forgets it.
"""

import bpy
import numpy

from . import scene_following
from .native import BakeGIError

DEBOUNCE_SECONDS = 0.05


class FollowState:
    """What the last Apply Grid of a scene lit, and how."""

    def __init__(self, options):
        self.options = options  # apply_grid's keyword arguments (path, interpolation, ...)
        self.matrices = {}  # object name -> its world matrix when it was lit
        self.shapes = {}  # object name -> its geometry's fingerprint when it was lit
        self.pending = set()  # names that moved since
        self.message = ""  # why following stopped ("" = it follows)
        self.updates = 0
        self.last_ms = 0.0


_states = {}  # scene name -> FollowState
_last_seen = {}  # scene name -> the pending objects' matrices at the timer's previous tick


def _matrix(obj):
    return tuple(round(x, 6) for row in obj.matrix_world for x in row)


IN_EDIT_MODE = "in Edit Mode"  # a shape not settled yet: whatever it becomes is a change


def _shape(obj, depsgraph):
    """The evaluated mesh's face count and a hash of its vertex positions (a millisecond for
    100k vertices), or IN_EDIT_MODE (the edit mesh, not the object's data, holds its shape)."""
    if obj.mode == "EDIT":
        return IN_EDIT_MODE
    mesh = obj.evaluated_get(depsgraph).data
    positions = numpy.empty(3 * len(mesh.vertices), numpy.float32)
    mesh.vertices.foreach_get("co", positions)
    return len(mesh.polygons), hash(positions.tobytes())


def remember(scene, objects, options):
    """Called by apply_grid after it wrote: these objects are now lit from the grid where they
    stand, with these options (they replace the scene's earlier ones)."""
    state = _states.get(scene.name)
    if state is None or state.options != options:
        previous = state
        state = _states[scene.name] = FollowState(options)
        if previous is not None:  # the objects lit before stay followed, as they were lit
            state.matrices.update(previous.matrices)
            state.shapes.update(previous.shapes)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for obj in objects:
        state.matrices[obj.name] = _matrix(obj)
        state.shapes[obj.name] = _shape(obj, depsgraph)
        state.pending.discard(obj.name)
    state.message = ""


def forget(scene_name=None):
    """Forgets what a scene's objects were lit at (all scenes: None)."""
    if scene_name is None:
        _states.clear()
    else:
        _states.pop(scene_name, None)


def status_text(scene):
    """One line for the panel ("" when there is nothing to say)."""
    state = _states.get(scene.name)
    if state is None or not scene.bakegi.grid_follow:
        return ""
    if state.message:
        return "Follow stopped: " + state.message
    if state.pending:
        return "Follow: updating…"
    if state.updates:
        return (f"Follow: {len(state.matrices)} object(s), last re-applied in "
                f"{state.last_ms:.0f} ms, {state.updates} update(s)")
    return f"Follow: {len(state.matrices)} object(s), waiting for a move"


def moved_objects(scene, depsgraph=None, reshaped=None):
    """Names of the remembered objects whose world matrix changed, or (with the depsgraph)
    whose shape changed, among `reshaped` (None: all of them). Objects deleted since are
    forgotten."""
    state = _states.get(scene.name)
    if state is None:
        return set()
    moved = set()
    for name in list(state.matrices):
        obj = scene.objects.get(name)
        if obj is None or obj.type != "MESH":
            del state.matrices[name]
            state.shapes.pop(name, None)
            state.pending.discard(name)
        elif _matrix(obj) != state.matrices[name]:
            moved.add(name)
        elif depsgraph is not None and (reshaped is None or name in reshaped):
            shape = _shape(obj, depsgraph)
            if shape == IN_EDIT_MODE:
                continue  # judged when it leaves Edit Mode
            if shape != state.shapes.get(name):
                moved.add(name)  # lit in Edit Mode counts as changed: re-applied once
    return moved


def _reshaped(depsgraph):
    """Names of the objects whose geometry this depsgraph update changed."""
    return {update.id.original.name for update in depsgraph.updates
            if update.is_updated_geometry and isinstance(update.id, bpy.types.Object)}


@bpy.app.handlers.persistent
def on_depsgraph_update(scene, depsgraph):
    settings = getattr(scene, "bakegi", None)
    if settings is None or not settings.grid_follow:
        return
    state = _states.get(scene.name)
    if state is None or state.message:
        return
    moved = moved_objects(scene, depsgraph, _reshaped(depsgraph)) - state.pending
    if moved:
        state.pending |= moved
        _schedule()


@bpy.app.handlers.persistent
def on_load_pre(*_args):
    forget()


@bpy.app.handlers.persistent
def on_undo_redo(scene, *_args):
    """Undo and redo bring back each object's matrix together with the attribute written for
    it there: what they restore is already lit, so it is taken as lit rather than re-applied
    (a re-apply would push an undo step and lose the redo history)."""
    state = _states.get(scene.name) if scene is not None else None
    if state is None:
        return
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for name in list(state.matrices):
        obj = scene.objects.get(name)
        if obj is not None:
            state.matrices[name] = _matrix(obj)
            state.shapes[name] = _shape(obj, depsgraph)
    state.pending.clear()
    _last_seen.pop(scene.name, None)


def update(context=None):
    """Re-applies the grid to the remembered objects that moved, now (scripts, background
    mode, and the timer). Returns apply_grid's report, or None when nothing moved. Raises
    BakeGIError (and stops following, with the reason in the panel) when the grid cannot be
    applied."""
    from . import api

    context = context if context is not None else bpy.context
    scene = context.scene
    state = _states.get(scene.name)
    if state is None:
        return None
    # Evaluating the depsgraph runs the handler on moves made since the last update.
    depsgraph = context.evaluated_depsgraph_get()
    state.pending |= moved_objects(scene, depsgraph)
    names = sorted(state.pending)
    if not names:
        return None
    try:
        report = api.apply_grid(names, context=context, **state.options)
    except BakeGIError as error:
        state.message = error.message
        state.pending.clear()
        raise
    state.updates += 1
    state.last_ms = report["seconds"]["total"] * 1000.0
    return report


def _schedule():
    if not bpy.app.background and not bpy.app.timers.is_registered(_tick):
        bpy.app.timers.register(_tick, first_interval=DEBOUNCE_SECONDS)


def _tick():
    """The timer: waits until the objects stop moving for DEBOUNCE_SECONDS, then re-applies."""
    context = bpy.context
    scene = getattr(context, "scene", None)
    state = _states.get(scene.name) if scene is not None else None
    if state is None or state.message or not state.pending:
        return None
    if not scene.bakegi.grid_follow:  # turned off while the objects were moving
        state.pending.clear()
        return None
    state.pending |= moved_objects(scene)  # moves; shape changes come from the handler
    if _still_moving(scene, state):
        return DEBOUNCE_SECONDS
    try:
        update(context)
        scene_following.push_undo_step("BakeGI Follow Moves")
    except BakeGIError:
        pass  # update() stopped following and kept the reason for the panel
    except Exception as error:  # a timer must never raise into Blender's loop
        state.message = f"stopped: {error}"
        state.pending.clear()
    scene_following.redraw()
    return None


def _still_moving(scene, state):
    """Whether a pending object's matrix changed since the previous tick (a drag in
    progress): the grid is applied once the object rests."""
    seen = {name: _matrix(scene.objects[name]) for name in state.pending
            if name in scene.objects}
    moving = seen != _last_seen.get(scene.name)
    _last_seen[scene.name] = seen
    return moving


def register():
    scene_following.add_handlers(on_depsgraph_update, on_load_pre)
    for handlers in (bpy.app.handlers.undo_post, bpy.app.handlers.redo_post):
        if on_undo_redo not in handlers:
            handlers.append(on_undo_redo)


def unregister():
    forget()
    scene_following.remove_handlers(on_depsgraph_update, on_load_pre, _tick)
    for handlers in (bpy.app.handlers.undo_post, bpy.app.handlers.redo_post):
        if on_undo_redo in handlers:
            handlers.remove(on_undo_redo)
