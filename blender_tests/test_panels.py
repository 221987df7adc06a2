"""The add-on's panels and preferences drawn in every Blender version of the suite, in every
state they have (each method, target and quality; a bake's report, an error check that flags
the bake, a bake running, live indirect, the debug settings), into a layout that checks each
call against this Blender's own UILayout: the function exists, its keyword arguments are
parameters of it, every icon is one of this version's icons, every property drawn exists on
its data, every operator is registered and every operator property set exists. Only
Debian's Blender 3.4 has a window in the suite (test_ui.py); the bpy modules of 4.2, 4.5 and
5.0 never draw a panel otherwise, and a name a version renamed (4.1 renamed the icon
LIGHTPROBE_GRID) fails there only when a user opens the panel."""

import json
import os
import sys
import types

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

UI_FUNCTIONS = bpy.types.UILayout.bl_rna.functions
ICONS = set(UI_FUNCTIONS["prop"].parameters["icon"].enum_items.keys())


class LayoutMisuse(AssertionError):
    pass


class OperatorProperties:
    """What layout.operator() returns: setting a property the operator lacks is an error."""

    def __init__(self, idname, rna):
        object.__setattr__(self, "_idname", idname)
        object.__setattr__(self, "_names", set(rna.properties.keys()))

    def __setattr__(self, name, value):
        if name not in self._names:
            raise LayoutMisuse(f"operator {self._idname} has no property {name!r}")


class CheckingLayout:
    """A stand-in for bpy.types.UILayout that checks every call against this Blender's RNA
    description of UILayout and records what was drawn."""

    # Attributes a panel may set on a layout (UILayout's RNA properties).
    SETTABLE = set(bpy.types.UILayout.bl_rna.properties.keys())

    def __init__(self, drawn):
        object.__setattr__(self, "_drawn", drawn)

    def __setattr__(self, name, value):
        if name not in self.SETTABLE:
            raise LayoutMisuse(f"UILayout has no attribute {name!r}")

    def __getattr__(self, name):
        if name not in UI_FUNCTIONS:
            raise LayoutMisuse(f"UILayout has no function {name!r} in Blender "
                               f"{bpy.app.version_string}")
        function = UI_FUNCTIONS[name]
        parameters = function.parameters

        def call(*args, **kwargs):
            for key, value in kwargs.items():
                if key not in parameters:
                    raise LayoutMisuse(f"UILayout.{name}() has no parameter {key!r}")
                if key == "icon" and value not in ICONS:
                    raise LayoutMisuse(f"UILayout.{name}(icon={value!r}): no such icon in "
                                       f"Blender {bpy.app.version_string}")
            self._drawn.append((name, args, kwargs))
            if name == "prop":
                data, prop_name = args[0], args[1]
                if prop_name not in data.bl_rna.properties:
                    raise LayoutMisuse(f"{data.bl_rna.identifier} has no property {prop_name!r}")
            if name == "operator":
                idname = args[0]
                module, _, operator = idname.partition(".")
                try:
                    rna = getattr(getattr(bpy.ops, module), operator).get_rna_type()
                except (AttributeError, KeyError) as error:
                    raise LayoutMisuse(f"no operator {idname!r} is registered") from error
                return OperatorProperties(idname, rna)
            outputs = [p for p in parameters if p.is_output]
            if outputs and outputs[0].identifier == "layout":
                return CheckingLayout(self._drawn)
            return None
        return call


class DrawnAs:
    """`self` for a panel's or preferences' draw(): the checking layout as .layout, anything
    else from the wrapped object (the class's helpers, the preferences' properties)."""

    def __init__(self, wrapped, layout):
        self._wrapped = wrapped
        self.layout = layout

    def __getattr__(self, name):
        value = getattr(self._wrapped, name)
        if isinstance(value, types.FunctionType):  # a method of the class, bound to self
            return value.__get__(self)
        return value

    @property
    def bl_rna(self):
        return self._wrapped.bl_rna


def draw(cls_or_object, context):
    """Everything the draw() of a panel class or of an object (the add-on's preferences)
    drew, as (function, args, kwargs)."""
    drawn = []
    owner = cls_or_object if isinstance(cls_or_object, type) else type(cls_or_object)
    owner.draw(DrawnAs(cls_or_object, CheckingLayout(drawn)), context)
    return drawn


def drawn_properties(drawn):
    return {args[1] for function, args, _ in drawn if function == "prop"}


# A report as the error check writes it when it flags a bake (ui/panels.py _draw_error_check).
FLAGGED_REPORT = {
    "method": "meshless",
    "error_check": {"error": 0.4, "low": 0.3, "high": 0.5, "probes": 256,
                    "causes": ["the light changes faster than the mesh's vertices can hold; "
                               "subdivide the named objects or bake a lightmap"],
                    "coarse_objects": ["Floor"]},
}


class PanelsDrawInThisBlender(common.SmallCornellCase):

    def setUp(self):
        super().setUp()
        from bakegi.ui import operators
        self.runtime = dict(operators.runtime)
        self.addCleanup(operators.runtime.update, self.runtime)
        settings = bpy.context.scene.bakegi
        self.addCleanup(self.restore, {name: getattr(settings, name)
                                       for name in ("method", "target", "quality", "use_cache",
                                                    "live_indirect", "show_debug",
                                                    "last_result", "last_report")})

    def restore(self, values):
        for name, value in values.items():
            setattr(bpy.context.scene.bakegi, name, value)

    def enum_values(self, name):
        return [item.identifier
                for item in bpy.context.scene.bakegi.bl_rna.properties[name].enum_items]

    def test_every_method_target_and_quality(self):
        from bakegi.ui import panels
        settings = bpy.context.scene.bakegi
        drawn = set()
        for method in self.enum_values("method"):
            for target in self.enum_values("target"):
                for quality in self.enum_values("quality"):
                    with self.subTest(method=method, target=target, quality=quality):
                        settings.method, settings.target, settings.quality = \
                            method, target, quality
                        settings.use_cache = settings.live_indirect = True
                        settings.show_debug = True
                        for panel in (panels.RENDER_PT_bakegi, panels.VIEW3D_PT_bakegi_live):
                            drawn |= drawn_properties(draw(panel, bpy.context))
        # Every setting the panel's branches show was drawn somewhere, so that a branch the
        # loops missed cannot pass unchecked.
        for name in ("bins", "meshless_levels", "samples", "denoise", "texels_per_meter",
                     "lightmap_uv_method", "grid_cell_size", "grid_follow", "linked_duplicates",
                     "live_indirect", "debug_direct"):
            self.assertIn(name, drawn)

    def test_after_a_bake_a_flagged_check_a_running_bake_and_live_indirect(self):
        from bakegi.ui import operators, panels
        settings = bpy.context.scene.bakegi
        self.bakegi.bake(method="pathtrace", samples=2, objects="VISIBLE")
        self.assertTrue(settings.last_result)
        drawn = draw(panels.RENDER_PT_bakegi, bpy.context)
        self.assertTrue(any(kwargs.get("text", "").startswith("Last: ")
                            for function, _, kwargs in drawn if function == "label"))
        settings.last_report = json.dumps(FLAGGED_REPORT)
        drawn = draw(panels.RENDER_PT_bakegi, bpy.context)
        operators_drawn = [args[0] for function, args, _ in drawn if function == "operator"]
        self.assertIn(operators.BAKEGI_OT_subdivide_copy.bl_idname, operators_drawn)
        operators.runtime.update(running=True, text="tracing 5%")
        for panel in (panels.RENDER_PT_bakegi, panels.VIEW3D_PT_bakegi_live):
            settings.method = "meshless"
            drawn = draw(panel, bpy.context)
            self.assertIn("tracing 5%", [kwargs.get("text") for function, _, kwargs in drawn
                                         if function == "label"])

    def test_preview_panel_and_preferences(self):
        from bakegi.ui import panels
        drawn = drawn_properties(draw(panels.RENDER_PT_bakegi_preview, bpy.context))
        self.assertIn("preview_vpl_count", drawn)
        addon = bpy.context.preferences.addons.get("bakegi")
        self.assertIsNotNone(addon, "the add-on's preferences are not registered")
        drawn = drawn_properties(draw(addon.preferences, bpy.context))
        self.assertEqual(drawn, {"threads", "memory_budget_mb", "cache_folder"})

    def test_the_checking_layout_catches_what_a_version_lacks(self):
        """The layout is no rubber stamp: a renamed icon, a property that does not exist, an
        unknown parameter or operator are each an error."""
        layout = CheckingLayout([])
        settings = bpy.context.scene.bakegi
        with self.assertRaises(LayoutMisuse):
            layout.label(text="x", icon="NO_SUCH_ICON_ANYWHERE")
        with self.assertRaises(LayoutMisuse):
            layout.prop(settings, "no_such_setting")
        with self.assertRaises(LayoutMisuse):
            layout.prop(settings, "method", no_such_parameter=True)
        with self.assertRaises(LayoutMisuse):
            layout.operator("bakegi.no_such_operator")
        with self.assertRaises(LayoutMisuse):
            layout.no_such_function()
        column = layout.column(align=True)
        column.prop(settings, "method", text="")
        self.assertIsInstance(column, CheckingLayout)


if __name__ == "__main__":
    common.run_tests(__name__)
