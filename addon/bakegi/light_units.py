# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender light settings -> the core's radiometric light description.

This is the ONE place where Blender's conventions (Watts, Strength, spot blend, area
shapes) become radiometric quantities. It never imports bpy: export.py reads the values
from Blender into a BlenderLight and passes them here, so the conversion can be tested
with plain Python and pinned against Cycles.

Conventions (Cycles 3.4, see CYCLES_FACTS.md and bakegi.h):
  point / spot, power P [W], color c : intensity c P / (4 pi) [W/sr]; the spot cone does
                                       not concentrate power; radius = shadow_soft_size
                                       (not scaled by the object).
  sun, strength S, color c           : irradiance c S [W/m^2] on a surface facing it.
  area, power P, color c, area A     : one-sided Lambertian emitter of radiance c P / (4 A)
                                       [W/(m^2 sr)], A measured AFTER the object's scale
                                       (Cycles builds the light's axes from the scaled
                                       object matrix, so scaling keeps P and lowers the
                                       radiance).
  emission shader, strength S        : radiance c S, two-sided on meshes in Cycles 3.4.
  world background, strength S       : radiance c S.
"""

import math
from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple

Vec3 = Tuple[float, float, float]

LIGHT_TYPES = ("POINT", "SPOT", "SUN", "AREA")
AREA_SHAPES = ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE")


@dataclass
class BlenderLight:
    """The settings of one Blender light instance, as plain values."""

    name: str
    type: str  # 'POINT' | 'SPOT' | 'SUN' | 'AREA'
    color: Vec3
    energy: float  # W for point/spot/area; W/m^2 (Strength) for sun
    # World matrix as 4 rows of 4 (mathutils.Matrix converts with [list(r) for r in m]).
    matrix_world: Sequence[Sequence[float]]
    shadow_soft_size: float = 0.0
    spot_size: float = math.radians(45.0)
    spot_blend: float = 0.15
    angle: float = 0.0  # sun angular diameter
    shape: str = "SQUARE"
    size: float = 1.0
    size_y: float = 1.0
    spread: float = math.pi  # area light spread (Cycles 3.0+); pi = Lambertian
    use_nodes: bool = False
    node_tree_is_default: bool = True  # an Emission node of strength 1, white, nothing else


@dataclass
class CoreLight:
    """Fields of bakegi_light_desc (bakegi.h), with type and shape as names."""

    type: str
    position: Vec3 = (0.0, 0.0, 0.0)
    direction: Vec3 = (0.0, 0.0, -1.0)
    axis_u: Vec3 = (1.0, 0.0, 0.0)
    color: Vec3 = (0.0, 0.0, 0.0)
    radius: float = 0.0
    spot_size: float = 0.0
    spot_blend: float = 0.0
    angle: float = 0.0
    shape: str = "SQUARE"
    size_x: float = 0.0
    size_y: float = 0.0


@dataclass
class Conversion:
    light: Optional[CoreLight]  # None: the light contributes nothing and is left out
    warnings: List[str] = field(default_factory=list)


def _column(matrix: Sequence[Sequence[float]], j: int) -> Vec3:
    return (float(matrix[0][j]), float(matrix[1][j]), float(matrix[2][j]))


def _length(v: Vec3) -> float:
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def _normalized(v: Vec3) -> Vec3:
    n = _length(v)
    if n == 0.0 or not math.isfinite(n):
        raise ValueError("zero or non-finite axis")
    return (v[0] / n + 0.0, v[1] / n + 0.0, v[2] / n + 0.0)  # + 0.0: no negative zeros


def _scaled(c: Sequence[float], s: float) -> Vec3:
    return (float(c[0]) * s, float(c[1]) * s, float(c[2]) * s)


def area_of_shape(shape: str, size_x: float, size_y: float) -> float:
    """Area in m^2 of an area light's shape with its (already scaled) sizes."""
    if shape == "SQUARE":
        return size_x * size_x
    if shape == "RECTANGLE":
        return size_x * size_y
    if shape == "DISK":
        return math.pi * size_x * size_x / 4.0
    if shape == "ELLIPSE":
        return math.pi * size_x * size_y / 4.0
    raise ValueError(f"unknown area light shape {shape!r}")


def point_intensity(color: Sequence[float], power: float) -> Vec3:
    """Radiant intensity [W/sr] of a point or spot light of `power` W."""
    return _scaled(color, power / (4.0 * math.pi))


def area_radiance(color: Sequence[float], power: float, area: float) -> Vec3:
    """Radiance [W/(m^2 sr)] of a one-sided area light of `power` W and `area` m^2."""
    return _scaled(color, power / (4.0 * area))


def sun_irradiance(color: Sequence[float], strength: float) -> Vec3:
    return _scaled(color, strength)


def emission_radiance(color: Sequence[float], strength: float) -> Vec3:
    """Radiance of an Emission shader (or Principled emission) of `strength`."""
    return _scaled(color, strength)


def world_radiance(color: Sequence[float], strength: float) -> Vec3:
    return _scaled(color, strength)


def convert_light(light: BlenderLight) -> Conversion:
    """Converts one Blender light; never raises for odd but legal settings."""
    warnings: List[str] = []
    name = light.name
    if light.type not in LIGHT_TYPES:
        return Conversion(None, [f"light '{name}': type {light.type} is not supported; left out"])
    values = list(light.color) + [light.energy]
    if not all(math.isfinite(float(v)) for v in values):
        return Conversion(None, [f"light '{name}': color or power is not finite; left out"])
    if light.energy < 0.0:
        return Conversion(None, [f"light '{name}': negative power is not supported; left out"])
    if light.energy == 0.0 or max(light.color) <= 0.0:
        return Conversion(None, [])  # emits nothing; silently left out
    if light.use_nodes and not light.node_tree_is_default:
        warnings.append(
            f"light '{name}': its shader nodes are ignored (only color and power are used)")

    m = light.matrix_world
    position = (float(m[0][3]), float(m[1][3]), float(m[2][3]))
    try:
        down = _normalized(_scaled(_column(m, 2), -1.0))  # the light's -Z axis
    except ValueError:
        return Conversion(None, [f"light '{name}': its object has zero scale; left out"])

    if light.type in ("POINT", "SPOT"):
        core = CoreLight(type=light.type, position=position, direction=down,
                         color=point_intensity(light.color, light.energy),
                         radius=max(0.0, float(light.shadow_soft_size)))
        if light.type == "SPOT":
            core.spot_size = min(max(float(light.spot_size), 1e-4), math.pi)
            core.spot_blend = min(max(float(light.spot_blend), 0.0), 1.0)
            sx, sy = _length(_column(m, 0)), _length(_column(m, 1))
            if abs(sx - sy) > 1e-4 * max(sx, sy):
                warnings.append(
                    f"spot light '{name}': non-uniform object scale (an elliptic cone) is "
                    "approximated by a round cone")
        return Conversion(core, warnings)

    if light.type == "SUN":
        core = CoreLight(type="SUN", direction=down,
                         color=sun_irradiance(light.color, light.energy),
                         angle=min(max(float(light.angle), 0.0), math.pi * 0.999))
        return Conversion(core, warnings)

    # AREA: sizes measured along the object's scaled X and Y axes.
    if light.shape not in AREA_SHAPES:
        return Conversion(None, [f"area light '{name}': unknown shape {light.shape}; left out"])
    axis_x, axis_y = _column(m, 0), _column(m, 1)
    scale_x, scale_y = _length(axis_x), _length(axis_y)
    size_x = float(light.size) * scale_x
    size_y = float(light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else light.size)
    size_y *= scale_y
    shape = light.shape
    if shape == "SQUARE" and abs(size_x - size_y) > 1e-6 * max(size_x, size_y):
        shape = "RECTANGLE"  # a square scaled non-uniformly is a rectangle
    elif shape == "DISK" and abs(size_x - size_y) > 1e-6 * max(size_x, size_y):
        shape = "ELLIPSE"
    area = area_of_shape(shape, size_x, size_y)
    if not area > 0.0:
        return Conversion(None, [f"area light '{name}': zero size; left out"])
    if light.spread < math.pi - 1e-4:
        warnings.append(
            f"area light '{name}': spread {math.degrees(light.spread):.0f} deg is approximated "
            "as 180 deg (a Lambertian emitter)")
    core = CoreLight(type="AREA", position=position, direction=down,
                     axis_u=_normalized(axis_x),
                     color=area_radiance(light.color, light.energy, area),
                     shape=shape, size_x=size_x, size_y=size_y)
    return Conversion(core, warnings)
