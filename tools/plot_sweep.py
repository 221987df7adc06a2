#!/usr/bin/python3
"""Speed-versus-accuracy chart of a sweep: wall time on x, error on y, log-log, one curve
per method.

    /usr/bin/python3 tools/plot_sweep.py docs/cornell_sweep.json --out docs/cornell_speed_accuracy.png

Input: the JSON written by tools/sweep_cornell.py: {"title": ..., "methods": {name: [run,
...]}, "reference_noise": e or null, ...}, each run with "seconds", "error" and "settings"
(the sample count, the antiradiance bin count, the splatting VPL count or the meshless settings
are written next to each point; meshless has two curves, the full bake and the relight alone).
A horizontal line marks the reference's
own noise: errors near it are not resolved; a dotted one marks how far Cycles' converged
bake lies from the reference beyond both noises (agreement.bias_estimate), where Cycles'
curve must flatten.
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the headless backend)

STYLES = {
    "pathtrace": {"color": "tab:blue", "marker": "o", "label": "bakegi pathtrace"},
    "cycles": {"color": "tab:orange", "marker": "s", "label": "Cycles (Diffuse bake, D+I − D)"},
    "antiradiance": {"color": "tab:green", "marker": "^", "label": "bakegi antiradiance (bins)"},
    "meshless": {"color": "tab:purple", "marker": "D", "label": "bakegi meshless: precompute + first solve"},
    "meshless_relight": {"color": "tab:purple", "marker": "d", "linestyle": "--",
                         "label": "bakegi meshless: relight alone"},
    "splatting": {"color": "tab:red", "marker": "v", "label": "bakegi splatting (one bounce; VPLs)"},
}


def plot(sweep, out_path):
    figure, axes = plt.subplots(figsize=(7.5, 5.0), dpi=120)
    for method, runs in sweep["methods"].items():
        runs = [r for r in runs if r.get("error") is not None and r.get("seconds")]
        if not runs:
            continue
        runs.sort(key=lambda r: (r.get("settings", {}).get("samples", 0), r.get("settings", {}).get("bins", 0),
                                 r.get("settings", {}).get("vpls", 0), r["seconds"]))
        style = dict(STYLES.get(method, {"marker": "^", "label": method}))
        linestyle = style.pop("linestyle", "-")
        xs = [r["seconds"] for r in runs]
        ys = [r["error"] for r in runs]
        axes.plot(xs, ys, linestyle=linestyle, linewidth=1.5, markersize=5, **style)
        for r in runs:
            settings = r.get("settings", {})
            label = settings.get("samples", settings.get("bins", settings.get("vpls", r.get("label"))))
            if label is not None:
                axes.annotate(str(label), (r["seconds"], r["error"]), textcoords="offset points",
                              xytext=(4, 4), fontsize=7, color=style.get("color", "black"))
    noise = sweep.get("reference_noise")
    if noise:
        axes.axhline(noise, color="gray", linestyle="--", linewidth=1.0,
                     label=f"reference noise ≈ {noise:.2g}")
    bias = sweep.get("agreement", {}).get("bias_estimate")
    if bias:
        axes.axhline(bias, color="tab:orange", linestyle=":", linewidth=1.0,
                     label=f"Cycles vs reference, beyond noise ≈ {bias:.2g}")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("wall time (s)")
    axes.set_ylabel("error: relative RMSE, luminance-weighted")
    axes.set_title(sweep.get("title", "speed versus accuracy"), fontsize=10)
    axes.grid(True, which="both", linewidth=0.3, alpha=0.6)
    axes.legend(fontsize=8)
    subtitle = sweep.get("subtitle")
    if subtitle:
        figure.text(0.5, 0.005, subtitle, ha="center", va="bottom", fontsize=7, color="dimgray")
    figure.tight_layout(rect=(0, 0.03, 1, 1))
    figure.savefig(out_path)
    plt.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep", help="sweep JSON (tools/sweep_cornell.py)")
    parser.add_argument("--out", required=True, help="PNG to write")
    arguments = parser.parse_args()
    with open(arguments.sweep) as f:
        plot(json.load(f), arguments.out)
    print(f"plot_sweep: wrote {arguments.out}")


if __name__ == "__main__":
    main()
