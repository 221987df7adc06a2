# SPDX-License-Identifier: GPL-3.0-or-later
"""The render engine "BakeGI Preview" (issue 17): direct light plus one bounce splatted
from reflective-shadow-map VPLs through the adaptive multiresolution buffer (Nichols & Wyman
2009), from the camera (F12) and in the viewport's rendered shading."""

from . import engine


def register():
    engine.register()


def unregister():
    engine.unregister()
