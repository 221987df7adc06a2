# SPDX-License-Identifier: GPL-3.0-or-later
"""The report of a bake as text for people: the one-line summary the panel and the
operator show, and the meshless and lightmap details of the panel."""

def summary(report):
    seconds = report.get("seconds", {}).get("total", 0.0)
    rays = report.get("rays")
    if rays is None and isinstance(report.get("counts"), dict):
        rays = report["counts"].get("rays")
    rays_text = f", {rays:,} rays" if isinstance(rays, (int, float)) else ""
    method = report.get("method", "")
    used = report.get("method_used")
    if used and used != method:  # the core handed the bake on (setting "fallback")
        method = f"{method} (baked by {used}: see the warnings)"
    grid = report.get("grid")
    if isinstance(grid, dict) and "vertex_count" in grid:
        return (f"{method}: a grid of {grid['vertex_count']:,} vertices in "
                f"{seconds:.2f} s{rays_text}")
    points = report.get("bake_points", 0)
    evaluated = report.get("evaluated_points")
    # Corners of one vertex in one light are baked once (export/point_sharing.py).
    shared = (f" ({evaluated:,} distinct)" if isinstance(evaluated, int) and
              isinstance(points, int) and evaluated < points else "")
    return (f"{method}: {points:,} points{shared} in "
            f"{seconds:.2f} s{rays_text}{_meshless_summary(report)}")


def _meshless_summary(report):
    """The precomputation's figures: basis size, links kept, cache."""
    points = report.get("meshless_points")
    if not isinstance(points, int):
        return ""
    text = f", {points:,} basis functions"
    kept = report.get("meshless_links_kept_percent")
    if isinstance(kept, (int, float)):
        text += f", {kept:.3g}% of links kept"
    cache = report.get("meshless_cache")
    if isinstance(cache, str) and cache not in ("off", ""):
        text += f", cache {cache}"
    return text


def meshless_details(report):
    """Lines for the panel: the statistics of a meshless bake's report."""
    if not isinstance(report.get("meshless_points"), int):
        return []
    seconds = report.get("seconds") or {}
    lines = [f"Basis: {report['meshless_points']:,} functions, levels "
             f"{report.get('meshless_points_per_level', [])}"]
    if "meshless_links" in report:
        lines.append(f"Links: {report['meshless_links']:,} of "
                     f"{report.get('meshless_potential_links', 0):,} "
                     f"({report.get('meshless_links_kept_percent', 0):.3g}%)")
    stages = [("placement", "meshless_placement"), ("refinement", "meshless_refinement"),
              ("bounces", "meshless_bounces"), ("lighting", "meshless_direct")]
    timed = [f"{label} {seconds[key]:.2f} s" for label, key in stages if key in seconds]
    if timed:
        lines.append("Time: " + ", ".join(timed))
    memory = report.get("meshless_precomputation_bytes")
    if isinstance(memory, (int, float)):
        lines.append(f"Memory: {memory / 2**20:.0f} MB precomputed, "
                     f"{report.get('meshless_refinement_rays', 0):,} rays")
    return lines


def lightmap_details(report):
    """Lines for the panel: the atlas of a lightmap bake."""
    lm = report.get("lightmap")
    if not isinstance(lm, dict) or "width" not in lm:
        return []
    lines = [f"Lightmap: {lm['width']} x {lm['height']} atlas, "
             f"{lm.get('covered_texels', 0):,} texels baked, "
             f"{lm.get('rejected_samples', 0):,} samples inside geometry"]
    if lm.get("path"):
        lines.append(f"File: {lm['path']}")
    return lines


def grid_details(report):
    """Lines for the panel: the extent, cells and file of a grid bake."""
    grid = report.get("grid")
    if not isinstance(grid, dict) or "resolution" not in grid:
        return []
    lines = [f"Grid: {grid.get('description', '')}",
             f"{grid.get('invalid_vertices', 0):,} vertices inside geometry (filled), "
             f"{grid.get('file_bytes', 0) / 1e6:.2f} MB"]
    estimated = report.get("estimated_error")
    if isinstance(estimated, (int, float)):
        lines.append(f"Estimated error of Apply Grid's light: {estimated * 100:.1f}% "
                     "(path-traced probes in the box)")
    if grid.get("path"):
        lines.append(f"File: {grid['path']}")
    return lines
