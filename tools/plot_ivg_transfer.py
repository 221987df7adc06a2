#!/usr/bin/env python3
"""The paper's Fig. 6 for bakegi's page: time to stream the whole grid into the page per
request size, quantized against floats (addon/web/test/run.mjs --fig6 writes the JSON).

    python3 tools/plot_ivg_transfer.py out/web_tests/transfer.json --out docs/ivg_transfer.png
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("transfer")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    with open(args.transfer) as f:
        rows = json.load(f)
    fig, (time_axes, part_axes) = plt.subplots(1, 2, figsize=(10, 4))
    for encoding, colour in (("quantized", "C0"), ("factored", "C3")):
        mine = sorted((r for r in rows if r["encoding"] == encoding),
                      key=lambda r: r["vectors_per_request"])
        sizes = [r["vectors_per_request"] for r in mine]
        label = f"{encoding} ({mine[0]['bytes'] / 1e6:.2f} MB)"
        time_axes.plot(sizes, [r["ms"] / 1000 for r in mine], "o-", color=colour,
                       label=f"{label}: total")
        time_axes.plot(sizes, [r["fetch_ms"] / 1000 for r in mine], "s--", color=colour,
                       alpha=0.6, label=f"{encoding}: transfer alone")
        part_axes.plot(sizes, [r["decode_ms"] / 1000 for r in mine], "o-", color=colour,
                       label=f"{encoding}: decoding")
        part_axes.plot(sizes, [r["upload_ms"] / 1000 for r in mine], "s--", color=colour,
                       alpha=0.6, label=f"{encoding}: texture uploads")
    for axes in (time_axes, part_axes):
        axes.set_xscale("log", base=2)
        axes.set_xlabel("grid vectors per request")
        axes.legend(fontsize=7)
    time_axes.set_yscale("log")
    time_axes.set_ylabel("seconds for the whole grid")
    time_axes.set_title("streaming the grid into the page (loopback, headless Chromium)",
                        fontsize=9)
    part_axes.set_ylabel("seconds")
    part_axes.set_title("where the page spends it", fontsize=9)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
