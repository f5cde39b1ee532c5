#!/usr/bin/env python3
"""The per-mesh stitch-mesh table (docs/results.md) from folders written by
`wearknit cut` and `wearknit stitch-mesh`.

    bench/stitch_mesh_table.py NAME=DIR [NAME=DIR ...]

Each DIR holds stitch-mesh.json (its report) and stitch-mesh.smobj.
Prints one Markdown row per mesh: stitches, faces by type, share of stitches
with a side on the sheet's boundary, course and wale mean / target and share
within 15%, stitches / (area / (course x wale)), stability rule counts, and
which of the stage's targets (docs/stitch-mesh.md) the mesh misses: means
within 1 +- 0.05 of the target, shares within 15% at least 90%, stitches
within 1 +- 0.10 of the estimate.
"""
import collections
import json
import sys


def boundary_share(smobj):
    faces = []
    for line in open(smobj):
        parts = line.split()
        if parts and parts[0] == "f":
            faces.append([int(p) for p in parts[1:]])
    uses = collections.Counter()
    for face in faces:
        for i, a in enumerate(face):
            b = face[(i + 1) % len(face)]
            uses[(min(a, b), max(a, b))] += 1
    on_boundary = 0
    for face in faces:
        if any(uses[(min(a, b), max(a, b))] == 1
               for a, b in zip(face, face[1:] + face[:1])):
            on_boundary += 1
    return on_boundary / len(faces) if faces else 0.0


HEADER = ["stitches", "knit / inc / dec / short-row", "on boundary", "course mean",
          "course ≤15%", "wale mean", "wale ≤15%", "stitches / estimate", "rules 1/2/3/4",
          "targets missed"]
ALIGN = ["---:", "---:", "---:", "---:", "---:", "---:", "---:", "---:", "---", "---"]


def cells(folder):
    """The row's cells after the mesh name, in HEADER's order."""
    s = json.load(open(f"{folder}/stitch-mesh.json"))["report"]
    f = s["faces"]
    course = s["course_edges"]
    wale = s["wale_edges"]
    cm = course["mean_mm"] / course["target_mm"]
    wm = wale["mean_mm"] / wale["target_mm"]
    cw = course["within_15_percent"]
    ww = wale["within_15_percent"]
    st = f["total"] / s["expected_stitches"]
    r = s["stability_rules"]
    missed = []
    if abs(cm - 1) > 0.05:
        missed.append("course mean")
    if abs(wm - 1) > 0.05:
        missed.append("wale mean")
    if cw < 0.9:
        missed.append("course 15%")
    if ww < 0.9:
        missed.append("wale 15%")
    if abs(st - 1) > 0.10:
        missed.append("stitches")
    share = boundary_share(f"{folder}/stitch-mesh.smobj")
    return [f"{f['total']}", f"{f['knit']} / {f['increase']} / {f['decrease']} / {f['short_row']}",
            f"{share:.0%}", f"{cm:.3f}", f"{cw:.0%}", f"{wm:.3f}", f"{ww:.0%}", f"{st:.3f}",
            f"{r['edge_shaping']}/{r['stacked_shaping']}/{r['opposed_shaping']}/"
            f"{r['one_stitch_rows']}", ", ".join(missed) or "all met"]


def row(name, folder):
    return "| " + " | ".join([name] + cells(folder)) + " |"


def main(args):
    if not args:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    print("| mesh | " + " | ".join(HEADER) + " |")
    print("| --- | " + " | ".join(ALIGN) + " |")
    for arg in args:
        name, _, folder = arg.partition("=")
        print(row(name, folder))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
