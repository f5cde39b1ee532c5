#!/usr/bin/env bash
# The elimination's arc order (docs/wearability.md, "The order of the
# arcs"): each mesh's default cut at 100 mm along its longest side
# (`wearknit cut`), then its wearability stage over itself twice, one after
# the other in the same run: with --arc-order opening (the default) and
# with --arc-order random (§5). Prints a Markdown table.
#   bench/arc_order.sh [BUILD_DIR]     (default build; needs ../shared)
# Environment: MESHES, file names (default the closed shared meshes whose
# stage took longest against their knit branch); OUT, the folder for the
# cuts (default a temporary one).
source "$(dirname "$0")/plan_common.sh"
source bench/wearability_pairs.sh
MESHES=${MESHES:-"man.obj horse-quad.obj armadillo-qd.obj teddy-quad.obj gargoyle.obj armadillo.obj 3torus-quad.obj fertility.obj bunny.obj anchor.obj"}
wearability_modes "opening=--arc-order opening" "random=--arc-order random"
python3 - "${rows[@]}" <<'EOF2'
import sys
sys.path.insert(0, "bench")
from wearability_runs import runs_of
runs = runs_of(sys.argv[1:])
def cells(s, wall):
    check = s["final_check"]
    return f"{s['tests']} | {s['sewn']} / {s['laced']} | {check['laced']} | {wall:.1f}"
print("| mesh | arcs | opening: tests | sewn / laced | laced by the check | s "
      "| random: tests | sewn / laced | laced by the check | s | ratio |")
print("| --- | ---: | ---: | --- | ---: | ---: | ---: | --- | ---: | ---: | ---: |")
total = [0.0, 0.0]
for name, modes in runs.items():
    (a, wa), (b, wb) = modes["opening"], modes["random"]
    if a is None or b is None or not a.get("wearable") or not b.get("wearable"):
        print(f"| {name} | not wearable in one of the runs |")
        continue
    total[0] += wa
    total[1] += wb
    arcs = a["sewn"] + a["laced"]
    print(f"| {name} | {arcs} | {cells(a, wa)} | {cells(b, wb)} | {wb / wa:.2f} |")
print(f"\nTotal: {total[0]:.1f} s with the opening order, {total[1]:.1f} s with random orders "
      f"({total[1] / max(total[0], 1e-9):.2f}).")
EOF2
