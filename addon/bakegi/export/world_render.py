# SPDX-License-Identifier: GPL-3.0-or-later
"""A world whose node tree bakegi does not read itself (a Sky Texture, gradients, mixes,
colour corrections) is rendered by Cycles into an equirectangular image: a panoramic camera at
the origin of a scratch scene that holds nothing but the world sees exactly the radiance the
world sends in every direction, in the layout of an Environment Texture (world.py reads it
like one). The scratch scene, its camera and the render are removed afterwards; the user's
scenes and worlds are not touched.

A Sky Texture's sun disc (0.5 degrees, most of the sky's light) is not left in the image: in
texels of 0.7 degrees, at 16 samples each, its light comes out several percent off and its
shadows blurred. It is rendered apart instead, in a narrow view around it, with the disc and
without it (on a copy of the world): the difference, summed over the view's pixels by their
solid angle, is its irradiance, its weighted centre its direction, and the sky image is
rendered without the disc. The sun then bakes as a sun light of the disc's size."""

import math
import os
import shutil
import tempfile
from dataclasses import dataclass

import bpy
import numpy as np

# 512 x 256 texels (0.7 degrees each) at 16 samples: a sun disc of Blender's default size
# (0.545 degrees) lands in one or two texels with its light kept; about 2 s on 2 cores.
RENDER_WIDTH = 512
RENDER_SAMPLES = 16
# The camera turned so that image column u looks where an Environment Texture's u does:
# x 90 degrees (from looking down -z to looking along +y), z -90 degrees (to +x at the centre).
CAMERA_ROTATION = (1.5707963267948966, 0.0, -1.5707963267948966)


def light_path_outputs_read(world):
    """The names of the Light Path outputs the world's tree reads (linked somewhere)."""
    return {socket.name for node in world.node_tree.nodes if node.type == "LIGHT_PATH"
            for socket in node.outputs if socket.is_linked}


# What a world seen by a bake's light reads from the Light Path outputs it can be given:
# "Is Camera Ray" is 0 for every ray that lights a surface. The other outputs depend on how
# Cycles evaluates the world for its light samples (shadow rays, depths): not replaced.
LIGHTING_RAY_VALUES = {"Is Camera Ray": 0.0}


def _as_lighting_rays(world):
    """A copy of `world` whose Light Path outputs in LIGHTING_RAY_VALUES are constants (the
    caller removes it): the panoramic camera then renders what lighting rays see."""
    scratch = world.copy()
    tree = scratch.node_tree
    for node in [n for n in tree.nodes if n.type == "LIGHT_PATH"]:
        for socket in node.outputs:
            if socket.name not in LIGHTING_RAY_VALUES or not socket.is_linked:
                continue
            value = tree.nodes.new("ShaderNodeValue")
            value.outputs[0].default_value = LIGHTING_RAY_VALUES[socket.name]
            for link in list(socket.links):
                tree.links.new(value.outputs[0], link.to_socket)
    return scratch


# The last render and the state of the world it was made from: a live relight re-exports the
# world after every light move, and a render costs seconds.
_last = {"fingerprint": None, "result": None}

# The narrow view around a sky's sun: this many pixels a side, this wide.
SUN_VIEW_PIXELS = 128
SUN_VIEW_ANGLE = math.radians(8.0)


@dataclass
class SkySun:
    direction: tuple  # unit, from the scene towards the sun
    angle: float  # angular diameter, radians
    irradiance: tuple  # W/m^2 on a surface facing it, RGB


def _value(value):
    """A property value as something comparable (vectors and colours as tuples; ID blocks
    by name and, for images, by their pixels' change count)."""
    if hasattr(value, "name_full"):
        return (value.name_full, getattr(value, "is_dirty", None))
    try:
        return tuple(value)
    except TypeError:
        return value


def world_fingerprint(world):
    """Everything a render of `world` depends on: its nodes' settings and inputs, and links."""
    parts = [world.name_full]
    for node in sorted(world.node_tree.nodes, key=lambda n: n.name):
        parts.append((node.name, node.bl_idname, getattr(node, "mute", False)))
        for prop in node.bl_rna.properties:
            if prop.identifier in ("rna_type", "location", "width", "height", "select",
                                   "dimensions", "show_options", "show_preview", "hide"):
                continue
            if prop.type in ("POINTER", "COLLECTION") and prop.identifier != "image":
                continue
            parts.append((prop.identifier, _value(getattr(node, prop.identifier, None))))
        for socket in node.inputs:
            if hasattr(socket, "default_value"):
                parts.append((socket.identifier, _value(socket.default_value)))
    for link in world.node_tree.links:
        parts.append((link.from_node.name, link.from_socket.identifier, link.to_node.name,
                      link.to_socket.identifier, getattr(link, "is_muted", False)))
    return repr(parts)


def rendered_world(world):
    """(image, suns) of render_world_and_suns(world), reused while the world is unchanged."""
    fingerprint = world_fingerprint(world)
    if _last["fingerprint"] != fingerprint:
        _last["result"] = render_world_and_suns(world)
        _last["fingerprint"] = fingerprint
    image, suns = _last["result"]
    return image.copy(), list(suns)


def _sky_suns(world):
    """The Sky Texture nodes of `world` that draw a sun disc."""
    return [n for n in world.node_tree.nodes
            if n.type == "TEX_SKY" and getattr(n, "sun_disc", False)]


def render_world_and_suns(world):
    """(the world's equirectangular image, [SkySun]): with one Sky Texture that draws a sun,
    the image without the disc and the disc as a SkySun; else the image as it is and none.
    A tree that asks Light Path whether a ray is the camera's is rendered as lighting rays see
    it (LIGHTING_RAY_VALUES)."""
    if light_path_outputs_read(world) & set(LIGHTING_RAY_VALUES):
        scratch = _as_lighting_rays(world)
        try:
            return render_world_and_suns(scratch)
        finally:
            bpy.data.worlds.remove(scratch)
    skies = _sky_suns(world)
    if len(skies) != 1:
        return render_world(world), []
    # Where the sky model puts its sun (Cycles: phi = pi / 2 - rotation, measured with the
    # narrow view); a Mapping node in front of the sky moves it out of the view, and the disc
    # then stays in the image.
    elevation, rotation = float(skies[0].sun_elevation), float(skies[0].sun_rotation)
    rough = (math.cos(elevation) * math.sin(rotation), math.cos(elevation) * math.cos(rotation),
             math.sin(elevation))
    scratch = world.copy()
    try:
        scratch.node_tree.nodes[skies[0].name].sun_disc = False
        view_with = render_view(world, rough)
        view_without = render_view(scratch, rough)
        difference = np.maximum(view_with - view_without, 0.0)
        directions, solid_angles = _view_pixels(rough)
        weighted = difference * solid_angles[:, :, None]
        weight = _luminance(weighted)
        if not weight.sum() > 0.0:
            return render_world(world), []
        sky = render_world(scratch)
    finally:
        bpy.data.worlds.remove(scratch)
    irradiance = weighted.sum(axis=(0, 1))
    centre = (directions * weight[:, :, None]).sum(axis=(0, 1))
    centre /= np.linalg.norm(centre)
    sun = SkySun(tuple(float(c) for c in centre), float(skies[0].sun_size),
                 tuple(float(c) for c in irradiance))
    return sky, [sun]


def _luminance(rgb):
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


def _view_frame(direction):
    """(right, up, forward) of a camera looking along `direction` (up towards +z)."""
    forward = np.array(direction, np.float64)
    helper = np.array([0.0, 0.0, 1.0]) if abs(forward[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(forward, helper)
    right /= np.linalg.norm(right)
    return right, np.cross(right, forward), forward


def _view_pixels(direction, pixels=SUN_VIEW_PIXELS, angle=SUN_VIEW_ANGLE):
    """Per pixel of render_view (row 0 at the bottom): its unit direction and solid angle."""
    right, up, forward = _view_frame(direction)
    half = math.tan(0.5 * angle)
    centres = (np.arange(pixels) + 0.5) / pixels * 2.0 - 1.0
    x, y = np.meshgrid(centres * half, centres * half)
    rays = forward[None, None, :] + x[:, :, None] * right + y[:, :, None] * up
    length = np.linalg.norm(rays, axis=2)
    pixel_area = (2.0 * half / pixels) ** 2
    return rays / length[:, :, None], pixel_area / length ** 3


def render_view(world, direction, pixels=SUN_VIEW_PIXELS, angle=SUN_VIEW_ANGLE,
                samples=RENDER_SAMPLES):
    """(pixels, pixels, 3) radiance of `world` seen by a square perspective camera at the
    origin looking along `direction`, `angle` wide, row 0 at the bottom."""
    right, up, forward = _view_frame(direction)

    def setup(camera, camera_data):
        import mathutils
        basis = mathutils.Matrix((right, up, -forward)).transposed()  # columns: x, y, z
        camera.matrix_world = basis.to_4x4()
        camera_data.type = "PERSP"
        camera_data.sensor_fit = "HORIZONTAL"
        camera_data.angle = angle

    return _render(world, setup, pixels, pixels, samples)


def render_world(world, width=RENDER_WIDTH, samples=RENDER_SAMPLES):
    """(height, width, 3) float32 linear radiance of `world` in every direction, row 0 the
    nadir, column 0 at u = 0 of an Environment Texture (Cycles' equirectangular mapping)."""
    def setup(camera, camera_data):
        camera.rotation_euler = CAMERA_ROTATION
        camera_data.type = "PANO"
        # 4.0 moved the panorama settings from Cycles' camera settings to the camera.
        if hasattr(camera_data, "panorama_type"):
            camera_data.panorama_type = "EQUIRECTANGULAR"
        else:
            camera_data.cycles.panorama_type = "EQUIRECTANGULAR"

    return _render(world, setup, width, max(1, width // 2), samples)


def _render(world, setup_camera, width, height, samples):
    """Renders `world` alone with Cycles in a scratch scene through a camera at the origin
    that setup_camera(camera object, camera data) sets up; (height, width, 3) radiance."""
    scene = bpy.data.scenes.new("BakeGI world render")
    camera_data = bpy.data.cameras.new("BakeGI world camera")
    camera = bpy.data.objects.new("BakeGI world camera", camera_data)
    folder = tempfile.mkdtemp(prefix="bakegi_world_")
    path = os.path.join(folder, "world.exr")
    image = None
    try:
        scene.world = world
        scene.collection.objects.link(camera)
        scene.camera = camera
        setup_camera(camera, camera_data)
        render = scene.render
        render.engine = "CYCLES"
        render.resolution_x, render.resolution_y = width, height
        render.resolution_percentage = 100
        render.film_transparent = False
        render.use_compositing = False
        render.use_sequencer = False
        render.image_settings.file_format = "OPEN_EXR"
        render.image_settings.color_depth = "32"
        render.filepath = path
        scene.view_settings.exposure = 0.0  # OpenEXR keeps the render's linear radiance
        scene.view_settings.gamma = 1.0
        scene.cycles.samples = samples
        scene.cycles.use_denoising = False
        scene.cycles.use_adaptive_sampling = False
        scene.cycles.device = "CPU"
        bpy.ops.render.render(write_still=True, scene=scene.name)
        image = bpy.data.images.load(path)  # a float image: its pixels are scene-linear
        flat = np.empty(width * height * 4, np.float32)
        image.pixels.foreach_get(flat)
        return np.ascontiguousarray(flat.reshape(height, width, 4)[:, :, :3])
    finally:
        if image is not None:
            bpy.data.images.remove(image)
        bpy.data.objects.remove(camera)
        bpy.data.cameras.remove(camera_data)
        bpy.data.scenes.remove(scene)
        shutil.rmtree(folder, ignore_errors=True)
