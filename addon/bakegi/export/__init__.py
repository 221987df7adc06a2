# SPDX-License-Identifier: GPL-3.0-or-later
"""Reading Blender for the core (Blender -> core; nothing here changes the user's data):

    targets.py      which objects are baked, linked duplicates
    scene.py        the evaluated scene -> a core Scene (meshes, instances, lights), and the
                    export of one bake (scene, points, atlas)
    points.py       the targets' bake points and display probes
    atlas.py        the lightmap atlas's tiles and texel samples
    materials.py    what the core needs of a material
    world.py        the world's radiance
    node_tree.py    walking node trees (materials, world, lights)
    mesh_arrays.py  mesh data as numpy arrays
"""
