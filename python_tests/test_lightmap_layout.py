"""bakegi.lightmap_layout: tile sizes from the texel density, and an atlas without overlaps."""

import itertools
import math

import numpy as np
import pytest

from bakegi import lightmap_layout as ll


def test_the_tile_side_gives_the_density_on_the_surface():
    # 4 m^2 whose charts fill a quarter of the UV square: 16 m^2 per UV unit, 4 m per side.
    assert ll.tile_side(4.0, 0.25, 10.0, 4096) == 40
    assert ll.tile_side(4.0, 0.25, 10.0, 32) == 32  # clamped
    assert ll.tile_side(0.0, 0.25, 10.0, 4096) == ll.MIN_SIDE


def test_triangle_areas_in_uv_and_world():
    uv = np.array([[0, 0], [1, 0], [0, 1]], float)
    world = np.array([[0, 0, 0], [2, 0, 0], [0, 3, 0]], float)
    assert ll.triangle_areas(uv)[0] == pytest.approx(0.5)
    assert ll.triangle_areas(world)[0] == pytest.approx(3.0)


@pytest.mark.parametrize("seed", range(5))
def test_packed_tiles_keep_their_gap_and_stay_inside(seed):
    rng = np.random.default_rng(seed)
    sides = [int(s) for s in rng.integers(ll.MIN_SIDE, 300, size=40)]
    gap = 8
    atlas = ll.pack_atlas(sides, gap)
    assert atlas.width % 4 == 0 and atlas.height % 4 == 0
    for t in atlas.tiles:
        assert t.x >= gap and t.y >= gap
        assert t.x + t.side + gap <= atlas.width and t.y + t.side + gap <= atlas.height
    for a, b in itertools.combinations(atlas.tiles, 2):
        apart_x = a.x + a.side + gap <= b.x or b.x + b.side + gap <= a.x
        apart_y = a.y + a.side + gap <= b.y or b.y + b.side + gap <= a.y
        assert apart_x or apart_y, (a, b)
    # Shelves waste space, but not most of it.
    used = sum(s * s for s in sides)
    assert used / (atlas.width * atlas.height) > 0.4


def test_an_atlas_too_large_shrinks_every_tile_alike():
    atlas = ll.pack_atlas([4096] * 8, 4, max_atlas_side=8192)
    assert max(atlas.width, atlas.height) <= 8192
    assert atlas.density_scale < 1.0
    assert len({t.side for t in atlas.tiles}) == 1


def test_to_atlas_maps_the_unit_square_onto_the_tile():
    atlas = ll.layout([1.0, 4.0], [1.0, 1.0], 64.0, 4096, padding=2)
    for index, tile in enumerate(atlas.tiles):
        corners = atlas.to_atlas(index, np.array([[0, 0], [1, 1]], float))
        assert corners[0] == pytest.approx((tile.x / atlas.width, tile.y / atlas.height))
        assert corners[1] == pytest.approx(((tile.x + tile.side) / atlas.width,
                                            (tile.y + tile.side) / atlas.height))
    assert atlas.tiles[1].side == pytest.approx(2 * atlas.tiles[0].side, abs=1)
