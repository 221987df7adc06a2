# SPDX-License-Identifier: GPL-3.0-or-later
"""The lightmap UV map of each target: the user's (by name, default "BakeGI"), or a new one
made with Blender's own unwrappers without touching the other UV maps.

A new UV map is added to the mesh, made active only while the unwrapper runs (both
unwrappers write the active UV map), and the previously active map is restored; the render
UV map (what textures use) never changes unless the mesh had no UV map at all.

    SMART: Smart UV Project (bpy.ops.uv.smart_project): charts split at sharp angles, few
           seams; needs Edit Mode, so the object is briefly made active and edited alone.
    LIGHTMAP_PACK: Lightmap Pack (bl_operators.uvcalc_lightmap): every face its own box,
           run on the mesh data directly, no mode switch; many seams, no wasted stretching.

The margin between charts is two texels of the object's expected tile: enough for
bilinear filtering at a chart's edge to read the chart's own dilated gutter.
"""

import math

import bpy

from .. import compat
from ..native import BakeGIError

UV_METHODS = ("SMART", "LIGHTMAP_PACK")
MAX_UV_MAPS = 8  # Blender's limit per mesh


def find(mesh, name):
    return mesh.uv_layers.get(name)


def _expected_side(obj, texels_per_meter, max_side):
    """A rough tile side before the UVs exist (charts usually cover ~60% of [0,1]^2)."""
    texels_per_meter = getattr(obj, "bakegi_texels_per_meter", 0.0) or texels_per_meter
    area = sum(p.area for p in obj.data.polygons)
    scale = obj.matrix_world.to_scale()
    area *= abs(scale.x * scale.y * scale.z) ** (2.0 / 3.0)
    side = texels_per_meter * math.sqrt(max(area, 1e-12) / 0.6)
    return min(max(side, 16.0), float(max_side))


def _new_layer(obj, name):
    mesh = obj.data
    if len(mesh.uv_layers) >= MAX_UV_MAPS:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"'{obj.name}' has {MAX_UV_MAPS} UV maps already, Blender's limit; "
                          f"remove one or name an existing map as the lightmap UV map")
    previous_active = mesh.uv_layers.active.name if mesh.uv_layers.active else None
    layer = mesh.uv_layers.new(name=name, do_init=False)
    if layer is None:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"'{obj.name}': Blender refused a new UV map '{name}'")
    return layer, previous_active


def _restore_active(mesh, previous_active):
    if previous_active is not None and previous_active in mesh.uv_layers:
        mesh.uv_layers.active = mesh.uv_layers[previous_active]


def _lightmap_pack(obj, layer, margin_fraction):
    obj.data.uv_layers.active = layer
    # PREF_MARGIN_DIV: the margin is 1/div of the packed width.
    compat.lightmap_uvpack([obj.data], PREF_SEL_ONLY=False, PREF_NEW_UVLAYER=False,
                    PREF_PACK_IN_ONE=True, PREF_APPLY_IMAGE=False, PREF_BOX_DIV=12,
                    PREF_MARGIN_DIV=max(int(round(1.0 / max(margin_fraction, 1e-4))), 2))


def _smart_project(context, obj, layer, margin_fraction):
    """Smart UV Project of obj alone, restoring selection, active object and mode."""
    view_layer = context.view_layer
    previous_active = view_layer.objects.active
    previous_selection = [o for o in view_layer.objects if o.select_get(view_layer=view_layer)]
    mesh = obj.data
    # Edit Mode writes the selection back for every element: keep it to restore it.
    saved = {name: _flags(getattr(mesh, name)) for name in ("vertices", "edges", "polygons")}
    attributes_before = {a.name for a in mesh.attributes}
    try:
        for o in previous_selection:
            o.select_set(False, view_layer=view_layer)
        obj.select_set(True, view_layer=view_layer)
        view_layer.objects.active = obj
        mesh.uv_layers.active = layer
        with context.temp_override(active_object=obj, object=obj,
                                   selected_objects=[obj], selected_editable_objects=[obj]) \
                if hasattr(context, "temp_override") else _nullcontext():
            bpy.ops.object.mode_set(mode="EDIT")
            try:
                bpy.ops.mesh.reveal(select=False)
                bpy.ops.mesh.select_all(action="SELECT")
                bpy.ops.uv.smart_project(angle_limit=math.radians(66.0),
                                         island_margin=margin_fraction,
                                         area_weight=0.0, correct_aspect=True,
                                         scale_to_bounds=False)
            finally:
                bpy.ops.object.mode_set(mode="OBJECT")
    finally:
        obj.select_set(False, view_layer=view_layer)
        for o in previous_selection:
            o.select_set(True, view_layer=view_layer)
        view_layer.objects.active = previous_active
        for name, (select, hide) in saved.items():
            elements = getattr(mesh, name)
            if len(elements) == len(select):
                elements.foreach_set("select", select)
                elements.foreach_set("hide", hide)
        _remove_new_ui_state(mesh, attributes_before)


# Selection and visibility flags Edit Mode stores as hidden attributes (4.x: .hide_*; 5.0 also
# .uv_select_*). Absent means all false, so the ones Edit Mode added are taken out again once
# the flags are restored: the mesh leaves the unwrap with the attributes it came with.
_UI_STATE_PREFIXES = (".select_", ".hide_", ".uv_select_")


def _remove_new_ui_state(mesh, attributes_before):
    for name in [a.name for a in mesh.attributes]:
        if name not in attributes_before and name.startswith(_UI_STATE_PREFIXES):
            attribute = mesh.attributes.get(name)
            if attribute is not None:
                mesh.attributes.remove(attribute)


def _flags(elements):
    n = len(elements)
    select, hide = [False] * n, [False] * n
    elements.foreach_get("select", select)
    elements.foreach_get("hide", hide)
    return select, hide


class _nullcontext:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def ensure(context, objects, name, method, texels_per_meter, max_side):
    """Makes sure every object's mesh has the UV map `name`; creates it where missing.
    Returns [(object name, mesh name_full)] of the maps created (to remove them again if
    the bake does not finish)."""
    if method not in UV_METHODS:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"lightmap UV method must be one of {UV_METHODS}, not {method!r}")
    if not name:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", "the lightmap UV map needs a name")
    created = []
    try:
        for obj in objects:
            mesh = obj.data
            if find(mesh, name) is not None:
                continue
            # Two texels between charts: bilinear filtering at a chart's edge then reads
            # its own (dilated) gutter. A wider margin (room for the whole padding on both
            # sides) left Sponza's many-island meshes (thousands of charts each) covering
            # about 10% of their map, the rest margin.
            margin = 2.0 / _expected_side(obj, texels_per_meter, max_side)
            margin = min(max(margin, 0.001), 0.2)
            layer, previous_active = _new_layer(obj, name)
            created.append((obj.name, mesh.name_full))
            try:
                if method == "LIGHTMAP_PACK":
                    _lightmap_pack(obj, layer, margin)
                else:
                    _smart_project(context, obj, layer, margin)
            finally:
                layer = mesh.uv_layers.get(name)
                _restore_active(mesh, previous_active)
            mesh.update()
    except BaseException:
        remove(context.blend_data, created, name)
        raise
    return created


def remove(data, created, name):
    """Removes the UV maps `ensure` created (a bake that failed or was cancelled)."""
    for object_name, mesh_name in created:
        mesh = data.meshes.get(mesh_name)
        if mesh is None or getattr(mesh, "is_editmode", False):
            continue
        layer = mesh.uv_layers.get(name)
        if layer is not None:
            mesh.uv_layers.remove(layer)
            mesh.update()
