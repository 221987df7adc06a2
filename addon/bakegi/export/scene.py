# SPDX-License-Identifier: GPL-3.0-or-later
# SPDX-License-Identifier: GPL-3.0-or-later
"""The evaluated Blender scene -> a core Scene, and the targets' bake points.

What is exported is what the viewport's depsgraph holds: modifiers applied, world
transforms, instances (depsgraph.object_instances). Meshes are triangulated
(loop_triangles) with the corner normals Blender shades with (smooth, flat, custom).
Lights go through light_units, materials through materials.read_material.

Bake points live on the ORIGINAL mesh (the attribute is written there): one per face corner,
also for a vertex ('POINT') target, whose vertices get their corners' mean when written (as
Cycles bakes vertex colours; export/points.py). When the evaluated mesh has the original's
element counts, its positions and normals are used (deforming modifiers, armatures);
when modifiers change the topology, the original mesh is baked in world space (with a
warning).

Nothing here changes the Blender data: evaluated meshes come from to_mesh() and are
cleared again.
"""

import hashlib
import math
import re
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np

from .. import compat, light_units, lightmap_layout, native
from ..native import BakeGIError
from ..request import TARGET_DOMAINS, LightmapOptions
from ..write import uv_maps
from . import materials
from .atlas import ExportedLightmaps, lightmap_points
from .node_tree import linked_from
from .mesh_arrays import (check_finite, corner_normals, get_array, invalid_scene,
                          matrix_array, normals_to_world, positions_to_world)
from .points import display_probes_per_object, target_points
from .targets import (MESH_LIKE, BakeTarget, name_elements, name_objects, resolve_targets,
                      some_names, with_surface)
from . import render_visibility
from .render_visibility import RenderVisibility
from .world import world_light


@dataclass
class ExportedScene:
    scene: native.Scene
    points: native.Points
    targets: List[BakeTarget]
    # name_full of original materials -> what was read from them (for the hook).
    materials: Dict[str, object] = field(default_factory=dict)
    warnings: List[str] = field(default_factory=list)
    skipped: List[str] = field(default_factory=list)
    counts: Dict[str, int] = field(default_factory=dict)
    seconds: float = 0.0
    object_names: List[str] = field(default_factory=list)  # by the core's object id
    lightmaps: ExportedLightmaps = None  # LIGHTMAP bakes only
    material_names: List[str] = field(default_factory=list)  # by the core's material id
    light_names: List[str] = field(default_factory=list)  # by the core's light index

    def named(self, message):
        """A core message with Blender's names for its objects, materials, lights and bake
        points (targets.name_elements)."""
        return name_elements(message, self.object_names, self.material_names, self.light_names,
                             self.targets)

    def close(self):
        self.scene.close()
        if self.points is not None:
            self.points.close()
        if self.lightmaps is not None:
            self.lightmaps.close()


@contextmanager
def _named_in_errors(pattern, name):
    """Re-raises a core error with `name` in place of the core's number (`pattern`)."""
    try:
        yield
    except BakeGIError as error:
        raise BakeGIError(error.status, re.sub(r"\b" + pattern, name, error.message)) from None


@dataclass
class _LocalMesh:
    """A triangulated evaluated mesh in object space, cached per object for instances."""

    positions: np.ndarray  # (V, 3)
    tri_vertices: np.ndarray  # (T, 3)
    normals: np.ndarray  # (T*3, 3) corner normals of the triangles' corners
    uvs: np.ndarray  # (T*3, 2) or None
    tri_materials: np.ndarray  # (T,) core material ids
    lightmap_uvs: np.ndarray = None  # (T*3, 2) of the lightmap UV map (LIGHTMAP targets)


@dataclass
class _LightmapSource:
    """A LIGHTMAP target as exported: its core mesh and the triangles' lightmap UVs."""

    mesh_id: int
    uvs: np.ndarray  # (T*3, 2)
    world_area: float


class SceneExporter:
    """Builds the core Scene from a depsgraph."""

    def __init__(self, depsgraph, warnings, scene=None, lightmap_objects=(), lightmap_uv_map=""):
        self.depsgraph = depsgraph
        self.warnings = warnings
        self.scene = scene if scene is not None else native.Scene()
        # LIGHTMAP bakes: the targets' names, whose lightmap UVs are read, and what was found.
        self.lightmap_objects = set(lightmap_objects)
        self.lightmap_uv_map = lightmap_uv_map
        self.lightmap_sources = {}  # object name -> _LightmapSource
        self.material_ids = {}  # original material name_full (or None) -> core id
        self.material_infos = {}  # original material name_full -> MaterialInfo
        self.texture_ids = {}  # (image name_full) -> core texture id
        self.emission_texture_ids = {}  # image name_full -> (core texture id, emission scale)
        self.opacity_texture_ids = {}  # (image name_full, channel, math) -> texture id or None
        self.local_meshes = {}
        self.triangles = 0
        self.meshes = 0
        self.lights = 0
        self.light_names = []  # by the core's light index
        self.material_names = []  # by the core's material id
        self.portals = 0  # Cycles' window portals: guide the world's light samples
        self.object_names = []

    # materials
    def _texture(self, image):
        key = image.name_full
        if key not in self.texture_ids:
            rgb = materials.image_linear_rgb(image, self.warnings)
            self.texture_ids[key] = None if rgb is None else self.scene.add_texture(rgb)
        return self.texture_ids[key]

    def texture_count(self):
        ids = {v for v in self.texture_ids.values() if v is not None}
        ids.update(v[0] for v in self.emission_texture_ids.values() if v[0] is not None)
        ids.update(v for v in self.opacity_texture_ids.values() if v is not None)
        return len(ids)

    def _opacity_texture(self, ref):
        """Core texture id (or None: no pixels) whose red channel is the image's alpha or its
        colour's luminance (TextureRef.channel), for a see-through material."""
        key = (ref.image.name_full, ref.channel, ref.math)
        if key not in self.opacity_texture_ids:
            values = materials.image_opacity(ref.image, ref.channel, self.warnings, ref.math)
            self.opacity_texture_ids[key] = (
                None if values is None
                else self.scene.add_texture(np.repeat(values[:, :, None], 3, axis=2)))
        return self.opacity_texture_ids[key]

    def _emission_texture(self, image):
        """(core texture id or None, scale) of an image that multiplies emission. The core's
        textures hold values in [0,1]: an HDR image (a float image brighter than 1) is passed
        divided by its maximum, which then multiplies the material's emission instead."""
        key = image.name_full
        if key not in self.emission_texture_ids:
            rgb = materials.image_linear_rgb(image, self.warnings)
            entry = (None, 1.0)
            if rgb is not None:
                negative = bool((rgb < 0.0).any())
                if negative:
                    self.warnings.append(f"image '{image.name}' has negative pixels; as an "
                                         "emission texture they are read as 0")
                    rgb = np.maximum(rgb, 0.0)
                peak = float(rgb.max()) if rgb.size else 0.0
                if peak <= 1.0 and not negative:  # the same texture as a base color's
                    if key not in self.texture_ids:
                        self.texture_ids[key] = self.scene.add_texture(rgb)
                    entry = (self.texture_ids[key], 1.0)
                else:
                    scale = max(peak, 1.0)
                    entry = (self.scene.add_texture(rgb / np.float32(scale)), scale)
            self.emission_texture_ids[key] = entry
        return self.emission_texture_ids[key]

    def is_volume_only(self, obj):
        """Whether every material of `obj` is a Volume without a Surface (a fog box)."""
        slots = [s.material for s in obj.material_slots]
        return bool(slots) and all(m is not None and self.material(m)[1].volume_only
                                   for m in slots)

    def material(self, material):
        """(core material id, MaterialInfo) of an (evaluated or original) material."""
        original = material.original if material is not None else None
        key = original.name_full if original is not None else None
        if key not in self.material_ids:
            info = materials.read_material(material)
            self.warnings.extend(info.warnings)
            texture = self._texture(info.texture.image) if info.texture is not None else None
            if info.texture is not None and texture is None:
                info.texture = None
            emission_texture, scale = None, 1.0
            if info.emission_texture is not None:
                emission_texture, scale = self._emission_texture(info.emission_texture.image)
                if emission_texture is None:  # no pixels (warned): emission as read, untextured
                    info.emission_texture = None
            name = key if key is not None else "(no material)"
            with _named_in_errors(r"material \d+", f"material '{name}'"):
                self.material_ids[key] = self.scene.add_material(
                    info.albedo, tuple(scale * e for e in info.emission), texture,
                    emission_two_sided=True, glossy=info.glossy,
                    glossy_exponent=info.glossy_exponent, emission_texture=emission_texture)
            self._name(self.material_names, self.material_ids[key], name)
            if info.lets_light_pass():
                opacity_texture = None
                if info.opacity_texture is not None:
                    opacity_texture = self._opacity_texture(info.opacity_texture)
                    if opacity_texture is None:  # no pixels (warned): opaque where present
                        info.opacity_texture = None
                self.scene.set_material_passing(self.material_ids[key], info.opacity,
                                                opacity_texture, info.transmission,
                                                info.transmission_ior)
            if original is not None:
                self.material_infos[key] = info
        info = self.material_infos[key] if key is not None else materials.MaterialInfo()
        return self.material_ids[key], info

    @staticmethod
    def _name(names, index, name):
        names.extend([""] * (index + 1 - len(names)))
        names[index] = name

    # meshes
    def _local_mesh(self, obj):
        # Instances of one object share its mesh; geometry-nodes instances carry their own
        # data under the instancer's name, hence the data pointer in the key.
        key = (obj.name_full, obj.data.as_pointer() if obj.data is not None else 0)
        if key in self.local_meshes:
            return self.local_meshes[key]
        try:
            mesh = obj.to_mesh()
        except RuntimeError as error:
            self.warnings.append(f"'{obj.name}' left out: it has no mesh ({error})")
            self.local_meshes[key] = None
            return None
        try:
            local = self._read_mesh(obj, mesh) if mesh is not None else None
        finally:
            obj.to_mesh_clear()
        self.local_meshes[key] = local
        return local

    def _read_mesh(self, obj, mesh):
        mesh.calc_loop_triangles()
        tris = mesh.loop_triangles
        t = len(tris)
        if t == 0:
            return None
        positions = get_array(mesh.vertices, "co", len(mesh.vertices), np.float32, 3)
        check_finite(obj.name, positions)
        tri_vertices = get_array(tris, "vertices", t, np.int32, 3)
        tri_loops = get_array(tris, "loops", t, np.int32, 3).reshape(-1)
        normals = corner_normals(mesh)[tri_loops]
        slot_index = get_array(tris, "material_index", t, np.int32)

        slots = [s.material for s in obj.material_slots] or list(mesh.materials)
        if not slots:
            slots = [None]
        ids, infos = [], []
        for m in slots:
            core_id, info = self.material(m)
            ids.append(core_id)
            infos.append(info)
        slot_index = np.clip(slot_index, 0, len(slots) - 1)
        tri_materials = np.asarray(ids, np.uint32)[slot_index]

        uvs = None
        textured = [i for i, info in enumerate(infos) if materials.sampled_uv_map(info) is not None]
        if textured:
            uvs = np.zeros((t * 3, 2), np.float32)
            layers = mesh.uv_layers
            active = next((l for l in layers if l.active_render), None)
            for i in textured:
                wanted = materials.sampled_uv_map(infos[i])
                layer = layers.get(wanted) if wanted else active
                if layer is None:
                    self.warnings.append(
                        f"object '{obj.name}': UV map '{wanted or '(active)'}' of material "
                        f"'{slots[i].name if slots[i] else ''}' not found; its texture is sampled at (0, 0)")
                    continue
                loop_uv = get_array(layer.data, "uv", len(mesh.loops), np.float32, 2)
                corner = np.repeat(slot_index == i, 3)
                uvs[corner] = loop_uv[tri_loops[corner]]
        lightmap_uvs = None
        if obj.name in self.lightmap_objects:
            layer = mesh.uv_layers.get(self.lightmap_uv_map)
            if layer is None:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  f"object '{obj.name}': its modifiers drop the lightmap UV map "
                                  f"'{self.lightmap_uv_map}'; apply them or bake to face corners")
            loop_uv = get_array(layer.data, "uv", len(mesh.loops), np.float32, 2)
            lightmap_uvs = loop_uv[tri_loops]
            if not np.isfinite(lightmap_uvs).all():
                raise invalid_scene(f"object '{obj.name}': UV map '{self.lightmap_uv_map}' has "
                               "non-finite coordinates")
        return _LocalMesh(positions, tri_vertices, normals, uvs, tri_materials, lightmap_uvs)

    @staticmethod
    def _mirrored(local):
        """The same triangles wound the other way round (corners 0, 2, 1). A transform with a
        negative determinant (negative scale, as a Mirror workflow leaves it) turns the
        winding around in world space while Blender keeps shading the outside; the core
        takes the front from the winding, so it must be restored."""
        def corners(array):
            return None if array is None else array.reshape(-1, 3, array.shape[-1])[:, (0, 2, 1)].reshape(array.shape)
        return _LocalMesh(local.positions, local.tri_vertices[:, (0, 2, 1)], corners(local.normals),
                          corners(local.uvs), local.tri_materials, corners(local.lightmap_uvs))

    def add_instance(self, obj, matrix_world, is_instance=False):
        local = self._local_mesh(obj)
        if local is None:
            return
        matrix = matrix_array(matrix_world)
        if np.linalg.det(matrix[:3, :3]) < 0.0:
            local = self._mirrored(local)
        positions = positions_to_world(matrix, local.positions)
        normals = normals_to_world(matrix, local.normals)
        check_finite(obj.name, positions)
        object_id = len(self.object_names)
        self.object_names.append(obj.name)
        try:
            mesh_id = self.scene.add_mesh(positions, local.tri_vertices,
                                          corner_normals=normals, corner_uvs=local.uvs,
                                          triangle_materials=local.tri_materials,
                                          object_id=object_id)
        except BakeGIError as error:
            raise BakeGIError(error.status, name_objects(error.message, self.object_names))
        if local.lightmap_uvs is not None and not is_instance:
            corners = positions[local.tri_vertices.reshape(-1)]
            self.lightmap_sources[obj.name] = _LightmapSource(
                mesh_id, local.lightmap_uvs,
                float(lightmap_layout.triangle_areas(corners).sum()))
        self.meshes += 1
        self.triangles += len(local.tri_vertices)

    # lights
    def add_light(self, obj, matrix_world):
        light = obj.data
        if not getattr(obj.original, "visible_diffuse", True):
            # Cycles' diffuse light (direct and indirect) has none of it (measured in 3.4, 4.5).
            self.warnings.append(
                f"light '{obj.name}' is invisible to diffuse rays (Object Properties > "
                "Visibility > Ray Visibility > Diffuse off): left out, as Cycles' diffuse light "
                "has none of it")
            return
        settings = light_units.BlenderLight(
            name=obj.name, type=light.type, color=tuple(light.color), energy=light.energy,
            matrix_world=[list(row) for row in matrix_world],
            shadow_soft_size=getattr(light, "shadow_soft_size", 0.0),
            spot_size=getattr(light, "spot_size", 0.0),
            spot_blend=getattr(light, "spot_blend", 0.0),
            angle=getattr(light, "angle", 0.0),
            shape=getattr(light, "shape", "SQUARE"),
            size=getattr(light, "size", 0.0),
            size_y=getattr(light, "size_y", 0.0),
            spread=getattr(light, "spread", math.pi),
            use_nodes=compat.uses_nodes(light),
            node_tint=_light_tree_tint(light),
            cycles_version=compat.cycles_conventions(),
            # Cycles' own settings are read from the original: setting them from a script
            # does not tag the depsgraph, so the evaluated copy can hold old values.
            is_portal=_is_portal(obj.original.data),
            cast_shadow=_casts_shadow(obj.original.data),
            **compat.light_settings(light))
        if settings.is_portal:
            # Cycles draws no light from a portal: it only samples the world through it.
            conversion = light_units.convert_portal(settings)
            self.warnings.extend(conversion.warnings)
            if conversion.light is not None:
                self.scene.add_portal(**vars(conversion.light))
                self.portals += 1
            return
        conversion = light_units.convert_light(settings)
        self.warnings.extend(conversion.warnings)
        if conversion.light is not None:
            with _named_in_errors(r"light \d+", f"light '{obj.name}'"):
                self.scene.add_light(**vars(conversion.light))
            self.light_names.append(obj.name)
            self.lights += 1
            bounces = getattr(getattr(obj.original.data, "cycles", None), "max_bounces", 1024)
            if bounces < MAX_BOUNCES_MODELLED:
                self.warnings.append(
                    f"light '{obj.name}': its Max Bounces ({bounces}) is ignored: the bake follows "
                    "its light through every bounce, where Cycles stops it sooner")

    def set_world(self, world):
        visibility = getattr(world, "cycles_visibility", None)
        if visibility is not None and not visibility.diffuse:
            # Cycles' diffuse light has none of it (measured in 3.4, 4.5).
            self.warnings.append("the world is invisible to diffuse rays (World Properties > "
                                 "Ray Visibility > Diffuse off): it adds no light, as in Cycles")
            self.scene.set_world((0.0, 0.0, 0.0))
            self.scene.set_world_texture(None)
            return
        light = world_light(world, self.warnings)
        self.scene.set_world(light.radiance)
        for direction, angle, irradiance in light.suns:
            self.scene.add_light("SUN", direction=tuple(-c for c in direction), color=irradiance,
                                 angle=angle)
            self.light_names.append("the world's sun")
            self.lights += 1
        if light.image is None:
            self.scene.set_world_texture(None)
            return
        # A live relight re-exports the world into the baked core scene: the same image must
        # reuse its texture (a new one would change the scene's textures, which a relight
        # refuses), so that turning or dimming the sky relights.
        key = (light.image.shape,
               hashlib.blake2b(light.image.tobytes(), digest_size=16).digest())
        kept = getattr(self.scene, "world_image", None)
        if kept is not None and kept[0] == key:
            texture = kept[1]
        else:
            texture = self.scene.add_texture(light.image)
            self.scene.world_image = (key, texture)
        self.scene.set_world_texture(texture, light.scale, light.rotation)


# The path tracer's default max_bounces: a light's own Max Bounces below it is not modelled.
MAX_BOUNCES_MODELLED = 64


def _casts_shadow(light):
    """Cycles' Cast Shadow: light.cycles.cast_shadow in 3.x (its light.use_shadow is EEVEE's
    alone there, measured), light.use_shadow from 4.0 on."""
    cycles = getattr(light, "cycles", None)
    if cycles is not None and hasattr(cycles, "cast_shadow"):
        return bool(cycles.cast_shadow)
    return bool(getattr(light, "use_shadow", True))


def _is_portal(light):
    """Whether an area light has Cycles' Portal on (light.cycles.is_portal, 3.x to 5.0)."""
    return light.type == "AREA" and bool(getattr(getattr(light, "cycles", None), "is_portal",
                                                 False))


def _light_tree_tint(light):
    """What a light's node tree multiplies its colour by (light_units.BlenderLight.node_tint):
    (1, 1, 1) without nodes; an Emission node into the Light Output gives its Color x Strength,
    the colour a constant or from an RGB or Blackbody node with constant inputs; None for any
    other tree (textures, falloff, math: not read)."""
    if not compat.uses_nodes(light):
        return (1.0, 1.0, 1.0)
    tree = light.node_tree
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_LIGHT"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None:
        return None
    surface = linked_from(output.inputs["Surface"])
    if surface is None or surface.node.type != "EMISSION":
        return None
    emission = surface.node
    strength = emission.inputs["Strength"]
    if strength.is_linked:
        return None
    color_socket = emission.inputs["Color"]
    if not color_socket.is_linked:
        color = tuple(color_socket.default_value)[:3]
    else:
        source = linked_from(color_socket).node
        if source.type == "RGB":
            color = tuple(source.outputs[0].default_value)[:3]
        elif source.type == "BLACKBODY" and not source.inputs["Temperature"].is_linked:
            color = light_units.blackbody_color(source.inputs["Temperature"].default_value)
        else:
            return None
    return tuple(float(c) * float(strength.default_value) for c in color)


# ---- the whole export ---------------------------------------------------------------------


def export_scene(context, target="CORNER", objects="SELECTED", depsgraph=None, lightmap=None,
                 defer_texels=False, display_probes=False):
    """Exports the evaluated scene and the bake points of the target objects.

    target 'GRID': no bake points and no targets (objects is ignored): the whole visible
    scene is exported for a grid bake (session.py).
    target 'LIGHTMAP': the bake points are the texels of the targets' lightmap UV maps
    (lightmap: LightmapOptions); a missing UV map is created first (the only change to the
    Blender data; ExportedLightmaps.created_uv_maps lists them, and export removes them
    again if it fails).
    defer_texels (LIGHTMAP): leave `points` None and the texels to
    ExportedLightmaps.build(), for a worker thread.
    display_probes (CORNER, POINT): give the bake points display probes inside the targets'
    faces, where the core checks the interpolated attribute against the path tracer.
    Raises BakeGIError (with the object and element named) for invalid input; the Blender
    data is left as it was."""
    start = time.perf_counter()
    if target not in TARGET_DOMAINS:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"target must be one of {TARGET_DOMAINS}, not {target!r}")
    if target == "GRID":
        # A grid has no target objects: every visible object lights it.
        return _export(context, target, [], [], depsgraph, lightmap, [], start)
    targets, skipped = resolve_targets(context, objects, shared_meshes=target == "LIGHTMAP")
    targets = with_surface(targets, skipped)
    if not targets:
        why = "; ".join(skipped) if skipped else "no mesh object is " + (
            "selected" if objects == "SELECTED" else "visible" if objects == "VISIBLE" else
            "given")
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"nothing to bake: {why}")
    created_uv_maps = []
    if target == "LIGHTMAP":
        lightmap = lightmap or LightmapOptions()
        _check_lightmap_options(lightmap)
        created_uv_maps = uv_maps.ensure(context, targets, lightmap.uv_map,
                                              lightmap.uv_method, lightmap.texels_per_meter,
                                              lightmap.max_side)
        depsgraph = None  # the new UV maps must be evaluated
    try:
        return _export(context, target, targets, skipped, depsgraph, lightmap, created_uv_maps,
                       start, defer_texels, display_probes)
    except BaseException:
        uv_maps.remove(context.blend_data, created_uv_maps,
                            lightmap.uv_map if lightmap else "")
        raise


def _check_lightmap_options(options):
    if not (isinstance(options.texels_per_meter, (int, float)) and
            0.0 < options.texels_per_meter <= 10000.0):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"texels_per_meter must be in (0, 10000], not "
                          f"{options.texels_per_meter!r}")
    if not (isinstance(options.max_side, int) and
            lightmap_layout.MIN_SIDE <= options.max_side <= lightmap_layout.MAX_ATLAS_SIDE):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"the largest lightmap must be {lightmap_layout.MIN_SIDE}.."
                          f"{lightmap_layout.MAX_ATLAS_SIDE} texels, not {options.max_side!r}")
    if not (isinstance(options.padding, int) and 0 <= options.padding <= 64):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"padding must be 0..64 texels, not {options.padding!r}")


# Object kinds Cycles renders that the export does not turn into triangles.
NOT_BAKED_KINDS = {"CURVES": "hair curves", "POINTCLOUD": "point cloud", "VOLUME": "volume"}


def _export(context, target, targets, skipped, depsgraph, lightmap, created_uv_maps, start,
            defer_texels=False, display_probes=False):
    if depsgraph is None:
        depsgraph = context.evaluated_depsgraph_get()
    warnings = []
    names = [o.name for o in targets] if target == "LIGHTMAP" else ()
    exporter = SceneExporter(depsgraph, warnings, lightmap_objects=names,
                             lightmap_uv_map=lightmap.uv_map if lightmap else "")
    points = None
    exported_lightmaps = None
    try:
        linked, ray_hidden, volumes, render_geometry = set(), set(), set(), {}
        not_baked = set()  # geometry Cycles renders that the bake has no form for
        visibility = RenderVisibility(context.scene)
        target_names = {o.name for o in targets}
        for instance in depsgraph.object_instances:
            obj = instance.object
            # A target is baked as asked, also where renders leave it out.
            is_target = not instance.is_instance and obj.original.name in target_names
            if obj.type in MESH_LIKE:
                if not is_target and visibility.leave_out(instance):
                    continue
                if not is_target and exporter.is_volume_only(obj):
                    volumes.add(obj.name)
                    continue
                # A curve, text, surface or metaball comes twice: as itself and as its
                # evaluated mesh, an instance of its own; like Cycles, take the mesh only
                # (both doubled every triangle).
                if obj.type == "MESH":
                    exporter.add_instance(obj, instance.matrix_world, instance.is_instance)
                if not instance.is_instance:
                    not_baked.update(f"'{obj.name}' (strands '{name}')"
                                     for name in render_visibility.rendered_strands(obj.original))
            elif obj.type in NOT_BAKED_KINDS:
                if not visibility.leave_out(instance):
                    not_baked.add(f"'{obj.name}' ({NOT_BAKED_KINDS[obj.type]})")
            elif obj.type == "LIGHT":
                if visibility.leave_out(instance):
                    continue
                exporter.add_light(obj, instance.matrix_world)
            if (obj.type in MESH_LIKE or obj.type == "LIGHT") and compat.light_linking_in_use(obj):
                linked.add(obj.name)
            if obj.type in MESH_LIKE and not (getattr(obj.original, "visible_diffuse", True) and
                                              getattr(obj.original, "visible_shadow", True)):
                ray_hidden.add(obj.name)
            if obj.type in MESH_LIKE and not instance.is_instance:
                difference = render_visibility.modifiers_differ_in_renders(obj.original)
                if difference:
                    render_geometry[obj.name] = difference
        warnings.extend(render_visibility.warnings_for(
            context, visibility, set(MESH_LIKE) | set(NOT_BAKED_KINDS) | {"LIGHT"}))
        if render_geometry:
            names = sorted(render_geometry)
            warnings.append("the bake uses the viewport's modifiers, and renders differ: " +
                            "; ".join(f"'{n}' {render_geometry[n]}" for n in names[:5]) +
                            (" ..." if len(names) > 5 else "") +
                            " (Cycles bakes the render's geometry; match them to bake it)")
        if not_baked:
            warnings.append(f"not in the bake: {some_names(not_baked)}: Cycles renders them, "
                            "the bake has meshes only, so the light they block, reflect or "
                            "scatter is missing (convert them to meshes to bake with them)")
        if volumes:
            warnings.append(f"left out {some_names(volumes)}: their materials are a Volume "
                            "without a Surface; the bake has no participating media, and Cycles "
                            "lets light through their boundary")
        if ray_hidden:
            warnings.append(f"ray visibility is ignored (Diffuse or Shadow off on "
                            f"{some_names(ray_hidden)}): they reflect light and cast shadows in "
                            "the bake, where Cycles lets those rays through them")
        if linked:
            warnings.append(f"light linking is ignored (set on {some_names(linked)}): their "
                            "light reaches every object in the bake")
        if compat.eevee_raytracing_on(context.scene):
            warnings.append("EEVEE's Raytracing is on (Render Properties): EEVEE then adds its "
                            "own indirect light and spreads the shown bake to other surfaces "
                            "again, so EEVEE shows more indirect light than the bake (Cycles "
                            "does not); turn it off to judge the bake in EEVEE")
        exporter.set_world(context.scene.world)

        if target == "LIGHTMAP":
            exported_lightmaps, bake_targets = lightmap_points(exporter, targets, lightmap,
                                                               warnings)
            exported_lightmaps.created_uv_maps = created_uv_maps
            points = None if defer_texels else exported_lightmaps.build()
            offset = len(points) if points is not None else 0
            return _exported(exporter, points, bake_targets, warnings, skipped, offset, start,
                             exported_lightmaps)

        if target == "GRID":
            if exporter.scene.triangle_count == 0:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  "nothing to bake: no visible mesh object lights the grid")
            return _exported(exporter, None, [], warnings, [], 0, start)

        positions, normals, ids, bake_targets, probes, candidates = [], [], [], [], [], []
        offset = 0
        per_object = display_probes_per_object(len(targets)) if display_probes else 0
        for index, obj in enumerate(targets):
            points_of = target_points(obj, depsgraph, target, warnings, per_object, seed=index,
                                      first_index=offset)
            count = len(points_of.positions)
            candidates.append(points_of.share_candidates)
            positions.append(points_of.positions)
            normals.append(points_of.normals)
            ids.append(np.full(count, index, np.uint32))
            if points_of.probes is not None:
                probes.append((index, offset, points_of.probes))
            bake_targets.append(BakeTarget(obj.name, obj.data.name_full, target, offset, count,
                                           vertex_of_point=points_of.vertex_of_point,
                                           vertex_count=points_of.vertex_count))
            offset += count
        points = native.Points(np.concatenate(positions), np.concatenate(normals),
                               np.concatenate(ids))
        points.set_share_candidates(np.concatenate(candidates))
        if probes:
            _set_display_probes(points, probes)
    except BaseException:
        exporter.scene.close()
        if points is not None:
            points.close()
        if exported_lightmaps is not None:
            exported_lightmaps.close()
        raise
    return _exported(exporter, points, bake_targets, warnings, skipped, offset, start)


def _set_display_probes(points, probes):
    """Hands the targets' display probes to the core (bake point indices made global, a
    fourth stencil entry of weight 0)."""
    count = sum(len(p.positions) for _, _, p in probes)
    indices = np.zeros((count, 4), np.uint32)
    weights = np.zeros((count, 4), np.float32)
    at = 0
    for _, offset, p in probes:
        k = len(p.positions)
        indices[at:at + k, :3] = p.points + offset
        weights[at:at + k, :3] = p.weights
        at += k
    points.set_display_probes(np.concatenate([p.positions for _, _, p in probes]),
                              np.concatenate([p.normals for _, _, p in probes]),
                              np.concatenate([np.full(len(p.positions), index, np.uint32)
                                              for index, _, p in probes]),
                              indices, weights)


def _exported(exporter, points, bake_targets, warnings, skipped, offset, start,
              exported_lightmaps=None):
    counts = {"meshes": exporter.meshes, "triangles": exporter.triangles,
              "lights": exporter.lights, "portals": exporter.portals,
              "materials": len(exporter.material_ids),
              "textures": exporter.texture_count(),
              "bake_points": offset, "targets": len(bake_targets)}
    if exported_lightmaps is not None:
        counts.update(lightmap_width=exported_lightmaps.width,
                      lightmap_height=exported_lightmaps.height,
                      lightmap_covered_texels=exported_lightmaps.covered_texels,
                      lightmap_rejected_samples=exported_lightmaps.rejected_samples)
    return ExportedScene(exporter.scene, points, bake_targets, exporter.material_infos,
                         _unique(warnings), skipped, counts, time.perf_counter() - start,
                         exporter.object_names, exported_lightmaps, exporter.material_names,
                         exporter.light_names)


def export_lights(context, scene, depsgraph=None):
    """Replaces the lights and the world of the core `scene` with the current ones (a live
    relight: the meshes and materials stay as exported). Returns (lights, warnings)."""
    if depsgraph is None:
        depsgraph = context.evaluated_depsgraph_get()
    warnings = []
    exporter = SceneExporter(depsgraph, warnings, scene=scene)
    scene.clear_lights()
    visibility = RenderVisibility(context.scene)
    for instance in depsgraph.object_instances:
        if instance.object.type == "LIGHT" and not visibility.leave_out(instance):
            exporter.add_light(instance.object, instance.matrix_world)
    exporter.set_world(context.scene.world)
    return exporter.lights, _unique(warnings)


def _unique(items):
    seen, out = set(), []
    for item in items:
        if item not in seen:
            seen.add(item)
            out.append(item)
    return out
