# SPDX-License-Identifier: GPL-3.0-or-later
"""The BakeGI panel in the Render properties."""

import bpy

from . import native, operators


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
        if settings.resolved_method() == "antiradiance":
            col.prop(settings, "bins")
            col.prop(settings, "iterations")
            col.prop(settings, "seed")
        else:
            col.prop(settings, "samples")
            col.prop(settings, "seed")
        col.prop(settings, "target")
        col.prop(settings, "objects")
        col.prop(settings, "threads")
        col.prop(settings, "hook_materials")

        row = layout.row(align=True)
        row.scale_y = 1.4
        row.operator(operators.BAKEGI_OT_bake_indirect.bl_idname, icon="RENDER_STILL")
        row.operator(operators.BAKEGI_OT_remove_bake.bl_idname, icon="TRASH", text="")

        box = layout.box()
        if operators.runtime["running"]:
            box.label(text=operators.runtime["text"], icon="TIME")
        elif settings.last_result:
            box.label(text="Last: " + settings.last_result, icon="CHECKMARK")
        else:
            box.label(text="Not baked yet", icon="INFO")
        if not native.library_loaded():
            try:
                native.load_library()
            except native.BakeGIError as error:
                box.label(text=error.message, icon="ERROR")

        sub = layout.column()
        sub.use_property_split = False
        sub.prop(settings, "show_debug")


def register():
    bpy.utils.register_class(RENDER_PT_bakegi)


def unregister():
    bpy.utils.unregister_class(RENDER_PT_bakegi)
