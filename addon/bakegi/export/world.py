# SPDX-License-Identifier: GPL-3.0-or-later
"""The world's light as the core takes it: a constant colour, or an equirectangular
environment image (an HDRI) read through the world's node tree (node_tree.py), with the
rotation of a Mapping node in front of it."""

import math
from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from .. import compat, light_units
from . import materials
from .node_tree import linked_from

# Wider images are averaged down by whole blocks of texels (an 8K sky to 2048 x 1024: 25 MB
# in the core with its sampling tables, instead of 400 MB); the light each block holds is
# kept, only its shape within the block is lost.
MAX_WORLD_IMAGE_WIDTH = 2048


@dataclass
class WorldLight:
    radiance: Tuple[float, float, float]  # the constant world; with an image, its mean
    image: Optional[np.ndarray] = None  # (height, width, 3) float32 in [0, 1], row 0 bottom
    scale: Tuple[float, float, float] = (1.0, 1.0, 1.0)  # radiance = scale x image
    rotation: Optional[List[List[float]]] = None  # world direction -> image frame; None: none


def world_radiance(world, warnings):
    """The constant background radiance of a world (an image's mean where it has one)."""
    return world_light(world, warnings).radiance


def world_light(world, warnings) -> WorldLight:
    """The world's light: its Background's colour x strength, or the Environment Texture's
    image feeding the colour (an equirectangular image, optionally turned by a Mapping node)
    x the strength. What is not read is said in `warnings`."""
    if world is None:
        return WorldLight((0.0, 0.0, 0.0))
    what = f"world '{world.name}'"
    if not compat.uses_nodes(world):
        return WorldLight(tuple(float(c) for c in world.color[:3]))
    tree = world.node_tree
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_WORLD"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None:
        return WorldLight((0.0, 0.0, 0.0))
    source = linked_from(output.inputs["Surface"])
    if source is None:
        return WorldLight((0.0, 0.0, 0.0))
    node = source.node
    if node.type != "BACKGROUND":
        warnings.append(f"{what}: a '{node.bl_label}' node is not a Background; the world is "
                        "read as black")
        return WorldLight((0.0, 0.0, 0.0))
    strength_socket = node.inputs["Strength"]
    if strength_socket.is_linked:
        warnings.append(f"{what}: a linked strength is read as its default value")
    strength = float(strength_socket.default_value)
    color_socket = node.inputs["Color"]
    color = tuple(float(c) for c in color_socket.default_value[:3])
    color_source = linked_from(color_socket)
    if color_source is None:
        return WorldLight(light_units.world_radiance(color, strength))
    tex = color_source.node
    if tex.type == "TEX_ENVIRONMENT" and tex.image is not None:
        light = _environment_light(tex, strength, what, warnings)
        if light is not None:
            return light
    elif tex.type == "RGB":
        color = tuple(float(c) for c in color_source.default_value[:3])
    else:
        warnings.append(f"{what}: the '{tex.bl_label}' node on the background color is not "
                        "evaluated; its default color is used")
    return WorldLight(light_units.world_radiance(color, strength))


def _environment_light(tex, strength, what, warnings):
    """The WorldLight of an Environment Texture node, or None where its image has no pixels."""
    rgb = materials.image_linear_rgb(tex.image, warnings)
    if rgb is None:
        return None
    if (rgb < 0.0).any():
        warnings.append(f"{what}: the environment image has negative pixels; they are read as 0")
        rgb = np.maximum(rgb, 0.0)
    rgb = _averaged_down(rgb, MAX_WORLD_IMAGE_WIDTH)
    mean = _mean_over_sphere(rgb)
    if getattr(tex, "projection", "EQUIRECTANGULAR") != "EQUIRECTANGULAR":
        warnings.append(f"{what}: the environment texture's '{tex.projection}' projection is "
                        "not read; its mean color lights the scene as a constant world")
        return WorldLight(light_units.world_radiance(mean, strength))
    if getattr(tex, "interpolation", "Linear") != "Linear":
        warnings.append(f"{what}: the environment texture is read with linear interpolation, "
                        f"not '{tex.interpolation}'")
    rotation = _mapping_rotation(tex, what, warnings)
    peak = float(rgb.max()) if rgb.size else 0.0
    if not peak > 0.0:
        return WorldLight((0.0, 0.0, 0.0))
    # The core's textures hold [0, 1]: an HDR image goes in divided by its peak, which then
    # scales its light.
    scale = light_units.world_radiance((peak, peak, peak), strength)
    return WorldLight(light_units.world_radiance(mean, strength),
                      image=np.ascontiguousarray(rgb / np.float32(peak), dtype=np.float32),
                      scale=scale, rotation=rotation)


def _averaged_down(rgb, max_width):
    """The image averaged over blocks of k x k texels so that it is at most max_width wide
    (k the smallest that does; rows and columns beyond a whole block are left out)."""
    height, width = rgb.shape[:2]
    k = -(-width // max_width)
    if k <= 1:
        return rgb
    h, w = height // k, width // k
    blocks = rgb[:h * k, :w * k].reshape(h, k, w, k, 3)
    return blocks.mean(axis=(1, 3), dtype=np.float64).astype(np.float32)


def _mean_over_sphere(rgb):
    """The mean of an equirectangular image over the sphere: rows weighted by the solid angle
    they cover (sin of the angle from the zenith)."""
    h = rgb.shape[0]
    weights = np.sin((np.arange(h) + 0.5) / h * np.pi)
    return tuple(float(c) for c in
                 (rgb.mean(axis=1) * weights[:, None]).sum(axis=0) / weights.sum())


def _mapping_rotation(tex, what, warnings):
    """The rotation (world -> image frame, 3 x 3 rows) of a Mapping node feeding the
    texture's vector, None without one. Only what turns a direction is read: a location, a
    scale that is not uniform or a vector from elsewhere are left out with a warning."""
    source = linked_from(tex.inputs["Vector"])
    if source is None:
        return None
    mapping = source.node
    if mapping.type != "MAPPING":
        warnings.append(f"{what}: the '{mapping.bl_label}' node on the environment texture's "
                        "vector is not evaluated; the image is read unrotated")
        return None
    coordinates = linked_from(mapping.inputs["Vector"])
    if coordinates is None or coordinates.node.type != "TEX_COORD" or \
            coordinates.name not in ("Generated", "Object", "Normal"):
        warnings.append(f"{what}: the Mapping node in front of the environment texture does not "
                        "take the Texture Coordinate's direction; the image is read unrotated")
        return None
    kind = mapping.vector_type
    sockets = {name: mapping.inputs.get(name) for name in ("Location", "Rotation", "Scale")}
    for name, socket in sockets.items():
        if socket is not None and socket.is_linked:
            warnings.append(f"{what}: the Mapping node's linked {name.lower()} is read as its "
                            "default value")
    if kind == "POINT" and sockets["Location"] is not None and \
            any(abs(float(c)) > 0.0 for c in sockets["Location"].default_value):
        warnings.append(f"{what}: the Mapping node's location is left out (it does not turn "
                        "directions)")
    if sockets["Scale"] is not None:
        scale = [float(c) for c in sockets["Scale"].default_value]
        if max(scale) - min(scale) > 1e-6 * max(abs(c) for c in scale) or min(scale) <= 0.0:
            warnings.append(f"{what}: the Mapping node's scale {tuple(scale)} is left out (only "
                            "a rotation is read)")
    euler = [float(c) for c in sockets["Rotation"].default_value] \
        if sockets["Rotation"] is not None else [0.0, 0.0, 0.0]
    rotation = _euler_xyz_matrix(euler)
    if kind == "TEXTURE":  # the inverse transform
        rotation = [list(row) for row in zip(*rotation)]
    return rotation


def _euler_xyz_matrix(euler):
    """Blender's XYZ Euler rotation (x first, then y, then z: Rz Ry Rx) as 3 x 3 rows."""
    (cx, cy, cz), (sx, sy, sz) = ([math.cos(a) for a in euler], [math.sin(a) for a in euler])
    return [[cy * cz, sx * sy * cz - cx * sz, cx * sy * cz + sx * sz],
            [cy * sz, sx * sy * sz + cx * cz, cx * sy * sz - sx * cz],
            [-sy, sx * cy, cx * cy]]
