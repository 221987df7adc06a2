# SPDX-License-Identifier: GPL-3.0-or-later
"""The world's radiance as the core takes it: a constant colour, or an equirectangular
environment image read through the world's node tree (node_tree.py)."""

import numpy as np

from .. import compat, light_units
from . import materials
from .node_tree import linked_from


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
    source = linked_from(output.inputs["Surface"])
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
    color_source = linked_from(color_socket)
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
