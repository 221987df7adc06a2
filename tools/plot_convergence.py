#!/usr/bin/python3
"""The convergence study of Antiradiance Fig. 5 as a chart: error after k iterations of the
symmetric (blue) and asymmetric (red) schemes, (a) linear and (b) log, from the JSON of
`bakegi converge`.

    build/bakegi converge /tmp/bakegi_scenes/office.bgs --method antiradiance --iterations 40 \\
        --out docs/antiradiance_convergence.json
    /usr/bin/python3 tools/plot_convergence.py docs/antiradiance_convergence.json \\
        --out docs/antiradiance_convergence.png --title "office (mean albedo 0.66)"

Error: relative RMSE (luminance-weighted) of the bake points after k iterations against the
solution iterated `reference_iterations` times; one asymmetric iteration is one radiance
step plus up to four antiradiance steps (the paper's setting).
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the headless backend)

STYLES = {"symmetric": {"color": "tab:blue", "marker": "o"},
          "asymmetric": {"color": "tab:red", "marker": "s"}}


def plot(study, out_path, title):
    figure, (linear, logarithmic) = plt.subplots(1, 2, figsize=(10, 4.2), dpi=120)
    for scheme, runs in study["schemes"].items():
        # A symmetric run that diverged was solved again by the asymmetric scheme: those
        # points belong to the asymmetric curve, so the symmetric one ends where they start.
        own = [r for r in runs if r.get("scheme_used", scheme) == scheme]
        xs = [r["iterations"] for r in own]
        ys = [r["error"] for r in own]
        label = scheme
        if len(own) < len(runs):
            label += f" (diverged at {len(own) + 1}: the driver falls back)"
        for axes in (linear, logarithmic):
            axes.plot(xs, ys, label=label, linewidth=1.3, markersize=3, **STYLES.get(scheme, {}))
    logarithmic.set_yscale("log")
    for axes, name in ((linear, "(a) linear"), (logarithmic, "(b) log")):
        axes.set_xlabel("iterations")
        axes.set_ylabel("error vs. converged solution (relative RMSE)")
        axes.set_title(name, fontsize=9)
        axes.grid(True, which="both", linewidth=0.3, alpha=0.6)
        axes.legend(fontsize=8)
    reference = study.get("reference_scheme") or "symmetric"
    figure.suptitle(f"{title}: {study['points']} bake points; reference: "
                    f"{study['reference_iterations']} iterations ({reference})", fontsize=10)
    figure.tight_layout()
    figure.savefig(out_path)
    plt.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study", help="JSON written by `bakegi converge`")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--title", default="Antiradiance convergence")
    arguments = parser.parse_args()
    with open(arguments.study) as f:
        plot(json.load(f), arguments.out, arguments.title)
    print(f"plot_convergence: wrote {arguments.out}")


if __name__ == "__main__":
    main()
