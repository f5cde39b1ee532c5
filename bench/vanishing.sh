#!/usr/bin/env bash
# The two vanishing-corner rules of `wearknit cut --vanishing` (docs/cutting.md)
# on every quad-dominant shared mesh, 100 mm along its longest side, seed 1:
# irregular vertices, arcs, cut length and overlapping faces of the cut, then
# the scheduling cuts and stitches after `stitch-mesh` and `schedule
# --trials 100`. Prints a Markdown table.
#   bench/vanishing.sh        (release build in $WEARKNIT_BENCH_BUILD, default build-bench; needs ../shared)
source "$(dirname "$0")/common.sh"
cd "$ROOT"
bench_build wearknit
wearknit="$BUILD/apps/wearknit/wearknit"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)" >&2
echo "| mesh | vanishing | irregular vertices | arcs | cut length mm | overlapping faces | schedule cuts | stitches |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"
for file in "$SHARED"/meshes/*-qd.obj "$SHARED"/meshes/*-quad*.obj; do
  mesh=$(basename "$file" .obj)
  scale=$(python3 -c "
import sys
lo = [float('inf')] * 3; hi = [-float('inf')] * 3
for line in open(sys.argv[1]):
    p = line.split()
    if p and p[0] == 'v':
        for i in range(3):
            x = float(p[i + 1]); lo[i] = min(lo[i], x); hi[i] = max(hi[i], x)
print(100.0 / max(h - l for h, l in zip(hi, lo)))" "$file")
  for rule in acute regular; do
    out="$work/$mesh-$rule"
    "$wearknit" cut "$file" -o "$out" --scale "$scale" --vanishing "$rule" --no-pictures -q
    "$wearknit" stitch-mesh "$out" -q >/dev/null 2>&1 || true
    "$wearknit" schedule "$out" --trials 100 --seed 1 -q >/dev/null 2>&1 || true
    python3 - "$out/report.json" "$mesh" "$rule" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r.get("schedule") or {}
def fig(d, k):
    v = d.get(k)
    return "failed" if v is None else v
pieces = s.get("pieces")
stitches = sum(p["stitches"] for p in pieces) if pieces else "failed"
print(f"| {sys.argv[2]} | {sys.argv[3]} | {r['irregular_vertex_count']} | {r['arcs']} | "
      f"{r['cut_length_mm']:.0f} | {r['overlapping_faces']} | {fig(s, 'cuts')} | {stitches} |")
PY
  done
done
