"""Chart of tools/denoise_study.py results: error (NRMSE) against seconds, path tracer with
and without the denoiser, at fixed samples and to target errors, one panel per scene.

    /usr/bin/python3 tools/plot_denoise_study.py docs/denoise_cornell.json \\
        docs/denoise_two_rooms.json docs/denoise_office.json --out docs/denoise_speed_accuracy.png
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("studies", nargs="+")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    studies = [json.load(open(path)) for path in args.studies]
    figure, axes = plt.subplots(1, len(studies), figsize=(4.2 * len(studies), 3.8), squeeze=False)
    for ax, study in zip(axes[0], studies):
        for denoise, style, label in ((False, "o-", "path tracer"), (True, "s-", "+ denoise")):
            rows = [r for r in study["rows"] if r["denoise"] == denoise]
            ax.plot([r["seconds"] for r in rows], [100 * r["nrmse"] for r in rows], style,
                    label=label)
            for r in rows:
                ax.annotate(str(r["samples"]), (r["seconds"], 100 * r["nrmse"]), fontsize=7,
                            textcoords="offset points", xytext=(4, 3))
        for denoise, style, label in ((False, "^--", "to a target"),
                                      (True, "v--", "to a target + denoise")):
            rows = [r for r in study.get("target_rows", []) if r["denoise"] == denoise]
            if not rows:
                continue
            ax.plot([r["seconds"] for r in rows], [100 * r["nrmse"] for r in rows], style,
                    label=label)
            for r in rows:
                ax.annotate("%g%%" % (100 * r["target_error"]), (r["seconds"], 100 * r["nrmse"]),
                            fontsize=7, textcoords="offset points", xytext=(4, -9))
        ax.axhline(100 * study["reference_noise"], color="grey", lw=0.8, ls=":",
                   label="reference noise")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("seconds (2 cores)")
        ax.set_ylabel("NRMSE (%)")
        ax.set_title("%s (%s points)" % (study["scene"], study.get("points") or "?"))
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
