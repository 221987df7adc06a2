# SPDX-License-Identifier: GPL-3.0-or-later
"""The BakeGI panel in the Render properties."""

import json
import textwrap

import bpy

from .. import cache_folder, error_check, grid_follow, live, native
from ..export import targets as export_targets
from . import operators, report_text


class RENDER_PT_bakegi(bpy.types.Panel):
    bl_label = "BakeGI Indirect Light"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.bakegi

        col = layout.column()
        col.prop(settings, "method")
        method = settings.resolved_method()
        if method == "antiradiance":
            col.prop(settings, "bins")
            col.prop(settings, "iterations")
            col.prop(settings, "seed")
        elif method == "splatting":
            col.label(text="One bounce from 1024 VPLs, 64 visibility rays, 32 gather rays")
        elif method == "meshless":
            col.prop(settings, "meshless_levels")
            col.prop(settings, "meshless_epsilon")
            col.prop(settings, "seed")
            col.prop(settings, "use_cache")
            if settings.use_cache:
                row = col.row(align=True)
                row.label(text="Cache: " + cache_folder.describe(settings.cache_directory()))
                row.operator("bakegi.clear_cache", text="", icon="TRASH")
            col.prop(settings, "live_indirect")
        else:
            col.prop(settings, "quality")
            if settings.quality == "SAMPLES":
                col.prop(settings, "samples")
            col.prop(settings, "denoise")
            col.prop(settings, "seed")
        col.prop(settings, "target")
        if settings.target == "LIGHTMAP":
            sub = col.column()
            sub.prop(settings, "texels_per_meter")
            active = context.active_object
            if active is not None and active.type == "MESH":
                sub.prop(active, "bakegi_texels_per_meter", text=f"'{active.name}' Texels")
            sub.prop(settings, "lightmap_max_size")
            sub.prop(settings, "lightmap_uv_map")
            sub.prop(settings, "lightmap_uv_method")
            sub.prop(settings, "lightmap_padding")
            sub.prop(settings, "lightmap_reject_inside")
            sub.prop(settings, "lightmap_folder")
            sub.prop(settings, "lightmap_float")
        if settings.target == "GRID":
            sub = col.column()
            row = sub.row(align=True)
            row.prop(settings, "grid_object")
            row.operator(operators.BAKEGI_OT_add_grid_box.bl_idname, text="", icon="ADD")
            sub.prop(settings, "grid_cell_size")
            sub.prop(settings, "grid_max_vertices")
            sub.prop(settings, "grid_rays")
            sub.prop(settings, "grid_quantized")
            sub.prop(settings, "grid_folder")
            sub.prop(settings, "grid_interpolation")
            sub.prop(settings, "grid_directional")
            sub.prop(settings, "grid_visibility")
            sub.prop(settings, "grid_darken_buried")
            sub.prop(settings, "grid_follow")
            follow = grid_follow.status_text(context.scene)
            if follow:
                sub.label(text=follow, icon="ERROR" if "stopped" in follow else "INFO")
        col.prop(settings, "objects")
        if settings.target not in ("LIGHTMAP", "GRID"):
            col.prop(settings, "linked_duplicates")
            shared = len(export_targets.linked_duplicates(context, settings.objects))
            if shared and settings.linked_duplicates == "SHARED":
                col.label(text=f"{shared} object(s) share a mesh with another: they show its "
                          "light", icon="INFO")
        col.prop(settings, "estimate_error")
        col.prop(settings, "hook_materials")

        row = layout.row(align=True)
        row.scale_y = 1.4
        row.operator(operators.BAKEGI_OT_bake_indirect.bl_idname, icon="RENDER_STILL",
                     text="Bake Grid" if settings.target == "GRID" else "Bake Indirect")
        if settings.target == "GRID":
            row.operator(operators.BAKEGI_OT_apply_grid.bl_idname, icon="LIGHTPROBE_GRID"
                         if "LIGHTPROBE_GRID" in _ICONS else "LIGHTPROBE_VOLUME")
        row.operator(operators.BAKEGI_OT_remove_bake.bl_idname, icon="TRASH", text="")
        if settings.target == "GRID":
            row = layout.row(align=True)
            row.operator(operators.BAKEGI_OT_simplify_copy.bl_idname, icon="MOD_DECIM")
            row.operator(operators.BAKEGI_OT_export_web.bl_idname, icon="URL")

        box = layout.box()
        if operators.runtime["running"]:
            box.label(text=operators.runtime["text"], icon="TIME")
        elif settings.last_result:
            box.label(text="Last: " + settings.last_result, icon="CHECKMARK")
            report = _last_report(settings)
            lines = (report_text.meshless_details(report) +
                     report_text.lightmap_details(report) + report_text.grid_details(report))
            for line in lines:
                box.label(text=line)
            _draw_error_check(box, report.get("error_check"))
        else:
            box.label(text="Not baked yet", icon="INFO")
        if method == "meshless" and settings.live_indirect:
            if live.is_active_for(context.scene.name):
                text = live.status_text()
                box.label(text=text, icon="ERROR" if "paused" in text else "LIGHT")
            else:
                box.label(text="Live: Bake Indirect once to start", icon="LIGHT")
        if not native.library_loaded():
            try:
                native.load_library()
            except native.BakeGIError as error:
                box.label(text=error.message, icon="ERROR")

        sub = layout.column()
        sub.use_property_split = False
        sub.prop(settings, "show_debug")
        if settings.show_debug:
            sub.prop(settings, "debug_direct")


class VIEW3D_PT_bakegi_live(bpy.types.Panel):
    """Live indirect where the lights are moved: the 3D viewport's sidebar (N)."""

    bl_label = "Live Indirect"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "BakeGI"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.bakegi
        layout.prop(settings, "method", text="")
        if settings.resolved_method() != "meshless":
            layout.label(text="Live needs the Meshless method", icon="INFO")
            return
        layout.prop(settings, "live_indirect")
        layout.operator(operators.BAKEGI_OT_bake_indirect.bl_idname, icon="RENDER_STILL")
        if operators.runtime["running"]:
            layout.label(text=operators.runtime["text"], icon="TIME")
        elif live.is_active_for(context.scene.name):
            text = live.status_text()
            layout.label(text=text, icon="ERROR" if "paused" in text else "LIGHT")
        elif settings.live_indirect:
            layout.label(text="Bake once to start", icon="INFO")


def _last_report(settings):
    try:
        report = json.loads(settings.last_report) if settings.last_report else {}
    except ValueError:
        return {}
    return report if isinstance(report, dict) else {}


# Icon names of this Blender (4.1 renamed LIGHTPROBE_GRID to LIGHTPROBE_VOLUME).
_ICONS = set(bpy.types.UILayout.bl_rna.functions["prop"].parameters["icon"].enum_items.keys())

# Characters per label line before wrapping (a Properties editor of the default width).
LABEL_WIDTH = 60


def _draw_error_check(layout, verdict):
    """The bake's estimate of its own error; above the threshold, why and what to do, and a
    Subdivide a Copy button for each target whose vertices cannot hold its light."""
    if not isinstance(verdict, dict):
        return
    flagged = verdict.get("error", 0.0) > error_check.THRESHOLD
    for line in error_check.summary_lines(verdict):
        layout.label(text=line, icon="ERROR" if flagged else "INFO")
    if flagged:
        for cause in verdict.get("causes") or []:
            for i, line in enumerate(textwrap.wrap(cause, LABEL_WIDTH)):
                layout.label(text=line, icon="DOT" if i == 0 else "BLANK1")
    for name in (verdict.get("coarse_objects") or [])[:5]:
        row = layout.row()
        row.label(text=f"'{name}': too few vertices for its light", icon="MESH_GRID")
        op = row.operator(operators.BAKEGI_OT_subdivide_copy.bl_idname, text="Subdivide a Copy")
        op.object_name = name


class RENDER_PT_bakegi_preview(bpy.types.Panel):
    """Settings of the BakeGI Preview render engine (splatting, issue 17)."""

    bl_label = "BakeGI Preview"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"BAKEGI_PREVIEW"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        props = context.scene.bakegi
        layout.prop(props, "preview_vpl_count")
        layout.prop(props, "preview_visibility_clusters")
        layout.prop(props, "preview_viewport_scale")
        layout.label(text="One splatted bounce: a draft of the indirect light", icon="INFO")


classes = (RENDER_PT_bakegi, VIEW3D_PT_bakegi_live, RENDER_PT_bakegi_preview)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
