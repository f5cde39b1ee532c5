#!/usr/bin/env bash
# The linking test against simulating every test (docs/wearability.md,
# "Linked garments"): each mesh's default cut at 100 mm along its longest
# side (`wearknit cut`), then its wearability stage over itself twice, one
# after the other in the same run: with the linking test (the default) and
# with --simulate-linked. Prints a Markdown table.
#   bench/linking.sh [BUILD_DIR]     (default build; needs ../shared)
# Environment: MESHES, file names (default the closed shared meshes with
# handles); OUT, the folder for the cuts (default a temporary one).
source "$(dirname "$0")/plan_common.sh"
source bench/wearability_pairs.sh
MESHES=${MESHES:-"3torus-quad.obj anchor.obj double-torus-qd.obj eight.obj eight-qd.obj fertility.obj fertility-qd.obj rockerarm.obj torus.obj torus-qd.obj"}
wearability_modes "linking=" "simulated=--simulate-linked"
python3 - "${rows[@]}" <<'EOF'
import sys
sys.path.insert(0, "bench")
from wearability_runs import runs_of
runs = runs_of(sys.argv[1:])
print("| mesh | arcs | tests | failed unsimulated | sewn / laced | s | simulated: tests | sewn / laced | s | ratio |")
print("| --- | ---: | ---: | ---: | --- | ---: | ---: | --- | ---: | ---: |")
for name, modes in runs.items():
    (a, wa), (b, wb) = modes["linking"], modes["simulated"]
    if a is None or b is None or not a.get("wearable") or not b.get("wearable"):
        print(f"| {name} | not wearable in one of the runs |")
        continue
    arcs = a["sewn"] + a["laced"]
    print(f"| {name} | {arcs} | {a['tests']} | {a['tests_linked']} | {a['sewn']} / {a['laced']} | {wa:.1f} "
          f"| {b['tests']} | {b['sewn']} / {b['laced']} | {wb:.1f} | {wb / wa:.1f} |")
EOF
