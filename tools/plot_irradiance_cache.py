"""Chart of tools/irradiance_cache_study.py results: error (NRMSE, the reference's noise
removed) against seconds, the plain path tracer and the irradiance cache at each accuracy a,
one panel per scene and target; with --table, the tables of docs/benchmarks.md section 0g
(markdown on stdout), whose "plain at that error" is the plain bake of nearest error scaled
by 1/error² and "gain" that time over the bake's.

    /usr/bin/python3 tools/plot_irradiance_cache.py docs/irradiance_cache.json \\
        docs/irradiance_cache_lightmap.json --out docs/irradiance_cache.png
    /usr/bin/python3 tools/plot_irradiance_cache.py docs/irradiance_cache_lightmap.json --table
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
    parser.add_argument("--out", help="the chart to write")
    parser.add_argument("--table", action="store_true", help="print the markdown table")
    args = parser.parse_args()
    rows = [row for path in args.studies for row in json.load(open(path))["rows"]]
    if args.table:
        print_table(rows)
    if args.out:
        plot(rows, args.out)


def plain_time_at(plain, error):
    """Seconds the plain path tracer needs for `error`: its bake of nearest error, 1/error²."""
    nearest = min(plain, key=lambda r: abs(r["nrmse_without_reference_noise"] - error))
    return nearest["seconds"] * (nearest["nrmse_without_reference_noise"] / error) ** 2


def print_table(rows):
    print("| scene (points evaluated, reference noise) | bake | seconds | records (first placement) "
          "| NRMSE / wRRMSE | leave-one-out | plain at that error | gain |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        mine = [r for r in rows if r["scene"] == scene]
        plain = [r for r in mine if r["accuracy"] == 0 and not r.get("denoised_target")]
        for r in mine:
            error = r["nrmse_without_reference_noise"]
            records, loo, extra = "—", "", "| | |"
            if r.get("denoised_target"):
                name = "default bake: target %g%%, denoised" % (100 * r["denoised_target"])
                seconds = plain_time_at(plain, error)
                extra = "| %.1f s | %.1f× |" % (seconds, seconds / r["seconds"])
            elif r["accuracy"] == 0:
                name = "plain, %d paths" % r["samples"]
            else:
                name = "a = %g, %d paths a record" % (r["accuracy"], r["samples"])
                if r.get("cache_target"):
                    name = "a = %g, target %g%%" % (r["accuracy"], 100 * r["cache_target"])
                if not r.get("records"):
                    records = "declined (%.0f%%)" % (100 * (r.get("record_fraction") or 0))
                else:
                    records = "%d (%.0f%%)" % (r["records"], 100 * r["record_fraction"])
                    loo = "%.1f%%" % (100 * (r["predicted_interpolation_error"] or 0))
                    seconds = plain_time_at(plain, error)
                    extra = "| %.1f s | **%.1f×** |" % (seconds, seconds / r["seconds"])
            print("| %s (%d, %.2f%%) | %s | %.2f | %s | %.2f%% / %.2f%% | %s %s"
                  % (scene.replace("_", " "), r["evaluated_points"], 100 * r["reference_noise"],
                     name, r["seconds"], records, 100 * error,
                     100 * r["weighted_relative_rmse"], loo, extra))


def plot(rows, out):
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
    figure.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
