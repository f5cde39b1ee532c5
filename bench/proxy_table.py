#!/usr/bin/env python3
"""The table of bench/proxy_singularities.sh.

proxy_table.py OUT COMMAND NAME...: OUT holds NAME-remesh/ and NAME-field/
cut folders; prints Markdown: per mesh the field's singularities, Q's
singular vertices, adjacent +1/-1 pairs, arcs, mean edges and mm per arc,
mean chord / length, the farthest distance of Q from the garment, as
"remesh -> field", then the targets of docs/cutting.md §9 on
the closed meshes with the field proxy.
"""
import json
import math
import os
import sys


def load(folder):
    try:
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
        with open(os.path.join(folder, "cuts.json")) as f:
            cuts = json.load(f)
    except (OSError, ValueError):
        return None
    positions = []
    with open(os.path.join(folder, "proxy.obj")) as f:
        for line in f:
            if line.startswith("v "):
                positions.append([float(x) for x in line.split()[1:4]])
    arcs = cuts.get("arcs", [])
    edges = sum(len(a["edges"]) for a in arcs)
    length = sum(a["length_mm"] for a in arcs)
    chords = []
    for a in arcs:
        if a.get("closed") or not a["edges"] or a["length_mm"] <= 0:
            continue
        p = positions[a["edges"][0][0]]
        q = positions[a["edges"][-1][1]]
        chords.append(math.dist(p, q) / a["length_mm"])
    proxy = report["proxy"]
    return {
        "closed": report["field"]["boundary_loops"] == 0,
        # The field's singularities in units of index: a pole of index +4
        # (a UV sphere's) needs four +1 vertices on any quad-like proxy.
        "field": sum(abs(int(k)) * n for k, n in report["field"].get("by_index", {}).items()),
        "singular": proxy["singular_vertices"],
        "pairs": proxy.get("adjacent_pairs", 0),
        "arcs": len(arcs),
        "edges_per_arc": edges / len(arcs) if arcs else 0.0,
        "mm_per_arc": length / len(arcs) if arcs else 0.0,
        "chord": sum(chords) / len(chords) if chords else 1.0,
        "method": proxy["method"],
        "off": proxy.get("surface_distance_max_mm", float("nan")),
    }


def pair(a, b, key, fmt="{}"):
    left = fmt.format(a[key]) if a else "—"
    right = fmt.format(b[key]) if b else "—"
    return f"{left} → {right}"


def main():
    out, command, names = sys.argv[1], sys.argv[2], sys.argv[3:]
    print(f"`{command}`\n")
    print("| mesh | Q (remesh → field) | field (Σ\\|index\\|) | singular vertices of Q | adjacent pairs | arcs "
          "| edges / arc | mm / arc | chord / length | Q off the surface, mm |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    rows = []
    for name in names:
        a = load(os.path.join(out, name + "-remesh"))
        b = load(os.path.join(out, name + "-field"))
        rows.append((name, a, b))
        field = (b or a or {}).get("field", "—")
        method = f"{a['method'] if a else '—'} → {b['method'] if b else '—'}"
        print(f"| {name} | {method} | {field} | {pair(a, b, 'singular')} | "
              f"{pair(a, b, 'pairs')} | {pair(a, b, 'arcs')} | "
              f"{pair(a, b, 'edges_per_arc', '{:.2f}')} | {pair(a, b, 'mm_per_arc', '{:.1f}')} | "
              f"{pair(a, b, 'chord', '{:.2f}')} | {pair(a, b, 'off', '{:.2f}')} |")
    closed = [(n, b) for n, a, b in rows if b and b["closed"]]
    checks = [
        ("singular vertices ≤ 1.2 × field + 4", lambda r: r["singular"] <= 1.2 * r["field"] + 4),
        ("arcs ≤ 1.3 × singular vertices + 4", lambda r: r["arcs"] <= 1.3 * r["singular"] + 4),
        ("adjacent pairs ≤ 10% of singular vertices", lambda r: r["pairs"] <= 0.1 * r["singular"]),
    ]
    print(f"\nWith `--proxy field`, over the {len(closed)} closed meshes:\n")
    for label, check in checks:
        failing = [n for n, r in closed if not check(r)]
        print(f"- {label}: {len(closed) - len(failing)} of {len(closed)}" +
              (f" (not: {', '.join(failing)})" if failing else ""))
    half_wale = 2.875 / 2
    far = [n for n, a, b in rows if b and b["off"] > half_wale]
    print(f"- Q within half a wale ({half_wale:.2f} mm at the default gauge) of the surface: "
          f"{len(rows) - len(far)} of {len(rows)} meshes" + (f" (not: {', '.join(far)})" if far else ""))
    failed = [n for n, a, b in rows if not a or not b]
    if failed:
        print(f"\nNo cut: {', '.join(failed)}.")


if __name__ == "__main__":
    main()
