"""Writes the real-scene suite's results (tools/real_scenes.py) into the docs: one JSON per
scene and target under docs/real_scenes/, one chart per scene (docs/real_scenes/<scene>.png:
per method and target, the error against the reference, the bake's own estimate beside it,
and the seconds), and the table between the markers of docs/real_scenes.md.

    /usr/bin/python3 tools/real_scenes_report.py WORK   (re-writes the docs from WORK's results)
"""

import glob
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(ROOT, "docs")
FOLDER = os.path.join(DOCS, "real_scenes")
PAGE = os.path.join(DOCS, "real_scenes.md")
BEGIN, END = "<!-- real-scenes table begin -->", "<!-- real-scenes table end -->"
# Targets of issue 12 for antiradiance and meshless at their defaults (NRMSE).
TARGETS = {"cornell_area": 0.05, "cornell_emissive": 0.05, "two_rooms": 0.10, "office": 0.10, "maze": 0.10,
           "sponza_spot": 0.15, "sponza_sun": 0.15, "living_room": 0.15, "bunny_dragon": 0.15}


def percent(x):
    return "–" if x is None else f"{100 * x:.1f}%"


def table(results):
    lines = [
        "| scene | target | bake points | reference (paths, noise) | method | seconds | memory (report / peak RSS) "
        "| NRMSE (noise removed) | weighted rel. RMSE | bias | estimated (interval) | est./true | worst object (NRMSE, share) "
        "| issue target |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        for m in r["methods"]:
            method = m["method"]
            if m.get("method_used") and m["method_used"] != method:  # the core's fallback
                method += f" → {m['method_used']}"
            head = (f"| {r['scene']} | {r['target'].lower()} | {r.get('bake_points') or '–'} | "
                    f"{r['reference_samples']}, {percent(r['reference_noise'])} | {method} | ")
            if "failed" in m:
                lines.append(head + f"**failed**: {m['failed'][:120]} | | | | | | | | |")
                continue
            worst = m["per_object"][0] if m.get("per_object") else None
            target = TARGETS.get(r["scene"]) if m["method"] in ("antiradiance", "meshless") else None
            fell_back = m.get("method_used", m["method"]) != m["method"]
            met = "" if target is None else ("met" if m["nrmse_without_reference_noise"] <= target else
                                             f"**not met** (≤ {percent(target)})")
            if fell_back and target is not None:
                met = "**not met**: the method did not bake (fallback)"
            interval = m.get("estimated_error_interval") or [None, None]
            lines.append(
                head + f"{m['seconds']:.1f} | {m['memory_bytes'] / 2**20:.0f} / {m['peak_rss_bytes'] / 2**20:.0f} MB | "
                f"{percent(m['nrmse'])} ({percent(m['nrmse_without_reference_noise'])}) | "
                f"{percent(m['weighted_relative_rmse'])} | {100 * m['bias']:+.1f}% | "
                f"{percent(m.get('estimated_error'))} ({percent(interval[0])}–{percent(interval[1])}) | "
                f"{'–' if m.get('estimate_over_true') is None else format(m['estimate_over_true'], '.2f')} | "
                + (f"{worst['object']} ({percent(worst['nrmse'])}, {100 * worst['error_share']:.0f}%)" if worst else "–")
                + f" | {met} |")
    return "\n".join(lines)


def chart(scene, results, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [(r["target"].lower(), m) for r in results for m in r["methods"] if "failed" not in m]
    if not rows:
        return False
    labels = [f"{m['method']}{'*' if m.get('method_used', m['method']) != m['method'] else ''}\n{target}"
              for target, m in rows]
    true = [100 * m["nrmse_without_reference_noise"] for _, m in rows]
    estimated = [100 * (m.get("estimated_error") or 0.0) for _, m in rows]
    seconds = [m["seconds"] for _, m in rows]
    figure, (left, right) = plt.subplots(1, 2, figsize=(10, 3.6))
    x = range(len(rows))
    left.bar([i - 0.2 for i in x], true, 0.4, label="error against the reference (NRMSE, its noise removed)")
    left.bar([i + 0.2 for i in x], estimated, 0.4, label="the bake's own estimate")
    if scene in TARGETS:
        left.axhline(100 * TARGETS[scene], color="k", linestyle="--", linewidth=1, label="issue target")
    left.set_xticks(list(x), labels, fontsize=7)
    left.set_ylabel("%")
    left.legend(fontsize=7)
    left.set_title(f"{scene}: error", fontsize=9)
    right.bar(list(x), seconds, 0.5, color="tab:gray")
    right.set_yscale("log")
    right.set_xticks(list(x), labels, fontsize=7)
    right.set_ylabel("seconds (2 cores)")
    right.set_title(f"{scene}: time", fontsize=9)
    figure.tight_layout()
    figure.savefig(path, dpi=80)
    plt.close(figure)
    return True


def write(results, command):
    os.makedirs(FOLDER, exist_ok=True)
    for r in results:
        with open(os.path.join(FOLDER, f"{r['scene']}_{r['target'].lower()}.json"), "w") as f:
            json.dump(r, f, indent=1, default=str)
    everything = []
    for path in sorted(glob.glob(os.path.join(FOLDER, "*.json"))):
        with open(path) as f:
            everything.append(json.load(f))
    order = {name: i for i, name in enumerate(TARGETS)}
    everything.sort(key=lambda r: (order.get(r["scene"], 99), r["target"]))
    for scene in sorted({r["scene"] for r in everything}):
        chart(scene, [r for r in everything if r["scene"] == scene], os.path.join(FOLDER, f"{scene}.png"))
    with open(PAGE) as f:
        page = f.read()
    if BEGIN not in page or END not in page:
        raise SystemExit(f"{PAGE} has no table markers")
    body = table(everything) + f"\n\nLast command: `/usr/bin/python3 tools/real_scenes.py {command}`"
    page = page[:page.index(BEGIN) + len(BEGIN)] + "\n" + body + "\n" + page[page.index(END):]
    with open(PAGE, "w") as f:
        f.write(page)
    print(f"wrote {len(results)} results, the charts and the table of {PAGE}")


if __name__ == "__main__":
    work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/bakegi_real_scenes"
    found = []
    for path in sorted(glob.glob(os.path.join(work, "*", "*", "results.json"))):
        with open(path) as f:
            found.append(json.load(f))
    write(found, f"(re-written from {work})")
