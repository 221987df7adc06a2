# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender light settings -> the core's radiometric light description.

This is the ONE place where Blender's conventions (Watts, Strength, spot blend, area
shapes) become radiometric quantities. It never imports bpy: export/scene.py reads the values
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
  Cast Shadow off                    : the core's BAKEGI_LIGHT_NO_SHADOW (no shadow rays).
  area spread s < 180 deg            : the core's spot_size = s (Cycles' soft-box falloff,
                                       lights/area_light.h; the same power).

What Cycles 4.0 and later do differently (measured against 4.2, 4.5 and 5.0's own Cycles,
blender_tests/test_light_units.py; `cycles_version` of a BlenderLight picks the rules):
  area                               : radiance c P / (pi A): 4/pi = 1.273x the 3.4 value;
                                       with normalize off (4.5+) c P / pi, whatever the size.
  spot                               : no cosine falloff inside the cone (the core's
                                       BAKEGI_LIGHT_SPOT_WITHOUT_COSINE).
  point / spot with soft falloff off : a sphere light (hard falloff); the core models the
                                       soft falloff, so the light is converted with a warning.
  normalize off (4.5+)               : point / spot power x 4 pi r^2 (x 4 for r = 0), sun
                                       irradiance x pi sin^2(angle / 2).
  exposure E (4.5+)                  : power / strength x 2^E, every light type.
  temperature T (4.5+, when used)    : color x the blackbody colour of T, of luminance 1.
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
    # What the light's node tree multiplies its colour and power by: an Emission node's
    # Color x Strength (its colour a constant, an RGB node or a Blackbody node of a constant
    # temperature); None where the tree is more than that (ignored, with a warning).
    node_tint: Optional[Vec3] = (1.0, 1.0, 1.0)
    # Added in later versions (compat.light_settings: the values that act as if absent).
    exposure: float = 0.0  # 4.5+: power x 2^exposure
    use_temperature: bool = False  # 4.5+: color x blackbody(temperature)
    temperature: float = 6500.0  # K
    normalize: bool = True  # 4.5+: area power spread over the area (False: per unit area)
    use_soft_falloff: bool = True  # 4.0+: point/spot radius; False = a true sphere
    cycles_version: Tuple[int, int] = (3, 4)  # whose conventions: compat.cycles_conventions()
    is_portal: bool = False  # an area light with Cycles' Portal on: guides the sky, emits nothing
    cast_shadow: bool = True  # Cast Shadow (3.x: light.cycles.cast_shadow; 4.0+: use_shadow)


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
    flags: int = 0  # bakegi_light_flags, e.g. SPOT_WITHOUT_COSINE


# The narrowest area-light spread baked: below it the soft box is a beam that light samples
# over the area would find too rarely.
MIN_SPREAD = math.radians(1.0)

# bakegi_light_flags (bakegi.h)
SPOT_WITHOUT_COSINE = 1
NO_SHADOW = 2


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


def area_radiance(color: Sequence[float], power: float, area: float,
                  cycles_version: Tuple[int, int] = (3, 4)) -> Vec3:
    """Radiance [W/(m^2 sr)] of a one-sided area light of `power` W and `area` m^2 (pass
    area 1 for a light that is not normalized)."""
    divisor = 4.0 if tuple(cycles_version) < (4, 0) else math.pi
    return _scaled(color, power / (divisor * area))


# CIE 1931 colour matching functions as sums of piecewise Gaussians (Wyman, Sloan and Shirley,
# "Simple Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2013, the
# multi-lobe fit): (weight, mean nm, sigma below the mean, sigma above it).
_CIE_X = ((1.056, 599.8, 37.9, 31.0), (0.362, 442.0, 16.0, 26.7), (-0.065, 501.1, 20.4, 26.2))
_CIE_Y = ((0.821, 568.8, 46.9, 40.5), (0.286, 530.9, 16.3, 31.1))
_CIE_Z = ((1.217, 437.0, 11.8, 36.0), (0.681, 459.0, 26.0, 13.8))
# XYZ -> linear Rec.709 (Blender's scene-linear colour space), D65.
_XYZ_TO_REC709 = ((3.2404542, -1.5371385, -0.4985314),
                  (-0.9692660, 1.8760108, 0.0415560),
                  (0.0556434, -0.2040259, 1.0572252))


def _cie(lobes, wavelength):
    total = 0.0
    for weight, mean, below, above in lobes:
        t = (wavelength - mean) / (below if wavelength < mean else above)
        total += weight * math.exp(-0.5 * t * t)
    return total


def blackbody_color(temperature: float) -> Vec3:
    """Linear Rec.709 colour of a black body at `temperature` K, scaled to luminance 1 and
    clamped at 0, as Blender's light temperature uses it (Blender fits the same curve;
    clamped to 800-12000 K as Blender does)."""
    t = min(max(float(temperature), 800.0), 12000.0)
    x = y = z = 0.0
    c2 = 1.4387769e-2  # h c / k, m K
    for nm in range(380, 781, 5):
        wavelength = nm * 1e-9
        planck = 1.0 / (wavelength ** 5 * (math.exp(c2 / (wavelength * t)) - 1.0))
        x += planck * _cie(_CIE_X, nm)
        y += planck * _cie(_CIE_Y, nm)
        z += planck * _cie(_CIE_Z, nm)
    rgb = [max(0.0, r[0] * x + r[1] * y + r[2] * z) for r in _XYZ_TO_REC709]
    luminance = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
    return (rgb[0] / luminance, rgb[1] / luminance, rgb[2] / luminance)


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
    if light.use_nodes and light.node_tint is None:
        warnings.append(
            f"light '{name}': its shader nodes are ignored (only color and power are used; "
            "an Emission node's constant, RGB or Blackbody colour and its strength are read)")
    exposure = float(light.exposure)
    if not math.isfinite(exposure):
        return Conversion(None, [f"light '{name}': exposure is not finite; left out"])
    energy = light.energy * 2.0 ** min(max(exposure, -64.0), 64.0)
    color = tuple(float(c) for c in light.color[:3])
    if light.use_nodes and light.node_tint is not None:
        color = tuple(c * float(t) for c, t in zip(color, light.node_tint))
    if light.use_temperature:
        tint = blackbody_color(light.temperature)
        color = (color[0] * tint[0], color[1] * tint[1], color[2] * tint[2])

    m = light.matrix_world
    try:
        down = _normalized(_scaled(_column(m, 2), -1.0))  # the light's -Z axis
    except ValueError:
        return Conversion(None, [f"light '{name}': its object has zero scale; left out"])
    convert = {"POINT": _point_or_spot, "SPOT": _point_or_spot, "SUN": _sun,
               "AREA": _area}[light.type]
    conversion = convert(light, color, energy, down, warnings)
    if conversion.light is not None and not light.cast_shadow:
        conversion.light.flags |= NO_SHADOW  # its light samples pass through everything
    return conversion


def convert_portal(light: BlenderLight) -> Conversion:
    """A portal's shape as a CoreLight (its colour 0: a portal emits nothing), or None with a
    warning where its shape cannot be one. Power, colour and spread do not matter."""
    m = light.matrix_world
    try:
        down = _normalized(_scaled(_column(m, 2), -1.0))
    except ValueError:
        return Conversion(None, [f"portal '{light.name}': its object has zero scale; left out"])
    conversion = _area(light, (0.0, 0.0, 0.0), 0.0, down, [])
    if conversion.light is None:
        return Conversion(None, [w.replace("area light", "portal", 1)
                                 for w in conversion.warnings])
    return Conversion(conversion.light, [])


def _position(light: BlenderLight) -> Vec3:
    m = light.matrix_world
    return (float(m[0][3]), float(m[1][3]), float(m[2][3]))


def _cycles4(light: BlenderLight) -> bool:
    return tuple(light.cycles_version) >= (4, 0)


def _point_or_spot(light, color, energy, down, warnings) -> Conversion:
    name, m = light.name, light.matrix_world
    cycles4 = _cycles4(light)
    core = CoreLight(type=light.type, position=_position(light), direction=down,
                     color=point_intensity(color, energy),
                     radius=max(0.0, float(light.shadow_soft_size)))
    if cycles4 and not light.use_soft_falloff and core.radius > 0.0:
        warnings.append(
            f"light '{name}': soft falloff is off (a sphere light); bakegi keeps the soft "
            "falloff, which is darker within a few radii of the light")
    if cycles4 and not light.normalize:
        # Measured with Cycles 4.5: the power is then not spread over the sphere's
        # surface, i.e. multiplied by 4 pi r^2 (by 4 for a point of radius 0).
        radius = core.radius
        core.color = _scaled(core.color, 4.0 * math.pi * radius * radius if radius > 0 else 4.0)
    if light.type == "SPOT":
        core.flags = SPOT_WITHOUT_COSINE if cycles4 else 0
        core.spot_size = min(max(float(light.spot_size), 1e-4), math.pi)
        core.spot_blend = min(max(float(light.spot_blend), 0.0), 1.0)
        sx, sy = _length(_column(m, 0)), _length(_column(m, 1))
        if abs(sx - sy) > 1e-4 * max(sx, sy):
            warnings.append(
                f"spot light '{name}': non-uniform object scale (an elliptic cone) is "
                "approximated by a round cone")
    return Conversion(core, warnings)


def _sun(light, color, energy, down, warnings) -> Conversion:
    core = CoreLight(type="SUN", direction=down,
                     color=sun_irradiance(color, energy),
                     angle=min(max(float(light.angle), 0.0), math.pi * 0.999))
    if _cycles4(light) and not light.normalize:
        # Measured with Cycles 4.5: the strength is then a radiance over the sun's disc,
        # i.e. the irradiance is multiplied by pi sin^2(angle / 2) (0 for angle 0).
        core.color = _scaled(core.color, math.pi * math.sin(0.5 * core.angle) ** 2)
    return Conversion(core, warnings)


def _area(light, color, energy, down, warnings) -> Conversion:
    """Sizes measured along the object's scaled X and Y axes."""
    name, m = light.name, light.matrix_world
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
    spread = 0.0  # Lambertian
    if light.spread < math.pi - 1e-4:
        spread = max(float(light.spread), MIN_SPREAD)
        if light.spread < MIN_SPREAD:
            warnings.append(f"area light '{name}': spread {math.degrees(light.spread):.2f} deg "
                            f"is baked as {math.degrees(MIN_SPREAD):.0f} deg")
    core = CoreLight(type="AREA", position=_position(light), direction=down, spot_size=spread,
                     axis_u=_normalized(axis_x),
                     color=area_radiance(color, energy, area if light.normalize else 1.0,
                                         light.cycles_version),
                     shape=shape, size_x=size_x, size_y=size_y)
    return Conversion(core, warnings)
