# SPDX-License-Identifier: GPL-3.0-or-later
"""The world's light as the core takes it: a constant colour, an equirectangular
environment image (an HDRI) read through the world's node tree (node_tree.py) with the
rotation of a Mapping node in front of it, or, for any other tree on the Background (a Sky
Texture, gradients, mixes), that tree rendered by Cycles into such an image
(world_render.py)."""

import math
from dataclasses import dataclass, field
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
    # Sky Textures' sun discs, taken out of the image: (direction to the sun, angular diameter,
    # irradiance RGB) each, baked as sun lights.
    suns: List[Tuple[Tuple[float, float, float], float, Tuple[float, float, float]]] = \
        field(default_factory=list)


def world_light(world, warnings) -> WorldLight:
    """The world's light: its Background's colour x strength; the Environment Texture's image
    feeding the colour (an equirectangular image, optionally turned by a Mapping node) x the
    strength; or, for any other tree (on the Background, or a mix of shaders), the tree
    rendered by Cycles (with a Sky Texture's sun as a sun light). What is not read is said in
    `warnings`."""
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
    volume = output.inputs.get("Volume")
    if volume is not None and linked_from(volume) is not None:
        warnings.append(f"{what}: its Volume (fog filling the scene) is ignored: the bake has no "
                        "participating media, which dim and scatter the light in Cycles")
    source = linked_from(output.inputs["Surface"])
    if source is None:
        return WorldLight((0.0, 0.0, 0.0))
    node = source.node
    if node.type != "BACKGROUND":
        # A mix of Backgrounds (the camera-ray trick: one world for the camera, another for
        # the light) or an Emission: Cycles renders whatever the tree sends.
        return _rendered_light(world, what, warnings, WorldLight((0.0, 0.0, 0.0)))
    strength_socket = node.inputs["Strength"]
    strength = float(strength_socket.default_value)
    color_socket = node.inputs["Color"]
    color = tuple(float(c) for c in color_socket.default_value[:3])
    color_source = linked_from(color_socket)
    constant = WorldLight(light_units.world_radiance(color, strength))
    if color_source is None and not strength_socket.is_linked:
        return constant
    tex = color_source.node if color_source is not None else None
    if not strength_socket.is_linked and tex is not None:
        if tex.type == "RGB":
            color = tuple(float(c) for c in color_source.default_value[:3])
            return WorldLight(light_units.world_radiance(color, strength))
        if tex.type == "TEX_ENVIRONMENT":
            if tex.image is None or not _has_pixels(tex.image):
                # Cycles would draw a missing image magenta: the Background's colour instead.
                warnings.append(f"{what}: the environment texture has no image (missing "
                                "file?); the Background's default color is used")
                return constant
            light = _environment_light(tex, strength, what, warnings)
            if light is not None:
                return light
    return _rendered_light(world, what, warnings, constant)


def _has_pixels(image):
    return int(image.size[0]) > 0 and int(image.size[1]) > 0 and int(image.channels) > 0


def _rendered_light(world, what, warnings, fallback):
    """The WorldLight of a world tree rendered by Cycles (world_render.py); `fallback` with a
    warning where it cannot be rendered."""
    from . import world_render  # bpy's render operators: only where a tree needs them

    unread = world_render.light_path_outputs_read(world) - set(world_render.LIGHTING_RAY_VALUES)
    if unread:
        warnings.append(f"{what}: its node tree reads the Light Path node's "
                        f"{', '.join(sorted(unread))}; the world is baked as the camera sees it")
    try:
        rgb, suns = world_render.rendered_world(world)
    except Exception as error:  # a world the render refuses must not stop the bake
        warnings.append(f"{what}: its node tree could not be rendered into an image ({error}); "
                        "the Background's default color is used")
        return fallback
    rgb = np.nan_to_num(np.maximum(rgb, 0.0), nan=0.0, posinf=0.0)
    suns = [(sun.direction, sun.angle, sun.irradiance) for sun in suns]
    peak = float(rgb.max()) if rgb.size else 0.0
    if not peak > 0.0:
        return WorldLight((0.0, 0.0, 0.0), suns=suns)
    return WorldLight(_mean_over_sphere(rgb),
                      image=np.ascontiguousarray(rgb / np.float32(peak), dtype=np.float32),
                      scale=(peak, peak, peak), suns=suns)


def _environment_light(tex, strength, what, warnings):
    """The WorldLight of an Environment Texture node read from its image, or None where that
    is not exact (a projection other than equirectangular, a vector that is not a rotation of
    the direction): the tree is then rendered."""
    if getattr(tex, "projection", "EQUIRECTANGULAR") != "EQUIRECTANGULAR":
        return None
    exact, rotation = _mapping_rotation(tex)
    if not exact:
        return None
    rgb = materials.image_linear_rgb(tex.image, warnings)
    if rgb is None:
        return None
    if (rgb < 0.0).any():
        warnings.append(f"{what}: the environment image has negative pixels; they are read as 0")
        rgb = np.maximum(rgb, 0.0)
    rgb = _averaged_down(rgb, MAX_WORLD_IMAGE_WIDTH)
    mean = _mean_over_sphere(rgb)
    if getattr(tex, "interpolation", "Linear") != "Linear":
        warnings.append(f"{what}: the environment texture is read with linear interpolation, "
                        f"not '{tex.interpolation}'")
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


def _mapping_rotation(tex):
    """(exact, rotation): the rotation (world -> image frame, 3 x 3 rows; None for none) of a
    Mapping node between the Texture Coordinate's direction and the texture, and whether
    that is all the vector does (no location, a uniform scale, nothing linked into it)."""
    source = linked_from(tex.inputs["Vector"])
    if source is None:
        return True, None
    mapping = source.node
    if mapping.type != "MAPPING":
        return False, None
    coordinates = linked_from(mapping.inputs["Vector"])
    if coordinates is None or coordinates.node.type != "TEX_COORD" or \
            coordinates.name not in ("Generated", "Object", "Normal"):
        return False, None
    kind = mapping.vector_type
    sockets = {name: mapping.inputs.get(name) for name in ("Location", "Rotation", "Scale")}
    if any(socket is None or socket.is_linked for socket in sockets.values()):
        return False, None
    if kind == "POINT" and any(abs(float(c)) > 0.0 for c in sockets["Location"].default_value):
        return False, None
    scale = [float(c) for c in sockets["Scale"].default_value]
    if min(scale) <= 0.0 or max(scale) - min(scale) > 1e-6 * max(scale):
        return False, None
    rotation = _euler_xyz_matrix([float(c) for c in sockets["Rotation"].default_value])
    if kind == "TEXTURE":  # the inverse transform
        rotation = [list(row) for row in zip(*rotation)]
    return True, rotation


def _euler_xyz_matrix(euler):
    """Blender's XYZ Euler rotation (x first, then y, then z: Rz Ry Rx) as 3 x 3 rows."""
    (cx, cy, cz), (sx, sy, sz) = ([math.cos(a) for a in euler], [math.sin(a) for a in euler])
    return [[cy * cz, sx * sy * cz - cx * sz, cx * sy * cz + sx * sz],
            [cy * sz, sx * sy * sz + cx * cz, cx * sy * sz - sx * cz],
            [-sy, sx * cy, cx * cy]]
