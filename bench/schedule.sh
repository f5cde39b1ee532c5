#!/usr/bin/env bash
# Scheduler speed and output figures: the in-process benchmark on the
# bunny-cover-sized synthetic stitch mesh, then whole `wearknit schedule` runs
# (100 trials, plain and seed) on that mesh and on the real bunny cover
# (../shared/meshes/bunny-qd.obj scaled to 100 mm along its longest side,
# `wearknit cut` then `wearknit stitch-mesh`, both with their defaults), with
# passes, transfers and estimated knit time beside the paper's bunny (16 min
# plain, 33 min seed on the machine), and the reference backend's time to
# turn a piece into DAT.
#   KNITOUT_TO_DAT=/path/to/knitout-to-dat.js bench/schedule.sh
source "$(dirname "$0")/common.sh"
bench_build schedule_bench make_cover_smobj wearknit
echo "== schedule_bench (in-process, all cores)"
"$BUILD/bench/schedule_bench" --benchmark_min_time=1
synthetic=$WORK/cover-plan
rm -rf "$synthetic"
"$BUILD/bench/make_cover_smobj" "$synthetic"
bunny=$WORK/bunny-plan
rm -rf "$bunny"
scale=$(python3 - "$SHARED/meshes/bunny-qd.obj" <<'PY'
import sys
lo = [float("inf")] * 3
hi = [-float("inf")] * 3
for line in open(sys.argv[1]):
    if line.startswith("v "):
        p = [float(x) for x in line.split()[1:4]]
        lo = [min(a, b) for a, b in zip(lo, p)]
        hi = [max(a, b) for a, b in zip(hi, p)]
print(100.0 / max(b - a for a, b in zip(lo, hi)))
PY
)
"$BUILD/apps/wearknit/wearknit" cut "$SHARED/meshes/bunny-qd.obj" -o "$bunny" --scale "$scale" \
  --no-pictures -q
"$BUILD/apps/wearknit/wearknit" stitch-mesh "$bunny" --no-picture -q
ref=$(reference)
for plan in "$synthetic" "$bunny"; do
for pattern in plain seed; do
  echo "== wearknit schedule $plan --trials 100 --pattern $pattern (median of 3)"
  read -r s kb < <(median_run 3 "$BUILD/apps/wearknit/wearknit" schedule "$plan" --trials 100 \
    --pattern "$pattern" --seed 1)
  printf 'wall %.3f s, peak %d KB\n' "$s" "$kb"
  python3 - "$plan/report.json" "$pattern" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["schedule"]
paper = {"plain": 16, "seed": 33}[sys.argv[2]]
p = r["pieces"]
print(f"trials {r['trials']}, cuts {r['cuts']}, pieces {len(p)}, "
      f"passes {sum(x['passes'] for x in p)}, transfers {sum(x['transfers'] for x in p)}, "
      f"estimated {sum(x['estimated_knit_time_s'] for x in p) / 60:.1f} min (paper's bunny: {paper} min)")
PY
  if [ -n "$ref" ]; then
    read -r rs rkb < <(median_run 1 node "$ref" "$plan/pieces/piece-1.k" "$WORK/piece-1.dat")
    printf 'node knitout-to-dat.js on piece-1.k: %.3f s (accepted)\n' "$rs"
  fi
done
done
