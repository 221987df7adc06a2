# SPDX-License-Identifier: GPL-3.0-or-later
"""The scripting API, re-exported by the package:

    import bakegi
    report = bakegi.bake(method="pathtrace", samples=64, target="CORNER", objects="VISIBLE")
    report = bakegi.bake(target="LIGHTMAP", texels_per_meter=40, objects="VISIBLE")
    report = bakegi.bake(target="GRID", grid_object="BakeGI Grid")   # report["grid"]["path"]
    bakegi.apply_grid(["Prop", "Character"])    # BakeGI_Indirect from the newest grid
    bakegi.export_scene_file("/tmp/scene.bgs", target="CORNER", objects="VISIBLE")
    bakegi.remove_bake()

bake() runs synchronously (timers do not run in background mode) through the same
session.BakeSession as the Bake Indirect operator.
"""

import os
import time

import bpy

from . import grid_follow, live, session
from .export import scene as export_scene_module, targets as export_targets
from .ui import operators, properties
from .write import attributes, grid_file
from .write.file_names import safe_name
from .native import BakeGIError
from .request import BakeRequest, GridOptions, LightmapOptions


def _context(context):
    """The context a scripted call works in, with its view layer brought up to date: a script
    that has just made objects would otherwise find them missing from the view layer's list
    ("nothing to bake: no mesh object is visible") or unevaluated."""
    context = context if context is not None else bpy.context
    view_layer = getattr(context, "view_layer", None)
    if view_layer is not None:
        view_layer.update()
    return context


def bake(method=None, samples=None, seed=0, target="CORNER", objects="SELECTED",
         threads=None, hook_materials=True, context=None, method_settings=None, live=False,
         texels_per_meter=40.0, lightmap_max_size=1024, lightmap_uv_map="BakeGI",
         lightmap_uv_method="SMART", lightmap_padding=4, lightmap_folder="//bakegi_lightmaps",
         lightmap_full_float=False, lightmap_reject_inside=True, linked_duplicates="SHARED",
         estimate_error=True, grid_object=None, grid_cell_size=0.0, grid_max_vertices=0,
         grid_rays=64, grid_quantized=True, grid_folder="//bakegi_grids"):
    """Bakes indirect light into the color attribute BakeGI_Indirect of the target meshes
    (target 'CORNER' or 'POINT'), or into a lightmap atlas (target 'LIGHTMAP').

    Lightmaps: each target's UV map lightmap_uv_map (made with lightmap_uv_method, 'SMART'
    or 'LIGHTMAP_PACK', where missing) gets a square tile of texels_per_meter texels per
    metre (at most lightmap_max_size) in one atlas, written as
    <lightmap_folder>/BakeGI_Lightmap_<blend>_<scene>_<id>.exr (// = next to the .blend;
    write/file_names.py) and loaded as the image BakeGI_Lightmap_<scene>; report["lightmap"]
    holds its size, texel counts and path. lightmap_reject_inside: drop texels that lie
    inside other geometry (off for single-sided foliage, which it rejects too).

    objects: 'SELECTED', 'VISIBLE', or a list of objects (or their names). Every visible
    object takes part in the light transport; only the targets receive the attribute.
    Returns the report: seconds per stage (export, bake, writeback, total and the core's
    own), bake_points, method, settings, warnings, memory, rays, objects.
    method_settings: further core settings of the method, e.g. {"bins": 300, "iterations":
    32} for method="antiradiance", {"denoise": 1} to filter a path-traced bake's noise
    (docs/settings.md lists every method's keys).
    method: None = the core's default bake: "pathtrace" to a 5% target error through the
    denoiser (bakegi.native.default_method() and default_method_settings(); method_settings
    may change any of them, e.g. {"target_error": 0.02}), the fastest to 5% on every scene
    measured (docs/benchmarks.md, section 0c); "pathtrace" (the Monte Carlo reference, 64
    paths per point unless samples or a target_error says otherwise; samples applies to the
    sampling methods only), "antiradiance" (fast and smooth, biased by patch size and bins) or
    "meshless" (precomputed transfer; relights in milliseconds; method_settings e.g.
    {"levels": 0, "epsilon": 0.01, "cache_dir": "/path"}).
    samples: None = 64 for a named method, the default bake's cap (65,536) otherwise.
    live: meshless only: keep the precomputation so that live_update() (or, in the UI, any
    change of a light) relights the bake.
    linked_duplicates (attribute targets): 'SHARED' bakes the first of the objects that share
    a mesh (the others show its light); 'SINGLE_USER' gives each its own mesh copy and bakes
    it.
    estimate_error: path-trace a few hundred probes after the bake and report the estimated
    error (report["estimated_error"], a fraction, and report["estimated_error_interval"],
    90%; report["error_check"] with the error between vertices, per object, and the likely
    causes, also as warnings when it is above 10%).
    target 'GRID': an Irradiance Vector Grid (docs/ivg.md) over the box of grid_object (an
    Empty, whose display cube is the box, or any object's bounding box; or its name), or the
    visible scene's bounds when None; cells of about grid_cell_size metres (0: 32 on the
    longest axis), at most grid_max_vertices (0: 64^3), grid_rays rays per vertex hemisphere.
    Written to <grid_folder>/BakeGI_Grid_<blend>_<scene>_<id>.bgivg (quantized: 42 bytes a
    vertex, else 216); report["grid"] holds its path, resolution, bounds and counts. objects and
    hook_materials do not apply; apply_grid() lights meshes from it.
    Raises bakegi.BakeGIError with the core's message; on error (or cancel) nothing in the
    scene is changed.
    threads: None = the add-on preferences' (0 there = every core); the preferences' memory
    budget applies unless method_settings names memory_budget_mb."""
    context = _context(context)
    method_settings = dict(method_settings or {})
    if not estimate_error:
        method_settings["error_probes"] = 0
    cache_dir = method_settings.get("cache_dir")
    if isinstance(cache_dir, str) and cache_dir:
        # Blender's // (next to the .blend), as every folder setting of the add-on reads it:
        # the core would take "//cache" for the folder /cache at the filesystem root.
        method_settings["cache_dir"] = properties.blend_relative_directory(cache_dir,
                                                                           "bakegi_cache")
    lightmap = LightmapOptions(uv_map=lightmap_uv_map, texels_per_meter=texels_per_meter,
                               max_side=lightmap_max_size, padding=lightmap_padding,
                               uv_method=lightmap_uv_method,
                               reject_inside=bool(lightmap_reject_inside))
    folder = properties.lightmap_directory(lightmap_folder) if target == "LIGHTMAP" else ""
    grid = GridOptions(bounds=_grid_bounds(context, grid_object), cell_size=grid_cell_size,
                       max_vertices=grid_max_vertices, rays=grid_rays,
                       quantized=bool(grid_quantized))
    request = BakeRequest(method=method, samples=samples, seed=seed, target=target,
                          objects=objects, threads=threads, hook_materials=hook_materials,
                          method_settings=method_settings, live=live, lightmap=lightmap,
                          lightmap_folder=folder, lightmap_full_float=lightmap_full_float,
                          linked_duplicates=linked_duplicates, grid=grid,
                          grid_folder=properties.grid_directory(grid_folder)
                          if target == "GRID" else "")
    report = session.BakeSession(context, request).run()
    scene = context.scene
    if hasattr(scene, "bakegi"):
        operators.store_report(scene, report)
    return report


def _grid_bounds(context, grid_object):
    """The world box of the grid object (an object or its name), or None."""
    if grid_object is None:
        return None
    obj = (context.blend_data.objects.get(grid_object) if isinstance(grid_object, str)
           else grid_object)
    if obj is None:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"no object named {grid_object!r}")
    return grid_file.object_bounds(obj)


def apply_grid(objects, path=None, interpolation="TRILINEAR", target="CORNER",
               hook_materials=True, visibility=True, darken_buried=True, directional="ABSOLUTE",
               context=None):
    """Writes BakeGI_Indirect on `objects` ('SELECTED', 'VISIBLE', or a list of objects or
    names) from a baked grid: the grid's indirect light at their face corners (target
    'CORNER') or vertices ('POINT': the mean of their corners), as they stand now (moved,
    added, decimated or subdivided meshes all work; no bake runs). path None: the scene's
    newest grid (the last GRID bake's file). interpolation 'TRILINEAR' or 'TRICUBIC'. directional: 'ABSOLUTE' (|n|
    weights between the axis hemispheres: exact under uniform light for any normal; a lower
    or equal error than the paper's in 19 of the 20 suite runs of docs/ivg.md) or 'SQUARED' (the paper's
    n^2). hook_materials: Material
    Preview shows the result as after a bake. visibility: each point reads only the grid
    vertices it sees (a ray to each), so light does not leak through walls thinner than a
    cell; darken_buried: points inside or under other geometry (a floor under a box) read 0,
    as in a bake. Either exports the visible scene and traces rays (8 a point, and 32 for
    the buried test); both False: the paper's reading, fastest. Returns a report: objects,
    points, buried_points, unsure_points, seconds (read, evaluate, write, total), the
    grid's info, warnings. Raises BakeGIError with nothing changed when the grid cannot be read."""
    context = _context(context)
    # What Follow Moves re-applies with (grid_follow.py): None stays None, the newest grid.
    follow_options = dict(path=path, interpolation=interpolation, target=target,
                          hook_materials=hook_materials, visibility=visibility,
                          darken_buried=darken_buried, directional=directional)
    if path is None:
        path = context.scene.get(grid_file.GRID_PATH_PROPERTY)
        if not path:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              "the scene has no baked grid: bake one with target='GRID' or "
                              "give the path of a .bgivg file")
    if target not in ("CORNER", "POINT"):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"target must be 'CORNER' or 'POINT', not {target!r}")
    if isinstance(objects, str) and objects not in ("SELECTED", "VISIBLE"):
        objects = [objects]
    targets, skipped = export_targets.resolve_targets(context, objects)
    if not targets:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          "nothing to light: " + ("; ".join(skipped) or "no mesh object given"))
    depsgraph = context.evaluated_depsgraph_get()
    exported = (export_scene_module.export_scene(context, "GRID", depsgraph=depsgraph)
                if visibility or darken_buried else None)
    try:
        report = grid_file.apply_grid(context.blend_data, depsgraph, targets,
                                      bpy.path.abspath(path), interpolation, target,
                                      hook_materials, exported.scene if exported else None,
                                      directional, visibility, darken_buried)
    finally:
        if exported is not None:
            exported.close()
    report["warnings"] = report["warnings"] + list(skipped)
    grid_follow.remember(context.scene, targets, follow_options)
    return report


def export_web(folder=None, path=None, context=None):
    """Export for Web: the visible scene (glTF 2.0 with progressive meshes), its grid and the
    web page in `folder` (default: //bakegi_web/<scene> beside the saved .blend). path: the
    grid file (default: the scene's newest grid; None and no grid: the page shows direct
    light only). `bakegi serve FOLDER` streams it to a browser (docs/ivg.md). Returns a
    report: folder, files, bytes per file, camera (whether the scene's was written),
    seconds, serve (the command), warnings (how the page draws the world's and emissive
    surfaces' light: from the grid, soft, when the grid carries it; else only its bounce)."""
    from .write import web_scene
    context = _context(context)
    if path is None:
        path = context.scene.get(grid_file.GRID_PATH_PROPERTY)
    if path and not os.path.isfile(bpy.path.abspath(path)):
        raise BakeGIError("BAKEGI_ERROR_IO", f"the grid file {path} is missing: bake the grid "
                          "again or give its path")
    if folder is None:
        if not bpy.data.filepath:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              "save the .blend first or give a folder")
        folder = bpy.path.abspath(f"//bakegi_web/{safe_name(context.scene.name)}")
    return web_scene.export_web(context, bpy.path.abspath(folder),
                                bpy.path.abspath(path) if path else None)


def live_update(context=None):
    """Relights the live bake of the scene with its current lights and world, now, and
    waits. Returns seconds: {"export", "core", "write", "total"} and "bake_points".
    Raises BakeGIError if no live bake is kept for the scene, or if meshes or materials
    changed since (then bake again)."""
    return live.update(_context(context))


def live_stop():
    """Releases the precomputation kept for live indirect."""
    live.stop()


def export_scene_file(path, target="CORNER", objects="SELECTED", context=None,
                      texels_per_meter=40.0, lightmap_max_size=1024, lightmap_uv_map="BakeGI",
                      lightmap_uv_method="SMART", lightmap_padding=4):
    """Writes the evaluated scene and the targets' bake points to a .bgs file (what the
    CLI and the sweep read). target 'LIGHTMAP' also writes the atlas layout beside it
    (<path without .bgs>.bgl: `bakegi bake X.bgs --lightmaps X.bgl --exr-dir D` writes the
    EXR) and creates missing lightmap UV maps. Returns a dict with counts, seconds,
    warnings and, per target object, its slice of the bake points."""
    context = _context(context)
    start = time.perf_counter()
    lightmap = LightmapOptions(uv_map=lightmap_uv_map, texels_per_meter=texels_per_meter,
                               max_side=lightmap_max_size, padding=lightmap_padding,
                               uv_method=lightmap_uv_method)
    exported = export_scene_module.export_scene(context, target, objects, lightmap=lightmap)
    layout_path = None
    try:
        exported.scene.write(str(path), exported.points)
        if exported.lightmaps is not None:
            stem = str(path)[:-4] if str(path).endswith(".bgs") else str(path)
            layout_path = stem + ".bgl"
            exported.lightmaps.lightmaps.write(layout_path)
    finally:
        exported.close()
    return {"path": str(path), "lightmap_layout": layout_path,
            "seconds": time.perf_counter() - start,
            "counts": exported.counts, "warnings": exported.warnings + exported.skipped,
            "targets": [{"object": t.object_name, "domain": t.domain, "start": t.start,
                         "count": t.count} for t in exported.targets]}


def _on_object(obj, context, make):
    """make(the object `obj` names, or `obj` itself); its ValueError as a BakeGIError."""
    context = _context(context)
    target = context.blend_data.objects.get(obj) if isinstance(obj, str) else obj
    if target is None:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"no object named {obj!r}")
    try:
        return make(target)
    except ValueError as error:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", str(error)) from None


def subdivide_copy(obj, vertices=4000, context=None):
    """Makes '<name>_BakeGI', a copy of the mesh object `obj` (or its name) with about
    `vertices` vertices spread over its surface, for a target whose vertices are too few for
    its light (report["error_check"]["coarse_objects"] names them); hides `obj`. Returns the
    copy."""
    from . import subdivision
    return _on_object(obj, context, lambda target: subdivision.subdivide_copy(target, vertices))


def simplify_copy(obj, ratio=0.1, context=None):
    """Makes '<name>_LOD<percent>', a level of detail of the mesh object `obj` (or its name)
    with about `ratio` (0, 1] of its triangles (meshoptimizer's simplifier in the core), to
    light from a grid (apply_grid) without a re-bake; hides `obj`. Returns (the copy,
    {"triangles", "lod_triangles", "deviation"}: the deviation reached over the mesh's
    extent)."""
    from . import simplification
    return _on_object(obj, context, lambda target: simplification.simplify_copy(target, ratio))


def remove_bake(objects=None, context=None):
    """Removes BakeGI_Indirect and restores hooked materials. objects: None (every mesh in
    the file), 'SELECTED', 'VISIBLE', or a list of objects or names.
    Returns {"objects": [names cleared], "materials": [names restored]}."""
    context = _context(context)
    if objects in ("SELECTED", "VISIBLE"):
        objects, _ = export_targets.resolve_targets(context, objects)
    elif isinstance(objects, str):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"objects must be None, 'SELECTED', 'VISIBLE' or a list, not "
                          f"{objects!r}")
    return attributes.remove_bake(context.blend_data, objects)
