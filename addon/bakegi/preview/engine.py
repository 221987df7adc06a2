# SPDX-License-Identifier: GPL-3.0-or-later
"""BakeGI Preview as a Blender render engine.

F12 (render) exports the visible scene, renders one frame from the scene camera at the
render resolution and writes it as the Combined pass. The viewport's rendered shading keeps
one core preview per viewport: view_update re-exports only when geometry or materials
changed and otherwise hands the core the new lights (no re-export, the BVH stays); view_draw
renders the viewport's view at a fraction of its size and draws it."""

import time
import types

import bpy
import numpy

from .. import native
from ..export import scene as export_scene_module
from ..export.targets import MESH_LIKE
from . import camera as preview_camera


def preview_settings(scene):
    """The core settings of the preview from the scene's BakeGI properties."""
    props = scene.bakegi
    return native.Settings(method="splatting", vpl_count=int(props.preview_vpl_count),
                           visibility_clusters=int(props.preview_visibility_clusters))


def _export_context(depsgraph):
    # export_scene reads the scene (world, Eevee settings) and blend data from a context;
    # a render has no UI context, so it gets just those.
    return types.SimpleNamespace(scene=depsgraph.scene, blend_data=bpy.data)


def build_preview(depsgraph):
    """A core preview of the depsgraph's visible scene, lit by its lights and world."""
    exported = export_scene_module.export_scene(_export_context(depsgraph), "GRID",
                                                depsgraph=depsgraph)
    try:
        preview = native.Preview(exported.scene)
        preview.set_lights(exported.scene)
    finally:
        exported.close()
    return preview


def relight_preview(preview, depsgraph):
    """Gives the preview the depsgraph's current lights and world (no geometry export)."""
    lights = native.Scene()
    try:
        export_scene_module.export_lights(_export_context(depsgraph), lights, depsgraph)
        preview.set_lights(lights)
    finally:
        lights.close()


def _geometry_changed(depsgraph):
    for update in depsgraph.updates:
        data = update.id
        if isinstance(data, (bpy.types.Mesh, bpy.types.Material)):
            return True
        # Only what is exported as geometry: a moved camera or light needs no re-export.
        if isinstance(data, bpy.types.Object) and data.type in MESH_LIKE:
            if update.is_updated_geometry or update.is_updated_transform:
                return True
    return False


class BakeGIPreviewEngine(bpy.types.RenderEngine):
    bl_idname = "BAKEGI_PREVIEW"
    bl_label = "BakeGI Preview"
    bl_use_preview = False
    bl_use_postprocess = True

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._preview = None

    def __del__(self):
        preview = getattr(self, "_preview", None)
        if preview is not None:
            preview.close()

    # F12 -------------------------------------------------------------------------------
    def render(self, depsgraph):
        scene = depsgraph.scene
        scale = scene.render.resolution_percentage / 100.0
        width = max(1, int(scene.render.resolution_x * scale))
        height = max(1, int(scene.render.resolution_y * scale))
        result = self.begin_result(0, 0, width, height)
        try:
            if scene.camera is None or scene.camera.type != "CAMERA":
                raise native.BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                         "BakeGI Preview needs a scene camera")
            self.update_stats("BakeGI Preview", "exporting the scene")
            start = time.perf_counter()
            preview = build_preview(depsgraph)
            try:
                self.update_stats("BakeGI Preview", "rendering")
                values = preview_camera.scene_camera_values(scene.camera, width, height)
                image = preview.render(values, width, height, preview_settings(scene))
                report = preview.report
            finally:
                preview.close()
            if not scene.render.film_transparent:
                image[..., 3] = 1.0
            combined = result.layers[0].passes["Combined"]
            combined.rect = image[::-1].reshape(-1, 4)
            seconds = time.perf_counter() - start
            self.update_stats("BakeGI Preview", f"{seconds:.2f} s, frame "
                              f"{report['seconds']['total'] * 1000:.0f} ms, {report['vpls']} "
                              f"VPLs, {report['subsplats']} subsplats")
        except native.BakeGIError as error:
            self.report({"ERROR"}, f"BakeGI Preview: {error}")
        finally:
            self.end_result(result)

    # Viewport --------------------------------------------------------------------------
    def view_update(self, context, depsgraph):
        try:
            if self._preview is None or _geometry_changed(depsgraph):
                if self._preview is not None:
                    self._preview.close()
                    self._preview = None
                self._preview = build_preview(depsgraph)
            else:
                relight_preview(self._preview, depsgraph)
        except native.BakeGIError as error:
            self.report({"ERROR"}, f"BakeGI Preview: {error}")

    def view_draw(self, context, depsgraph):
        if self._preview is None:
            return
        region = context.region
        scale = depsgraph.scene.bakegi.preview_viewport_scale
        width = max(1, int(region.width * scale))
        height = max(1, int(region.height * scale))
        try:
            values = preview_camera.viewport_camera_values(context.region_data, width, height)
            image = self._preview.render(values, width, height,
                                         preview_settings(depsgraph.scene))
        except native.BakeGIError as error:
            self.report({"ERROR"}, f"BakeGI Preview: {error}")
            return
        image[..., 3] = 1.0
        _draw_image(self, depsgraph, image, region.width, region.height)


def _draw_image(engine, depsgraph, image, width, height):
    """Draws the linear image over the viewport region. Blender 3.5+ draws it through the
    scene's display transform (draw_texture_2d under bind_display_space_shader); older
    versions lack draw_texture_2d, so the image is encoded to sRGB here and drawn with the
    built-in image shader (the view transform and exposure are then not applied)."""
    import gpu

    rows, columns = image.shape[:2]
    try:
        from gpu_extras.presentation import draw_texture_2d
    except ImportError:
        draw_texture_2d = None
    if draw_texture_2d is None:
        linear = numpy.clip(image[..., :3], 0.0, 1.0)
        image = image.copy()
        image[..., :3] = numpy.where(linear <= 0.0031308, 12.92 * linear,
                                     1.055 * numpy.power(linear, 1.0 / 2.4) - 0.055)
    buffer = gpu.types.Buffer("FLOAT", rows * columns * 4, image[::-1].ravel().tolist())
    texture = gpu.types.GPUTexture((columns, rows), format="RGBA16F", data=buffer)
    if draw_texture_2d is not None:
        engine.bind_display_space_shader(depsgraph.scene)
        draw_texture_2d(texture, (0, 0), width, height)
        engine.unbind_display_space_shader()
        return
    from gpu_extras.batch import batch_for_shader

    shader = gpu.shader.from_builtin("2D_IMAGE")
    batch = batch_for_shader(shader, "TRI_FAN", {
        "pos": ((0, 0), (width, 0), (width, height), (0, height)),
        "texCoord": ((0, 0), (1, 0), (1, 1), (0, 1))})
    shader.bind()
    shader.uniform_sampler("image", texture)
    batch.draw(shader)


def _compatible_panels():
    """Blender's own panels that work with any engine (those Workbench and Eevee share) get
    this engine too, so the Render and Material properties stay usable."""
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is not None and "BLENDER_RENDER" in engines:
            panels.append(panel)
    return panels


def register():
    bpy.utils.register_class(BakeGIPreviewEngine)
    for panel in _compatible_panels():
        panel.COMPAT_ENGINES.add("BAKEGI_PREVIEW")


def unregister():
    for panel in _compatible_panels():
        panel.COMPAT_ENGINES.discard("BAKEGI_PREVIEW")
    bpy.utils.unregister_class(BakeGIPreviewEngine)
