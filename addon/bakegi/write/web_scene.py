# SPDX-License-Identifier: GPL-3.0-or-later
"""Export for Web (issue 16, §4 of the grid's paper): the visible scene as glTF with
progressive meshes, its baked grid and the page (index.html + viewer.js, built from
addon/web) in one folder, which `bakegi serve FOLDER` streams to a browser, or which the
page opens from disk. The camera is the scene's, so the page starts on the render's view."""

import json
import math
import os
import shutil
import time

from .. import native
from ..export import scene as export_scene_module

WEB_PAGE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "web")
PAGE_FILES = ("index.html", "viewer.js")


def vertical_field_of_view(camera, aspect):
    """The vertical angle of view (radians) Blender renders `camera` with at `aspect`."""
    data = camera.data
    fit = data.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if aspect >= 1.0 else "VERTICAL"
        sensor = data.sensor_width  # AUTO fits the sensor width to the longer side
    else:
        sensor = data.sensor_width if fit == "HORIZONTAL" else data.sensor_height
    half = math.atan(sensor / (2.0 * data.lens))
    if fit == "HORIZONTAL":
        return 2.0 * math.atan(math.tan(half) / aspect)
    return 2.0 * half


def camera_values(scene):
    """The nine numbers bakegi_web_export takes for the scene's camera, or None."""
    camera = scene.camera
    if camera is None or camera.type != "CAMERA" or camera.data.type != "PERSP":
        return None
    render = scene.render
    aspect = (render.resolution_x * render.pixel_aspect_x) / max(
        render.resolution_y * render.pixel_aspect_y, 1e-9)
    location, rotation, _ = camera.matrix_world.decompose()
    return [location.x, location.y, location.z, rotation.x, rotation.y, rotation.z, rotation.w,
            vertical_field_of_view(camera, aspect), aspect]


def page_available():
    return all(os.path.isfile(os.path.join(WEB_PAGE, name)) for name in PAGE_FILES)


def export_web(context, folder, grid_path):
    """Writes the folder; returns a report (folder, files, bytes, seconds, camera, warnings:
    how the page draws the scene's light other than its lamps, lighting_notes). Raises
    BakeGIError naming what is missing; the Blender data is not changed."""
    if not page_available():
        raise native.BakeGIError(
            "BAKEGI_ERROR_IO", f"the add-on lacks its web page ({WEB_PAGE}): build it with "
            "'npm ci && npm run build' in addon/web (tools/setup.sh does) and reinstall")
    start = time.perf_counter()
    camera = camera_values(context.scene)
    exported = export_scene_module.export_scene(context, "GRID")
    grid = native.Grid.read(grid_path) if grid_path else None
    try:
        native.web_export(exported.scene, folder, grid=grid, camera=camera)
    finally:
        exported.close()
        if grid is not None:
            grid.close()
    for name in PAGE_FILES:
        shutil.copyfile(os.path.join(WEB_PAGE, name), os.path.join(folder, name))
    files = sorted(os.listdir(folder))
    with open(os.path.join(folder, "scene.gltf"), encoding="utf-8") as f:
        warnings = lighting_notes(json.load(f))
    return {"folder": folder, "files": files,
            "bytes": {name: os.path.getsize(os.path.join(folder, name)) for name in files},
            "camera": camera is not None, "seconds": time.perf_counter() - start,
            "serve": f"bakegi serve {folder}", "warnings": warnings}


def lighting_notes(gltf):
    """How the page draws the scene's light other than its lamps: the notes the exporter wrote
    into the glTF (native/src/web/gltf_export.cpp), which the page shows too."""
    return list(gltf.get("extras", {}).get("bakegi", {}).get("notes", []))
