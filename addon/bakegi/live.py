# SPDX-License-Identifier: GPL-3.0-or-later
"""Live indirect: after one meshless bake, moving or changing a light updates BakeGI_Indirect
in milliseconds (the precomputed direct-to-indirect transfer is relit, Lehtinen et al. 2008).

    bakegi.bake(method="meshless", live=True)  # precompute once; the job is kept here
    ... move a light ...                       # the UI: a timer relights after 50 ms
    bakegi.live_update()                       # scripts and background mode: at once

How it follows the scene:
- A depsgraph update handler sorts what changed. Lights (their objects, their data) and the
  world ask for a relight. Meshes (transform, geometry), instancers and materials mean the
  precomputation no longer fits: live indirect pauses with a message, and Bake Indirect
  precomputes again (with the cache, an unchanged scene loads in well under a second).
  BakeGI's own writes (the attribute, the hooked materials) are recognized and ignored.
- A timer starts the relight on the core's threads, polls it and writes the result; the UI
  never waits on the core. Changes that arrive during a relight are folded into the next one
  (debounced), so dragging a light never queues work.
- Only lights and the world are re-exported for a relight; the core checks them.

The state lives in this module (not in the .blend); loading a file or disabling the add-on
releases it. Writes are not undo steps: Ctrl+Z of a light move relights again.
"""

import time

import bpy

from . import scene_following
from .export import scene as export_scene, targets as export_targets
from .write import attributes
from .native import BakeGIError

DEBOUNCE_SECONDS = 0.05
POLL_SECONDS = 0.01


class LiveState:
    """A finished meshless bake that can be relit, and what the writes need."""

    def __init__(self, scene_name, job, core_scene, targets, hooked_materials):
        self.scene_name = scene_name
        self.job = job  # the precomputing job: every relight starts from it
        self.core_scene = core_scene  # its meshes and materials; lights are replaced
        self.targets = targets
        self.target_objects = {t.object_name for t in targets}
        self.target_meshes = {t.mesh_name for t in targets}
        # Names whose next update is BakeGI's own write, not the user's.
        self.own_materials = set(hooked_materials)
        self.running = None  # the relight job in flight
        self.running_since = 0.0
        self.pending = False
        self.paused = ""  # why live indirect stopped following the scene ("" = it follows)
        self.last = {}  # timings and counts of the last update
        self.export_seconds = 0.0
        self.updates = 0
        # What each light object looked like at the bake or the last relight: Blender 5.0
        # tags every object's shading when a material changes (BakeGI's own hooks too), so an
        # update flag alone does not say a light changed.
        scene = bpy.data.scenes.get(scene_name)
        self.light_signatures = {o.name_full: light_signature(o) for o in
                                 (scene.objects if scene else ()) if o.type == "LIGHT"}

    def light_changed(self, obj):
        signature = light_signature(obj)
        if self.light_signatures.get(obj.name_full) == signature:
            return False
        self.light_signatures[obj.name_full] = signature
        return True

    def close(self):
        if self.running is not None:
            self.running.close()
            self.running = None
        self.job.close()
        self.core_scene.close()


_state = None
_timer_registered = False


def state():
    return _state


def status_text():
    """One line for the panel."""
    if _state is None:
        return ""
    if _state.paused:
        return "Live paused: " + _state.paused
    if _state.running is not None or _state.pending:
        return "Live: updating…"
    if not _state.last:
        return "Live: waiting for a light to change"
    last = _state.last
    # total: from the relight's start to the written attribute, as the UI saw it; relight:
    # the core's own time (lighting, P†, S e, evaluation).
    return (f"Live: updated in {last['total'] * 1000:.0f} ms (relight "
            f"{last['core_solve'] * 1000:.0f} ms, write {last['write'] * 1000:.0f} ms), "
            f"{_state.updates} update(s)")


def adopt(scene_name, job, core_scene, targets, hooked_materials):
    """Keeps a finished meshless job for live relighting (replacing any earlier one)."""
    stop()
    if not job.can_relight:
        job.close()
        core_scene.close()
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          "live indirect needs a finished bake that can be relit (meshless)")
    global _state
    _state = LiveState(scene_name, job, core_scene, targets, hooked_materials)
    scene_following.redraw()


def stop():
    """Releases the kept precomputation (and cancels a relight in flight)."""
    global _state
    if _state is not None:
        if _state.running is not None:
            _state.running.cancel()
        _state.close()
        _state = None
        scene_following.redraw()


def is_active_for(scene_name):
    return _state is not None and _state.scene_name == scene_name


# ---- what changed -------------------------------------------------------------------------


def light_signature(obj):
    """A light object's placement and every plain setting of its light, as a comparable tuple
    (every setting, so settings later versions add are covered too)."""
    light = obj.data
    values = []
    for prop in light.bl_rna.properties:
        if prop.type in ("POINTER", "COLLECTION") or prop.identifier == "rna_type":
            continue
        value = getattr(light, prop.identifier, None)
        try:
            value = tuple(value)
        except TypeError:
            pass
        values.append((prop.identifier, value))
    matrix = tuple(round(x, 7) for row in obj.matrix_world for x in row)
    return matrix, tuple(values)


def classify(updates, live):
    """("relight" | "paused: why" | None) for one depsgraph update's list of updates."""
    relight = False
    for update in updates:
        id_data = update.id
        original = getattr(id_data, "original", id_data)
        name = getattr(original, "name_full", "")
        if isinstance(original, (bpy.types.Light, bpy.types.World)):
            relight = True
        elif isinstance(original, bpy.types.Object):
            if original.type == "LIGHT":
                if update.is_updated_transform or update.is_updated_shading:
                    relight = live.light_changed(original) or relight
            elif original.type in export_targets.MESH_LIKE and update.is_updated_transform:
                return f"'{original.name}' moved; Bake Indirect to precompute again"
        elif isinstance(original, bpy.types.Mesh):
            # Writing the attribute updates the target meshes' geometry; other meshes
            # (and targets edited in Edit Mode) have changed shape.
            if update.is_updated_geometry and (name not in live.target_meshes or
                                               original.is_editmode):
                return f"mesh '{original.name}' changed; Bake Indirect to precompute again"
        elif isinstance(original, bpy.types.Material):
            if name in live.own_materials:
                live.own_materials.discard(name)
            elif update.is_updated_shading:
                return f"material '{original.name}' changed; Bake Indirect to precompute again"
    return "relight" if relight else None


@bpy.app.handlers.persistent
def on_depsgraph_update(scene, depsgraph):
    live = _state
    if live is None or scene.name != live.scene_name or live.paused:
        return
    verdict = classify(depsgraph.updates, live)
    if verdict is None:
        return
    if verdict != "relight":
        live.paused = verdict
        live.pending = False
        scene_following.redraw()
        return
    live.pending = True
    _schedule(DEBOUNCE_SECONDS)


@bpy.app.handlers.persistent
def on_load_pre(*_args):
    stop()


# ---- relighting ---------------------------------------------------------------------------


def _start_relight(context):
    live = _state
    t0 = time.perf_counter()
    export_scene.export_lights(context, live.core_scene)
    live.export_seconds = time.perf_counter() - t0
    live.pending = False
    live.running = live.job.relight(live.core_scene)
    live.running_since = time.perf_counter()


def _finish_relight(data):
    """Writes the finished relight; returns the timings."""
    live = _state
    job, live.running = live.running, None
    try:
        job.wait()
        core_seconds = time.perf_counter() - live.running_since
        rgb = job.result()
        report = job.report()
    finally:
        job.close()
    t0 = time.perf_counter()
    attributes.write_results(data, live.targets, rgb)
    write_seconds = time.perf_counter() - t0
    live.updates += 1
    live.last = {"export": live.export_seconds, "core": core_seconds, "write": write_seconds,
                 "total": live.export_seconds + core_seconds + write_seconds,
                 "core_solve": (report.get("seconds") or {}).get("solve", 0.0),
                 "bake_points": sum(t.count for t in live.targets)}
    return dict(live.last)


def _pause_on_error(error):
    live = _state
    if live is not None:
        live.paused = f"{error.message}"
        live.pending = False
    scene_following.redraw()


def update(context=None):
    """Relights now and waits (scripts, background mode). Returns the timings in seconds
    (export, core, write, total). Raises BakeGIError if live indirect is not active or
    paused."""
    context = context if context is not None else bpy.context
    live = _state
    if live is None or context.scene.name != live.scene_name:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          "live indirect is not active for this scene: bake with the "
                          "meshless method and live indirect on first")
    if live.paused:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", "live indirect is paused: " +
                          live.paused)
    if live.running is not None:
        live.running.wait()
    # Evaluating the depsgraph runs the update handler on the changes made since the last
    # update, so a moved mesh pauses live indirect instead of being relit.
    context.evaluated_depsgraph_get()
    if live.paused:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", "live indirect is paused: " +
                          live.paused)
    try:
        _start_relight(context)
        return _finish_relight(context.blend_data)
    except BakeGIError as error:
        _pause_on_error(error)
        raise


def _schedule(delay):
    global _timer_registered
    if bpy.app.background or _timer_registered:
        return
    _timer_registered = True
    bpy.app.timers.register(_tick, first_interval=delay)


def _tick():
    """The timer: starts, polls and finishes relights without blocking the UI."""
    global _timer_registered
    live = _state
    if live is None or live.paused:
        _timer_registered = False
        return None
    try:
        if live.running is not None:
            if not live.running.is_done:
                return POLL_SECONDS
            _finish_relight(bpy.data)
            scene_following.push_undo_step("BakeGI Live Indirect")
            scene_following.redraw()
        if live.pending:
            _start_relight(bpy.context)
            return POLL_SECONDS
    except BakeGIError as error:
        _pause_on_error(error)
    except Exception as error:  # a timer must never raise into Blender's loop
        _pause_on_error(BakeGIError("BAKEGI_ERROR_INTERNAL", f"live indirect stopped: {error}"))
    _timer_registered = False
    return None


def register():
    scene_following.add_handlers(on_depsgraph_update, on_load_pre)


def unregister():
    stop()
    scene_following.remove_handlers(on_depsgraph_update, on_load_pre, _tick)
