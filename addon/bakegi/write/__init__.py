# SPDX-License-Identifier: GPL-3.0-or-later
"""Writing into Blender (core -> Blender): every change the add-on makes to the user's data
happens here, after a bake succeeded (or before it, for lightmap UV maps, undone on failure).

    attributes.py      the BakeGI_Indirect color attribute; removing a bake
    file_names.py      file and folder names made from scene names
    grid_file.py       the grid's file, and Apply Grid
    lightmap_image.py  the lightmap image and each object's tile
    material_hook.py   the Material Preview hook (and its undoing)
    uv_maps.py         lightmap UV maps made where missing
    web_scene.py       Export for Web
"""
