"""bakegi.export.point_sharing: which corners the add-on offers the core to bake once."""

import numpy as np

from bakegi.export import point_sharing


def grid_corners(normals=None):
    """The 16 face corners of a 2 x 2 grid of unit quads in z = 0 (9 vertices), in loop
    order, with their vertex indices."""
    vertices = np.array([(x, y, 0.0) for y in range(3) for x in range(3)], np.float32)
    quads = [(y * 3 + x, y * 3 + x + 1, y * 3 + x + 4, y * 3 + x + 3)
             for y in range(2) for x in range(2)]
    loop_vertex = np.array([v for q in quads for v in q])
    if normals is None:
        normals = np.tile(np.float32([0, 0, 1]), (len(loop_vertex), 1))
    return vertices[loop_vertex], normals, loop_vertex


def test_corners_of_one_vertex_name_the_first_of_them():
    positions, normals, loop_vertex = grid_corners()
    candidates = point_sharing.share_candidates(positions, normals)
    for corner, candidate in enumerate(candidates):
        assert loop_vertex[candidate] == loop_vertex[corner]
        assert candidate <= corner
        assert candidates[candidate] == candidate  # a group's first names itself
    assert len(set(candidates.tolist())) == 9  # one group per vertex
    assert (np.bincount(loop_vertex)[loop_vertex[candidates]] >= 1).all()


def test_a_different_normal_is_a_different_group():
    positions, normals, loop_vertex = grid_corners()
    normals = normals.copy()
    centre_corners = np.flatnonzero(loop_vertex == 4)  # the middle vertex: 4 corners
    normals[centre_corners[1]] = (0.0, np.sin(0.01), np.cos(0.01))  # 0.6 degrees off
    candidates = point_sharing.share_candidates(positions, normals)
    assert candidates[centre_corners[1]] == centre_corners[1]
    assert candidates[centre_corners[2]] == candidates[centre_corners[0]]
    # A rounding-level difference (1e-6) still shares.
    normals[centre_corners[1]] = (0.0, 1e-6, 1.0)
    candidates = point_sharing.share_candidates(positions, normals)
    assert candidates[centre_corners[1]] == candidates[centre_corners[0]]


def test_indices_are_offset_to_the_target_slice():
    positions, normals, _ = grid_corners()
    alone = point_sharing.share_candidates(positions, normals)
    offset = point_sharing.share_candidates(positions, normals, first_index=100)
    assert (offset == alone + 100).all()
    assert offset.dtype == np.uint32
    assert len(point_sharing.share_candidates(np.zeros((0, 3)), np.zeros((0, 3)))) == 0
