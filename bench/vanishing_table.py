#!/usr/bin/env python3
"""The table of bench/vanishing_corners.sh from its work folder.

    bench/vanishing_table.py OUT COMMAND NAME...

OUT holds NAME-acute and NAME-optimal, the cut folders of each mesh NAME
with `--vanishing acute` and `--vanishing optimal`. Prints Markdown.
"""
import collections
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in bench/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from results_tables import load, obj_faces, table  # noqa: E402

RULES = ["acute", "optimal"]


def figures(folder):
    """Of a cut folder: Q's triangles, the sum of |corners - 4| over its
    interior vertices, its irregular and singular vertices (corners not
    counting vanishing ones, docs/cutting.md §3), the cut-arcs and cut edges;
    None when the cut failed."""
    labels = load(os.path.join(folder, "labels.json"))
    report = load(os.path.join(folder, "report.json"))
    if labels is None or report is None:
        return None
    faces = obj_faces(os.path.join(folder, "proxy.obj"))
    corners = collections.Counter()
    edge_uses = collections.Counter()
    for f, face in enumerate(faces):
        vanishing = labels["vanishing_corner"][f]
        for i, v in enumerate(face):
            if i != vanishing:
                corners[v] += 1
            w = face[(i + 1) % len(face)]
            edge_uses[(min(v, w), max(v, w))] += 1
    boundary = {v for edge, n in edge_uses.items() if n == 1 for v in edge}
    interior = {v for face in faces for v in face} - boundary
    irregular = sum(1 for v in interior if corners[v] != 4)
    if irregular != report["irregular_vertex_count"]:
        sys.exit(f"{folder}: {irregular} irregular vertices, the report says "
                 f"{report['irregular_vertex_count']}")
    return {
        "triangles": sum(1 for face in faces if len(face) == 3),
        "misfit": sum(abs(corners[v] - 4) for v in interior),
        "irregular": irregular,
        "singular": sum(1 for v in interior if corners[v] % 4 != 0),
        "arcs": report["arcs"],
        "cut_edges": report["cut_edges"],
    }


def per_arc(f):
    return f["cut_edges"] / f["arcs"] if f["arcs"] else 0.0


def main():
    out, command, names = sys.argv[1], sys.argv[2], sys.argv[3:]
    rows = []
    total = {rule: collections.Counter() for rule in RULES}
    failed = []
    for name in names:
        fig = {rule: figures(os.path.join(out, f"{name}-{rule}")) for rule in RULES}
        if None in fig.values():
            failed.append(name)
            continue
        for rule in RULES:
            total[rule].update(fig[rule])

        def pair(key, fmt="{}"):
            return " → ".join(fmt.format(fig[rule][key]) for rule in RULES)

        rows.append([name, fig["acute"]["triangles"], pair("misfit"), pair("irregular"),
                     pair("singular"), pair("arcs"),
                     " → ".join("%.2f" % per_arc(fig[rule]) for rule in RULES)])
    rows.append(["**all**", total["acute"]["triangles"]] +
                [" → ".join(str(total[rule][key]) for rule in RULES)
                 for key in ["misfit", "irregular", "singular", "arcs"]] +
                [" → ".join("%.2f" % per_arc(total[rule]) for rule in RULES)])
    print("```sh\n%s\n```\n" % command)
    print(table(["mesh", "triangles of Q", "Σ\\|corners − 4\\|", "irregular vertices",
                 "singular vertices", "cut-arcs", "cut edges per arc"],
                ["---", "---:", "---:", "---:", "---:", "---:", "---:"], rows))
    if failed:
        print("\nNo cut: " + ", ".join(failed))


if __name__ == "__main__":
    main()
