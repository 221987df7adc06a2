# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake Indirect and Remove Bake.

Bake Indirect exports the scene, starts the core on its own threads and, in the UI,
polls it from a window-manager timer (progress indicator and status-bar text with
percentage, stage and time left; Esc or right-click cancels and leaves the scene exactly
as it was). In background mode (timers do not run there) and from execute() it bakes
synchronously. Both paths, and bakegi.bake(), go through session.BakeSession.
"""

import json

import bpy
from mathutils import Vector

from .. import cache_folder, session, simplification, subdivision
from ..export import targets as export_targets
from ..native import BakeGIError
from ..write import attributes, grid_file
from . import report_text

# Runtime state shown by the panel (not saved, so a cancel or failure changes no data).
runtime = {"running": False, "text": "", "fraction": 0.0}


def store_report(scene, report):
    settings = scene.bakegi
    settings.last_result = report_text.summary(report)
    settings.last_report = json.dumps(report, default=str)


def _has_mesh_target(context, objects):
    if objects == "SELECTED":
        return any(o.type == "MESH" for o in context.selected_objects)
    view_layer = context.view_layer
    return any(o is not None and o.type == "MESH" and o.visible_get(view_layer=view_layer)
               for o in view_layer.objects)


def _idle_in_object_mode(cls, context):
    """The poll of operators that change meshes: no bake running, Object Mode."""
    if runtime["running"]:
        cls.poll_message_set("A bake is running")
        return False
    if context.mode != "OBJECT":
        cls.poll_message_set("Switch to Object Mode")
        return False
    return True


def _session_from_scene(context):
    return session.BakeSession(context, context.scene.bakegi.request())


def _report_warnings(operator, report):
    for warning in report.get("warnings", [])[:20]:
        operator.report({"WARNING"}, str(warning))


class BAKEGI_OT_bake_indirect(bpy.types.Operator):
    """Bake the indirect light of the scene into the color attribute BakeGI_Indirect"""

    bl_idname = "bakegi.bake_indirect"
    bl_label = "Bake Indirect"
    bl_options = {"REGISTER", "UNDO"}

    _session = None
    _timer = None

    @classmethod
    def poll(cls, context):
        if runtime["running"]:
            cls.poll_message_set("A bake is already running")
            return False
        if context.mode != "OBJECT":
            cls.poll_message_set("Switch to Object Mode to bake")
            return False
        settings = getattr(context.scene, "bakegi", None)
        objects = settings.objects if settings is not None else "SELECTED"
        if settings is not None and settings.target == "GRID":
            objects = "VISIBLE"  # a grid has no targets: the visible scene lights it
        if not _has_mesh_target(context, objects):
            cls.poll_message_set("No mesh object is " +
                                 ("selected" if objects == "SELECTED" else "visible"))
            return False
        return True

    def execute(self, context):
        """Synchronous bake (background mode, scripts, F3 with EXEC_DEFAULT)."""
        try:
            bake = _session_from_scene(context)
            report = bake.run()
        except BakeGIError as error:
            self.report({"ERROR"}, error.message)
            return {"CANCELLED"}
        store_report(context.scene, report)
        _report_warnings(self, report)
        self.report({"INFO"}, "BakeGI: " + report_text.summary(report))
        return {"FINISHED"}

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        try:
            self._session = _session_from_scene(context)
            self._session.start()
        except BakeGIError as error:
            self._session = None
            self.report({"ERROR"}, error.message)
            return {"CANCELLED"}
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, 100)
        runtime.update(running=True, text="BakeGI: starting", fraction=0.0)
        wm.modal_handler_add(self)
        self._set_status(context, runtime["text"])
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        try:
            return self._modal(context, event)
        except Exception as error:  # never leave a bake running behind a dead operator
            if self._session is not None:
                self._session.cancel(wait=False)
            self._end(context)
            self.report({"ERROR"}, f"BakeGI: {error}; nothing was changed")
            return {"CANCELLED"}

    def _modal(self, context, event):
        if event.type == "ESC" or (event.type == "RIGHTMOUSE" and event.value == "PRESS"):
            self._session.cancel(wait=False)
            self._end(context)
            self.report({"INFO"}, "BakeGI: bake cancelled; nothing was changed")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        progress = self._session.poll()
        runtime.update(text=progress.text(), fraction=progress.fraction)
        context.window_manager.progress_update(int(progress.fraction * 100))
        if not progress.done:
            self._set_status(context, progress.text())
            self._redraw(context)
            return {"PASS_THROUGH"}
        if context.mode != "OBJECT":
            self._set_status(context, "BakeGI: finished; return to Object Mode to write the "
                             "bake (Esc discards it)")
            return {"PASS_THROUGH"}
        try:
            report = self._session.finish(context.blend_data)
        except BakeGIError as error:
            self._end(context)
            if error.cancelled:
                self.report({"INFO"}, "BakeGI: bake cancelled; nothing was changed")
            else:
                self.report({"ERROR"}, error.message)
            return {"CANCELLED"}
        self._end(context)
        store_report(context.scene, report)
        _report_warnings(self, report)
        self.report({"INFO"}, "BakeGI: " + report_text.summary(report))
        return {"FINISHED"}

    def cancel(self, context):
        # Blender ends the modal operator (e.g. the file is closed): stop the core.
        if self._session is not None:
            self._session.cancel()
        self._end(context)

    def _end(self, context):
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
            wm.progress_end()
        runtime.update(running=False, text="", fraction=0.0)
        self._set_status(context, None)
        self._redraw(context)
        self._session = None

    @staticmethod
    def _set_status(context, text):
        workspace = getattr(context, "workspace", None)
        if workspace is not None:
            workspace.status_text_set(text)

    @staticmethod
    def _redraw(context):
        screen = getattr(context, "screen", None)
        if screen is None:
            return
        for area in screen.areas:
            if area.type == "PROPERTIES":
                area.tag_redraw()


class BAKEGI_OT_remove_bake(bpy.types.Operator):
    """Remove BakeGI_Indirect from the objects' meshes and restore their materials"""

    bl_idname = "bakegi.remove_bake"
    bl_label = "Remove Bake"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _idle_in_object_mode(cls, context)

    def execute(self, context):
        objects = context.scene.bakegi.objects
        baked, _ = export_targets.resolve_targets(context, objects)
        result = attributes.remove_bake(context.blend_data, baked)
        self.report({"INFO"}, f"BakeGI: removed the bake from {len(result['objects'])} "
                    f"object(s), restored {len(result['materials'])} material(s)")
        return {"FINISHED"}


class BAKEGI_OT_clear_cache(bpy.types.Operator):
    """Delete the saved precomputations (*.bgcache) in the cache folder; later bakes compute
    them again"""

    bl_idname = "bakegi.clear_cache"
    bl_label = "Clear Cache"
    bl_options = {"REGISTER"}  # files on disk: not part of the .blend's undo

    @classmethod
    def poll(cls, context):
        if runtime["running"]:
            cls.poll_message_set("A bake is running")
            return False
        if cache_folder.usage(context.scene.bakegi.cache_directory())[0] == 0:
            cls.poll_message_set("The cache folder holds no cache files")
            return False
        return True

    def execute(self, context):
        folder = context.scene.bakegi.cache_directory()
        removed = cache_folder.clear(folder)
        self.report({"INFO"}, f"BakeGI: deleted {removed} cache file(s) in {folder}")
        return {"FINISHED"}


class BAKEGI_OT_subdivide_copy(bpy.types.Operator):
    """Make a finer copy of a mesh whose vertices are too few for the light on it (the
    original is hidden, not changed); then bake again"""

    bl_idname = "bakegi.subdivide_copy"
    bl_label = "Subdivide a Copy"
    bl_options = {"REGISTER", "UNDO"}

    object_name: bpy.props.StringProperty(name="Object", description="The mesh object to copy")
    vertices: bpy.props.IntProperty(
        name="Vertices", default=subdivision.DEFAULT_VERTICES, min=100,
        max=subdivision.MAX_VERTICES,
        description="About how many vertices the copy spreads over its surface")

    @classmethod
    def poll(cls, context):
        return _idle_in_object_mode(cls, context)

    def execute(self, context):
        obj = context.blend_data.objects.get(self.object_name)
        if obj is None:
            self.report({"ERROR"}, f"BakeGI: no object named '{self.object_name}'")
            return {"CANCELLED"}
        try:
            copy = subdivision.subdivide_copy(obj, self.vertices)
        except ValueError as error:
            self.report({"ERROR"}, f"BakeGI: {error}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"BakeGI: made '{copy.name}' ({len(copy.data.vertices):,} "
                    f"vertices) from '{obj.name}' ({len(obj.data.vertices):,}), which is now "
                    "hidden; bake again")
        return {"FINISHED"}


class BAKEGI_OT_simplify_copy(bpy.types.Operator):
    """Make a level of detail of the active mesh with fewer triangles (meshoptimizer's
    simplifier; the original is hidden, not changed), to light from the grid without a
    re-bake"""

    bl_idname = "bakegi.simplify_copy"
    bl_label = "Simplify a Copy"
    bl_options = {"REGISTER", "UNDO"}

    ratio: bpy.props.FloatProperty(
        name="Triangles Kept", default=0.1, min=0.001, max=1.0, subtype="FACTOR",
        description="The share of the mesh's triangles the copy keeps (it may keep more where "
                    "borders hold collapses back)")

    @classmethod
    def poll(cls, context):
        if not _idle_in_object_mode(cls, context):
            return False
        obj = context.active_object
        if obj is None or obj.type != "MESH":
            cls.poll_message_set("Select a mesh object")
            return False
        return True

    def execute(self, context):
        obj = context.active_object
        try:
            copy, info = simplification.simplify_copy(obj, self.ratio)
        except (ValueError, BakeGIError) as error:
            self.report({"ERROR"}, f"BakeGI: {error}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"BakeGI: made '{copy.name}' ({info['lod_triangles']:,} of "
                    f"{info['triangles']:,} triangles) from '{obj.name}', which is now hidden; "
                    "Apply Grid lights it")
        return {"FINISHED"}


class BAKEGI_OT_add_grid_box(bpy.types.Operator):
    """Add an Empty whose cube is the box an Irradiance Grid covers, around the visible
    meshes, and make it the scene's Grid Box"""

    bl_idname = "bakegi.add_grid_box"
    bl_label = "Add Grid Box"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _idle_in_object_mode(cls, context)

    def execute(self, context):
        view_layer = context.view_layer
        corners = [obj.matrix_world @ Vector(corner) for obj in view_layer.objects
                   if obj.type == "MESH" and obj.visible_get(view_layer=view_layer)
                   for corner in obj.bound_box]
        if corners:
            lo = Vector([min(c[a] for c in corners) for a in range(3)])
            hi = Vector([max(c[a] for c in corners) for a in range(3)])
        else:
            lo, hi = Vector((-1.0, -1.0, -1.0)), Vector((1.0, 1.0, 1.0))
        half = (hi - lo) / 2.0
        size = max(max(half), 1e-3)
        box = context.blend_data.objects.new("BakeGI Grid", None)
        box.empty_display_type = "CUBE"
        box.empty_display_size = 1.0
        box.location = (lo + hi) / 2.0
        # The cube's half size is 1: scale it to the box (a flat axis keeps a thin slab).
        box.scale = [max(h, size * 1e-3) for h in half]
        context.collection.objects.link(box)
        context.scene.bakegi.grid_object = box
        self.report({"INFO"}, f"BakeGI: added '{box.name}' ({2 * half.x:.2f} x "
                    f"{2 * half.y:.2f} x {2 * half.z:.2f} m); bake with Target Irradiance Grid")
        return {"FINISHED"}


class BAKEGI_OT_apply_grid(bpy.types.Operator):
    """Light the objects (Selected or Visible, as the panel's Objects says) from the scene's
    newest Irradiance Grid: writes BakeGI_Indirect without baking"""

    bl_idname = "bakegi.apply_grid"
    bl_label = "Apply Grid"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        if not _idle_in_object_mode(cls, context):
            return False
        if not context.scene.get(grid_file.GRID_PATH_PROPERTY):
            cls.poll_message_set("Bake a grid first (Target: Irradiance Grid)")
            return False
        return True

    def execute(self, context):
        from .. import api
        settings = context.scene.bakegi
        try:
            report = api.apply_grid(settings.objects, interpolation=settings.grid_interpolation,
                                    hook_materials=settings.hook_materials,
                                    visibility=settings.grid_visibility,
                                    darken_buried=settings.grid_darken_buried,
                                    directional=settings.grid_directional, context=context)
        except BakeGIError as error:
            self.report({"ERROR"}, error.message)
            return {"CANCELLED"}
        for warning in report["warnings"][:20]:
            self.report({"WARNING"}, str(warning))
        self.report({"INFO"}, f"BakeGI: lit {len(report['objects'])} object(s), "
                    f"{report['points']:,} points from the grid in "
                    f"{report['seconds']['total'] * 1000:.0f} ms")
        return {"FINISHED"}


class BAKEGI_OT_export_web(bpy.types.Operator):
    """Write the visible scene, its newest grid and the web page into a folder, for
    'bakegi serve FOLDER' to stream to a browser (or to open from disk)"""

    bl_idname = "bakegi.export_web"
    bl_label = "Export for Web"
    # Writes files only: nothing in the .blend changes, so nothing to undo.
    bl_options = {"REGISTER"}

    directory: bpy.props.StringProperty(name="Folder", subtype="DIR_PATH",
                                        description="Where the web scene is written")

    @classmethod
    def poll(cls, context):
        if runtime["running"]:
            cls.poll_message_set("A bake is running")
            return False
        if not context.scene.get(grid_file.GRID_PATH_PROPERTY):
            cls.poll_message_set("Bake a grid first (Target: Irradiance Grid)")
            return False
        return True

    def invoke(self, context, event):
        if not self.directory:
            context.window_manager.fileselect_add(self)
            return {"RUNNING_MODAL"}
        return self.execute(context)

    def execute(self, context):
        from .. import api
        try:
            report = api.export_web(self.directory or None, context=context)
        except BakeGIError as error:
            self.report({"ERROR"}, error.message)
            return {"CANCELLED"}
        for warning in report["warnings"]:
            self.report({"WARNING"}, "BakeGI: " + warning)
        total = sum(report["bytes"].values())
        self.report({"INFO"}, f"BakeGI: wrote {report['folder']} ({total / 1e6:.1f} MB); "
                    f"stream it with: {report['serve']}")
        return {"FINISHED"}


classes = (BAKEGI_OT_bake_indirect, BAKEGI_OT_remove_bake, BAKEGI_OT_clear_cache,
           BAKEGI_OT_subdivide_copy,
           BAKEGI_OT_simplify_copy, BAKEGI_OT_add_grid_box, BAKEGI_OT_apply_grid,
           BAKEGI_OT_export_web)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
