"""Chart of tools/suite_cycles.py's rows: per scene, Cycles' time against its error (its
measured bake and the 1/sqrt(samples) law through its error and through its own noise) and
bakegi's default bake.

    /usr/bin/python3 tools/plot_suite_cycles.py docs/suite_cycles.json docs/suite_cycles.png
"""

import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy  # noqa: E402


def main():
    source, out = sys.argv[1], sys.argv[2]
    with open(source) as f:
        rows = json.load(f)["rows"]
    figure, axes = plt.subplots(figsize=(8.5, 5.5))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, row in enumerate(rows):
        color = colors[k % len(colors)]
        c, b = row["cycles"], row["bakegi"]
        error = c["nrmse_without_reference_noise"]
        errors = numpy.geomspace(0.02, max(error, 0.5), 50)
        for measured, style in ((error, "--"), (c["own_noise"], ":")):
            seconds = c["fixed_seconds"] + c["seconds_per_sample"] * c["samples"] * (measured / errors) ** 2
            axes.plot(100 * errors, seconds, style, color=color, linewidth=1)
        axes.plot(100 * error, c["seconds"], "s", color=color, markerfacecolor="none")
        axes.plot(100 * b["nrmse_without_reference_noise"], b["seconds"], "o", color=color,
                  label=f"{row['scene']} ({row['ratio']:.0f}x)")
    axes.axvline(5.0, color="grey", linewidth=0.8)
    axes.set_xscale("log")
    axes.set_yscale("log")
    ticks = [2, 3, 5, 10, 20, 50]
    axes.set_xticks(ticks)
    axes.set_xticklabels([str(t) for t in ticks])
    axes.set_xlabel("NRMSE against the reference, reference noise removed (%)")
    axes.set_ylabel("seconds (2 cores)")
    axes.set_title("bakegi's default bake (dots) and Cycles (squares: measured; lines: 1/sqrt(samples)\n"
                   "through its error (dashed) and through its own noise (dotted))")
    axes.title.set_fontsize(10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(title="scene (Cycles time / bakegi time at bakegi's error)", fontsize=8,
                title_fontsize=8)
    figure.tight_layout()
    figure.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
