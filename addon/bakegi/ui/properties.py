# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake settings stored on the scene: bpy.types.Scene.bakegi."""

import os

import bpy

from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from .. import compat, native
from ..request import BakeRequest, GridOptions, LightmapOptions
from . import preferences

# The methods the panel offers, with their labels. The default is the core's (register() sets
# it from bakegi_settings_describe): the path tracer, which with the panel's default Quality
# (Good, 5%) and Denoise on is the core's default bake, the fastest to 5% on every scene
# measured (docs/benchmarks.md, section 0c). A method not listed here is still bakeable from
# scripts: bakegi.bake(method=...) takes any the core registers.
METHOD_ITEMS = [
    ("antiradiance", "Antiradiance", "Dachsbacher et al. 2007: light exchanged between "
     "surface patches through directional bins, occlusion by antiradiance instead of "
     "visibility rays; fast and smooth, biased by patch size and bin count"),
    ("pathtrace", "Path Tracing", "Monte Carlo reference: converges to the exact indirect "
     "light; noise falls as samples grow"),
    ("meshless", "Meshless (Live)", "Lehtinen et al. 2008: precomputes how direct light "
     "becomes indirect light once, then relights in milliseconds; with Live Indirect the "
     "bake follows the lights as they move"),
    ("splatting", "Splatting (Draft)", "Nichols & Wyman 2009: one bounce from virtual point "
     "lights through an adaptive multiresolution hierarchy; fastest, a draft (one bounce, no "
     "visibility for the bounce unless Visibility Rays is set)"),
]

TARGET_ITEMS = [
    ("CORNER", "Face Corners", "One value per face corner: hard edges stay hard"),
    ("POINT", "Vertices", "One value per vertex, the mean of its face corners (as Cycles): "
              "smooth across edges"),
    ("LIGHTMAP", "Lightmap Textures", "An OpenEXR lightmap atlas on a lightmap UV map: "
     "detail independent of the mesh, for export to game engines and the web"),
    ("GRID", "Irradiance Grid", "An Irradiance Vector Grid over a box (a .bgivg file next to "
     "the .blend): Apply Grid then lights any mesh inside it, moved, added or of another "
     "level of detail, without a new bake"),
]

GRID_DIRECTIONAL_ITEMS = [
    ("ABSOLUTE", "Uniform-Exact (|n|)", "Weights |n| per axis: exact along the axes and under "
     "evenly spread light for any normal; as good or better in 19 of 20 measured runs"),
    ("SQUARED", "Paper (n\u00b2)", "Pacanowski et al.'s weights: exact for normals along the "
     "axes, darker between them"),
]

GRID_INTERPOLATION_ITEMS = [
    ("TRILINEAR", "Trilinear", "The 8 grid vertices around each point (fast)"),
    ("TRICUBIC", "Tricubic", "A cubic B-spline over 64 grid vertices: smoother, slower"),
]


def _is_grid_box(self, obj):
    return obj.type in ("EMPTY", "MESH")

LIGHTMAP_UV_METHOD_ITEMS = [
    ("SMART", "Smart UV Project", "Charts split at sharp edges: few seams"),
    ("LIGHTMAP_PACK", "Lightmap Pack", "Every face its own box: no stretching, many seams"),
]

LINKED_DUPLICATE_ITEMS = [
    ("SHARED", "Keep Shared Mesh", "Objects that share a mesh share its color attribute: the "
     "first is baked and the others show its light"),
    ("SINGLE_USER", "Make Single User", "Give each object that shares a mesh its own copy of "
     "the mesh and bake each with its own light (more memory; undo restores the sharing)"),
]

# Path tracing: the quality is the error to reach (the core's target_error: samples go where the
# noise is until the predicted NRMSE meets it, an upper bound with its quasi-random samples;
# docs/benchmarks.md section 0), or a fixed sample count.
QUALITY_ITEMS = [
    ("DRAFT", "Draft (10%)", "Sample until the predicted error is 10%"),
    ("GOOD", "Good (5%)", "Sample until the predicted error is 5%"),
    ("FINAL", "Final (2%)", "Sample until the predicted error is 2%"),
    ("SAMPLES", "Fixed Samples", "Exactly Samples paths per bake point"),
]
QUALITY_TARGETS = {"DRAFT": 0.10, "GOOD": 0.05, "FINAL": 0.02}
# A target's cap on the paths of one point: far above what 2% needs on the scenes measured
# (a few thousand), so that the target, not the cap, ends the bake.
QUALITY_MAX_SAMPLES = 1 << 16

OBJECTS_ITEMS = [
    ("SELECTED", "Selected", "Bake the selected mesh objects"),
    ("VISIBLE", "All Visible", "Bake every visible mesh object"),
]


def _live_toggled(self, context):
    if not self.live_indirect:
        from .. import live
        live.stop()


class BakeGISettings(bpy.types.PropertyGroup):
    preview_vpl_count: IntProperty(
        name="VPLs", default=256, min=1, max=65536, soft_max=4096,
        description="BakeGI Preview: virtual point lights of the one splatted bounce")
    preview_visibility_clusters: IntProperty(
        name="Visibility Rays", default=0, min=0, max=4096, soft_max=64,
        description="BakeGI Preview: shadow rays per subsplat towards clustered VPLs (0: no "
        "visibility for the bounce, as the paper; light may leak through walls)")
    preview_viewport_scale: FloatProperty(
        name="Viewport Resolution", default=0.5, min=0.1, max=1.0, subtype="FACTOR",
        description="BakeGI Preview: the viewport renders at this fraction of its size")
    show_debug: BoolProperty(
        name="Debug Methods", default=False,
        description="Offer methods meant for checking the add-on rather than for baking")
    # Static items: a PropertyGroup with an items callback crashes (4.2) or hangs (4.5) the
    # bpy module when Python exits, so the debug method is a separate switch.
    method: EnumProperty(name="Method", items=METHOD_ITEMS,
                         description="How the indirect light is computed")
    debug_direct: BoolProperty(
        name="Bake Direct Light", default=False,
        description="Debug: bake the direct light instead of the indirect light, to compare "
        "light units with Cycles")
    samples: IntProperty(name="Samples", default=64, min=1, max=1 << 30, soft_max=4096,
                         description="Paths per bake point: more is slower and less noisy")
    quality: EnumProperty(
        name="Quality", items=QUALITY_ITEMS, default="GOOD",
        description="Path tracing: the error to reach (samples go where the noise is and the "
        "bake stops when its own estimate meets it), or a fixed number of samples")
    denoise: BoolProperty(
        name="Denoise", default=True,
        description="Path tracing: filter the noise over neighbouring points on the same "
        "surface (edge- and noise-aware); 2-3.5x less error at the same samples for a bias of "
        "about 1-3%, which Check Error measures. With a Quality target the bake stops when "
        "the error left after the filter meets it")
    bins: IntProperty(name="Bins", default=300, min=12, max=3072,
                      description="Antiradiance: directional bins per element; more bins "
                      "sharpen indirect shadows and cost memory and time")
    iterations: IntProperty(name="Iterations", default=32, min=1, max=100000, soft_max=256,
                            description="Antiradiance: light bounces at most (stops early "
                            "once converged)")
    meshless_levels: IntProperty(
        name="Levels", default=0, min=0, max=8,
        description="Meshless: levels of the hierarchical basis; more resolve finer indirect "
        "detail and cost time and memory (0 = automatic, 4)")
    meshless_epsilon: FloatProperty(
        name="Link Threshold", default=0.01, min=0.0, max=10.0, soft_max=0.1, precision=3,
        step=0.1,
        description="Meshless: links that carry less than this are dropped; lower is more "
        "accurate and uses more memory (the paper used 0.025)")
    live_indirect: BoolProperty(
        name="Live Indirect", default=False, update=_live_toggled,
        description="Meshless: after a bake, relight BakeGI_Indirect whenever a light or the "
        "world changes (meshes and materials must stay as baked)")
    use_cache: BoolProperty(
        name="Cache Precomputation", default=True,
        description="Meshless: save the precomputed basis and transfer, so that baking the "
        "same geometry, materials and settings again (after reopening the file, too) skips "
        "the precompute; a changed scene is detected and computed again")
    seed: IntProperty(name="Seed", default=0, min=0,
                      description="Random seed; a bake is repeatable for a seed")
    target: EnumProperty(name="Target", items=TARGET_ITEMS, default="CORNER",
                         description="Where the bake is stored: the color attribute "
                         "BakeGI_Indirect, or lightmap textures")
    texels_per_meter: FloatProperty(
        name="Texels per Metre", default=40.0, min=0.1, max=10000.0, soft_max=500.0,
        description="Lightmaps: texel density on the surfaces; each object's lightmap is "
        "sized from its area")
    lightmap_max_size: IntProperty(
        name="Max Size", default=1024, min=8, max=8192,
        description="Lightmaps: the largest lightmap of one object, in texels")
    lightmap_uv_map: StringProperty(
        name="UV Map", default="BakeGI",
        description="Lightmaps: the UV map that holds the lightmap layout; a mesh without it "
        "gets a new one (the other UV maps stay as they are)")
    lightmap_uv_method: EnumProperty(
        name="Unwrap", items=LIGHTMAP_UV_METHOD_ITEMS, default="SMART",
        description="Lightmaps: how a missing lightmap UV map is made")
    lightmap_padding: IntProperty(
        name="Padding", default=4, min=0, max=64,
        description="Lightmaps: texels the charts are dilated into the gutters, so filtering "
        "and mipmaps never read black at a seam")
    lightmap_reject_inside: BoolProperty(
        name="Reject Texels Inside Geometry", default=True,
        description="Lightmaps: texels whose rays mostly hit back faces lie inside or under "
        "other geometry and are filled from their neighbours instead of baked; turn off for "
        "foliage of single-sided leaves, which it also rejects")
    lightmap_folder: StringProperty(
        name="Folder", default="//bakegi_lightmaps", subtype="DIR_PATH",
        description="Lightmaps: where the EXR file is written (// = next to the .blend; an "
        "unsaved file uses the add-on's user folder)")
    lightmap_float: BoolProperty(
        name="Full Float", default=False,
        description="Lightmaps: 32-bit floats instead of half floats (twice the size; half "
        "floats hold light to 0.1%)")
    grid_object: bpy.props.PointerProperty(
        name="Grid Box", type=bpy.types.Object, poll=_is_grid_box,
        description="Grid: the box the grid covers (an Empty's display cube, or a mesh's "
        "bounding box; Add Grid Box makes one); empty = every visible object")
    grid_cell_size: FloatProperty(
        name="Cell Size", default=0.0, min=0.0, soft_max=2.0, unit="LENGTH",
        description="Grid: about how far apart the grid vertices are; 0 = 32 cells along "
        "the box's longest side")
    grid_max_vertices: IntProperty(
        name="Max Vertices", default=262144, min=8, max=1 << 26,
        description="Grid: the cells grow until the grid has at most this many vertices "
        "(217 bytes each while baking)")
    grid_rays: IntProperty(
        name="Rays", default=64, min=1, max=65536,
        description="Grid: rays per vertex and hemisphere (six hemispheres a vertex); more "
        "is less noise, proportionally slower")
    grid_quantized: BoolProperty(
        name="Compress", default=True,
        description="Grid: store each hemisphere in 7 bytes (a 24-bit direction and a "
        "shared-exponent colour, as the paper does) instead of 36")
    grid_folder: StringProperty(
        name="Folder", default="//bakegi_grids", subtype="DIR_PATH",
        description="Grid: where the .bgivg file is written (// = next to the .blend)")
    grid_interpolation: EnumProperty(
        name="Interpolation", items=GRID_INTERPOLATION_ITEMS, default="TRILINEAR",
        description="Apply Grid: how the grid is read between its vertices")
    grid_directional: EnumProperty(
        name="Directional", items=GRID_DIRECTIONAL_ITEMS, default="ABSOLUTE",
        description="Apply Grid: how the six hemispheres are blended for a normal between "
        "the axes")
    grid_visibility: BoolProperty(
        name="Visibility", default=True,
        description="Apply Grid: each point reads only the grid vertices it sees, so light "
        "does not leak through walls thinner than a cell (a ray to each vertex)")
    grid_darken_buried: BoolProperty(
        name="Darken Buried", default=True,
        description="Apply Grid: points inside or under other geometry (a floor under a box) "
        "get no light, as in a bake; the grid alone cannot know them. Costs an export of the "
        "scene and a few rays a point")
    grid_follow: BoolProperty(
        name="Follow Moves", default=False,
        description="Apply Grid: the objects it lit are lit from the grid again when they "
        "move or change shape (after 50 ms at rest; edits once out of Edit Mode), with the "
        "options of the last Apply Grid")
    objects: EnumProperty(name="Objects", items=OBJECTS_ITEMS, default="SELECTED",
                          description="Which objects receive the bake (every visible object "
                          "always takes part in the light transport)")
    linked_duplicates: EnumProperty(
        name="Linked Duplicates", items=LINKED_DUPLICATE_ITEMS, default="SHARED",
        description="Color attributes: what to do with objects that share a mesh (lightmaps "
        "give each object its own texels anyway)")
    estimate_error: BoolProperty(
        name="Check Error", default=True,
        description="After the bake, path-trace a few hundred probe points and estimate the "
        "bake's error (also between vertices); a warning names the likely cause above 10%")
    hook_materials: BoolProperty(
        name="Show in Material Preview", default=True,
        description="Add nodes to the baked objects' materials so that Material Preview "
        "shows albedo x (direct + baked indirect); Remove Bake restores them")
    # Written by a successful bake (a cancelled or failed one leaves the scene untouched).
    last_result: StringProperty(name="Last Result", default="",
                                description="Summary of the last successful bake")
    last_report: StringProperty(name="Last Report", default="",
                                description="JSON report of the last successful bake")

    def resolved_method(self):
        if self.show_debug and self.debug_direct:
            return "direct"
        if self.method:
            return self.method
        try:  # a file saved with the old debug item reads "": the default
            return native.default_method()
        except (native.BakeGIError, OSError):
            return METHOD_ITEMS[0][0]

    def method_settings(self):
        """Core settings that only the resolved method reads."""
        method = self.resolved_method()
        settings = {} if self.estimate_error else {"error_probes": 0}
        if method == "antiradiance":
            settings.update(bins=self.bins, iterations=self.iterations)
        elif method == "pathtrace":
            if self.quality in QUALITY_TARGETS:
                settings["target_error"] = QUALITY_TARGETS[self.quality]
            if self.denoise:
                settings["denoise"] = 1
        elif method == "meshless":
            settings.update(levels=self.meshless_levels, epsilon=self.meshless_epsilon)
            if self.use_cache:
                settings["cache_dir"] = self.cache_directory()
        return settings

    def cache_directory(self):
        """The meshless cache folder: the preferences' (Edit > Preferences > Add-ons), else
        next to the .blend."""
        return preferences.current().cache_folder or blend_relative_directory("", "bakegi_cache")

    def request(self):
        """The bake these settings ask for (threads: the add-on preferences')."""
        return BakeRequest(method=self.resolved_method(), samples=self.request_samples(),
                           seed=self.seed,
                           target=self.target, objects=self.objects,
                           hook_materials=self.hook_materials,
                           method_settings=self.method_settings(), live=self.live_requested(),
                           lightmap=self.lightmap_options(),
                           lightmap_folder=self.lightmap_directory(),
                           lightmap_full_float=self.lightmap_float,
                           linked_duplicates=self.linked_duplicates,
                           grid=self.grid_options(), grid_folder=self.grid_directory())

    def grid_options(self):
        from ..write import grid_file
        bounds = grid_file.object_bounds(self.grid_object) if self.grid_object else None
        return GridOptions(bounds=bounds, cell_size=self.grid_cell_size,
                           max_vertices=self.grid_max_vertices, rays=self.grid_rays,
                           quantized=self.grid_quantized)

    def grid_directory(self):
        return grid_directory(self.grid_folder)

    def request_samples(self):
        """Samples per point: the fixed count, or a quality target's cap."""
        if self.resolved_method() == "pathtrace" and self.quality in QUALITY_TARGETS:
            return QUALITY_MAX_SAMPLES
        return self.samples

    def lightmap_options(self):
        return LightmapOptions(uv_map=self.lightmap_uv_map, texels_per_meter=self.texels_per_meter,
                               max_side=self.lightmap_max_size, padding=self.lightmap_padding,
                               uv_method=self.lightmap_uv_method,
                               reject_inside=self.lightmap_reject_inside)

    def lightmap_directory(self):
        """The lightmap folder as an absolute path."""
        return lightmap_directory(self.lightmap_folder)

    def live_requested(self):
        return (self.live_indirect and self.resolved_method() == "meshless" and
                self.target not in ("LIGHTMAP", "GRID"))


def blend_relative_directory(folder, name):
    """A folder setting as an absolute path: // is next to the .blend (empty: //<name>);
    an unsaved file has no folder, so its // folders go to the add-on's user folder."""
    folder = folder or "//" + name
    if folder.startswith("//") and not bpy.data.filepath:
        return compat.user_folder(name)
    return os.path.abspath(bpy.path.abspath(folder))


def lightmap_directory(folder):
    """The lightmap folder as an absolute path."""
    return blend_relative_directory(folder, "bakegi_lightmaps")


def grid_directory(folder):
    """The grid folder as an absolute path."""
    return blend_relative_directory(folder, "bakegi_grids")


# Panel properties that are core settings: (property, method, key). Their default and range
# come from the method's schema at register time (docs/settings.md), so the panel cannot
# offer a value the core refuses; the values written in the class stand only when the core
# library cannot be loaded (the preferences then say why).
SCHEMA_PROPERTIES = (("samples", "pathtrace", "samples"), ("seed", "pathtrace", "seed"),
                     ("bins", "antiradiance", "bins"), ("iterations", "antiradiance", "iterations"),
                     ("meshless_levels", "meshless", "levels"),
                     ("meshless_epsilon", "meshless", "epsilon"))
_INT32_MAX = (1 << 31) - 1  # an IntProperty's limit


def _take_defaults_and_ranges_from_the_core():
    try:
        default_method = native.default_method()
        schemas = {method: {s["key"]: s for s in native.describe_settings(method)["settings"]}
                   for method in {method for _, method, _ in SCHEMA_PROPERTIES}}
    except (native.BakeGIError, OSError):
        return
    annotations = BakeGISettings.__annotations__

    def redefine(prop, **changes):
        deferred = annotations[prop]  # bpy.props._PropertyDeferred: the function and keywords
        annotations[prop] = deferred.function(**{**deferred.keywords, **changes})

    if default_method in {item[0] for item in METHOD_ITEMS}:
        redefine("method", default=default_method)
    for prop, method, key in SCHEMA_PROPERTIES:
        spec = schemas[method][key]
        changes = {"default": spec["default"]}
        if "min" in spec:
            changes["min"] = spec["min"]
        if "max" in spec:
            changes["max"] = min(spec["max"], _INT32_MAX) if spec["type"] == "integer" else spec["max"]
            soft_max = annotations[prop].keywords.get("soft_max")
            if soft_max is not None and soft_max > changes["max"]:
                changes["soft_max"] = changes["max"]
        redefine(prop, **changes)


def register():
    _take_defaults_and_ranges_from_the_core()
    bpy.utils.register_class(BakeGISettings)
    bpy.types.Scene.bakegi = bpy.props.PointerProperty(type=BakeGISettings)
    bpy.types.Object.bakegi_texels_per_meter = FloatProperty(
        name="Texels per Metre", default=0.0, min=0.0, max=10000.0, soft_max=500.0,
        description="Lightmaps: this object's texel density (0 = the bake's Texels per "
        "Metre): more for a hero object, less for one seen from afar")


def unregister():
    del bpy.types.Object.bakegi_texels_per_meter
    del bpy.types.Scene.bakegi
    bpy.utils.unregister_class(BakeGISettings)
