#!/usr/bin/env bash
# The covers of the paper's examples (§8) with `wearknit plan`: each
# quad-dominant proxy as the garment over its own source mesh as the wearer,
# 100 mm along the longest side, plain; then the same schedule in the seed
# pattern (`wearknit schedule DIR --pattern seed` on a copy). Prints the
# table of docs/results.md.
#   bench/plan_results.sh [BUILD_DIR]        (default build)
# Environment: PLAN_OPTS extra plan options, OUT the folder for the plans
# (default a temporary one, removed), TIMEOUT seconds per plan (3600).
source "$(dirname "$0")/plan_common.sh"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); options: ${PLAN_OPTS:-none}" >&2
rows=()
seed_rows=()
for pair in bunny-qd:bunny fertility-qd:fertility rockerarm-qd:rockerarm-10k torus-qd:torus-npm; do
  garment=${pair%%:*}
  wearer=${pair##*:}
  start=$(date +%s.%N)
  set +e
  # shellcheck disable=SC2086
  timeout "${TIMEOUT:-3600}" "$wearknit" plan "$shared/meshes/$garment.obj" \
    --wearer "$shared/meshes/$wearer.obj" -o "$out/$garment" --size-mm 100 --quiet ${PLAN_OPTS:-} \
    2>"$out/$garment.err"
  code=$?
  set -e
  wall=$(python3 -c "import time; print('%.0f' % (time.time() - $start))")
  echo "$garment over $wearer: exit $code, ${wall} s" >&2
  rows+=("$garment=$out/$garment:$code:$wall")
  if [ -f "$out/$garment/stitch-mesh.smobj" ]; then
    rm -rf "$out/$garment-seed"
    cp -r "$out/$garment" "$out/$garment-seed"
    "$wearknit" schedule "$out/$garment-seed" --pattern seed --quiet >&2 || true
    seed_rows+=("$garment-seed=$out/$garment-seed:$code:$wall")
  fi
done
python3 bench/plan_table.py "${rows[@]}"
echo
echo "Seed pattern (the same plan folders, scheduled again with --pattern seed; the stage times are the plain plan's):"
echo
python3 bench/plan_table.py "${seed_rows[@]}"
