#!/usr/bin/env python3
"""Chart of tools/ivg_sweep.py's runs on one scene: error against grid resolution (per rays
per hemisphere; Apply Grid's default reading, which sees the scene, and the paper's), and
the grid bake's seconds.

    python3 tools/plot_ivg.py docs/ivg_cornell.json --scene cornell_area --out docs/ivg_cornell.png
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sweep")
    parser.add_argument("--scene", default="cornell_area")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    with open(args.sweep) as f:
        # The scene's own box (rows of a widened box, --pad-cells, are apart).
        runs = [r for r in json.load(f)["runs"]
                if r["scene"] == args.scene and not r.get("pad_cells")]
    fig, (error_axes, time_axes) = plt.subplots(1, 2, figsize=(10, 4))
    for rays in sorted({r["rays_per_hemisphere"] for r in runs}):
        rows = sorted((r for r in runs if r["rays_per_hemisphere"] == rays),
                      key=lambda r: r["cells_on_longest_axis"])
        cells = [r["cells_on_longest_axis"] for r in rows]
        error_axes.plot(cells, [100 * r["visibility_absolute"]["nrmse"] for r in rows], "o-",
                        label=f"{rays} rays: Apply Grid (visibility, |n|)")
        error_axes.plot(cells, [100 * r["trilinear"]["nrmse"] for r in rows], "s--", alpha=0.7,
                        label=f"{rays} rays: the paper's reading (n\u00b2, no scene)")
        time_axes.plot(cells, [r["seconds"] for r in rows], "o-", label=f"{rays} rays")
    noise = 100 * runs[0]["reference_noise"] if runs else 0.0
    error_axes.axhline(10, color="grey", lw=0.8)
    error_axes.set_xlabel("cells on the longest axis")
    error_axes.set_ylabel("NRMSE against the reference (%)")
    error_axes.set_title(f"{args.scene}: grid light (trilinear); reference noise {noise:.1f}%",
                         fontsize=9)
    error_axes.legend(fontsize=7)
    time_axes.set_yscale("log")
    time_axes.set_xlabel("cells on the longest axis")
    time_axes.set_ylabel("grid bake seconds (2 cores)")
    time_axes.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
