# SPDX-License-Identifier: GPL-3.0-or-later
"""The evaluated Blender scene -> a core Scene, and the targets' bake points.

What is exported is what the viewport's depsgraph holds: modifiers applied, world
transforms, instances (depsgraph.object_instances). Meshes are triangulated
(loop_triangles) with the corner normals Blender shades with (smooth, flat, custom).
Lights go through light_units, materials through materials.read_material.

Bake points live on the ORIGINAL mesh's domain (the attribute is written there): one per
face corner ('CORNER') or per vertex ('POINT'). When the evaluated mesh has the original's
element counts, its positions and normals are used (deforming modifiers, armatures);
when modifiers change the topology, the original mesh is baked in world space (with a
warning).

Nothing here changes the Blender data: evaluated meshes come from to_mesh() and are
cleared again.
"""

import math
import re
import time
from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np

from . import compat, light_units, lightmap_layout, lightmap_uvs, materials, native
from .native import BakeGIError
from .request import LINKED_DUPLICATES, TARGET_DOMAINS, LightmapOptions  # noqa: F401 (re-exported)

MESH_LIKE = {"MESH", "CURVE", "SURFACE", "META", "FONT"}
# Where a bake goes: a color attribute on face corners or vertices, or lightmap textures.


@dataclass
class BakeTarget:
    """One object whose mesh receives the bake, and its slice of the bake points."""

    # Names, not references: the result is written after the bake, and references do not
    # survive an undo (or a deletion) in between.
    object_name: str
    mesh_name: str  # name_full of the original mesh, where the attribute goes
    domain: str
    start: int
    count: int
    # LIGHTMAP only: (scale_u, scale_v, offset_u, offset_v) of its tile in the atlas, and the
    # tile's side in texels.
    atlas_scale_offset: tuple = ()
    tile_side: int = 0


@dataclass
class ExportedLightmaps:
    """The atlas of a LIGHTMAP bake: the core's texel samples and where each target sits."""

    lightmaps: native.Lightmaps
    width: int
    height: int
    options: LightmapOptions
    created_uv_maps: list = field(default_factory=list)  # [(object, mesh)] made for this bake
    rejected_samples: int = 0
    covered_texels: int = 0
    density_scale: float = 1.0
    seconds: Dict[str, float] = field(default_factory=dict)
    # Before build(): the core scene and, per target, (core mesh id, atlas UVs (3T, 2)).
    scene: native.Scene = None
    pending: list = field(default_factory=list)

    def build(self):
        """Rasterizes every target's texels into the atlas and drops those inside geometry
        (core work, seconds on large scenes; no bpy, so it may run on a worker thread).
        Returns the bake points (a new native.Points)."""
        t0 = time.perf_counter()
        for i, (mesh_id, uvs) in enumerate(self.pending):
            if i == 0:
                self.lightmaps.add(self.scene, mesh_id, uvs, self.width, self.height)
            else:
                self.lightmaps.add_to(0, self.scene, mesh_id, uvs)
        self.pending = []
        self.seconds["rasterize"] = time.perf_counter() - t0
        if self.options.reject_inside:
            t1 = time.perf_counter()
            self.rejected_samples = self.lightmaps.reject_inside(self.scene)
            self.seconds["reject_inside"] = time.perf_counter() - t1
        self.covered_texels = self.lightmaps.info(0)["covered_texels"]
        return self.lightmaps.points()

    def close(self):
        self.lightmaps.close()


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

    def close(self):
        self.scene.close()
        if self.points is not None:
            self.points.close()
        if self.lightmaps is not None:
            self.lightmaps.close()


def name_objects(message, object_names):
    """Puts Blender object names into a core message: "(object 3)" -> "(object 'Cube')"."""
    def name(match):
        i = int(match.group(1))
        return f"object '{object_names[i]}'" if i < len(object_names) else match.group(0)
    return re.sub(r"\bobject (\d+)", name, message)


def _invalid(message):
    return BakeGIError("BAKEGI_ERROR_INVALID_SCENE", message)


# ---- which objects ----------------------------------------------------------------------


def resolve_targets(context, objects, shared_meshes=False):
    """objects: 'SELECTED', 'VISIBLE' or a list of objects or names. shared_meshes: objects
    that share a mesh are all baked (lightmaps: each object has its own tile); otherwise
    only the first of them (a color attribute lives on the mesh).
    Returns (mesh objects to bake, [reasons for skipped objects])."""
    view_layer = context.view_layer
    if objects == "SELECTED":
        candidates = list(context.selected_objects)
    elif objects == "VISIBLE":
        # (None entries: objects removed since the view layer was last updated)
        candidates = [o for o in view_layer.objects
                      if o is not None and o.visible_get(view_layer=view_layer)]
    elif isinstance(objects, str):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"objects must be 'SELECTED', 'VISIBLE' or a list, not {objects!r}")
    else:
        candidates = []
        data_objects = context.blend_data.objects
        for item in objects:
            obj = data_objects.get(item) if isinstance(item, str) else item
            if obj is None:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"no object named {item!r}")
            candidates.append(obj)
    targets, skipped, meshes = [], [], {}
    for obj in candidates:
        if obj.type != "MESH":
            if objects != "VISIBLE":
                skipped.append(f"'{obj.name}' skipped: a {obj.type.lower()}, not a mesh")
            continue
        if view_layer.objects.get(obj.name) is None or not obj.visible_get(
                view_layer=view_layer):
            skipped.append(f"'{obj.name}' skipped: not visible in the view layer")
            continue
        mesh = obj.data
        if mesh.library is not None or getattr(mesh, "override_library", None) is not None:
            skipped.append(f"'{obj.name}' skipped: its mesh is linked from a library")
            continue
        if len(mesh.polygons) == 0:
            skipped.append(f"'{obj.name}' skipped: its mesh has no faces")
            continue
        if mesh.name_full in meshes and not shared_meshes:
            skipped.append(f"'{obj.name}' not baked: it shares mesh '{mesh.name}' with "
                           f"'{meshes[mesh.name_full]}' and shows that object's light (Linked "
                           f"Duplicates: Make Single User bakes each)")
            continue
        meshes[mesh.name_full] = obj.name
        targets.append(obj)
    return targets, skipped


# What an attribute bake does with linked duplicates (objects sharing one mesh, which holds
# one color attribute for all of them).


def linked_duplicates(context, objects):
    """Target objects that share their mesh with an earlier target: [(object, the target it
    shares with)]. An attribute bake bakes only the first of each group."""
    targets, _ = resolve_targets(context, objects, shared_meshes=True)
    first, shared = {}, []
    for obj in targets:
        key = obj.data.name_full
        if key in first:
            shared.append((obj, first[key]))
        else:
            first[key] = obj
    return shared


def make_single_users(context, objects):
    """Gives every linked duplicate among the targets its own copy of the mesh (Blender's
    Make Single User), so that each is baked with its own light. Returns [(object, shared
    mesh, copy)] for undo_single_users."""
    made = []
    for obj, _ in linked_duplicates(context, objects):
        shared = obj.data
        copy = shared.copy()
        obj.data = copy
        made.append((obj, shared, copy))
    return made


def undo_single_users(data, made):
    """Puts the shared meshes back and deletes the copies (a bake that failed or was
    cancelled leaves the scene as it was)."""
    for obj, shared, copy in reversed(made):
        try:
            obj.data = shared
            if copy.users == 0:
                data.meshes.remove(copy)
        except ReferenceError:  # the object or mesh was deleted meanwhile
            pass


# ---- mesh arrays ------------------------------------------------------------------------


def _get(collection, attr, count, dtype, width=1):
    out = np.empty(count * width, dtype)
    if count:
        collection.foreach_get(attr, out)
    return out.reshape(-1, width) if width > 1 else out


def corner_normals(mesh):
    """(loops, 3) normals as Blender shades each face corner (smooth/flat/custom)."""
    n = len(mesh.loops)
    if hasattr(mesh, "corner_normals"):  # Blender 4.1+: always up to date
        return _get(mesh.corner_normals, "vector", n, np.float32, 3)
    mesh.calc_normals_split()  # Blender < 4.1 (the mesh here is a temporary one)
    return _get(mesh.loops, "normal", n, np.float32, 3)


def _matrix(m):
    return np.array([list(row) for row in m], dtype=np.float64)


def _positions_to_world(matrix, positions):
    p = positions.astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
    return p.astype(np.float32)


def _normals_to_world(matrix, normals):
    """Normals transform with the inverse transpose: n' = n^T M^-1, then renormalized."""
    m3 = matrix[:3, :3]
    try:
        normal_matrix = np.linalg.inv(m3)
    except np.linalg.LinAlgError:
        normal_matrix = m3
    n = normals.astype(np.float64) @ normal_matrix
    length = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.where(length > 0, n / np.maximum(length, 1e-30), 0.0)
    return n.astype(np.float32)


def _check_finite(name, positions, what="vertex"):
    finite = np.isfinite(positions).all(axis=1)
    if not finite.all():
        i = int(np.argmin(finite))
        x, y, z = (float(v) for v in positions[i])
        raise _invalid(f"object '{name}': {what} {i} has a non-finite position "
                       f"({x:g}, {y:g}, {z:g}); fix the mesh (or its modifiers) and bake again")


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
        self.local_meshes = {}
        self.triangles = 0
        self.meshes = 0
        self.lights = 0
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
        return len(ids)

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
            self.material_ids[key] = self.scene.add_material(
                info.albedo, tuple(scale * e for e in info.emission), texture,
                emission_two_sided=True, glossy=info.glossy,
                glossy_exponent=info.glossy_exponent, emission_texture=emission_texture)
            if original is not None:
                self.material_infos[key] = info
        info = self.material_infos[key] if key is not None else materials.MaterialInfo()
        return self.material_ids[key], info

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
        positions = _get(mesh.vertices, "co", len(mesh.vertices), np.float32, 3)
        _check_finite(obj.name, positions)
        tri_vertices = _get(tris, "vertices", t, np.int32, 3)
        tri_loops = _get(tris, "loops", t, np.int32, 3).reshape(-1)
        normals = corner_normals(mesh)[tri_loops]
        slot_index = _get(tris, "material_index", t, np.int32)

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
                loop_uv = _get(layer.data, "uv", len(mesh.loops), np.float32, 2)
                corner = np.repeat(slot_index == i, 3)
                uvs[corner] = loop_uv[tri_loops[corner]]
        lightmap_uvs = None
        if obj.name in self.lightmap_objects:
            layer = mesh.uv_layers.get(self.lightmap_uv_map)
            if layer is None:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  f"object '{obj.name}': its modifiers drop the lightmap UV map "
                                  f"'{self.lightmap_uv_map}'; apply them or bake to face corners")
            loop_uv = _get(layer.data, "uv", len(mesh.loops), np.float32, 2)
            lightmap_uvs = loop_uv[tri_loops]
            if not np.isfinite(lightmap_uvs).all():
                raise _invalid(f"object '{obj.name}': UV map '{self.lightmap_uv_map}' has "
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
        matrix = _matrix(matrix_world)
        if np.linalg.det(matrix[:3, :3]) < 0.0:
            local = self._mirrored(local)
        positions = _positions_to_world(matrix, local.positions)
        normals = _normals_to_world(matrix, local.normals)
        _check_finite(obj.name, positions)
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
            node_tree_is_default=_light_tree_is_default(light),
            cycles_version=compat.cycles_conventions(),
            **compat.light_settings(light))
        conversion = light_units.convert_light(settings)
        self.warnings.extend(conversion.warnings)
        if conversion.light is not None:
            self.scene.add_light(**vars(conversion.light))
            self.lights += 1

    def set_world(self, world):
        self.scene.set_world(world_radiance(world, self.warnings))


def _light_tree_is_default(light):
    tree = getattr(light, "node_tree", None)
    if not compat.uses_nodes(light):
        return True
    kinds = sorted(n.type for n in tree.nodes)
    if kinds != ["EMISSION", "OUTPUT_LIGHT"]:
        return False
    emission = next(n for n in tree.nodes if n.type == "EMISSION")
    color, strength = emission.inputs["Color"], emission.inputs["Strength"]
    return (not color.is_linked and not strength.is_linked and
            tuple(color.default_value)[:3] == (1.0, 1.0, 1.0) and
            strength.default_value == 1.0)


def world_radiance(world, warnings):
    """Constant background radiance of a world: color x strength (a textured world is
    replaced by its mean colour, with a warning)."""
    if world is None:
        return (0.0, 0.0, 0.0)
    what = f"world '{world.name}'"
    if not compat.uses_nodes(world):
        return tuple(float(c) for c in world.color[:3])
    tree = world.node_tree
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_WORLD"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None:
        return (0.0, 0.0, 0.0)
    source = materials._linked_from(output.inputs["Surface"])
    if source is None:
        return (0.0, 0.0, 0.0)
    node = source.node
    if node.type != "BACKGROUND":
        warnings.append(f"{what}: a '{node.bl_label}' node is not a Background; the world is "
                        "read as black")
        return (0.0, 0.0, 0.0)
    strength_socket = node.inputs["Strength"]
    if strength_socket.is_linked:
        warnings.append(f"{what}: a linked strength is read as its default value")
    strength = float(strength_socket.default_value)
    color_socket = node.inputs["Color"]
    color = tuple(float(c) for c in color_socket.default_value[:3])
    color_source = materials._linked_from(color_socket)
    if color_source is not None:
        tex = color_source.node
        if tex.type == "TEX_ENVIRONMENT" and tex.image is not None:
            rgb = materials.image_linear_rgb(tex.image, warnings)
            if rgb is not None:
                # Mean radiance over the sphere of an equirectangular map: rows weighted by
                # the solid angle they cover (cos of latitude).
                h = rgb.shape[0]
                latitude = (np.arange(h) + 0.5) / h * np.pi - np.pi / 2
                weights = np.cos(latitude)
                color = tuple(float(c) for c in
                              (rgb.mean(axis=1) * weights[:, None]).sum(axis=0) / weights.sum())
                warnings.append(f"{what}: the environment texture is replaced by its mean "
                                "color (a constant world)")
        elif color_source.node.type == "RGB":
            color = tuple(float(c) for c in color_source.default_value[:3])
        else:
            warnings.append(f"{what}: the '{tex.bl_label}' node on the background color is not "
                            "evaluated; its default color is used")
    return light_units.world_radiance(color, strength)


# ---- bake points --------------------------------------------------------------------------


def _original_corner_normals(mesh):
    """Corner normals of an original mesh read without changing it (custom normals are not
    read): the vertex normal on smooth faces, the face normal on flat ones."""
    loops = len(mesh.loops)
    vertex_normals = _get(mesh.vertices, "normal", len(mesh.vertices), np.float32, 3)
    loop_vertex = _get(mesh.loops, "vertex_index", loops, np.int32)
    polys = len(mesh.polygons)
    face_normals = _get(mesh.polygons, "normal", polys, np.float32, 3)
    smooth = _get(mesh.polygons, "use_smooth", polys, bool)
    totals = _get(mesh.polygons, "loop_total", polys, np.int32)
    loop_face = np.repeat(np.arange(polys), totals)
    return np.where(smooth[loop_face][:, None], vertex_normals[loop_vertex],
                    face_normals[loop_face])


# How far a bake point moves from its vertex towards the centre of its face(s), as a fraction
# of that distance. A corner on a concave junction (a floor corner at the foot of a wall) lies
# exactly in the plane of the neighbouring surface; rays leaving it then hit or miss that
# surface by float rounding, and the value came out 36% dark there against Cycles. Moved this
# little into its own face, the point gives the limit from inside the face, which is what
# Cycles' bake returns there, and the value moves by a negligible 0.2% of a face's size.
INWARD_FRACTION = 2e-3


def nudge_into_faces(positions, inward_targets):
    """Moves each bake point INWARD_FRACTION of the way towards its target point."""
    return positions + INWARD_FRACTION * (inward_targets - positions)


def _mean_face_center_per_vertex(vertices, loop_vertex, loop_face_center):
    """Mean of the centres of the faces around each vertex (the vertex itself if loose)."""
    sums = np.zeros_like(vertices, dtype=np.float64)
    np.add.at(sums, loop_vertex, loop_face_center)
    counts = np.bincount(loop_vertex, minlength=len(vertices))[:, None]
    return np.where(counts > 0, sums / np.maximum(counts, 1), vertices).astype(np.float32)


# Display probes (points inside faces where the bake checks what a viewer sees between bake
# points, interpolation included): this many per target object, fewer when there are many
# targets, so that the check costs about the same on any scene.
DISPLAY_PROBES_PER_OBJECT = 16
DISPLAY_PROBES_MIN_PER_OBJECT = 8
DISPLAY_PROBES_TOTAL = 2048


def display_probes_per_object(target_count):
    if target_count <= 0:
        return 0
    return max(DISPLAY_PROBES_MIN_PER_OBJECT,
               min(DISPLAY_PROBES_PER_OBJECT, DISPLAY_PROBES_TOTAL // target_count))


@dataclass
class DisplayProbes:
    """Probes of one target in object space: positions, normals, and per probe the target's
    three bake points (of the face corner triangle it lies in) with barycentric weights."""
    positions: np.ndarray  # (k, 3)
    normals: np.ndarray  # (k, 3)
    points: np.ndarray  # (k, 3) bake point indices within the target
    weights: np.ndarray  # (k, 3)


def _display_probes(source, domain, normals, count, rng):
    """`count` points spread uniformly over the area of `source`'s faces (loop triangles),
    each with the corner (or vertex) bake points and weights that interpolate the color
    attribute there, as the viewport does."""
    source.calc_loop_triangles()
    tris = len(source.loop_triangles)
    if count <= 0 or tris == 0:
        return None
    tri_loops = _get(source.loop_triangles, "loops", tris, np.int32, 3)
    loop_vertex = _get(source.loops, "vertex_index", len(source.loops), np.int32)
    vertices = _get(source.vertices, "co", len(source.vertices), np.float32, 3).astype(np.float64)
    corners = vertices[loop_vertex[tri_loops]]  # (T, 3, 3)
    areas = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                          corners[:, 2] - corners[:, 0]), axis=1)
    total = areas.sum()
    if not (total > 0.0):
        return None
    chosen = rng.choice(tris, size=count, p=areas / total)
    # Uniform barycentrics (Osada et al.): sqrt folds the square onto the triangle.
    r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
    weights = np.stack([1.0 - r1, r1 * (1.0 - r2), r1 * r2], axis=1)
    positions = np.einsum("kj,kjc->kc", weights, corners[chosen])
    loops = tri_loops[chosen]
    points = loops if domain == "CORNER" else loop_vertex[loops]
    corner_normals = normals[points].astype(np.float64)
    probe_normals = np.einsum("kj,kjc->kc", weights, corner_normals)
    return DisplayProbes(positions.astype(np.float32), probe_normals.astype(np.float32),
                         points.astype(np.uint32), weights.astype(np.float32))


def repair_normals(normals, fallback, name, warnings):
    """Bake points need a direction: a zero or non-finite normal (imported meshes carry them
    on degenerate faces and in broken custom normals) takes its face's normal (`fallback`, the
    summed face normals for vertices), and where that is zero too, +z, with a warning."""
    normals = np.asarray(normals, np.float32)
    length = np.linalg.norm(normals, axis=1)
    bad = ~(np.isfinite(length) & (length > 1e-12))
    if not bad.any():
        return normals
    repaired = normals.copy()
    replacement = np.nan_to_num(np.asarray(fallback, np.float64)[bad], nan=0.0, posinf=0.0,
                                neginf=0.0)
    replacement_length = np.linalg.norm(replacement, axis=1)
    arbitrary = ~(replacement_length > 1e-12)
    replacement[arbitrary] = (0.0, 0.0, 1.0)
    replacement_length[arbitrary] = 1.0
    repaired[bad] = (replacement / replacement_length[:, None]).astype(np.float32)
    if arbitrary.any():
        warnings.append(f"'{name}': {int(arbitrary.sum())} bake points lie on faces without "
                        "area (no normal); they are baked facing +z (merge or delete the "
                        "degenerate faces)")
    return repaired


def target_points(obj, depsgraph, domain, warnings, probe_count=0, seed=0):
    """World-space (positions, normals, display probes or None) of one target's bake points
    on its original mesh's domain, and `probe_count` display probes inside its faces
    (positions and normals in world space, bake point indices within the target)."""
    original = obj.data
    obj_eval = obj.evaluated_get(depsgraph)
    matrix = _matrix(obj_eval.matrix_world)
    want = len(original.loops) if domain == "CORNER" else len(original.vertices)
    mesh = obj_eval.to_mesh()
    try:
        same = (mesh is not None and len(mesh.vertices) == len(original.vertices) and
                len(mesh.loops) == len(original.loops))
        source = mesh if same else original
        if not same:
            warnings.append(f"'{obj.name}': modifiers change its topology; the bake is made on "
                            "the mesh without them (placed in world space)")
        vertices = _get(source.vertices, "co", len(source.vertices), np.float32, 3)
        loop_vertex = _get(source.loops, "vertex_index", len(source.loops), np.int32)
        polys = len(source.polygons)
        face_centers = _get(source.polygons, "center", polys, np.float32, 3)
        loop_face = np.repeat(np.arange(polys),
                              _get(source.polygons, "loop_total", polys, np.int32))
        face_normals = _get(source.polygons, "normal", polys, np.float32, 3)
        if domain == "CORNER":
            positions = vertices[loop_vertex]
            inward = face_centers[loop_face]
            normals = corner_normals(source) if same else _original_corner_normals(source)
            fallback = face_normals[loop_face]
        else:
            positions = vertices
            inward = _mean_face_center_per_vertex(vertices, loop_vertex, face_centers[loop_face])
            normals = _get(source.vertices, "normal", want, np.float32, 3)
            fallback = np.zeros((len(vertices), 3), np.float64)
            np.add.at(fallback, loop_vertex, face_normals[loop_face])
        normals = repair_normals(normals, fallback, obj.name, warnings)
        positions = nudge_into_faces(positions, inward)
        probes = _display_probes(source, domain, normals, probe_count,
                                 np.random.default_rng(seed)) if probe_count else None
    finally:
        obj_eval.to_mesh_clear()
    _check_finite(obj.name, positions, "vertex" if domain == "POINT" else "face corner")
    if probes is not None:
        probes.positions = _positions_to_world(matrix, probes.positions)
        probes.normals = _normals_to_world(matrix, probes.normals)
    return _positions_to_world(matrix, positions), _normals_to_world(matrix, normals), probes


def mesh_facts(mesh):
    """What the error check says about a target (error_check.ObjectFacts): its vertex count
    and the share of its edges that bound a single face (open, sheet-like geometry)."""
    from .error_check import ObjectFacts
    edges = len(mesh.edges)
    if edges == 0:
        return ObjectFacts(vertices=len(mesh.vertices))
    loop_edges = _get(mesh.loops, "edge_index", len(mesh.loops), np.int32)
    faces_per_edge = np.bincount(loop_edges, minlength=edges)
    return ObjectFacts(vertices=len(mesh.vertices),
                       open_edge_share=float(np.count_nonzero(faces_per_edge == 1)) / edges)


# ---- the whole export ---------------------------------------------------------------------


def export_scene(context, target="CORNER", objects="SELECTED", depsgraph=None, lightmap=None,
                 defer_texels=False, display_probes=False):
    """Exports the evaluated scene and the bake points of the target objects.

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
    targets, skipped = resolve_targets(context, objects, shared_meshes=target == "LIGHTMAP")
    if not targets:
        why = "; ".join(skipped) if skipped else "no mesh object is " + (
            "selected" if objects == "SELECTED" else "visible" if objects == "VISIBLE" else
            "given")
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"nothing to bake: {why}")
    created_uv_maps = []
    if target == "LIGHTMAP":
        lightmap = lightmap or LightmapOptions()
        _check_lightmap_options(lightmap)
        created_uv_maps = lightmap_uvs.ensure(context, targets, lightmap.uv_map,
                                              lightmap.uv_method, lightmap.texels_per_meter,
                                              lightmap.max_side)
        depsgraph = None  # the new UV maps must be evaluated
    try:
        return _export(context, target, targets, skipped, depsgraph, lightmap, created_uv_maps,
                       start, defer_texels, display_probes)
    except BaseException:
        lightmap_uvs.remove(context.blend_data, created_uv_maps,
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
        linked = set()
        for instance in depsgraph.object_instances:
            obj = instance.object
            if obj.type in MESH_LIKE:
                exporter.add_instance(obj, instance.matrix_world, instance.is_instance)
            elif obj.type == "LIGHT":
                exporter.add_light(obj, instance.matrix_world)
            if (obj.type in MESH_LIKE or obj.type == "LIGHT") and compat.light_linking_in_use(obj):
                linked.add(obj.name)
        if linked:
            warnings.append(f"light linking is ignored (set on {', '.join(sorted(linked)[:5])}"
                            f"{' ...' if len(linked) > 5 else ''}): their light reaches every "
                            "object in the bake")
        if compat.eevee_raytracing_on(context.scene):
            warnings.append("EEVEE's Raytracing is on (Render Properties): EEVEE then adds its "
                            "own indirect light and spreads the shown bake to other surfaces "
                            "again, so EEVEE shows more indirect light than the bake (Cycles "
                            "does not); turn it off to judge the bake in EEVEE")
        exporter.set_world(context.scene.world)

        if target == "LIGHTMAP":
            exported_lightmaps, bake_targets = _lightmap_points(exporter, targets, lightmap,
                                                               warnings)
            exported_lightmaps.created_uv_maps = created_uv_maps
            points = None if defer_texels else exported_lightmaps.build()
            offset = len(points) if points is not None else 0
            return _exported(exporter, points, bake_targets, warnings, skipped, offset, start,
                             exported_lightmaps)

        positions, normals, ids, bake_targets, probes = [], [], [], [], []
        offset = 0
        per_object = display_probes_per_object(len(targets)) if display_probes else 0
        for index, obj in enumerate(targets):
            p, n, object_probes = target_points(obj, depsgraph, target, warnings, per_object,
                                                seed=index)
            positions.append(p)
            normals.append(n)
            ids.append(np.full(len(p), index, np.uint32))
            if object_probes is not None:
                probes.append((index, offset, object_probes))
            bake_targets.append(BakeTarget(obj.name, obj.data.name_full, target, offset, len(p)))
            offset += len(p)
        points = native.Points(np.concatenate(positions), np.concatenate(normals),
                               np.concatenate(ids))
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
              "lights": exporter.lights, "materials": len(exporter.material_ids),
              "textures": exporter.texture_count(),
              "bake_points": offset, "targets": len(bake_targets)}
    if exported_lightmaps is not None:
        counts.update(lightmap_width=exported_lightmaps.width,
                      lightmap_height=exported_lightmaps.height,
                      lightmap_covered_texels=exported_lightmaps.covered_texels,
                      lightmap_rejected_samples=exported_lightmaps.rejected_samples)
    return ExportedScene(exporter.scene, points, bake_targets, exporter.material_infos,
                         _unique(warnings), skipped, counts, time.perf_counter() - start,
                         exporter.object_names, exported_lightmaps)


def _lightmap_points(exporter, targets, options, warnings):
    """Lays the targets' lightmaps out in one atlas (their texels are rasterized by
    ExportedLightmaps.build()). Returns (ExportedLightmaps, [BakeTarget])."""
    sources = []
    for obj in targets:
        source = exporter.lightmap_sources.get(obj.name)
        if source is None:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"'{obj.name}' has no triangles to bake a lightmap on")
        sources.append(source)
    uv_areas = []
    for obj, source in zip(targets, sources):
        outside = (source.uvs < -1e-4) | (source.uvs > 1.0 + 1e-4)
        if outside.any():
            warnings.append(f"'{obj.name}': UV map '{options.uv_map}' reaches outside [0, 1]; "
                            "those parts are clipped to the edge of its lightmap")
        uv_areas.append(float(lightmap_layout.triangle_areas(
            np.clip(source.uvs, 0.0, 1.0)).sum()))
    # An object's own density (Object properties > BakeGI Lightmap; 0 = the bake's).
    densities = [float(getattr(obj, "bakegi_texels_per_meter", 0.0)) or
                 options.texels_per_meter for obj in targets]
    atlas = lightmap_layout.layout([s.world_area for s in sources], uv_areas, densities,
                                   options.max_side, options.padding)
    for i in atlas.clamped:
        warnings.append(f"'{targets[i].name}': its lightmap is limited to {options.max_side} "
                        f"texels, below {densities[i]:g} texels per metre")
    if atlas.density_scale < 1.0:
        warnings.append(f"the lightmaps did not fit one {lightmap_layout.MAX_ATLAS_SIDE}-texel "
                        f"atlas; every object got {atlas.density_scale:.0%} of the asked "
                        "density")
    samples = native.Lightmaps()
    samples.set_memory_budget(options.memory_budget_mb)
    result = ExportedLightmaps(samples, atlas.width, atlas.height, options,
                               density_scale=atlas.density_scale, scene=exporter.scene,
                               pending=[(s.mesh_id, atlas.to_atlas(i, s.uvs))
                                        for i, s in enumerate(sources)])
    bake_targets = [BakeTarget(obj.name, obj.data.name_full, "LIGHTMAP", 0, 0,
                               atlas.scale_offset(i), atlas.tiles[i].side)
                    for i, obj in enumerate(targets)]
    return result, bake_targets


def export_lights(context, scene, depsgraph=None):
    """Replaces the lights and the world of the core `scene` with the current ones (a live
    relight: the meshes and materials stay as exported). Returns (lights, warnings)."""
    if depsgraph is None:
        depsgraph = context.evaluated_depsgraph_get()
    warnings = []
    exporter = SceneExporter(depsgraph, warnings, scene=scene)
    scene.clear_lights()
    for instance in depsgraph.object_instances:
        if instance.object.type == "LIGHT":
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
