# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes binding of the bakegi core (native/include/bakegi/bakegi.h).

Never imports bpy. Every C function is declared with its argument and result types; the
handles are wrapped in classes (Scene, Points, Settings, Job) that free them in close(),
on leaving a `with` block, or when garbage collected. A failing call raises BakeGIError
with the core's status name and message.

The library is looked up, in order: the path in the environment variable BAKEGI_LIBRARY,
then lib/libbakegi.so next to this file (where the add-on zip puts it).
"""

import ctypes
import json
import os
import sys
import threading
from ctypes import (POINTER, Structure, byref, c_char, c_char_p, c_double, c_float, c_int,
                    c_int64, c_size_t, c_uint32, c_uint64, c_void_p)

import numpy as np

LIBRARY_ENV = "BAKEGI_LIBRARY"
LIBRARY_NAME = {"win32": "bakegi.dll", "darwin": "libbakegi.dylib"}.get(sys.platform,
                                                                       "libbakegi.so")
NO_TEXTURE = 0xFFFFFFFF
# BAKEGI_ABI_VERSION of the bakegi.h these bindings mirror (checked at load, with the sizes of
# the structs below).
ABI_VERSION = 1

STATUS_NAMES = (
    "BAKEGI_OK",
    "BAKEGI_ERROR_INVALID_ARGUMENT",
    "BAKEGI_ERROR_INVALID_SCENE",
    "BAKEGI_ERROR_OUT_OF_MEMORY",
    "BAKEGI_ERROR_CANCELLED",
    "BAKEGI_ERROR_IO",
    "BAKEGI_ERROR_BAD_FILE",
    "BAKEGI_ERROR_NOT_READY",
    "BAKEGI_ERROR_RAY_TRACER",
    "BAKEGI_ERROR_INTERNAL",
)
OK = 0
ERROR_CANCELLED = 4

LIGHT_TYPES = {"POINT": 0, "SPOT": 1, "SUN": 2, "AREA": 3}
AREA_SHAPES = {"SQUARE": 0, "RECTANGLE": 1, "DISK": 2, "ELLIPSE": 3}


class BakeGIError(Exception):
    """A failure reported by the core (or found by the add-on before calling it).

    status: the core's status name, e.g. "BAKEGI_ERROR_INVALID_SCENE" (the add-on's own
    checks use the same names); message: what was wrong and where."""

    def __init__(self, status, message):
        super().__init__(f"{message} [{status}]" if status else message)
        self.status = status
        self.message = message

    @property
    def cancelled(self):
        return self.status == STATUS_NAMES[ERROR_CANCELLED]


class MaterialDesc(Structure):
    _fields_ = [
        ("albedo", c_float * 3),
        ("albedo_texture", c_uint32),
        ("emission", c_float * 3),
        ("emission_two_sided", c_uint32),
        ("glossy", c_float * 3),
        ("glossy_exponent", c_float),
    ]


class MeshDesc(Structure):
    _fields_ = [
        ("positions", POINTER(c_float)),
        ("vertex_count", c_uint32),
        ("indices", POINTER(c_uint32)),
        ("triangle_count", c_uint32),
        ("corner_normals", POINTER(c_float)),
        ("corner_uvs", POINTER(c_float)),
        ("triangle_materials", POINTER(c_uint32)),
        ("material", c_uint32),
        ("object_id", c_uint32),
    ]


class LightDesc(Structure):
    _fields_ = [
        ("type", c_int),
        ("position", c_float * 3),
        ("direction", c_float * 3),
        ("axis_u", c_float * 3),
        ("color", c_float * 3),
        ("radius", c_float),
        ("spot_size", c_float),
        ("spot_blend", c_float),
        ("angle", c_float),
        ("shape", c_int),
        ("size_x", c_float),
        ("size_y", c_float),
        ("flags", c_uint32),
    ]


_P = c_void_p  # opaque handles
_PP = POINTER(c_void_p)

# name: (restype, argtypes)
_SIGNATURES = {
    "bakegi_version": (c_uint32, []),
    "bakegi_abi_version": (c_uint32, []),
    "bakegi_struct_size": (c_size_t, [c_char_p]),
    "bakegi_settings_describe": (c_int, [c_char_p, c_char_p, c_size_t, POINTER(c_size_t)]),
    "bakegi_settings_check": (c_int, [c_void_p]),
    "bakegi_version_string": (c_char_p, []),
    "bakegi_status_string": (c_char_p, [c_int]),
    "bakegi_last_error": (c_char_p, []),
    "bakegi_scene_create": (c_int, [_PP]),
    "bakegi_scene_destroy": (None, [_P]),
    "bakegi_scene_add_texture": (c_int, [_P, c_uint32, c_uint32, POINTER(c_float),
                                         POINTER(c_uint32)]),
    "bakegi_scene_add_material": (c_int, [_P, POINTER(MaterialDesc), POINTER(c_uint32)]),
    "bakegi_scene_set_material_emission_texture": (c_int, [_P, c_uint32, c_uint32]),
    "bakegi_scene_set_material_passing": (c_int, [_P, c_uint32, c_float, c_uint32, c_float,
                                                  c_float]),
    "bakegi_scene_add_mesh": (c_int, [_P, POINTER(MeshDesc), POINTER(c_uint32)]),
    "bakegi_scene_add_light": (c_int, [_P, POINTER(LightDesc), POINTER(c_uint32)]),
    "bakegi_scene_set_world": (c_int, [_P, POINTER(c_float)]),
    "bakegi_scene_set_world_texture": (c_int, [_P, c_uint32, POINTER(c_float),
                                               POINTER(c_float)]),
    "bakegi_scene_validate": (c_int, [_P]),
    "bakegi_scene_triangle_count": (c_uint64, [_P]),
    "bakegi_scene_light_count": (c_uint32, [_P]),
    "bakegi_points_create": (c_int, [POINTER(c_float), POINTER(c_float), POINTER(c_uint32),
                                     c_uint64, _PP]),
    "bakegi_points_destroy": (None, [_P]),
    "bakegi_points_count": (c_uint64, [_P]),
    "bakegi_points_get": (c_int, [_P, POINTER(c_float), POINTER(c_float), POINTER(c_uint32)]),
    "bakegi_points_set_share_candidates": (c_int, [_P, POINTER(c_uint32), c_uint64]),
    "bakegi_points_set_display_probes": (c_int, [_P, POINTER(c_float), POINTER(c_float),
                                                 POINTER(c_uint32), POINTER(c_uint32),
                                                 POINTER(c_float), c_uint64]),
    "bakegi_file_write": (c_int, [c_char_p, _P, _P]),
    "bakegi_file_read": (c_int, [c_char_p, _PP, _PP]),
    "bakegi_settings_create": (c_int, [_PP]),
    "bakegi_settings_destroy": (None, [_P]),
    "bakegi_settings_set_int": (c_int, [_P, c_char_p, c_int64]),
    "bakegi_settings_set_float": (c_int, [_P, c_char_p, c_double]),
    "bakegi_settings_set_string": (c_int, [_P, c_char_p, c_char_p]),
    "bakegi_job_start": (c_int, [_P, _P, _P, _PP]),
    "bakegi_job_progress": (c_double, [_P]),
    "bakegi_job_stage": (None, [_P, POINTER(c_char), c_size_t]),
    "bakegi_job_cancel": (None, [_P]),
    "bakegi_job_is_done": (c_int, [_P]),
    "bakegi_job_wait": (c_int, [_P]),
    "bakegi_job_get_result": (c_int, [_P, POINTER(c_float), c_uint64]),
    "bakegi_job_get_report": (c_int, [_P, POINTER(c_char), c_size_t, POINTER(c_size_t)]),
    "bakegi_job_destroy": (None, [_P]),
    "bakegi_scene_get_light": (c_int, [_P, c_uint32, _P]),
    "bakegi_scene_clear_lights": (c_int, [_P]),
    "bakegi_scene_add_portal": (c_int, [_P, POINTER(LightDesc)]),
    "bakegi_scene_portal_count": (c_uint32, [_P]),
    "bakegi_job_can_relight": (c_int, [_P]),
    "bakegi_job_start_relight": (c_int, [_P, _P, _P, _P, _PP]),
    "bakegi_lightmaps_create": (c_int, [_PP]),
    "bakegi_lightmaps_set_memory_budget": (c_int, [c_void_p, c_uint64]),
    "bakegi_lightmaps_cancel": (c_int, [c_void_p]),
    "bakegi_lightmaps_destroy": (None, [_P]),
    "bakegi_lightmaps_add": (c_int, [_P, _P, c_uint32, POINTER(c_float), c_uint32, c_uint32,
                                     POINTER(c_uint32)]),
    "bakegi_lightmaps_add_to": (c_int, [_P, c_uint32, _P, c_uint32, POINTER(c_float)]),
    "bakegi_lightmaps_reject_inside": (c_int, [_P, _P, c_uint32, c_float, c_float,
                                               POINTER(c_uint64)]),
    "bakegi_lightmaps_count": (c_uint32, [_P]),
    "bakegi_lightmaps_get_info": (c_int, [_P, c_uint32, _P]),
    "bakegi_lightmaps_get_points": (c_int, [_P, _PP]),
    "bakegi_lightmaps_write_exr": (c_int, [_P, c_uint32, POINTER(c_float), c_uint64, c_char_p,
                                           c_uint32, c_int, c_uint32]),
    "bakegi_lightmaps_resolve": (c_int, [_P, c_uint32, POINTER(c_float), c_uint64, c_uint32,
                                         c_uint32, POINTER(c_float), c_uint64]),
    "bakegi_lightmaps_write_file": (c_int, [_P, c_char_p]),
    "bakegi_lightmaps_read_file": (c_int, [c_char_p, _PP]),
    "bakegi_scene_get_bounds": (c_int, [_P, POINTER(c_float), POINTER(c_float)]),
    "bakegi_points_flag_inside": (c_int, [_P, _P, c_uint32, c_float, c_float,
                                          POINTER(ctypes.c_uint8)]),
    "bakegi_mesh_simplify": (c_int, [POINTER(c_float), c_uint64, POINTER(c_uint32), c_uint64,
                                     c_float, c_float, POINTER(c_uint32),
                                     POINTER(c_uint64), POINTER(c_float)]),
    "bakegi_web_export": (c_int, [_P, _P, c_char_p, POINTER(c_float)]),
    "bakegi_grid_stream_order": (c_int, [_P, c_uint64, POINTER(c_uint32)]),
    "bakegi_preview_create": (c_int, [_P, _PP]),
    "bakegi_preview_destroy": (None, [_P]),
    "bakegi_preview_set_lights": (c_int, [_P, _P]),
    "bakegi_preview_render": (c_int, [_P, POINTER(c_float), c_uint32, c_uint32, _P,
                                      POINTER(c_float), POINTER(c_float), POINTER(c_float),
                                      POINTER(ctypes.c_uint8)]),
    "bakegi_preview_get_report": (c_int, [_P, POINTER(c_char), c_size_t, POINTER(c_size_t)]),
    "bakegi_grid_encode_vertices": (c_int, [_P, POINTER(c_uint32), c_uint64, c_int,
                                            POINTER(ctypes.c_uint8)]),
    "bakegi_grid_create": (c_int, [POINTER(c_float), POINTER(c_float), c_float, c_uint64, _PP]),
    "bakegi_grid_destroy": (None, [_P]),
    "bakegi_grid_get_info": (c_int, [_P, _P]),
    "bakegi_job_start_grid": (c_int, [_P, _P, c_uint32, _P, _PP]),
    "bakegi_job_get_grid": (c_int, [_P, _PP]),
    "bakegi_grid_evaluate": (c_int, [_P, POINTER(c_float), POINTER(c_float), c_uint64, c_int,
                                     c_int, POINTER(c_float)]),
    "bakegi_grid_evaluate_in_scene": (c_int, [_P, _P, POINTER(c_float), POINTER(c_float),
                                              c_uint64, c_int, c_int, c_uint32,
                                              POINTER(c_float), POINTER(ctypes.c_uint8)]),
    "bakegi_grid_write_file": (c_int, [_P, c_char_p, c_int, c_char_p]),
    "bakegi_grid_read_file": (c_int, [c_char_p, _PP]),
    "bakegi_grid_get_info_json": (c_int, [_P, POINTER(c_char), c_size_t, POINTER(c_size_t)]),
    "bakegi_grid_with_emitted_light": (c_int, [_P, _PP, POINTER(ctypes.c_int)]),
}

GRID_INTERPOLATION = {"TRILINEAR": 0, "TRICUBIC": 1}
GRID_DIRECTIONAL = {"SQUARED": 0, "ABSOLUTE": 1}
GRID_ENCODING = {"FLOAT": 0, "QUANTIZED": 1, "FACTORED": 2}

EXR_COMPRESSION = {"ZIP": 0, "PIZ": 1, "NONE": 2}

_library = None
_library_lock = threading.Lock()


def default_library_path():
    """Where the library is looked for: $BAKEGI_LIBRARY, else lib/ next to this file."""
    env = os.environ.get(LIBRARY_ENV)
    if env:
        return env
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "lib", LIBRARY_NAME)


def load_library(path=None):
    """Loads (once) and returns the core library with every function declared."""
    global _library
    with _library_lock:
        if _library is not None:
            return _library
        path = path or default_library_path()
        if not os.path.isfile(path):
            raise BakeGIError(
                "BAKEGI_ERROR_IO",
                f"the bakegi core library was not found at {path}; reinstall the add-on zip "
                f"(it carries lib/{LIBRARY_NAME}) or set {LIBRARY_ENV} to its path")
        try:
            lib = ctypes.CDLL(path)
        except OSError as error:
            raise BakeGIError("BAKEGI_ERROR_IO",
                              f"the bakegi core library at {path} could not be loaded: {error}")
        missing = []
        for name, (restype, argtypes) in _SIGNATURES.items():
            try:
                function = getattr(lib, name)
            except AttributeError:
                missing.append(name)
                continue
            function.restype = restype
            function.argtypes = argtypes
        if missing:
            raise BakeGIError("BAKEGI_ERROR_IO",
                              f"the bakegi core library at {path} lacks {', '.join(missing)}; "
                              "it does not match this add-on version")
        _check_binary_interface(lib, path)
        _library = lib
        return lib


def _check_binary_interface(lib, path):
    """Refuses a library whose structs these bindings would misread (a stale lib/ next to a
    newer add-on, or the other way round)."""
    abi = int(lib.bakegi_abi_version())
    if abi != ABI_VERSION:
        raise BakeGIError("BAKEGI_ERROR_IO",
                          f"the bakegi core library at {path} has binary interface {abi}, this "
                          f"add-on expects {ABI_VERSION}; reinstall the add-on zip, which "
                          "carries the matching library")
    for name, struct in (("bakegi_material_desc", MaterialDesc), ("bakegi_mesh_desc", MeshDesc),
                         ("bakegi_light_desc", LightDesc),
                         ("bakegi_lightmap_info", LightmapInfo),
                         ("bakegi_grid_info", GridInfo)):
        theirs, ours = int(lib.bakegi_struct_size(name.encode())), ctypes.sizeof(struct)
        if theirs != ours:
            raise BakeGIError("BAKEGI_ERROR_IO",
                              f"the bakegi core library at {path} does not match this add-on: "
                              f"{name} is {theirs} bytes there and {ours} here")


def _read_text(function, arguments, what):
    """The text of a core call ending in (buffer, capacity, out_length): its length first,
    then the text."""
    length = c_size_t(0)
    _check(function(*arguments, None, 0, byref(length)), what)
    buffer = ctypes.create_string_buffer(length.value + 1)
    _check(function(*arguments, buffer, len(buffer), byref(length)), what)
    return _decode(buffer.value)


def describe_settings(method=""):
    """The settings schema of a method as a dict (bakegi_settings_describe; docs/settings.md),
    or {"methods": [...], "default": name} for method ""."""
    return json.loads(_read_text(load_library().bakegi_settings_describe,
                                 (method.encode("utf-8"),), "describing settings"))


def method_names():
    """The methods the core registers, in listing order (each solver folder registers its
    own: native/src/solvers/<name>/<name>_method.cpp)."""
    return tuple(describe_settings()["methods"])


def default_method():
    """The method a bake uses when none is named: the core's, the same in every layer."""
    return describe_settings()["default"]


def default_method_settings():
    """The settings a bake that names no method gets where it does not set them (the core's
    default_method_settings: target_error, denoise and the paths' cap)."""
    return dict(describe_settings().get("default_settings", {}))


def library_loaded():
    return _library is not None


def _decode(raw):
    return raw.decode("utf-8", "replace") if raw else ""


def status_name(status):
    if 0 <= status < len(STATUS_NAMES):
        return STATUS_NAMES[status]
    lib = load_library()
    return _decode(lib.bakegi_status_string(status)) or f"BAKEGI_STATUS_{status}"


def _check(status, what=""):
    """Raises BakeGIError for a non-OK status with the thread's last error message."""
    if status == OK:
        return
    message = _decode(load_library().bakegi_last_error())
    if not message:
        message = f"{what} failed" if what else "the bakegi core reported an error"
    raise BakeGIError(status_name(status), message)


def version():
    lib = load_library()
    return int(lib.bakegi_version())


def version_string():
    return _decode(load_library().bakegi_version_string())


def _floats(array, columns, what):
    """C-contiguous float32 array of shape (n, columns) (from anything array-like)."""
    a = np.ascontiguousarray(np.asarray(array, dtype=np.float32).reshape(-1, columns))
    return a


def _uints(array, what):
    a = np.asarray(array)
    if a.size and (a.dtype.kind == "f" or (a.dtype.kind == "i" and a.min() < 0)):
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                          f"{what}: indices must be non-negative integers")
    return np.ascontiguousarray(a.astype(np.uint32, copy=False).reshape(-1))


def _fptr(a):
    return None if a is None else a.ctypes.data_as(POINTER(c_float))


def _uptr(a):
    return None if a is None else a.ctypes.data_as(POINTER(c_uint32))


def _triple(values, what):
    v = [float(x) for x in values]
    if len(v) != 3:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"{what} needs 3 values, got {len(v)}")
    return (c_float * 3)(*v)


def _light_desc(type, position, direction, axis_u, color, radius, spot_size, spot_blend, angle,
                shape, size_x, size_y, flags):
    """A bakegi_light_desc, type and shape by name ('POINT', 'DISK'...)."""
    if type not in LIGHT_TYPES:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"unknown light type {type!r}")
    if shape not in AREA_SHAPES:
        raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", f"unknown area shape {shape!r}")
    return LightDesc(LIGHT_TYPES[type], _triple(position, "position"),
                     _triple(direction, "direction"), _triple(axis_u, "axis_u"),
                     _triple(color, "color"), radius, spot_size, spot_blend, angle,
                     AREA_SHAPES[shape], size_x, size_y, int(flags))


def simplify_mesh(positions, indices, ratio, max_error=1.0):
    """A level of detail (bakegi_mesh_simplify, meshoptimizer's edge collapses): the
    triangles of `indices` ((n, 3) into (v, 3) `positions`) reduced towards `ratio` (0, 1] of
    them within max_error of the mesh's extent. Returns ((m, 3) uint32 triangles into the
    same vertices, the deviation reached over the extent)."""
    xyz = _floats(positions, 3, "positions")
    tris = _uints(indices, "indices")
    out = np.zeros(len(tris), np.uint32)
    written, error = c_uint64(0), c_float(0.0)
    _check(load_library().bakegi_mesh_simplify(
        _fptr(xyz), len(xyz), _uptr(tris), len(tris), float(ratio), float(max_error),
        _uptr(out), byref(written), byref(error)), "bakegi_mesh_simplify")
    return out[:written.value].reshape(-1, 3), float(error.value)


def web_export(scene, folder, grid=None, camera=None):
    """Writes the scene for the web page into `folder` (bakegi_web_export): scene.gltf +
    scene.bin (progressive meshes) and, with a Grid, grid.bgivg and its visibility volume
    grid_visibility.bin (which grid vertices each place sees). camera: None or nine
    numbers (position xyz, rotation quaternion xyzw looking down -Z, vertical field of view
    in radians, aspect ratio)."""
    values = None
    if camera is not None:
        numbers = [float(v) for v in camera]
        if len(numbers) != 9:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"camera needs 9 numbers, got {len(numbers)}")
        values = (c_float * 9)(*numbers)
    _check(load_library().bakegi_web_export(scene.handle, grid.handle if grid else None,
                                            os.fsencode(folder), values), "bakegi_web_export")


class _Handle:
    """Owns one core handle; frees it exactly once."""

    _destroy_name = ""

    def __init__(self, handle):
        self._handle = handle

    @property
    def handle(self):
        if not self._handle:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"{type(self).__name__} was already closed")
        return self._handle

    def close(self):
        handle, self._handle = getattr(self, "_handle", None), None
        if handle and _library is not None:
            getattr(_library, self._destroy_name)(handle)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: nothing sensible left to do
            pass


class Scene(_Handle):
    """A scene being built for the core (bakegi_scene)."""

    _destroy_name = "bakegi_scene_destroy"

    def __init__(self, handle=None):
        lib = load_library()
        if handle is None:
            out = c_void_p()
            _check(lib.bakegi_scene_create(byref(out)), "bakegi_scene_create")
            handle = out.value
        super().__init__(handle)

    def add_texture(self, rgb_pixels):
        """rgb_pixels: (height, width, 3) linear float RGB, row 0 at v = 0. Returns its id."""
        a = np.asarray(rgb_pixels, dtype=np.float32)
        if a.ndim != 3 or a.shape[2] != 3:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"texture pixels must have shape (height, width, 3), got {a.shape}")
        a = np.ascontiguousarray(a)
        out = c_uint32()
        _check(load_library().bakegi_scene_add_texture(self.handle, a.shape[1], a.shape[0],
                                                       _fptr(a), byref(out)),
               "bakegi_scene_add_texture")
        return out.value

    def add_material(self, albedo, emission=(0.0, 0.0, 0.0), albedo_texture=None,
                     emission_two_sided=True, glossy=(0.0, 0.0, 0.0), glossy_exponent=0.0,
                     emission_texture=None):
        """glossy, glossy_exponent: the optional modified Phong lobe (bakegi.h);
        albedo + glossy must not exceed 1 per channel. emission_texture: a texture id that
        multiplies emission (set_material_emission_texture)."""
        desc = MaterialDesc()
        desc.albedo = _triple(albedo, "albedo")
        desc.albedo_texture = NO_TEXTURE if albedo_texture is None else int(albedo_texture)
        desc.emission = _triple(emission, "emission")
        desc.emission_two_sided = 1 if emission_two_sided else 0
        desc.glossy = _triple(glossy, "glossy")
        desc.glossy_exponent = float(glossy_exponent)
        out = c_uint32()
        _check(load_library().bakegi_scene_add_material(self.handle, byref(desc), byref(out)),
               "bakegi_scene_add_material")
        if emission_texture is not None:
            self.set_material_emission_texture(out.value, emission_texture)
        return out.value

    def set_material_emission_texture(self, material, texture):
        """Material `material` emits emission x texture(uv); texture None removes it."""
        _check(load_library().bakegi_scene_set_material_emission_texture(
            self.handle, int(material), NO_TEXTURE if texture is None else int(texture)),
            "bakegi_scene_set_material_emission_texture")

    def set_material_passing(self, material, opacity=1.0, opacity_texture=None,
                             transmission=0.0, transmission_ior=0.0):
        """See-through surfaces: rays pass with probability 1 - opacity x texture (red channel)
        x (1 - transmission); albedo and glossy are then those of a surface a ray stopped at.
        transmission_ior > 0: glass, passing less at grazing angles (its average stays
        transmission)."""
        _check(load_library().bakegi_scene_set_material_passing(
            self.handle, int(material), float(opacity),
            NO_TEXTURE if opacity_texture is None else int(opacity_texture),
            float(transmission), float(transmission_ior)), "bakegi_scene_set_material_passing")

    def add_mesh(self, positions, indices, corner_normals=None, corner_uvs=None,
                 triangle_materials=None, material=0, object_id=0):
        """positions (V,3); indices (T,3); corner_normals (T,3,3); corner_uvs (T,3,2);
        triangle_materials (T,). World space. Returns the mesh id."""
        p = _floats(positions, 3, "positions")
        i = _uints(indices, "indices")
        if i.size % 3:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              "indices must hold 3 entries per triangle")
        n = None if corner_normals is None else _floats(corner_normals, 3, "corner_normals")
        uv = None if corner_uvs is None else _floats(corner_uvs, 2, "corner_uvs")
        tm = None if triangle_materials is None else _uints(triangle_materials,
                                                            "triangle_materials")
        triangles = i.size // 3
        for name, array, rows in (("corner_normals", n, 3 * triangles),
                                  ("corner_uvs", uv, 3 * triangles),
                                  ("triangle_materials", tm, triangles)):
            if array is not None and array.shape[0] != rows:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  f"{name} has {array.shape[0]} entries, expected {rows}")
        desc = MeshDesc(_fptr(p), p.shape[0], _uptr(i), triangles, _fptr(n), _fptr(uv),
                        _uptr(tm), int(material), int(object_id))
        out = c_uint32()
        _check(load_library().bakegi_scene_add_mesh(self.handle, byref(desc), byref(out)),
               "bakegi_scene_add_mesh")
        return out.value

    def add_light(self, type, position=(0, 0, 0), direction=(0, 0, -1), axis_u=(1, 0, 0),
                  color=(0, 0, 0), radius=0.0, spot_size=0.0, spot_blend=0.0, angle=0.0,
                  shape="SQUARE", size_x=0.0, size_y=0.0, flags=0):
        """Arguments as in bakegi_light_desc; type and shape by name ('POINT', 'DISK'...).
        light_units.CoreLight's fields can be passed with add_light(**vars(core_light))."""
        desc = _light_desc(type, position, direction, axis_u, color, radius, spot_size,
                           spot_blend, angle, shape, size_x, size_y, flags)
        out = c_uint32()
        _check(load_library().bakegi_scene_add_light(self.handle, byref(desc), byref(out)),
               "bakegi_scene_add_light")
        return out.value

    def clear_lights(self):
        """Removes every light and portal (to add changed ones for a relight)."""
        _check(load_library().bakegi_scene_clear_lights(self.handle), "bakegi_scene_clear_lights")

    def add_portal(self, position, direction, axis_u, shape, size_x, size_y=0.0, **_ignored):
        """A window portal (Cycles' area light with Portal on): the area light's shape, which
        emits nothing and guides the world's light samples through it. Takes a CoreLight's
        fields (add_portal(**vars(core_light)); its colour is ignored)."""
        desc = _light_desc("AREA", position, direction, axis_u, (0.0, 0.0, 0.0), 0.0, 0.0, 0.0,
                           0.0, shape, size_x, size_y, 0)
        _check(load_library().bakegi_scene_add_portal(self.handle, byref(desc)),
               "bakegi_scene_add_portal")

    def portal_count(self):
        return int(load_library().bakegi_scene_portal_count(self.handle))

    def set_world(self, radiance):
        _check(load_library().bakegi_scene_set_world(self.handle, _triple(radiance, "world")),
               "bakegi_scene_set_world")

    def set_world_texture(self, texture, scale=(1.0, 1.0, 1.0), rotation=None):
        """The world's light from the equirectangular texture `texture` (an id from
        add_texture, None for the constant world again): radiance = scale x texture at the
        direction turned by `rotation` (a 3 x 3 rotation, world -> image, rows as nested
        sequences; None: the identity), as Cycles' Environment Texture maps it."""
        lib = load_library()
        if texture is None:
            _check(lib.bakegi_scene_set_world_texture(self.handle, 0xFFFFFFFF, None, None),
                   "bakegi_scene_set_world_texture")
            return
        matrix = None
        if rotation is not None:
            r = np.asarray(rotation, dtype=np.float32)
            if r.shape != (3, 3):
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  f"world rotation must be 3 x 3, got shape {r.shape}")
            matrix = np.ascontiguousarray(r.T)  # column-major for the core
        _check(lib.bakegi_scene_set_world_texture(self.handle, int(texture),
                                                  _triple(scale, "world texture scale"),
                                                  _fptr(matrix)),
               "bakegi_scene_set_world_texture")

    def validate(self):
        _check(load_library().bakegi_scene_validate(self.handle), "bakegi_scene_validate")

    @property
    def triangle_count(self):
        return int(load_library().bakegi_scene_triangle_count(self.handle))

    @property
    def light_count(self):
        return int(load_library().bakegi_scene_light_count(self.handle))

    def bounds(self):
        """((x, y, z) min, (x, y, z) max) around every mesh vertex."""
        lo, hi = (c_float * 3)(), (c_float * 3)()
        _check(load_library().bakegi_scene_get_bounds(self.handle, lo, hi),
               "bakegi_scene_get_bounds")
        return tuple(lo), tuple(hi)

    def write(self, path, points=None):
        """Writes a .bgs scene file (with the bake points if given)."""
        _check(load_library().bakegi_file_write(os.fsencode(path), self.handle,
                                                points.handle if points is not None else None),
               "bakegi_file_write")

    @classmethod
    def read(cls, path):
        """Reads a .bgs file; returns (Scene, Points or None)."""
        lib = load_library()
        scene, points = c_void_p(), c_void_p()
        _check(lib.bakegi_file_read(os.fsencode(path), byref(scene), byref(points)),
               "bakegi_file_read")
        return cls(scene.value), (Points(handle=points.value) if points.value else None)


class Points(_Handle):
    """Bake points: where the indirect field is evaluated (bakegi_points)."""

    _destroy_name = "bakegi_points_destroy"

    def __init__(self, positions=None, normals=None, object_ids=None, handle=None):
        lib = load_library()
        if handle is None:
            p = _floats(positions, 3, "positions")
            n = _floats(normals, 3, "normals")
            if p.shape != n.shape:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  f"{p.shape[0]} positions but {n.shape[0]} normals")
            ids = None if object_ids is None else _uints(object_ids, "object_ids")
            if ids is not None and ids.shape[0] != p.shape[0]:
                raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                                  f"{p.shape[0]} positions but {ids.shape[0]} object ids")
            out = c_void_p()
            _check(lib.bakegi_points_create(_fptr(p), _fptr(n), _uptr(ids), p.shape[0],
                                            byref(out)), "bakegi_points_create")
            handle = out.value
        super().__init__(handle)

    def __len__(self):
        return int(load_library().bakegi_points_count(self.handle))

    @property
    def count(self):
        return len(self)

    def get(self):
        """Returns (positions (n,3) float32, normals (n,3) float32, object_ids (n,) uint32)."""
        n = len(self)
        p = np.empty((n, 3), np.float32)
        nn = np.empty((n, 3), np.float32)
        ids = np.empty(n, np.uint32)
        _check(load_library().bakegi_points_get(self.handle, _fptr(p), _fptr(nn), _uptr(ids)),
               "bakegi_points_get")
        return p, nn, ids

    def flag_inside(self, scene, rays=0, backface_fraction=0.0, max_distance=0.0):
        """(n,) bool: the points inside or under geometry of `scene` (their rays meet back
        faces; bakegi_points_flag_inside)."""
        flags = np.zeros(len(self), np.uint8)
        _check(load_library().bakegi_points_flag_inside(
            self.handle, scene.handle, int(rays), float(backface_fraction), float(max_distance),
            flags.ctypes.data_as(POINTER(ctypes.c_uint8))), "bakegi_points_flag_inside")
        return flags.astype(bool)

    def set_share_candidates(self, candidates):
        """Per point, an earlier point (or itself) at the same place with the same normal
        whose value it may share; the core checks each pair before it shares
        (export/point_sharing.py)."""
        c = _uints(candidates, "candidates")
        _check(load_library().bakegi_points_set_share_candidates(self.handle, _uptr(c),
                                                                 c.shape[0]),
               "bakegi_points_set_share_candidates")

    def set_display_probes(self, positions, normals, object_ids, indices, weights):
        """Points inside faces where the job also estimates the error of what a viewer shows:
        the value shown at probe k is sum_j weights[k, j] * result[indices[k, j]] (j < 4)."""
        p = _floats(positions, 3, "positions")
        n = _floats(normals, 3, "normals")
        ids = _uints(object_ids, "object_ids")
        idx = np.ascontiguousarray(indices, dtype=np.uint32).reshape(-1, 4)
        w = np.ascontiguousarray(weights, dtype=np.float32).reshape(-1, 4)
        count = p.shape[0]
        if not (n.shape[0] == ids.shape[0] == idx.shape[0] == w.shape[0] == count):
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", "display probe arrays differ in length")
        _check(load_library().bakegi_points_set_display_probes(
            self.handle, _fptr(p), _fptr(n), _uptr(ids), _uptr(idx), _fptr(w), count),
            "bakegi_points_set_display_probes")


class LightmapInfo(Structure):
    _fields_ = [
        ("width", c_uint32),
        ("height", c_uint32),
        ("first_point", c_uint64),
        ("point_count", c_uint64),
        ("covered_texels", c_uint64),
        ("rejected_samples", c_uint64),
        ("skipped_triangles", c_uint64),
    ]


class Lightmaps(_Handle):
    """Lightmap texels as bake points, and the baked values as EXR files (bakegi_lightmaps):

        lightmaps = Lightmaps()
        index = lightmaps.add(scene, mesh_id, uvs, 512, 512)   # uvs: (triangles*3, 2)
        lightmaps.add_to(index, scene, other_mesh_id, other_uvs)  # a second object, same map
        lightmaps.reject_inside(scene)
        points = lightmaps.points()   # -> Job(scene, points, settings)
        lightmaps.write_exr(index, job.result(), "/path/lightmap.exr", padding=4)
    """

    _destroy_name = "bakegi_lightmaps_destroy"

    def __init__(self, handle=None):
        lib = load_library()
        if handle is None:
            out = c_void_p()
            _check(lib.bakegi_lightmaps_create(byref(out)), "bakegi_lightmaps_create")
            handle = out.value
        super().__init__(handle)

    def set_memory_budget(self, megabytes):
        """What the texel samples may take (MB): refused before they are made beyond it."""
        _check(load_library().bakegi_lightmaps_set_memory_budget(self.handle, int(megabytes)),
               "bakegi_lightmaps_set_memory_budget")

    def cancel(self):
        """From any thread: a running or later add/add_to/reject_inside stops with
        BAKEGI_ERROR_CANCELLED (bakegi_lightmaps_cancel)."""
        _check(load_library().bakegi_lightmaps_cancel(self.handle), "bakegi_lightmaps_cancel")

    def add(self, scene, mesh, uvs, width, height):
        """A width x height lightmap for core mesh `mesh` of `scene`; uvs: (3*T, 2) lightmap
        UVs of its triangles' corners. Returns the lightmap's index."""
        uv = _floats(uvs, 2, "lightmap uvs")
        out = c_uint32()
        _check(load_library().bakegi_lightmaps_add(self.handle, scene.handle, int(mesh),
                                                   _fptr(uv), int(width), int(height),
                                                   byref(out)), "bakegi_lightmaps_add")
        return out.value

    def add_to(self, lightmap, scene, mesh, uvs):
        """Rasterizes another mesh into lightmap `lightmap` (an atlas: uvs already placed in
        the mesh's own region)."""
        uv = _floats(uvs, 2, "lightmap uvs")
        _check(load_library().bakegi_lightmaps_add_to(self.handle, int(lightmap), scene.handle,
                                                      int(mesh), _fptr(uv)),
               "bakegi_lightmaps_add_to")

    def reject_inside(self, scene, rays=0, backface_fraction=0.0, max_distance=0.0):
        """Drops samples inside or under other geometry; returns how many."""
        out = c_uint64()
        _check(load_library().bakegi_lightmaps_reject_inside(
            self.handle, scene.handle, int(rays), float(backface_fraction),
            float(max_distance), byref(out)), "bakegi_lightmaps_reject_inside")
        return int(out.value)

    def __len__(self):
        return int(load_library().bakegi_lightmaps_count(self.handle))

    def info(self, lightmap):
        info = LightmapInfo()
        _check(load_library().bakegi_lightmaps_get_info(self.handle, int(lightmap),
                                                        byref(info)), "bakegi_lightmaps_get_info")
        return {name: int(getattr(info, name)) for name, _ in LightmapInfo._fields_}

    def points(self):
        """All lightmaps' samples as Points (a new handle)."""
        out = c_void_p()
        _check(load_library().bakegi_lightmaps_get_points(self.handle, byref(out)),
               "bakegi_lightmaps_get_points")
        return Points(handle=out.value)

    def write_exr(self, lightmap, rgb, path, padding=4, full_float=False, compression="ZIP"):
        """Writes lightmap `lightmap` as an OpenEXR file (atomically). rgb: the whole bake
        result, (points, 3)."""
        if compression not in EXR_COMPRESSION:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"compression must be one of {tuple(EXR_COMPRESSION)}, not "
                              f"{compression!r}")
        values = _floats(rgb, 3, "rgb")
        _check(load_library().bakegi_lightmaps_write_exr(
            self.handle, int(lightmap), _fptr(values), values.shape[0], os.fsencode(path),
            int(padding), 1 if full_float else 0, EXR_COMPRESSION[compression]),
            "bakegi_lightmaps_write_exr")

    def resolve(self, lightmap, rgb, padding=4, channels=4):
        """Lightmap `lightmap` as the image write_exr writes (before half rounding), in
        memory: (height, width, channels) float32, row 0 at the bottom as Blender's
        Image.pixels holds it (channels 4: alpha 1). rgb: the whole bake result."""
        values = _floats(rgb, 3, "rgb")
        info = self.info(lightmap)
        pixels = np.empty((info["height"], info["width"], int(channels)), dtype=np.float32)
        _check(load_library().bakegi_lightmaps_resolve(
            self.handle, int(lightmap), _fptr(values), values.shape[0], int(padding),
            int(channels), _fptr(pixels), pixels.size), "bakegi_lightmaps_resolve")
        return pixels

    def write(self, path):
        """Writes the .bgl layout file (for the CLI: bakegi bake ... --lightmaps)."""
        _check(load_library().bakegi_lightmaps_write_file(self.handle, os.fsencode(path)),
               "bakegi_lightmaps_write_file")

    @classmethod
    def read(cls, path):
        out = c_void_p()
        _check(load_library().bakegi_lightmaps_read_file(os.fsencode(path), byref(out)),
               "bakegi_lightmaps_read_file")
        return cls(out.value)


class GridInfo(Structure):
    _fields_ = [
        ("bounds_min", c_float * 3),
        ("bounds_max", c_float * 3),
        ("resolution", c_uint32 * 3),
        ("vertex_count", c_uint64),
        ("invalid_vertices", c_uint64),
    ]


class Grid(_Handle):
    """An Irradiance Vector Grid (bakegi_grid; docs/ivg.md):

        layout = Grid.create((x0, y0, z0), (x1, y1, z1), cell_size=0.1)
        job = GridJob(scene, layout, settings, rays=64); job.wait(); grid = job.grid()
        grid.write("/path/scene.bgivg", quantized=True)
        rgb = Grid.read("/path/scene.bgivg").evaluate(positions, normals)
    """

    _destroy_name = "bakegi_grid_destroy"

    @classmethod
    def create(cls, bounds_min, bounds_max, cell_size=0.0, max_vertices=0):
        """A layout (all zero) over the box with cells of about cell_size metres (0: 32 on
        the longest axis), at most max_vertices vertices (0: 64^3)."""
        lo, hi = _triple(bounds_min, "bounds_min"), _triple(bounds_max, "bounds_max")
        out = c_void_p()
        _check(load_library().bakegi_grid_create(lo, hi, float(cell_size), int(max_vertices),
                                                 byref(out)), "bakegi_grid_create")
        return cls(out.value)

    @classmethod
    def read(cls, path):
        out = c_void_p()
        _check(load_library().bakegi_grid_read_file(os.fsencode(path), byref(out)),
               "reading the grid")
        return cls(out.value)

    def info(self):
        info = GridInfo()
        _check(load_library().bakegi_grid_get_info(self.handle, byref(info)),
               "bakegi_grid_get_info")
        return {"bounds_min": list(info.bounds_min), "bounds_max": list(info.bounds_max),
                "resolution": list(info.resolution), "vertex_count": int(info.vertex_count),
                "invalid_vertices": int(info.invalid_vertices)}

    def with_emitted_light(self):
        """(Grid, had_emitted): the grid the web page streams, the bounced light plus the
        world's and emitters' direct light this grid carries (a copy of it if none)."""
        out = c_void_p()
        has = ctypes.c_int(0)
        _check(load_library().bakegi_grid_with_emitted_light(self.handle, byref(out), byref(has)),
               "bakegi_grid_with_emitted_light")
        return Grid(out.value), bool(has.value)

    def info_json(self):
        """The JSON stored with the grid (what made it), as a dict."""
        text = _read_text(load_library().bakegi_grid_get_info_json, (self.handle,),
                          "bakegi_grid_get_info_json")
        try:
            value = json.loads(text)
        except ValueError:
            return {}
        return value if isinstance(value, dict) else {}

    def evaluate(self, positions, normals, interpolation="TRILINEAR", directional="SQUARED"):
        """(n, 3) float32 indirect light at the points (the bake's output convention).
        directional: 'SQUARED' (the paper's n^2 weights) or 'ABSOLUTE' (|n|; docs/ivg.md)."""
        self._check_lookup(interpolation, directional)
        p = _floats(positions, 3, "positions")
        n = _floats(normals, 3, "normals")
        if len(p) != len(n):
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"{len(p)} positions but {len(n)} normals")
        out = np.empty((len(p), 3), np.float32)
        _check(load_library().bakegi_grid_evaluate(self.handle, _fptr(p), _fptr(n), len(p),
                                                   GRID_INTERPOLATION[interpolation],
                                                   GRID_DIRECTIONAL[directional], _fptr(out)),
               "bakegi_grid_evaluate")
        return out

    def evaluate_in_scene(self, scene, positions, normals, interpolation="TRILINEAR",
                          directional="SQUARED", visibility=True, darken_buried=True,
                          page_visibility=False):
        """evaluate() where `scene` is known: each point reads only the grid vertices it sees
        (visibility) and points inside or under geometry read 0 (darken_buried). Returns
        ((n, 3) float32, (n,) uint8 codes: 0 read, 1 unsure (saw no vertex), 2 buried).
        page_visibility: read as the web page does instead (the visibility volume the web
        export writes, no rays from the points; trilinear, the other two flags off)."""
        self._check_lookup(interpolation, directional)
        p = _floats(positions, 3, "positions")
        n = _floats(normals, 3, "normals")
        if len(p) != len(n):
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"{len(p)} positions but {len(n)} normals")
        out = np.empty((len(p), 3), np.float32)
        codes = np.zeros(len(p), np.uint8)
        flags = 4 if page_visibility else (1 if visibility else 0) | (2 if darken_buried else 0)
        _check(load_library().bakegi_grid_evaluate_in_scene(
            self.handle, scene.handle, _fptr(p), _fptr(n), len(p),
            GRID_INTERPOLATION[interpolation], GRID_DIRECTIONAL[directional], flags, _fptr(out),
            codes.ctypes.data_as(POINTER(ctypes.c_uint8))), "bakegi_grid_evaluate_in_scene")
        return out, codes

    @staticmethod
    def _check_lookup(interpolation, directional):
        if interpolation not in GRID_INTERPOLATION:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"interpolation must be one of {tuple(GRID_INTERPOLATION)}, not "
                              f"{interpolation!r}")
        if directional not in GRID_DIRECTIONAL:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"directional must be one of {tuple(GRID_DIRECTIONAL)}, not "
                              f"{directional!r}")

    def write(self, path, quantized=True, info=None, encoding=None):
        """Writes the .bgivg file atomically; info: a dict stored with it. encoding (overrides
        quantized): 'FLOAT' (exact matrices), 'QUANTIZED' (the paper's 7 bytes a hemisphere)
        or 'FACTORED' (its direction and colour in floats)."""
        encoding = encoding or ("QUANTIZED" if quantized else "FLOAT")
        if encoding not in GRID_ENCODING:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"encoding must be one of {tuple(GRID_ENCODING)}, not {encoding!r}")
        text = json.dumps(info).encode("utf-8") if info is not None else None
        _check(load_library().bakegi_grid_write_file(self.handle, os.fsencode(path),
                                                     GRID_ENCODING[encoding], text),
               "writing the grid")


class Settings(_Handle):
    """Key/value bake settings; Settings(method='pathtrace', samples=64, seed=0)."""

    _destroy_name = "bakegi_settings_destroy"

    def __init__(self, **values):
        lib = load_library()
        out = c_void_p()
        _check(lib.bakegi_settings_create(byref(out)), "bakegi_settings_create")
        super().__init__(out.value)
        for key, value in values.items():
            self.set(key, value)

    def set(self, key, value):
        lib = load_library()
        k = key.encode("utf-8")
        if isinstance(value, bool):
            status = lib.bakegi_settings_set_int(self.handle, k, int(value))
        elif isinstance(value, int):
            status = lib.bakegi_settings_set_int(self.handle, k, value)
        elif isinstance(value, float):
            status = lib.bakegi_settings_set_float(self.handle, k, value)
        elif isinstance(value, str):
            status = lib.bakegi_settings_set_string(self.handle, k, value.encode("utf-8"))
        else:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"setting {key!r}: unsupported value type {type(value).__name__}")
        _check(status, f"setting {key!r}")

    def check(self):
        """Raises BakeGIError naming the first setting a bake would refuse (bakegi_settings_check:
        the method's schema and its own reading), before any scene is exported."""
        _check(load_library().bakegi_settings_check(self.handle), "checking the settings")


class Preview(_Handle):
    """The splatting preview (bakegi_preview): the scene's geometry and BVH built once, lights
    replaced with set_lights, frames rendered from a camera in milliseconds."""

    _destroy_name = "bakegi_preview_destroy"

    def __init__(self, scene):
        lib = load_library()
        out = c_void_p()
        _check(lib.bakegi_preview_create(scene.handle, byref(out)), "bakegi_preview_create")
        super().__init__(out.value)
        self.report = {}

    def set_lights(self, scene):
        """Takes the lights and the world of the core scene `scene` (its meshes are ignored)."""
        _check(load_library().bakegi_preview_set_lights(self.handle, scene.handle),
               "bakegi_preview_set_lights")

    def render(self, camera, width, height, settings=None, layers=False):
        """One frame, top row first: a float32 (height, width, 4) numpy array of radiance
        (alpha 1 where a surface is seen), and with layers=True also the (height, width, 3)
        direct and indirect E/pi. camera: 12 numbers (position, quaternion xyzw looking down
        -Z, vertical field of view, shift x, shift y, orthographic scale or 0, 0). The frame's
        report (timings, VPLs, subsplats per level) is in self.report."""
        numbers = [float(v) for v in camera]
        if len(numbers) != 12:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"camera needs 12 numbers, got {len(numbers)}")
        width, height = int(width), int(height)
        if width < 1 or height < 1:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", "the image needs pixels")
        rgba = np.empty((height, width, 4), dtype=np.float32)
        direct = np.empty((height, width, 3), dtype=np.float32) if layers else None
        indirect = np.empty((height, width, 3), dtype=np.float32) if layers else None
        _check(load_library().bakegi_preview_render(
            self.handle, (c_float * 12)(*numbers), width, height,
            settings.handle if settings is not None else None, _fptr(rgba),
            _fptr(direct) if layers else None, _fptr(indirect) if layers else None, None),
            "bakegi_preview_render")
        self.report = json.loads(_read_text(load_library().bakegi_preview_get_report,
                                            [self.handle], "the preview's report"))
        return (rgba, direct, indirect) if layers else rgba


class Job(_Handle):
    """A bake running on the core's threads (bakegi_job)."""

    _destroy_name = "bakegi_job_destroy"

    def __init__(self, scene, points, settings, _handle=None, _point_count=None):
        if _handle is not None:  # made by relight()
            super().__init__(_handle)
            self.point_count = _point_count
            return
        lib = load_library()
        out = c_void_p()
        _check(lib.bakegi_job_start(scene.handle, points.handle, settings.handle, byref(out)),
               "bakegi_job_start")
        super().__init__(out.value)
        self.point_count = len(points)

    @property
    def can_relight(self):
        """True once the job finished and its method kept what a relight reuses."""
        return bool(load_library().bakegi_job_can_relight(self.handle))

    def relight(self, scene, settings=None):
        """Starts a job that bakes `scene` (same geometry and materials, other lights) at
        this job's points, reusing its precomputation (bakegi_job_start_relight). `settings`
        may change only what the method allows (antiradiance: iterations, tolerance,
        scheme, direct_samples, seed)."""
        out = c_void_p()
        _check(load_library().bakegi_job_start_relight(
            self.handle, scene.handle, None, settings.handle if settings is not None else None,
            byref(out)), "bakegi_job_start_relight")
        return Job(None, None, None, _handle=out.value, _point_count=self.point_count)

    @property
    def progress(self):
        return float(load_library().bakegi_job_progress(self.handle))

    @property
    def stage(self):
        buffer = ctypes.create_string_buffer(256)
        load_library().bakegi_job_stage(self.handle, buffer, len(buffer))
        return _decode(buffer.value)

    @property
    def is_done(self):
        return bool(load_library().bakegi_job_is_done(self.handle))

    def cancel(self):
        if self._handle:
            load_library().bakegi_job_cancel(self._handle)

    def wait(self):
        """Blocks until the job ends (the GIL is released); raises BakeGIError if it failed
        or was cancelled."""
        _check(load_library().bakegi_job_wait(self.handle), "bake")

    def result(self):
        """(n, 3) float32 RGB per bake point, after success."""
        out = np.empty((self.point_count, 3), np.float32)
        if self.point_count == 0:  # a grid job: its result is grid()
            return out
        _check(load_library().bakegi_job_get_result(self.handle, _fptr(out), self.point_count),
               "bakegi_job_get_result")
        return out

    def report_json(self):
        return _read_text(load_library().bakegi_job_get_report, (self.handle,),
                          "bakegi_job_get_report")

    def grid(self):
        """A grid job's grid (a new Grid), after success."""
        out = c_void_p()
        _check(load_library().bakegi_job_get_grid(self.handle, byref(out)), "bakegi_job_get_grid")
        return Grid(out.value)

    def report(self):
        """The core's report as a dict (empty if it is not valid JSON)."""
        try:
            value = json.loads(self.report_json())
        except ValueError:
            return {}
        return value if isinstance(value, dict) else {"core": value}


class GridJob(Job):
    """A grid bake (bakegi_job_start_grid): progress, cancel, wait and report as for a Job;
    grid() gives the result."""

    def __init__(self, scene, layout, settings, rays=0):
        out = c_void_p()
        _check(load_library().bakegi_job_start_grid(scene.handle, layout.handle, int(rays),
                                                    settings.handle, byref(out)),
               "bakegi_job_start_grid")
        super().__init__(None, None, None, _handle=out.value, _point_count=0)
