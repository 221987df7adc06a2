# SPDX-License-Identifier: GPL-3.0-or-later
"""A bake's check of itself, in words.

The core path-traces a few hundred probes after every full bake and compares (report
"estimated_error", its 90% "estimated_error_interval", and "error_estimate" with the figures
per kind of probe and per object; docs/settings.md, "error_probes"). This module turns that into
what the user reads: the estimate, and when it is high, the likely causes and what to do. No
bpy here: facts about the objects come in as plain data (export.mesh_facts).
"""

from dataclasses import dataclass

# Above this estimated NRMSE a bake is flagged: the user sees a warning.
THRESHOLD = 0.10
# A target's vertices are too few for its light when what a viewer sees between them is off
# by more than THRESHOLD and clearly more than at the vertices themselves: by half as much
# again plus 3 points, at the low end of its 90% interval (it rests on 8-16 probes).
COARSE_RATIO = 1.5
COARSE_MARGIN = 0.03
# An object is single-sided sheet geometry (curtains, leaves, blinds, planes) when this share
# of its edges bound only one face.
OPEN_EDGE_SHARE = 0.05
# The error the path tracer's sample count is sized for in the advice.
TARGET_ERROR = 0.05


@dataclass
class ObjectFacts:
    vertices: int = 0
    open_edge_share: float = 0.0  # edges with one face / all edges


def percent(value):
    return f"{100.0 * value:.0f}%" if value >= 0.095 else f"{100.0 * value:.1f}%"


def _number(value):
    return float(value) if isinstance(value, (int, float)) and value == value else None


def _interval(stats):
    interval = stats.get("interval") if isinstance(stats, dict) else None
    if isinstance(interval, list) and len(interval) == 2:
        low, high = _number(interval[0]), _number(interval[1])
        if low is not None and high is not None:
            return [low, high]
    return None


def _stats(stats):
    """(nrmse, interval, probes) of one probe set of the core's report, or None."""
    if not isinstance(stats, dict) or not stats.get("probes"):
        return None
    error = _number(stats.get("nrmse"))
    return None if error is None else (error, _interval(stats), int(stats["probes"]))


def assess(report, object_names, facts=None, method="", samples=0):
    """The verdict on one bake. report: the core's report (dict). object_names: index = the
    bake points' object id. facts: {name: ObjectFacts} for the objects the estimate names.
    Returns None when the bake made no estimate, else a dict: error, interval, probes,
    display_error, display_interval, objects [{name, error, display_error}], coarse_objects,
    causes [text], warnings [text]."""
    estimate = report.get("error_estimate")
    error = _number(report.get("estimated_error"))
    if not isinstance(estimate, dict) or error is None:
        return None
    facts = facts or {}
    at_points = _stats(estimate.get("at_points"))
    display = _stats(estimate.get("display"))
    verdict = {"error": error, "interval": _interval({"interval": report.get(
        "estimated_error_interval")}), "probes": at_points[2] if at_points else 0,
        "samples": estimate.get("samples"),
        "display_error": display[0] if display else None,
        "display_interval": display[1] if display else None,
        "objects": [], "coarse_objects": [], "causes": [], "warnings": []}

    for entry in estimate.get("objects") or []:
        index = entry.get("object")
        if not isinstance(index, int) or not 0 <= index < len(object_names):
            continue
        own = _stats(entry.get("at_points"))
        seen = _stats(entry.get("display"))
        verdict["objects"].append({"name": object_names[index],
                                   "error": own[0] if own else None,
                                   "display_error": seen[0] if seen else None,
                                   "display_interval": seen[1] if seen else None})
    verdict["objects"].sort(key=lambda o: -max(o["error"] or 0.0, o["display_error"] or 0.0))

    # Too few vertices for the light: flagged whatever the overall error,
    # but only when even the low end of the object's interval says so (8-16 probes of an
    # object can be noisy).
    for o in verdict["objects"]:
        interval = o["display_interval"]
        if o["display_error"] is None or interval is None:
            continue
        own = o["error"] if o["error"] is not None else error
        if interval[0] > THRESHOLD and interval[0] > COARSE_RATIO * own + COARSE_MARGIN:
            verdict["coarse_objects"].append(o["name"])
    for name in verdict["coarse_objects"]:
        o = next(x for x in verdict["objects"] if x["name"] == name)
        vertices = facts.get(name, ObjectFacts()).vertices
        count = f"its {vertices:,} vertices" if vertices else "its vertices"
        verdict["warnings"].append(
            f"'{name}': the light changes faster across it than {count} can hold (about "
            f"{percent(o['display_error'])} off between them): bake to Lightmap Textures, or "
            f"use Subdivide a Copy and bake again")

    if error > THRESHOLD:
        verdict["causes"] = _causes(verdict, report, facts, method, samples, error)
        interval = verdict["interval"]
        around = f" ({percent(interval[0])}-{percent(interval[1])})" if interval else ""
        verdict["warnings"].insert(0, (
            f"estimated error {percent(error)}{around} at {verdict['probes']} path-traced "
            f"probes: above {percent(THRESHOLD)}. Likely: " + "; ".join(verdict["causes"])))
    return verdict


def _causes(verdict, report, facts, method, samples, error):
    causes = []
    if method == "pathtrace":
        needed = samples * (error / TARGET_ERROR) ** 2 if samples else 0
        causes.append(f"too few samples for the path tracer's noise (about {needed:,.0f} would "
                      f"give {percent(TARGET_ERROR)})")
        return causes
    worst = [o for o in verdict["objects"] if (o["error"] or 0.0) > THRESHOLD][:5]
    thin = [o["name"] for o in worst
            if facts.get(o["name"], ObjectFacts()).open_edge_share > OPEN_EDGE_SHARE]
    if thin:
        causes.append("thin single-sided geometry (" + ", ".join(f"'{n}'" for n in thin) +
                      ") that light leaks through: give it thickness (Solidify) or bake with "
                      "Path Trace")
    if (report.get("emissive_triangles") or 0) > 0:
        causes.append("emissive meshes light the scene: near them the method's coarse light "
                      "transport is least accurate")
    if any("coarsen" in str(w) for w in report.get("warnings") or []):
        causes.append("the memory budget coarsened the solution: raise memory_budget_mb")
    if verdict["coarse_objects"]:
        causes.append("too few vertices to hold the light on " +
                      ", ".join(f"'{n}'" for n in verdict["coarse_objects"][:5]))
    if worst and not thin:
        causes.append("the largest errors are on " +
                      ", ".join(f"'{o['name']}' ({percent(o['error'])})" for o in worst[:3]))
    if not causes:
        causes.append("the method's approximation does not fit this scene")
    causes.append("for an exact result bake with Path Trace")
    return causes


def summary_lines(verdict):
    """Panel lines: the estimate, and its warnings."""
    if not verdict:
        return []
    interval = verdict.get("interval")
    around = f" ({percent(interval[0])}-{percent(interval[1])})" if interval else ""
    line = f"Estimated error: {percent(verdict['error'])}{around}"
    if verdict.get("display_error") is not None:
        line += f", between vertices {percent(verdict['display_error'])}"
    return [line]
