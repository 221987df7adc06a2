"""Chart of tools/irradiance_cache_study.py results: error (NRMSE, the reference's noise
removed) against seconds, the plain path tracer and the irradiance cache at each accuracy a,
one panel per scene and target.

    /usr/bin/python3 tools/plot_irradiance_cache.py docs/irradiance_cache.json \\
        docs/irradiance_cache_lightmap.json --out docs/irradiance_cache.png
"""

import argparse
import json
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("studies", nargs="+")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    rows = [row for path in args.studies for row in json.load(open(path))["rows"]]
    panels = []
    for row in rows:
        key = (row["scene"], row.get("target", "CORNER"))
        if key not in panels:
            panels.append(key)
    columns = min(4, len(panels))
    lines = math.ceil(len(panels) / columns)
    figure, axes = plt.subplots(lines, columns, figsize=(4.0 * columns, 3.5 * lines),
                                squeeze=False)
    for ax, (scene, target) in zip(axes.flat, panels):
        mine = [r for r in rows if r["scene"] == scene and r.get("target", "CORNER") == target]
        plain = sorted((r for r in mine if r["accuracy"] == 0 and not r.get("denoised_target")),
                       key=lambda r: r["seconds"])
        denoised = sorted((r for r in mine if r.get("denoised_target")),
                          key=lambda r: r["seconds"])
        if denoised:
            ax.plot([r["seconds"] for r in denoised],
                    [100 * r["nrmse_without_reference_noise"] for r in denoised], "^:",
                    color="gray", label="default bake (target, denoised)")
        ax.plot([r["seconds"] for r in plain],
                [100 * r["nrmse_without_reference_noise"] for r in plain], "ko-",
                label="path tracer")
        for accuracy in sorted({r["accuracy"] for r in mine if r["accuracy"] > 0}):
            used = sorted((r for r in mine if r["accuracy"] == accuracy and r.get("records")),
                          key=lambda r: r["seconds"])
            if used:
                ax.plot([r["seconds"] for r in used],
                        [100 * r["nrmse_without_reference_noise"] for r in used], "s--",
                        label="cache a = %g" % accuracy)
        ax.set_xscale("log")
        ax.set_yscale("log")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(ticker.FormatStrFormatter("%g"))
            axis.set_minor_formatter(ticker.FormatStrFormatter("%g"))
        ax.tick_params(which="both", labelsize=7)
        ax.set_title("%s (%s)" % (scene, "texels" if target == "LIGHTMAP" else "corners"),
                     fontsize=9)
        ax.set_xlabel("seconds (2 threads)", fontsize=8)
        ax.set_ylabel("NRMSE % (reference noise removed)", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    figure.tight_layout()
    figure.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
