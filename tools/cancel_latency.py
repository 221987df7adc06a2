"""Cancel at every stage of every method, and how long the core takes to stop.

For each method a probe bake lists its stages (the job's progress text with numbers made
'#': "tracing 32/256 samples" and "tracing 64/256 samples" are one stage). Then, for each
stage in turn, a new bake runs until its progress text first shows that stage (waiting on
state, not on the clock) and is cancelled there; the latency is the time from
bakegi_job_cancel until the job reports done, and the job must end CANCELLED. The worst
latency per (method, stage) over --repeat runs goes to a JSON file and a Markdown table.

    /usr/bin/python3 tools/cancel_latency.py --scene X.bgs --out docs/cancel_latency.json \\
        [--library build/libbakegi.so] [--repeat 3] [--methods pathtrace,antiradiance,...]
        [--set method.key=value ...]

python_tests/test_cancel.py runs the same code on a small box (every stage must end
CANCELLED; the latencies are printed, not asserted: timing belongs here, in the record).
"""

import argparse
import json
import os
import re
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))

# Settings that make every stage of a method last long enough to be caught on a real room,
# without changing which stages run.
DEFAULT_SETTINGS = {
    "pathtrace": {"samples": 256, "error_probes": 64},
    "direct": {"samples": 256},
    "antiradiance": {"bins": 768, "near_field_rays": 1024, "error_probes": 64},
    "meshless": {"gather_rays": 1024, "error_probes": 64},
    "splatting": {"gather_rays": 256, "vpl_count": 4096, "error_probes": 64},
}
POLL_SECONDS = 0.0005


def stage_key(text):
    """The stage without its counters and percentages."""
    return re.sub(r"\d+(\.\d+)?", "#", text).strip()


def probe_stages(native, scene, points, settings, timeout):
    """The stages of one full bake in the order seen, with the seconds each was shown."""
    order, seconds = [], {}
    with native.Settings(**settings) as handle:
        job = native.Job(scene, points, handle)
    try:
        last, since = None, time.perf_counter()
        deadline = since + timeout
        while not job.is_done and time.perf_counter() < deadline:
            key = stage_key(job.stage)
            now = time.perf_counter()
            if key != last:
                if last is not None:
                    seconds[last] = seconds.get(last, 0.0) + now - since
                if key and key not in seconds and key not in order:
                    order.append(key)
                last, since = key, now
            time.sleep(POLL_SECONDS)
        if last is not None:
            seconds[last] = seconds.get(last, 0.0) + time.perf_counter() - since
        job.cancel()
    finally:
        job.close()
    return [(key, seconds.get(key, 0.0)) for key in order]


def cancel_at(native, scene, points, settings, stage, timeout):
    """Cancels a bake when its progress first shows `stage`. Returns (latency seconds or None
    when the bake never showed it, the status name the job ended with)."""
    with native.Settings(**settings) as handle:
        job = native.Job(scene, points, handle)
    try:
        deadline = time.perf_counter() + timeout
        while not job.is_done and stage_key(job.stage) != stage:
            if time.perf_counter() > deadline:
                break
            time.sleep(POLL_SECONDS)
        if job.is_done or stage_key(job.stage) != stage:
            return None, "missed"
        started = time.perf_counter()
        job.cancel()
        while not job.is_done:
            time.sleep(POLL_SECONDS)
        latency = time.perf_counter() - started
        try:
            job.wait()
            status = "BAKEGI_OK"
        except native.BakeGIError as error:
            status = error.status
        return latency, status
    finally:
        job.close()


def measure(native, scene, points, methods, repeat=1, timeout=600.0, log=print):
    """{method: [{"stage", "probe_seconds", "latencies", "statuses", "worst"}]}."""
    results = {}
    for method, settings in methods.items():
        settings = {"method": method, **settings}
        rows = []
        for stage, seconds in probe_stages(native, scene, points, settings, timeout):
            latencies, statuses = [], []
            for _ in range(repeat):
                latency, status = cancel_at(native, scene, points, settings, stage, timeout)
                statuses.append(status)
                if latency is not None:
                    latencies.append(latency)
            row = {"stage": stage, "probe_seconds": seconds, "latencies": latencies,
                   "statuses": statuses, "worst": max(latencies) if latencies else None}
            rows.append(row)
            worst = f"{1e3 * row['worst']:.1f} ms" if latencies else "not caught"
            log(f"{method:13s} {stage:60.60s} {worst:>12s}  {','.join(sorted(set(statuses)))}")
        results[method] = rows
    return results


def markdown(results):
    lines = ["| method | stage | stage lasted (probe) | worst cancel latency | ended |",
             "|---|---|---:|---:|---|"]
    for method, rows in results.items():
        for row in rows:
            worst = f"{1e3 * row['worst']:.0f} ms" if row["worst"] is not None else "not caught"
            ended = ", ".join(sorted(set(row["statuses"])))
            lines.append(f"| {method} | {row['stage']} | {row['probe_seconds']:.2f} s | {worst} "
                         f"| {ended} |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True, help=".bgs scene file with bake points")
    parser.add_argument("--out", required=True, help="JSON results (a .md table beside it)")
    parser.add_argument("--library", default=os.path.join(ROOT, "build", "libbakegi.so"))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--methods", default=",".join(DEFAULT_SETTINGS))
    parser.add_argument("--set", action="append", default=[],
                        help="method.key=value, added to that method's settings")
    args = parser.parse_args()
    from bakegi import native
    native.load_library(args.library)
    methods = {m: dict(DEFAULT_SETTINGS.get(m, {})) for m in args.methods.split(",")}
    for assignment in args.set:
        target, value = assignment.split("=", 1)
        method, key = target.split(".", 1)
        try:
            methods[method][key] = int(value)
        except ValueError:
            try:
                methods[method][key] = float(value)
            except ValueError:
                methods[method][key] = value
    scene, points = native.Scene.read(args.scene)
    started = time.perf_counter()
    results = measure(native, scene, points, methods, args.repeat)
    record = {"scene": os.path.basename(args.scene), "points": len(points),
              "repeat": args.repeat, "settings": methods, "cpus": os.cpu_count(),
              "seconds": time.perf_counter() - started, "results": results}
    with open(args.out, "w") as f:
        json.dump(record, f, indent=1)
    with open(os.path.splitext(args.out)[0] + ".md", "w") as f:
        f.write(markdown(results) + "\n")
    print(markdown(results))


if __name__ == "__main__":
    main()
