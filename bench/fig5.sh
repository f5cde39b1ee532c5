#!/usr/bin/env bash
# Reproduces Fig. 5 of the paper (§4.2): the cut of a quad-dominant proxy
# with four edge prioritisations -- random (c_s = 0, c_o = 0), straightness
# only (c_s = 1000, c_o = 0), overlap only (c_s = 0, c_o = 1) and both
# (c_s = 1000, c_o = 1) -- on bunny-qd and fertility-qd, with the paper's
# vanishing corners (--vanishing acute, §4.1). Prints a Markdown
# table (means over seeds 1..5, and seed 1 alone) and writes the seed-1
# pictures to docs/figures/fig5/.
# usage: bench/fig5.sh   (release build in $WEARKNIT_BENCH_BUILD, default build-bench; needs ../shared)
source "$(dirname "$0")/common.sh"
cd "$ROOT"
build="$BUILD"
shared="$SHARED"
bench_build wearknit
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
figures=docs/figures/fig5
mkdir -p "$figures"
variants=("random 0 0" "straightness 1000 0" "overlap 0 1" "both 1000 1")
for mesh in bunny-qd fertility-qd; do
  units=mm
  [ "$mesh" = bunny-qd ] && units=m  # the scanned bunny is stored in metres (0.16 wide)
  for v in "${variants[@]}"; do
    read -r name cs co <<<"$v"
    for seed in 1 2 3 4 5; do
      out="$work/$mesh-$name-$seed"
      if [ "$seed" = 1 ]; then
        "$build/apps/wearknit/wearknit" cut "$shared/meshes/$mesh.obj" -o "$out" --cs "$cs" --co "$co" \
          --units "$units" --seed "$seed" --vanishing acute --picture-px 300 -q
        cp "$out/cuts-3d.png" "$figures/$mesh-$name-3d.png"
        cp "$out/layout-2d.png" "$figures/$mesh-$name-2d.png"
      else
        "$build/apps/wearknit/wearknit" cut "$shared/meshes/$mesh.obj" -o "$out" --cs "$cs" --co "$co" \
          --units "$units" --seed "$seed" --vanishing acute --no-pictures -q
      fi
    done
  done
done
python3 - "$work" <<'PY'
import json, sys, os
work = sys.argv[1]
print("| mesh | variant | c_s | c_o | arcs | cut edges | cut edges per arc | cut length (mm) | overlapping faces | seed 1: arcs / length mm / overlapping |")
print("|---|---|---|---|---|---|---|---|---|---|")
for mesh in ["bunny-qd", "fertility-qd"]:
    for name, cs, co in [("random", 0, 0), ("straightness", 1000, 0), ("overlap", 0, 1), ("both", 1000, 1)]:
        r = [json.load(open(os.path.join(work, f"{mesh}-{name}-{s}", "report.json"))) for s in range(1, 6)]
        mean = lambda k: sum(x[k] for x in r) / len(r)
        per_arc = sum(x["cut_edges"] / max(1, x["arcs"]) for x in r) / len(r)
        first = r[0]
        print(f"| {mesh} | {name} | {cs} | {co} | {mean('arcs'):.1f} | {mean('cut_edges'):.1f} | {per_arc:.2f} | "
              f"{mean('cut_length_mm'):.1f} | {mean('overlapping_faces'):.1f} | "
              f"{first['arcs']} / {first['cut_length_mm']:.1f} / {first['overlapping_faces']} |")
PY
