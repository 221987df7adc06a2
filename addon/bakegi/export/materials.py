# SPDX-License-Identifier: GPL-3.0-or-later
# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender materials: what the core needs to know of them, and the Material Preview hook.

read_material(material) -> MaterialInfo: diffuse albedo (a constant times an optional
image texture sampled at a UV map), an optional glossy lobe (see "glossy lobes" below for the
mapping and its approximations) and emitted radiance (a constant times an optional image
texture), from the node tree:
  - Principled BSDF: diffuse base color x (1 - metallic) x (1 - transmission) (x (1 - F_avg)
    in Blender 4.x, whose Principled v2 layers the specular over the base);
    glossy metallic x base color + dielectric F_avg; emission color x emission strength;
  - Diffuse BSDF: its color, no glossy lobe (exported exactly as before glossy lobes);
  - Glossy BSDF (and Blender 3.x's Anisotropic BSDF): a glossy lobe of its color;
  - Emission shader: an emitter with black albedo, color x strength;
  - Mix / Add Shader: mixed best-effort, with a warning;
  - see-through surfaces (the core's bakegi_scene_set_material_passing): a Principled BSDF's
    Alpha (a constant, or an Image Texture's Alpha or Color output) and the old cut-out
    setup, a Mix Shader of a Transparent BSDF and a surface whose Fac is an image's alpha,
    become an opacity; transmission (Principled), Glass, Refraction and Transparent BSDFs a
    share of light that passes straight on (thin glass: no refraction, caustics or tint);
    the reflectances are then those of a surface a ray stopped at (divided by 1 - that share);
  - an Image Texture linked (directly or through reroutes) into a base color or an emission
    color (the Emission shader's Color, the Principled BSDF's Emission / Emission Color) is
    sampled, with the UV map of its vector input (default: the mesh's active render UV
    map), bilinearly with repeat (other interpolations and extensions are read so, with a
    warning); the core takes one UV map per material, so a material whose base color and
    emission textures use different UV maps samples both with the emission's (warning);
  - anything else: the node's unlinked (default) color, with a warning.

This module does not import bpy: it only reads the objects it is given, so the pure parts
(colour-space conversion, Fresnel averages) can be tested without Blender.
"""

import math
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from .. import compat, light_units
from ..write.material_hook import NODE_PREFIX
from .node_tree import active_output, color_value, input_socket, linked_from


# Cycles' default surface for faces without a material.
DEFAULT_ALBEDO = (0.8, 0.8, 0.8)

LINEAR_COLORSPACES = {"Linear", "Linear Rec.709", "Linear Rec.2020", "Linear ACES",
                      "Linear ACEScg", "ACEScg", "Non-Color", "Raw", "XYZ", "Linear CIE-XYZ E",
                      "Linear CIE-XYZ D65", "Linear FilmLight E-Gamut", "Linear DCI-P3 D65"}
SRGB_COLORSPACES = {"sRGB", "sRGB OETF", "Filmic sRGB", "AgX Base sRGB"}


@dataclass
class TextureRef:
    """An image to sample and the UV map to sample it with ("" = active render UV map)."""

    image: object
    uv_map: str = ""
    # What an opacity texture reads of the image: "alpha" (its alpha channel, as an Image
    # Texture's Alpha output) or "luminance" (its colour, as a Color output read as a float).
    channel: str = "rgb"
    # Math nodes between the image and the Alpha socket (glTF's alpha cut-off in Blender
    # 4.x's importer: 1 - (alpha < 0.5)): (operation, constant, which input the value feeds,
    # clamp), in the order they apply (ALPHA_MATH).
    math: tuple = ()


@dataclass
class MaterialInfo:
    albedo: Tuple[float, float, float] = DEFAULT_ALBEDO
    texture: Optional[TextureRef] = None  # multiplies albedo
    emission: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    emission_texture: Optional[TextureRef] = None  # multiplies emission
    warnings: List[str] = field(default_factory=list)
    # For the hook: (node name, output index) of the socket that gives the base color
    # (None: the constant albedo). Names, not references: the hook is made after the bake,
    # and references into node trees do not survive an undo in between.
    color_source: Optional[Tuple[str, int]] = None
    albedo_factor: float = 1.0  # what multiplies color_source's color to give the albedo
    # The modified Phong lobe of the core (bakegi.h): reflectance and exponent; 0 = none.
    glossy: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    glossy_exponent: float = 0.0
    # A Volume and no Surface (fog, a light shaft's box): Cycles lets light through its
    # boundary; the bake has no participating media, so objects made of it are left out.
    volume_only: bool = False
    # See-through surfaces (bakegi_scene_set_material_passing): the share of the surface that
    # is there (times opacity_texture), and of that the share passing straight through.
    opacity: float = 1.0
    opacity_texture: Optional[TextureRef] = None
    transmission: float = 0.0
    # Glass: its index of refraction, so that the core passes less at grazing angles
    # (Fresnel), `transmission` being the average; 0 = the same share at every angle.
    transmission_ior: float = 0.0

    def lets_light_pass(self):
        return self.opacity < 1.0 or self.opacity_texture is not None or self.transmission > 0.0


# ---- colour -----------------------------------------------------------------------------


def srgb_to_linear(values):
    """The sRGB transfer function, inverted (IEC 61966-2-1), elementwise on an array."""
    v = np.asarray(values, dtype=np.float32)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def image_linear_rgb(image, warnings):
    """(height, width, 3) float32 linear RGB of a Blender image, row 0 at the bottom.

    image.pixels holds float images in scene-linear already; byte images hold their
    encoded values (/255), which are decoded here according to the image's colour space.
    """
    width, height = int(image.size[0]), int(image.size[1])
    channels = int(image.channels)
    if width == 0 or height == 0 or channels == 0:
        warnings.append(f"image '{image.name}' has no pixels (missing file?); its texture "
                        "is ignored")
        return None
    flat = np.empty(width * height * channels, np.float32)
    image.pixels.foreach_get(flat)
    pixels = flat.reshape(height, width, channels)
    if channels >= 3:
        rgb = pixels[:, :, :3]
    else:  # grey (or grey + alpha)
        rgb = np.repeat(pixels[:, :, :1], 3, axis=2)
    rgb = np.ascontiguousarray(rgb, dtype=np.float32)
    if not image.is_float:
        space = image.colorspace_settings.name
        if space in LINEAR_COLORSPACES:
            pass
        elif space in SRGB_COLORSPACES:
            rgb = srgb_to_linear(rgb)
        else:
            warnings.append(f"image '{image.name}': colour space '{space}' is read as sRGB")
            rgb = srgb_to_linear(rgb)
    if not np.all(np.isfinite(rgb)):
        warnings.append(f"image '{image.name}' has non-finite pixels; they are read as 0")
        rgb = np.nan_to_num(rgb, nan=0.0, posinf=0.0, neginf=0.0)
    return rgb


def image_opacity(image, channel, warnings, math=()):
    """(height, width) float32 in [0, 1] of a Blender image, row 0 at the bottom: its alpha
    channel (1 where it has none), or the luminance of its linear colour; then `math`
    (TextureRef.math) applied."""
    if channel == "alpha":
        width, height = int(image.size[0]), int(image.size[1])
        channels = int(image.channels)
        if width == 0 or height == 0 or channels == 0:
            warnings.append(f"image '{image.name}' has no pixels (missing file?); its alpha is "
                            "read as opaque")
            return None
        if channels not in (2, 4):
            return np.ones((height, width), np.float32)
        flat = np.empty(width * height * channels, np.float32)
        image.pixels.foreach_get(flat)
        alpha = flat.reshape(height, width, channels)[:, :, channels - 1]
    else:
        rgb = image_linear_rgb(image, warnings)
        if rgb is None:
            return None
        alpha = rgb @ np.asarray(LUMINANCE, np.float32)
    alpha = np.clip(np.nan_to_num(alpha, nan=1.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    if math:  # Math nodes may leave [0, 1] (or divide by 0): cleaned the same way after
        alpha = np.clip(np.nan_to_num(apply_alpha_math(alpha, math), nan=1.0, posinf=1.0,
                                      neginf=0.0), 0.0, 1.0)
    return np.ascontiguousarray(alpha, dtype=np.float32)


def _float_input(node, names, fallback, info, what):
    socket = input_socket(node, *names)
    if socket is None:
        return fallback
    if socket.is_linked:
        info.warnings.append(f"{what}: a linked '{socket.name}' is read as its default value")
    return float(socket.default_value)


def _texture_uv_map(tex_node, info, what):
    vector = tex_node.inputs.get("Vector")
    source = linked_from(vector) if vector is not None else None
    if source is None:
        return ""
    node = source.node
    if node.type == "UVMAP":
        return node.uv_map
    if node.type == "TEX_COORD" and source.name == "UV":
        return ""
    info.warnings.append(f"{what}: texture coordinates from a '{node.name}' node are read as "
                         "the active UV map")
    return ""


def _texture_sampling(tex_node, info, what):
    """Warns where Cycles samples the image otherwise than the core (bilinear, repeat)."""
    if getattr(tex_node, "interpolation", "Linear") != "Linear":
        info.warnings.append(f"{what}: image texture '{tex_node.name}' uses "
                             f"'{tex_node.interpolation}' interpolation; it is read as Linear")
    if getattr(tex_node, "extension", "REPEAT") != "REPEAT":
        info.warnings.append(f"{what}: image texture '{tex_node.name}' uses extension "
                             f"'{tex_node.extension}'; it is read as Repeat")
    if getattr(tex_node, "projection", "FLAT") != "FLAT":
        info.warnings.append(f"{what}: image texture '{tex_node.name}' uses "
                             f"'{tex_node.projection}' projection; it is read as Flat")


def _read_color(socket, info, what):
    """(constant rgb, TextureRef or None, socket giving the colour or None)."""
    source = linked_from(socket)
    if source is None:
        return color_value(socket), None, None
    node = source.node
    if node.type == "TEX_IMAGE" and node.image is not None:
        _texture_sampling(node, info, what)
        return (1.0, 1.0, 1.0), TextureRef(node.image, _texture_uv_map(node, info, what)), source
    if node.type == "RGB":
        return color_value(source), None, source
    info.warnings.append(f"{what}: the '{node.name}' node feeding '{socket.name}' of "
                         f"'{socket.node.name}' is not evaluated; its default color is used")
    return color_value(socket), None, None


def _scaled(c, s):
    return (c[0] * s, c[1] * s, c[2] * s)


def sampled_uv_map(info):
    """The UV map the core samples a material's textures with ("" = the active render UV
    map), or None if it has no texture. One per material: the emission texture's wins, then
    the base color's, then the opacity's."""
    for texture in (info.emission_texture, info.texture, info.opacity_texture):
        if texture is not None:
            return texture.uv_map
    return None


# ---- glossy lobes ------------------------------------------------------------------------
#
# The core's glossy lobe is the normalized modified Phong BRDF (Lafortune & Willems 1994),
# f = rho_g (n + 2) / (2 pi) cos^n(angle to the mirror direction): a reflectance rho_g and
# an exponent n, no Fresnel, no anisotropy. Blender's microfacet lobes map onto it as:
#   - exponent from roughness r: Blender's alpha = r^2; n_h = 2 / alpha^2 - 2 is the Phong
#     exponent of the microfacet normals (half vectors) that matches a Beckmann
#     distribution of that alpha near its peak (Walter et al. 2007). The core's lobe is
#     around the mirror direction, which turns twice as fast as the half vector:
#     cos^n_h(a / 2) ~ exp(-n_h a^2 / 8) = cos^(n_h / 4)(a), so n = n_h / 4, clamped to
#     [0, MAX_GLOSSY_EXPONENT]; r = 1 gives n = 0, r = 0.5 gives 7.5, r = 0.2 about 312;
#   - reflectance: a conductor (metallic, Glossy BSDF) reflects its color; a dielectric
#     reflects the exact dielectric Fresnel term averaged over the hemisphere,
#     cosine-weighted (F_avg, fresnel_hemispherical_average), with F0 from
#     Specular (3.x: F0 = 0.08 x specular) or IOR and Specular IOR Level (4.x:
#     F0 = ((ior - 1) / (ior + 1))^2 x 2 x level). Specular tint and anisotropy are ignored.
# Approximations: the angular shape of Fresnel (stronger at grazing) is averaged away;
# multiple scattering on rough metal (Cycles' multiscatter GGX) is ignored; the diffuse
# base under a dielectric is attenuated by (1 - F_avg) in 4.x, as Principled v2 does, and
# kept whole in 3.x, which adds the specular on top (where the sum would exceed 1, which
# the core refuses, the glossy part is clamped to 1 - albedo).
# Above this luminance of glossy reflectance (metals, Glossy BSDFs; a dielectric coat is 0.09)
# the Phong approximation's shortfall shows in what the surface lights (measured on the
# Cornell box with a rough metal tall box: neighbours 6-20% darker than Cycles 4.5).
STRONG_GLOSSY_REFLECTANCE = 0.25
MAX_GLOSSY_EXPONENT = 10000.0  # ~0.8 degree lobe: far narrower than any bin or patch


def phong_exponent(roughness):
    r = min(max(float(roughness), 0.0), 1.0)
    alpha = r * r
    if alpha <= 0.0:
        return MAX_GLOSSY_EXPONENT
    return min(max((2.0 / (alpha * alpha) - 2.0) / 4.0, 0.0), MAX_GLOSSY_EXPONENT)


def fresnel_hemispherical_average(f0):
    """Cosine-weighted hemispherical average of the exact (unpolarized) dielectric Fresnel
    reflectance whose normal-incidence value is f0: 2 * integral of F(mu) mu over mu in [0, 1],
    by the midpoint rule on 512 points (error < 1e-5). 0 for f0 = 0 (no interface: Cycles'
    Principled v2 with Specular IOR Level 0 reflects nothing specular), 0.0918 for glass'
    f0 = 0.04, 1 for f0 = 1. (Schlick's form f0 + (1 - f0) / 21 was used before; it leaves a
    4.8% specular where there is none.)"""
    f0 = min(max(float(f0), 0.0), 1.0)
    if f0 <= 0.0 or f0 >= 1.0:
        return f0
    root = math.sqrt(f0)
    eta = (1.0 + root) / (1.0 - root)
    count = 512
    total = 0.0
    for i in range(count):
        c = (i + 0.5) / count
        g = math.sqrt(eta * eta - 1.0 + c * c)
        a = (g - c) / (g + c)
        b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
        total += 0.5 * a * a * (1.0 + b * b) * c
    return 2.0 * total / count


def _principled_f0(node, info, what):
    level = input_socket(node, "Specular IOR Level")
    if level is not None:  # Blender 4.x
        ior = _float_input(node, ("IOR",), 1.5, info, what)
        r = (ior - 1.0) / (ior + 1.0) if ior > 0.0 else 0.0
        return r * r * 2.0 * _float_input(node, ("Specular IOR Level",), 0.5, info, what)
    return 0.08 * _float_input(node, ("Specular",), 0.5, info, what)


def _glossy_lobe(reflectance, roughness):
    if max(reflectance) <= 0.0:
        return None
    return (tuple(min(max(float(c), 0.0), 1.0) for c in reflectance), phong_exponent(roughness))


@dataclass
class _Shader:
    """What _read_shader finds behind one shader socket."""

    albedo: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    texture: Optional[TextureRef] = None  # multiplies albedo
    emission: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    color_socket: object = None  # the socket giving the base colour (for the hook)
    albedo_factor: float = 1.0
    glossy: Optional[tuple] = None  # (reflectance rgb, exponent)
    emission_texture: Optional[TextureRef] = None  # multiplies emission
    # See-through (MaterialInfo): albedo and glossy above are shares of the light meeting the
    # present surface; `transmission` the share of it passing straight on.
    opacity: float = 1.0
    opacity_texture: Optional[TextureRef] = None
    transmission: float = 0.0
    transmission_ior: float = 0.0


def _read_emission(socket, strength, info, what):
    """(emitted radiance, TextureRef or None) of an emission colour socket x strength: an
    image texture linked into it (directly or through reroutes) multiplies a white colour."""
    color, texture, _ = _read_color(socket, info, what)
    return light_units.emission_radiance(color, strength), texture


LUMINANCE = (0.2126, 0.7152, 0.0722)
_THIN_GLASS_NOTE = ("is baked as thin glass: light passes straight through it (no refraction, "
                    "caustics or tint), right for window panes, approximate for solid glass")


def _luminance(c):
    return sum(w * float(x) for w, x in zip(LUMINANCE, c))


# The Math node operations an alpha may pass through on its way from an image, as Cycles
# computes them: f(value, constant, index of the input the value feeds).
ALPHA_MATH = {
    "ADD": lambda x, c, i: x + c,
    "SUBTRACT": lambda x, c, i: x - c if i == 0 else c - x,
    "MULTIPLY": lambda x, c, i: x * c,
    "DIVIDE": lambda x, c, i: (x / c if c != 0.0 else x * 0.0) if i == 0
    else np.divide(c, x, out=np.zeros_like(x), where=x != 0.0),
    "MINIMUM": lambda x, c, i: np.minimum(x, c),
    "MAXIMUM": lambda x, c, i: np.maximum(x, c),
    "LESS_THAN": lambda x, c, i: ((x < c) if i == 0 else (c < x)).astype(np.float32),
    "GREATER_THAN": lambda x, c, i: ((x > c) if i == 0 else (c > x)).astype(np.float32),
    "ROUND": lambda x, c, i: np.floor(x + 0.5),
}
_UNARY_MATH = {"ROUND"}


def apply_alpha_math(values, math):
    """An opacity texture's values through TextureRef.math, texel by texel (Cycles applies it
    after filtering: a cut-off's edge is then soft over one texel here, hard there)."""
    for operation, constant, index, clamp in math:
        values = ALPHA_MATH[operation](values, np.float32(constant), index)
        if clamp:
            values = np.clip(values, 0.0, 1.0)
    return values.astype(np.float32)


def _alpha_math_chain(source):
    """(operations from the image outwards, the socket the chain starts from) for Math nodes
    of ALPHA_MATH, each fed by one linked value and constants; (None, None) otherwise."""
    chain = []
    while source is not None and source.node.type == "MATH" and len(chain) < 8:
        node = source.node
        operation = node.operation
        if operation not in ALPHA_MATH:
            return None, None
        used = node.inputs[:1] if operation in _UNARY_MATH else node.inputs[:2]
        linked = [i for i, s in enumerate(used) if s.is_linked]
        if len(linked) != 1:
            return None, None
        index = linked[0]
        constant = 0.0 if operation in _UNARY_MATH else float(used[1 - index].default_value)
        chain.append((operation, constant, index, bool(node.use_clamp)))
        source = linked_from(node.inputs[index])
    return tuple(reversed(chain)), source


def _opacity_source(socket, info, what):
    """(constant opacity, TextureRef or None) behind an alpha-like float socket: its value,
    or an Image Texture's Alpha (its alpha channel) or Color output (read as a float, which
    Blender does by luminance), possibly through Math nodes (ALPHA_MATH). Anything else
    linked is read as opaque, with a warning."""
    source = linked_from(socket)
    if source is None:
        return min(max(float(socket.default_value), 0.0), 1.0), None
    math, image_source = _alpha_math_chain(source)
    node = image_source.node if image_source is not None else source.node
    if (image_source is not None and node.type == "TEX_IMAGE" and node.image is not None
            and image_source.name in ("Alpha", "Color")):
        _texture_sampling(node, info, what)
        if image_source.name == "Alpha" and getattr(node.image, "alpha_mode", "") == "NONE":
            if not math:
                return 1.0, None  # Cycles reads such an image's alpha as 1
        channel = "alpha" if image_source.name == "Alpha" else "luminance"
        return 1.0, TextureRef(node.image, _texture_uv_map(node, info, what), channel, math)
    node = source.node
    info.warnings.append(f"{what}: the '{node.name}' node feeding '{socket.name}' of "
                         f"'{socket.node.name}' is not evaluated: the surface is read as "
                         "opaque (a cut-out or transparency made so blocks light in the bake)")
    return 1.0, None


def _warn_unmodelled_layers(node, info, what):
    """Names the Principled layers the core's one diffuse and one glossy lobe leave out: a
    coat (Coat Weight in 4.x, Clearcoat in 3.x) and sheen. Cycles reflects them on top of the
    base (and a coat dims the base under it); the bake reflects the base alone."""
    for names, layer in ((("Coat Weight", "Clearcoat"), "coat"),
                         (("Sheen Weight", "Sheen"), "sheen")):
        socket = input_socket(node, *names)
        if socket is not None and (socket.is_linked or float(socket.default_value) > 0.0):
            info.warnings.append(f"{what}: its {layer} ('{socket.name}') is not modelled: the "
                                 f"bake reflects the layers under it alone (a few percent of "
                                 f"the light it sends on)")


def _read_principled(node, info, what):
    """A Principled BSDF: diffuse base x (1 - metallic) x (1 - transmission) (x (1 - F_avg)
    in 4.x), a glossy lobe of metal colour and dielectric F_avg, and its emission."""
    base, texture, color_socket = _read_color(input_socket(node, "Base Color"), info, what)
    metallic = _float_input(node, ("Metallic",), 0.0, info, what)
    transmission = _float_input(node, ("Transmission Weight", "Transmission"), 0.0, info,
                                what)
    transmission = min(max(transmission, 0.0), 1.0)
    dielectric = max(0.0, 1.0 - metallic) * (1.0 - transmission)
    _warn_unmodelled_layers(node, info, what)
    roughness = _float_input(node, ("Roughness",), 0.5, info, what)
    f0 = _principled_f0(node, info, what)  # once: a linked IOR or Specular warns
    f_avg = fresnel_hemispherical_average(f0)
    if texture is not None and metallic > 0.0:
        info.warnings.append(f"{what}: a textured metallic color is read as the base "
                             "color's default value for the glossy lobe")
    metal_color = color_value(input_socket(node, "Base Color")) if texture is not None else base
    # Glass (transmission) reflects F_avg too and passes the rest, tinted by the base colour,
    # which the core cannot tint: it passes the tint's luminance.
    glass = max(0.0, 1.0 - metallic) * transmission
    passing = glass * (1.0 - f_avg) * min(max(_luminance(metal_color), 0.0), 1.0)
    if glass > 0.0:
        info.warnings.append(f"{what}: transmission {transmission:g} {_THIN_GLASS_NOTE}")
    glossy = _glossy_lobe([metallic * c + (dielectric + glass) * f_avg for c in metal_color],
                          roughness)
    # Cycles 4.x's Principled v2 layers the specular over the diffuse base (which loses
    # what the coat reflects); 3.x's v1 adds it on top, leaving the diffuse untouched, so
    # each version is matched as rendered (the glossy part is clamped to 1 - albedo below).
    layered = input_socket(node, "Specular IOR Level") is not None
    factor = dielectric * (1.0 - f_avg) if layered else dielectric
    emission, emission_texture = (0.0, 0.0, 0.0), None
    em_socket = input_socket(node, "Emission Color", "Emission")
    if em_socket is not None:
        strength = _float_input(node, ("Emission Strength",), 1.0, info, what)
        emission, emission_texture = _read_emission(em_socket, strength, info, what)
    opacity, opacity_texture = 1.0, None
    alpha = input_socket(node, "Alpha")
    if alpha is not None:
        opacity, opacity_texture = _opacity_source(alpha, info, what)
    return _Shader(_scaled(base, factor), texture, emission, color_socket, factor, glossy,
                   emission_texture, opacity, opacity_texture, passing,
                   _ior_of_f0(f0) if passing > 0.0 else 0.0)


def _read_glass(node, info, what):
    """Glass, Refraction and Transparent BSDFs as thin surfaces: the share of light passing
    straight on is the colour's luminance (times 1 - F_avg for Glass, which reflects F_avg
    as a glossy lobe); nothing else is reflected."""
    color, texture, _ = _read_color(node.inputs["Color"], info, what)
    if texture is not None:
        info.warnings.append(f"{what}: a textured '{node.name}' colour is read as its default")
        color = color_value(node.inputs["Color"])
    share = min(max(_luminance(color), 0.0), 1.0)
    if node.type == "BSDF_TRANSPARENT":
        return _Shader(transmission=share)
    info.warnings.append(f"{what}: '{node.name}' ({node.bl_label}) {_THIN_GLASS_NOTE}")
    if node.type == "BSDF_REFRACTION":
        return _Shader(transmission=share)
    ior = _float_input(node, ("IOR",), 1.45, info, what)
    r = (ior - 1.0) / (ior + 1.0) if ior > 0.0 else 0.0
    f_avg = fresnel_hemispherical_average(r * r)
    roughness = _float_input(node, ("Roughness",), 0.0, info, what)
    return _Shader(glossy=_glossy_lobe((f_avg, f_avg, f_avg), roughness),
                   transmission=share * (1.0 - f_avg), transmission_ior=max(ior, 1.0))


def _ior_of_f0(f0):
    """The index of refraction whose normal-incidence reflectance is f0 (1: none)."""
    root = math.sqrt(min(max(float(f0), 0.0), 0.9))
    return min((1.0 + root) / (1.0 - root), 10.0)


def _cut_out_mix(node, info, what, depth):
    """The classic cut-out: a Mix Shader whose Fac comes from an image (its alpha, or its
    colour) and whose first shader is a white Transparent BSDF: the second shader where the
    image says so. None where the mix is not of that form."""
    fac = node.inputs[0]
    shaders = [s for s in node.inputs if s.type == "SHADER"]
    if not fac.is_linked or len(shaders) != 2:
        return None
    first = linked_from(shaders[0])
    if first is None or first.node.type != "BSDF_TRANSPARENT":
        return None
    if _luminance(color_value(first.node.inputs["Color"])) < 0.999:
        return None
    opacity, texture = _opacity_source(fac, info, what)
    if texture is None:
        return None
    second = linked_from(shaders[1])
    shader = _read_shader(second, info, what, depth + 1) if second is not None else _Shader()
    shader.opacity *= opacity
    if shader.opacity_texture is not None:
        info.warnings.append(f"{what}: '{node.name}' cuts out a surface that has its own alpha "
                             "texture: only the mix's is read")
    shader.opacity_texture = texture
    return shader


def _read_shader(socket_out, info, what, depth=0):
    """Reads the shader behind output socket `socket_out` into a _Shader."""
    node = socket_out.node
    kind = node.type
    if depth > 16:
        info.warnings.append(f"{what}: shader tree too deep; read as black")
        return _Shader()
    if kind == "BSDF_PRINCIPLED":
        return _read_principled(node, info, what)
    if kind == "BSDF_DIFFUSE":
        base, texture, color_socket = _read_color(node.inputs["Color"], info, what)
        return _Shader(base, texture, color_socket=color_socket)
    if kind in ("BSDF_GLOSSY", "BSDF_ANISOTROPIC"):
        color, texture, _ = _read_color(node.inputs["Color"], info, what)
        if texture is not None:
            info.warnings.append(f"{what}: a textured glossy color is read as its default value")
            color = color_value(node.inputs["Color"])
        roughness = _float_input(node, ("Roughness",), 0.5, info, what)
        return _Shader(glossy=_glossy_lobe(color, roughness))
    if kind == "EMISSION":
        strength = _float_input(node, ("Strength",), 1.0, info, what)
        emission, emission_texture = _read_emission(node.inputs["Color"], strength, info, what)
        return _Shader(emission=emission, emission_texture=emission_texture)
    if kind in ("BSDF_GLASS", "BSDF_REFRACTION", "BSDF_TRANSPARENT"):
        return _read_glass(node, info, what)
    if kind == "MIX_SHADER":
        cut_out = _cut_out_mix(node, info, what, depth)
        if cut_out is not None:
            return cut_out
    if kind in ("MIX_SHADER", "ADD_SHADER"):
        shader_inputs = [s for s in node.inputs if s.type == "SHADER"]
        parts = []
        for s in shader_inputs:
            src = linked_from(s)
            parts.append(_read_shader(src, info, what, depth + 1) if src is not None
                         else _Shader())
        if kind == "MIX_SHADER":
            fac = min(max(_float_input(node, ("Fac",), 0.5, info, what), 0.0), 1.0)
            weights = (1.0 - fac, fac)
        else:
            weights = (1.0, 1.0)
        info.warnings.append(f"{what}: '{node.name}' ({node.bl_label}) is approximated by a "
                             "weighted sum of its shaders")
        albedo = [0.0, 0.0, 0.0]
        emission = [0.0, 0.0, 0.0]
        passing = 0.0
        for w, part in zip(weights, parts):
            # A part's reflectances are of its present surface; the mix's of the whole.
            for k in range(3):
                albedo[k] += w * part.opacity * part.albedo[k]
                emission[k] += w * part.emission[k]
            passing += w * (1.0 - part.opacity * (1.0 - part.transmission))
            if part.opacity_texture is not None:
                info.warnings.append(f"{what}: an alpha texture inside '{node.name}' is read "
                                     "as opaque")
        albedo = tuple(min(a, 1.0) for a in albedo)
        glossy = _mixed_glossy(weights, parts)
        passing = min(max(passing, 0.0), 1.0)
        emission_texture = _mixed_emission_texture(weights, parts, info, what)
        # Keep the texture of the part that weighs most, scaled by its weight.
        best = max(range(len(parts)), key=lambda i: weights[i] * max(parts[i].albedo),
                   default=None)
        if best is not None and parts[best].texture is not None:
            w = weights[best] * parts[best].opacity
            return _Shader(_scaled(parts[best].albedo, w), parts[best].texture, tuple(emission),
                           parts[best].color_socket, parts[best].albedo_factor * w, glossy,
                           emission_texture, transmission=passing)
        return _Shader(albedo, None, tuple(emission), None, 1.0, glossy, emission_texture,
                       transmission=passing)
    # Any other shader: its colour input's default value, as diffuse.
    color = input_socket(node, "Color", "Base Color")
    info.warnings.append(f"{what}: '{node.name}' ({node.bl_label}) is approximated as a diffuse "
                         "surface")
    if color is None or not hasattr(color.default_value, "__len__"):
        return _Shader(DEFAULT_ALBEDO)
    base, texture, color_socket = _read_color(color, info, what)
    return _Shader(base, texture, color_socket=color_socket)


def _mixed_emission_texture(weights, parts, info, what):
    """The emission texture of a mix: kept where exactly one part emits (its emission is
    weighted like any other); a textured emission mixed with another emission cannot be one
    texture times one colour, so the texture is then dropped (read as white), with a warning."""
    emitting = [i for i, part in enumerate(parts) if weights[i] > 0.0 and max(part.emission) > 0.0]
    textured = [i for i in emitting if parts[i].emission_texture is not None]
    if not textured:
        return None
    if len(emitting) == 1:
        return parts[textured[0]].emission_texture
    info.warnings.append(f"{what}: a textured emission mixed with another emission is read "
                         "with its texture as white")
    return None


def _mixed_glossy(weights, parts):
    """The weighted sum of the parts' glossy reflectances, with their exponents averaged
    by reflectance (one lobe cannot hold two; the mix already warns)."""
    reflectance = [0.0, 0.0, 0.0]
    exponent_sum = 0.0
    weight_sum = 0.0
    for w, part in zip(weights, parts):
        if part.glossy is None:
            continue
        rgb, exponent = part.glossy
        w *= part.opacity
        for k in range(3):
            reflectance[k] += w * rgb[k]
        strength = w * max(rgb)
        exponent_sum += strength * exponent
        weight_sum += strength
    if weight_sum <= 0.0:
        return None
    return tuple(min(c, 1.0) for c in reflectance), exponent_sum / weight_sum


def _stopped_surface(shader):
    """The core reflects light only where a ray stops at a surface (1 - transmission of its
    present part): its reflectances are divided by that share, so that what a surface reflects
    of all the light meeting it stays what Cycles reflects."""
    t = min(max(float(shader.transmission), 0.0), 1.0)
    if t <= 0.0:
        return
    if t >= 0.9999:  # every ray passes: nothing is ever reflected
        shader.albedo, shader.glossy, shader.albedo_factor = (0.0, 0.0, 0.0), None, 0.0
        shader.texture = shader.color_socket = None
        return
    k = 1.0 / (1.0 - t)
    shader.albedo = _scaled(shader.albedo, k)
    shader.albedo_factor *= k
    if shader.glossy is not None:
        rgb, exponent = shader.glossy
        shader.glossy = (tuple(min(c * k, 1.0) for c in rgb), exponent)


def read_material(material):
    """What the core needs of a Blender material (None: Cycles' default grey)."""
    info = MaterialInfo()
    if material is None:
        return info
    what = f"material '{material.name}'"
    if not compat.uses_nodes(material):
        c = material.diffuse_color
        info.albedo = (float(c[0]), float(c[1]), float(c[2]))
        return info
    output = active_output(material.node_tree)
    if output is None:
        info.warnings.append(f"{what}: no Material Output node; read as black")
        info.albedo = (0.0, 0.0, 0.0)
        return info
    surface = linked_from(output.inputs["Surface"])
    volume_socket = output.inputs.get("Volume")
    volume = linked_from(volume_socket) if volume_socket is not None else None
    if surface is None and volume is not None:
        info.volume_only = True
        info.albedo = (0.0, 0.0, 0.0)
        return info
    if volume is not None:
        info.warnings.append(f"{what}: its Volume is ignored (the bake has no participating "
                             "media: inside, light passes as through air)")
    if surface is not None and surface.node.name.startswith(NODE_PREFIX):
        # Hooked by an earlier bake: read the material as it was before the hook.
        surface = linked_from(surface.node.inputs[0])
    if surface is None:
        info.albedo = (0.0, 0.0, 0.0)  # Cycles renders an unconnected surface black
        return info
    shader = _read_shader(surface, info, what)
    _stopped_surface(shader)
    info.opacity = min(max(float(shader.opacity), 0.0), 1.0)
    info.opacity_texture = shader.opacity_texture
    info.transmission = min(max(float(shader.transmission), 0.0), 1.0)
    info.transmission_ior = float(shader.transmission_ior) if info.transmission > 0.0 else 0.0
    albedo, texture, emission = shader.albedo, shader.texture, shader.emission
    color_socket, factor, glossy = shader.color_socket, shader.albedo_factor, shader.glossy
    info.albedo = tuple(min(max(float(a), 0.0), 1.0) for a in albedo)
    if glossy is not None:
        # The core refuses albedo + glossy > 1 per channel: a mix can exceed it, so the glossy
        # lobe gives way (the diffuse albedo is what the bake's output is defined with).
        info.glossy = tuple(max(0.0, min(float(g), 1.0 - a)) for g, a in zip(glossy[0], info.albedo))
        info.glossy_exponent = float(glossy[1]) if max(info.glossy) > 0.0 else 0.0
        reflectance = _luminance(info.glossy)
        if reflectance > STRONG_GLOSSY_REFLECTANCE:
            info.warnings.append(
                f"{what}: glossy reflectance {reflectance:.2f} (a metal or a Glossy BSDF) is "
                "baked as a Phong lobe, which reflects less than Cycles' GGX at grazing angles: "
                "surfaces lit by it can bake up to 20% darker than Cycles (docs/compatibility.md)")
    info.texture = texture
    info.emission = tuple(max(float(e), 0.0) for e in emission)
    info.emission_texture = shader.emission_texture if max(info.emission) > 0.0 else None
    if (info.opacity_texture is not None
            and info.opacity_texture.uv_map != sampled_uv_map(info)):
        info.warnings.append(
            f"{what}: its alpha texture uses another UV map than its other textures; it is "
            "sampled with theirs")
    if (info.texture is not None and info.emission_texture is not None
            and info.texture.uv_map != info.emission_texture.uv_map):
        info.warnings.append(
            f"{what}: its base color and emission textures use different UV maps "
            f"('{info.texture.uv_map or '(active)'}', "
            f"'{info.emission_texture.uv_map or '(active)'}'); both are sampled with the "
            "emission's")
    if color_socket is not None:
        node = color_socket.node
        info.color_source = (node.name, list(node.outputs).index(color_socket))
    info.albedo_factor = factor
    if any(a > 1.0 for a in albedo):
        info.warnings.append(f"{what}: albedo above 1 is clamped to 1")
    return info
