#!/usr/bin/env bash
# `wearknit plan` on every closed mesh of ../shared/meshes, the mesh as the
# garment over itself, scaled to 100 mm along its longest side; prints a
# Markdown table (docs/results.md): result, time per stage, pieces, arcs and seams sewn
# and laced, stitches, passes, estimated knit time.
#   bench/plan_all.sh [BUILD_DIR]            (default build)
# Environment: PLAN_OPTS extra options for every plan (e.g. "--wear-trials 2"),
# MESHES a list of file names instead of every closed mesh, OUT the folder for
# the plans (default a temporary one, removed), TIMEOUT seconds per mesh (600).
# Run again with the same OUT after a timeout: each plan resumes its
# wearability stage from the journal in its folder (the table says how many
# tests it read back; its times are those of the last run).
source "$(dirname "$0")/plan_common.sh"
if [ -z "${MESHES:-}" ]; then
  MESHES=$(cd "$shared/meshes" && python3 tools/meshstats.py stats --json ./*.obj |
    python3 -c 'import json,sys
for line in sys.stdin:
    m = json.loads(line)
    if m["boundary_loops"] == 0: print(m["file"].split("/")[-1])')
fi
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); options: ${PLAN_OPTS:-none}" >&2
rows=()
for mesh in $MESHES; do
  name=${mesh%.obj}
  start=$(date +%s.%N)
  set +e
  # shellcheck disable=SC2086
  timeout "${TIMEOUT:-600}" "$wearknit" plan "$shared/meshes/$mesh" --wearer "$shared/meshes/$mesh" \
    -o "$out/$name" --size-mm 100 --quiet ${PLAN_OPTS:-} 2>"$out/$name.err"
  code=$?
  set -e
  wall=$(python3 -c "import time; print('%.0f' % (time.time() - $start))")
  echo "$name: exit $code, ${wall} s" >&2
  rows+=("$name=$out/$name:$code:$wall")
done
python3 bench/plan_table.py "${rows[@]}"
