#!/usr/bin/env python3
"""Why a stitch mesh's wale sides miss their length (docs/stitch-mesh.md).

    bench/wale_sides.py NAME=DIR [NAME=DIR ...]

Each DIR holds stitch-mesh.smobj (written by `wearknit stitch-mesh`). Every
wale side of every stitch is counted once per stitch it bounds, and split
into its part along the course side next to it in the same stitch (a lean)
and its part across it (the row's height there). Prints one Markdown row per
mesh: the wale sides' mean length and share within 15% (as the stage's
targets count them, per stitch side), the mean of their part across the row, the share
that are too long and how many of those are too long only because they lean
(their part across the row is within 15% of the wale length or shorter),
how many of the leaning ones are on the sheet's boundary, and the share that
are too short.
"""
import math
import statistics
import sys


def read_smobj(path):
    """Vertices, faces (vertex lists), face types and the library's side
    roles, and the wale length, from a .smobj file."""
    vertices, faces, types, library = [], [], [], []
    wale_mm = None
    for line in open(path):
        words = line.split()
        if not words:
            continue
        if words[0] == "#" and words[1:3] == ["wearknit", "course_mm"]:
            wale_mm = float(words[words.index("wale_mm") + 1])
        elif words[0] == "L":
            library.append(words[2:])
        elif words[0] == "v":
            vertices.append(tuple(float(x) for x in words[1:4]))
        elif words[0] == "f":
            faces.append([int(x) - 1 for x in words[1:]])
        elif words[0] == "T":
            types.append(int(words[1]) - 1)
    if wale_mm is None:
        raise SystemExit(f"{path}: no '# wearknit course_mm ... wale_mm ...' line")
    if len(types) != len(faces):
        raise SystemExit(f"{path}: {len(faces)} faces but {len(types)} face types")
    return vertices, faces, types, library, wale_mm


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def norm(a):
    return math.sqrt(sum(x * x for x in a))


def wale_sides(path):
    """(length, part across the row, on the boundary) of every wale side of
    every stitch, lengths in wale lengths."""
    vertices, faces, types, library, wale_mm = read_smobj(path)
    def side_key(face, i):
        return frozenset((face[i], face[(i + 1) % len(face)]))

    uses = {}
    for face in faces:
        for i in range(len(face)):
            uses[side_key(face, i)] = uses.get(side_key(face, i), 0) + 1
    sides = []
    for face, t in zip(faces, types):
        roles = library[t]
        k = len(face)
        for i in range(k):
            if not roles[i].startswith("y"):
                continue
            w = sub(vertices[face[(i + 1) % k]], vertices[face[i]])
            # The course side next to it (before it, else after it).
            course = None
            for j in ((i - 1) % k, (i + 1) % k):
                if roles[j].lstrip("+-").startswith("l"):
                    course = sub(vertices[face[(j + 1) % k]], vertices[face[j]])
                    break
            length = norm(w)
            across = length
            course_length = norm(course) if course is not None else 0.0
            if course_length > 0:
                along = abs(sum(w[x] * course[x] for x in range(3))) / course_length
                across = math.sqrt(max(0.0, length * length - along * along))
            boundary = uses[side_key(face, i)] == 1
            sides.append((length / wale_mm, across / wale_mm, boundary))
    return sides


def row(name, directory):
    sides = wale_sides(f"{directory}/stitch-mesh.smobj")
    n = len(sides)
    within = sum(1 for length, _, _ in sides if 0.85 <= length <= 1.15) / n
    long_sides = [side for side in sides if side[0] > 1.15]
    leaning = [side for side in long_sides if side[1] <= 1.15]
    on_boundary = sum(1 for side in leaning if side[2])
    short = sum(1 for length, _, _ in sides if length < 0.85) / n

    def percent(part, whole):
        return 100 * part / max(1, whole)

    return (
        f"| {name} | {n} | {statistics.mean(side[0] for side in sides):.3f} "
        f"| {100 * within:.1f}% | {statistics.mean(side[1] for side in sides):.3f} "
        f"| {percent(len(long_sides), n):.1f}% | {percent(len(leaning), len(long_sides)):.0f}% "
        f"| {percent(on_boundary, len(leaning)):.0f}% | {100 * short:.1f}% |"
    )


def main(args):
    if not args:
        raise SystemExit(__doc__)
    print("| mesh | wale sides | mean / wale | within 15% | part across the row, mean / wale "
          "| too long | of those, leaning | leaning, on the boundary | too short |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for arg in args:
        name, _, directory = arg.partition("=")
        print(row(name, directory or name))


if __name__ == "__main__":
    main(sys.argv[1:])
