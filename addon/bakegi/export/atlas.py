# SPDX-License-Identifier: GPL-3.0-or-later
"""The lightmap atlas of a LIGHTMAP bake: every target's tile placed by lightmap_layout, its
lightmap UVs scaled into the atlas, and the core's texel samples (native.Lightmaps) built
from them on a worker thread."""

import time
from dataclasses import dataclass, field
from typing import Dict

import numpy as np

from .. import lightmap_layout, native
from ..native import BakeGIError
from ..request import LightmapOptions
from .targets import BakeTarget


@dataclass
class ExportedLightmaps:
    """The atlas of a LIGHTMAP bake: the core's texel samples and where each target sits."""

    lightmaps: native.Lightmaps
    width: int
    height: int
    options: LightmapOptions
    created_uv_maps: list = field(default_factory=list)  # [(object, mesh)] made for this bake
    rejected_samples: int = 0
    covered_texels: int = 0
    density_scale: float = 1.0
    seconds: Dict[str, float] = field(default_factory=dict)
    # Before build(): the core scene and, per target, (core mesh id, atlas UVs (3T, 2)).
    scene: native.Scene = None
    pending: list = field(default_factory=list)
    stage: str = "rasterizing lightmap texels"  # what build() does now (the progress text)

    def build(self):
        """Rasterizes every target's texels into the atlas and drops those inside geometry
        (core work, seconds on large scenes; no bpy, so it may run on a worker thread).
        Returns the bake points (a new native.Points)."""
        t0 = time.perf_counter()
        for i, (mesh_id, uvs) in enumerate(self.pending):
            self.stage = f"rasterizing lightmap texels ({i + 1}/{len(self.pending)} objects)"
            if i == 0:
                self.lightmaps.add(self.scene, mesh_id, uvs, self.width, self.height)
            else:
                self.lightmaps.add_to(0, self.scene, mesh_id, uvs)
        self.pending = []
        self.seconds["rasterize"] = time.perf_counter() - t0
        if self.options.reject_inside:
            t1 = time.perf_counter()
            self.stage = "rejecting lightmap texels inside geometry"
            self.rejected_samples = self.lightmaps.reject_inside(self.scene)
            self.seconds["reject_inside"] = time.perf_counter() - t1
        self.covered_texels = self.lightmaps.info(0)["covered_texels"]
        return self.lightmaps.points()

    def close(self):
        self.lightmaps.close()


# Bytes a texel sample takes in the core (kBytesPerSample, native/src/lightmap/lightmap_set.cpp).
SAMPLE_BYTES = 76


def check_sample_budget(uv_areas, tile_sides, budget_mb):
    """Refuses an atlas whose texel samples surely exceed the memory budget, before any is
    rasterized (the core checks each object's upper bound as it rasterizes it, which refused a
    16.7-million-texel atlas only after 32 s of work). Every (texel, triangle) overlap is one
    sample of weight at most 1, and a triangle's weights sum to its area in texels, so the
    samples are at least the charts' area in texels."""
    least = sum(area * side * side for area, side in zip(uv_areas, tile_sides))
    if least * SAMPLE_BYTES > budget_mb * 2 ** 20:
        raise BakeGIError(
            "BAKEGI_ERROR_OUT_OF_MEMORY",
            f"the lightmaps need at least {least:,.0f} texel samples "
            f"({least * SAMPLE_BYTES / 2 ** 20:,.0f} MiB), more than the {budget_mb} MiB budget "
            "(memory_budget_mb); lower the texel density or the lightmap size, or raise the "
            "budget")


def lightmap_points(exporter, targets, options, warnings):
    """Lays the targets' lightmaps out in one atlas (their texels are rasterized by
    ExportedLightmaps.build()). Returns (ExportedLightmaps, [BakeTarget])."""
    sources = []
    for obj in targets:
        source = exporter.lightmap_sources.get(obj.name)
        if source is None:
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT",
                              f"'{obj.name}' has no triangles to bake a lightmap on")
        sources.append(source)
    uv_areas = []
    for obj, source in zip(targets, sources):
        outside = (source.uvs < -1e-4) | (source.uvs > 1.0 + 1e-4)
        if outside.any():
            warnings.append(f"'{obj.name}': UV map '{options.uv_map}' reaches outside [0, 1]; "
                            "those parts are clipped to the edge of its lightmap")
        uv_areas.append(float(lightmap_layout.triangle_areas(
            np.clip(source.uvs, 0.0, 1.0)).sum()))
    # An object's own density (Object properties > BakeGI Lightmap; 0 = the bake's).
    densities = [float(getattr(obj, "bakegi_texels_per_meter", 0.0)) or
                 options.texels_per_meter for obj in targets]
    atlas = lightmap_layout.layout([s.world_area for s in sources], uv_areas, densities,
                                   options.max_side, options.padding)
    for i in atlas.clamped:
        warnings.append(f"'{targets[i].name}': its lightmap is limited to {options.max_side} "
                        f"texels, below {densities[i]:g} texels per metre")
    if atlas.density_scale < 1.0:
        warnings.append(f"the lightmaps did not fit one {lightmap_layout.MAX_ATLAS_SIDE}-texel "
                        f"atlas; every object got {atlas.density_scale:.0%} of the asked "
                        "density")
    check_sample_budget(uv_areas, [tile.side for tile in atlas.tiles], options.memory_budget_mb)
    samples = native.Lightmaps()
    samples.set_memory_budget(options.memory_budget_mb)
    result = ExportedLightmaps(samples, atlas.width, atlas.height, options,
                               density_scale=atlas.density_scale, scene=exporter.scene,
                               pending=[(s.mesh_id, atlas.to_atlas(i, s.uvs))
                                        for i, s in enumerate(sources)])
    bake_targets = [BakeTarget(obj.name, obj.data.name_full, "LIGHTMAP", 0, 0,
                               atlas.scale_offset(i), atlas.tiles[i].side)
                    for i, obj in enumerate(targets)]
    return result, bake_targets
