#!/usr/bin/env python3
"""Chart of tools/ivg_lod.py's run: grid lighting's error against the share of triangles
kept, per grid resolution, with a direct bake of the same points at the defaults for scale.

    python3 tools/plot_ivg_lod.py docs/ivg_lod.json --out docs/ivg_lod.png
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    with open(args.run) as f:
        run = json.load(f)
    rows = run["rows"]
    fig, axes = plt.subplots(figsize=(6.5, 4))
    for cells in sorted({r["cells_on_longest_axis"] for r in rows}):
        mine = sorted((r for r in rows if r["cells_on_longest_axis"] == cells),
                      key=lambda r: r["ratio"])
        axes.plot([100 * r["ratio"] for r in mine], [100 * r["apply_grid"]["nrmse"] for r in mine],
                  "o-", label=f"Apply Grid, {cells}\u00b3 grid baked once at full detail")
    coarsest = rows[0]["cells_on_longest_axis"]
    first = sorted((r for r in rows if r["cells_on_longest_axis"] == coarsest),
                   key=lambda r: r["ratio"])
    axes.plot([100 * r["ratio"] for r in first],
              [100 * r["direct_bake_at_defaults"]["nrmse"] for r in first], "s--", color="grey",
              label="direct bake of each level (path tracer defaults)")
    axes.axhline(12, color="grey", lw=0.8, ls=":")
    axes.set_xscale("log")
    axes.invert_xaxis()
    axes.set_xlabel("triangles kept (% of the full scene, meshoptimizer)")
    axes.set_ylabel("NRMSE against the level's reference (%)")
    noise = 100 * max(r["reference_noise"] for r in rows)
    axes.set_title(f"{run['scene']}: grid light per level of detail "
                   f"(reference noise \u2264 {noise:.1f}%)", fontsize=9)
    axes.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
