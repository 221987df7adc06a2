# SPDX-License-Identifier: GPL-3.0-or-later
"""How big each object's lightmap is, and where it sits in the scene's lightmap atlas.

Every object's lightmap UV map spans [0,1]^2. Its tile in the atlas is square, sized from
a texel density: an object with world area A whose UV charts cover a fraction U of [0,1]^2
needs side = density * sqrt(A / U) texels for `density` texels per metre on its surfaces.
The side is clamped to [MIN_SIDE, max_side], so a pebble does not get a huge tile and a
wall is not blurry. Tiles are packed on shelves into one atlas (the way Unity's lightmapper
gives each renderer a scale and offset into a shared lightmap), with `gap` texels between
tiles, so that the dilated gutters of two objects never meet inside a filter footprint.
A material shared by several objects then needs one image: the material hook reads the
object's tile through its scale and offset (custom properties, see write/lightmap_image.py).

Pure Python and numpy (no bpy): tested outside Blender.
"""

import math
from dataclasses import dataclass
from typing import List

import numpy as np

MIN_SIDE = 8
MAX_ATLAS_SIDE = 8192  # the core's largest lightmap side


@dataclass
class Tile:
    """One object's square tile: texels [x, x+side) x [y, y+side) of the atlas."""

    side: int
    x: int = 0
    y: int = 0


@dataclass
class AtlasLayout:
    width: int
    height: int
    tiles: List[Tile]
    density_scale: float  # < 1 when the atlas had to shrink every tile to fit
    clamped: List[int]  # indices of tiles clamped to max_side (or MIN_SIDE)

    def scale_offset(self, index):
        """(scale_u, scale_v, offset_u, offset_v): atlas UV = uv * scale + offset."""
        t = self.tiles[index]
        return (t.side / self.width, t.side / self.height, t.x / self.width, t.y / self.height)

    def to_atlas(self, index, uvs):
        """Object UVs (n, 2) -> atlas UVs, clipped to the object's tile."""
        su, sv, ou, ov = self.scale_offset(index)
        uv = np.clip(np.asarray(uvs, np.float64), 0.0, 1.0)
        return np.stack([uv[:, 0] * su + ou, uv[:, 1] * sv + ov], axis=1).astype(np.float32)


def triangle_areas(corners):
    """Areas of triangles given as (3T, d) corners, d = 2 (UV) or 3 (world)."""
    c = np.asarray(corners, np.float64).reshape(-1, 3, corners.shape[-1])
    e1, e2 = c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]
    if c.shape[-1] == 2:
        return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)


def tile_side(world_area, uv_area, texels_per_meter, max_side):
    """The side (texels) that gives texels_per_meter on the surfaces, clamped. The UV area
    counts only what lies in [0,1]^2 (at most 1); an empty UV map gets MIN_SIDE."""
    uv_area = min(max(float(uv_area), 0.0), 1.0)
    if uv_area <= 1e-12 or world_area <= 0.0:
        return MIN_SIDE
    side = math.ceil(texels_per_meter * math.sqrt(world_area / uv_area))
    return int(min(max(side, MIN_SIDE), max_side))


def _shelf_pack(sides, width, gap):
    """Places squares (largest first) on shelves of a `width`-wide atlas; returns (xs, ys,
    height). Every tile keeps `gap` texels from its neighbours and from the atlas border."""
    order = sorted(range(len(sides)), key=lambda i: -sides[i])
    xs, ys = [0] * len(sides), [0] * len(sides)
    x, y, shelf = gap, gap, 0
    for i in order:
        s = sides[i]
        if x + s + gap > width and x > gap:
            y += shelf + gap
            x, shelf = gap, 0
        xs[i], ys[i] = x, y
        x += s + gap
        shelf = max(shelf, s)
    return xs, ys, y + shelf + gap


def pack_atlas(sides, gap, max_atlas_side=MAX_ATLAS_SIDE):
    """Packs square tiles into one atlas no wider or taller than max_atlas_side, as square as
    shelves allow; when they do not fit, every side shrinks by the same factor (and
    density_scale says by how much)."""
    if not sides:
        raise ValueError("no tiles to pack")
    gap = max(int(gap), 0)
    scale = 1.0
    current = [int(s) for s in sides]
    for _ in range(64):
        area = sum((s + gap) ** 2 for s in current)
        width = max(max(current) + 2 * gap, math.ceil(math.sqrt(area)))
        while True:
            xs, ys, height = _shelf_pack(current, width, gap)
            if height <= width or width >= max_atlas_side:
                break
            width = min(max_atlas_side, math.ceil(width * 1.05) + 1)
        width = _round_up(width, 4)
        height = _round_up(height, 4)
        if width <= max_atlas_side and height <= max_atlas_side:
            return AtlasLayout(width, height, [Tile(s, x, y) for s, x, y in zip(current, xs, ys)],
                               scale, [])
        shrink = 0.97 * max_atlas_side / max(width, height)
        scale *= shrink
        current = [max(MIN_SIDE, int(s * shrink)) for s in current]
    raise ValueError("the lightmaps do not fit into one atlas; bake fewer objects at once")


def _round_up(value, multiple):
    return int(math.ceil(value / multiple) * multiple)


def layout(world_areas, uv_areas, texels_per_meter, max_side, padding):
    """The atlas for objects with these areas: sides from the density (one for all, or one
    per object), then packed with a gap of 2 * padding (each tile's gutter dilates `padding`
    texels, so two gutters meet in the middle of the gap). Returns an AtlasLayout with
    `clamped` listing the objects whose tile hit max_side."""
    densities = (list(texels_per_meter) if isinstance(texels_per_meter, (list, tuple))
                 else [texels_per_meter] * len(world_areas))
    if len(densities) != len(world_areas) or min(densities, default=1.0) <= 0:
        raise ValueError("every texels_per_meter must be > 0")
    if max_side < MIN_SIDE:
        raise ValueError("max_side must be >= %d" % MIN_SIDE)
    sides, clamped = [], []
    for i, (a, u, d) in enumerate(zip(world_areas, uv_areas, densities)):
        s = tile_side(a, u, d, max_side)
        unclamped = math.ceil(d * math.sqrt(a / u)) if u > 1e-12 and a > 0 else s
        if unclamped > max_side:
            clamped.append(i)
        sides.append(s)
    atlas = pack_atlas(sides, 2 * max(int(padding), 1))
    atlas.clamped = clamped
    return atlas
