# SPDX-License-Identifier: GPL-3.0-or-later
"""The 12 numbers bakegi_preview_render takes for a camera: position, rotation quaternion
xyzw (looking down -Z, up +Y), vertical field of view, lens shift x and y (in units of the
larger image side), orthographic scale (0: perspective), and a reserved 0."""

import math

from ..write.web_scene import vertical_field_of_view


def scene_camera_values(camera, width, height):
    """For a camera object rendering width x height pixels (F12)."""
    location, rotation, _ = camera.matrix_world.decompose()
    data = camera.data
    aspect = width / max(height, 1)
    ortho = data.ortho_scale if data.type == "ORTHO" else 0.0
    fov = vertical_field_of_view(camera, aspect) if not ortho else 1.0
    return [location.x, location.y, location.z, rotation.x, rotation.y, rotation.z,
            rotation.w, fov, data.shift_x, data.shift_y, ortho, 0.0]


def viewport_camera_values(region_3d, width, height):
    """For the 3D viewport's view (perspective or orthographic) at width x height pixels:
    read from its view and projection matrices, so camera views, lens and zoom all agree
    with what the viewport draws (lens shift of a camera view is not carried)."""
    view = region_3d.view_matrix.inverted()
    location, rotation, _ = view.decompose()
    window = region_3d.window_matrix
    if region_3d.is_perspective:
        fov = 2.0 * math.atan(1.0 / window[1][1])
        ortho = 0.0
    else:
        fov = 1.0
        ortho = 2.0 / (window[0][0] if width >= height else window[1][1])
    return [location.x, location.y, location.z, rotation.x, rotation.y, rotation.z,
            rotation.w, fov, 0.0, 0.0, ortho, 0.0]
