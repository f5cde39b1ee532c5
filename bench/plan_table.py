#!/usr/bin/env python3
"""Prints one Markdown table row per plan folder from its report.json and
cuts.json (bench/plan_all.sh, bench/plan_results.sh, bench/results.sh).

  bench/plan_table.py NAME=DIR[:EXIT:WALL_S] ...
"""
import json
import os
import sys

STAGES = ["cut", "wearability", "stitch-mesh", "schedule"]

print("| mesh | result | cut s | wearability s | stitch mesh s | schedule s | total s "
      "| pieces | arcs sewn / laced | seams sewn / laced | schedule cuts | stitches | passes "
      "| est. knit time |")
print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- | ---: | ---: | ---: "
      "| ---: |")
for arg in sys.argv[1:]:
    name, rest = arg.split("=", 1)
    parts = rest.split(":")
    folder = parts[0]
    exit_code = parts[1] if len(parts) > 1 else "?"
    wall = parts[2] if len(parts) > 2 else ""
    try:
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
    except (OSError, ValueError):
        report = {}
    plan = report.get("plan", {})
    times = {}
    failed = []
    partial = ""
    if not plan:
        # Killed (timeout) or stopped before plan.json: the folder's summary
        # holds what the stages that finished wrote.
        if "time_s" in report:
            times["cut"] = report["time_s"].get("total", 0.0)
        if "stitch_mesh" in report:
            times["stitch-mesh"] = report["stitch_mesh"].get("seconds", 0.0)
        if "schedule" in report:
            times["schedule"] = report["schedule"].get("time_s", 0.0)
        s = {}
        if "stitch_mesh" in report:
            s["stitches"] = report["stitch_mesh"]["faces"]["total"]
        if "schedule" in report:
            pieces = report["schedule"]["pieces"]
            s["pieces"] = len(pieces)
            s["schedule_cuts"] = report["schedule"]["cuts"]
            s["passes"] = sum(p["passes"] for p in pieces)
            s["estimated_knit_time_s"] = sum(p["estimated_knit_time_s"] for p in pieces)
        if "arcs" in report:
            partial = " (%d arcs)" % report["arcs"]
        plan = {"partial_summary": s}
    for stage in plan.get("stages", []):
        # A re-run after a re-cut is added to its stage's time.
        base = stage["name"].split(" (")[0]
        times[base] = times.get(base, 0.0) + stage["time_s"]
        if stage["exit"] != 0:
            failed.append(base)
    # A plan run again after it was cut short resumes its wearability stage
    # from the journal; its times are then those of the last run only.
    try:
        with open(os.path.join(folder, "cuts.json")) as f:
            wear = json.load(f).get("wearability", {})
    except (OSError, ValueError):
        wear = {}
    replayed = wear.get("tests_replayed", 0)
    try:
        with open(os.path.join(folder, "wearability.journal")) as f:
            journal = sum(1 for _ in f) - 1
    except OSError:
        journal = 0
    if exit_code == "0":
        result = "ok" + (" (re-cut)" if plan.get("recut") else "")
        if replayed:
            result += " (resumed: %d of %d tests from the journal)" % (replayed, wear.get("tests", 0))
    elif exit_code == "124":
        result = "timeout after %s s%s" % (wall, partial)
        if journal > 0:
            result += " (%d tests in its journal)" % journal
    elif failed:
        result = "failed: " + ", ".join(failed)
    elif not plan:
        result = "failed: cut"
    else:
        result = "failed (exit %s)" % exit_code
    s = dict(plan.get("summary", plan.get("partial_summary", {})))
    if plan.get("summary") and "schedule" in report:
        # The folder may have been scheduled again after the plan (another
        # pattern or seed): its schedule figures are the ones that count.
        pieces = report["schedule"]["pieces"]
        s["pieces"] = len(pieces)
        s["schedule_cuts"] = report["schedule"]["cuts"]
        s["passes"] = sum(p["passes"] for p in pieces)
        s["estimated_knit_time_s"] = sum(p["estimated_knit_time_s"] for p in pieces)

    def t(stage):
        return "%.1f" % times[stage] if stage in times else "–"

    def g(key, fmt="%d"):
        return fmt % s[key] if key in s else "–"

    knit = "%.0f min" % (s["estimated_knit_time_s"] / 60) if "estimated_knit_time_s" in s else "–"
    total = "%.1f" % plan["total_s"] if "total_s" in plan else (wall or "–")
    arcs = "%d / %d" % (s["sewn"], s["laced"]) if "sewn" in s and s.get("arcs") else "–"
    # The assembly guide's seams (chained cut-arcs, scheduling cuts, wale
    # seams; docs/assembly.md), from report.json's copy of assembly.json.
    guide = report.get("assembly", {})
    seams = "%d / %d" % (guide["sewn"], guide["laced"]) if "sewn" in guide else "–"
    print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
        name, result, t("cut"), t("wearability"), t("stitch-mesh"), t("schedule"), total,
        g("pieces"), arcs, seams, g("schedule_cuts"), g("stitches"), g("passes"), knit))
