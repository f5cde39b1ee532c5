#!/usr/bin/env bash
# The knit branch of `wearknit plan` (cut, stitch mesh, schedule, then every
# piece through the VM) over the shared meshes x seeds x sizes, and the whole
# plan (garment over itself) on a few small meshes: a stage must never end
# in an internal error, and every failure must be a diagnostic with a code.
#   bench/sweep.sh [BUILD_DIR]               (default build)
# Environment:
#   MESHES       mesh names without .obj (default every mesh of ../shared/meshes)
#   SEEDS        cut seeds (default "1 2 3 4 5")
#   SIZES        longest side in mm (default "60 100 250")
#   PLAN_MESHES  meshes planned whole at 100 mm, seed 1 (default "sphere-qd torus-quad-coarse
#                3torus-quad"; "" for none)
#   JOBS         runs at once (default 2)
#   OUT          folder for the runs and the table (default a temporary one, removed)
# Writes OUT/sweep.tsv (one line per run: mesh, seed, size_mm, result, stage,
# code, exit, pieces, vm_rejected, seconds, message), OUT/sweep.md (the table
# of docs/results.md, bench/sweep_table.py) and prints the summary:
# runs, ok, failures by stage and code, internal errors. Exit 1 when there is
# an internal error, a failure without a code, a failed run whose folder is
# left inconsistent (result "inconsistent": a finished stage's result
# missing, the failed stage's result or a temporary file present) or a piece
# the VM rejects.
source "$(dirname "$0")/plan_common.sh"
if [ -z "${MESHES:-}" ]; then
  MESHES=$(cd "$shared/meshes" && for f in *.obj; do echo "${f%.obj}"; done)
fi
SEEDS=${SEEDS:-1 2 3 4 5}
SIZES=${SIZES:-60 100 250}
PLAN_MESHES=${PLAN_MESHES-sphere-qd torus-quad-coarse 3torus-quad}
table=$out/sweep.tsv
: >"$table"

# The longest side of each mesh, once.
declare -A longest
for mesh in $MESHES $PLAN_MESHES; do
  longest[$mesh]=$(python3 -c 'import sys
v = [list(map(float, l.split()[1:4])) for l in open(sys.argv[1]) if l.startswith("v ")]
print(repr(max(max(p[i] for p in v) - min(p[i] for p in v) for i in range(3))))' \
    "$shared/meshes/$mesh.obj")
done

# One line of the table from a run's log: the first diagnostic code, the
# first line of the message.
record() {
  local mesh=$1 seed=$2 size=$3 result=$4 stage=$5 code=$6 pieces=$7 rejected=$8 start=$9 log=${10}
  local seconds message=""
  seconds=$(($(date +%s) - start))
  [ -f "$log" ] && message=$(grep -m1 -E 'error|internal' "$log" | tr '\t' ' ' | cut -c1-300 || true)
  local diag
  diag=$( [ -f "$log" ] && grep -m1 -oE '\[[A-Z][0-9]{3}\]' "$log" | tr -d '[]' || true)
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$mesh" "$seed" "$size" "$result" "$stage" \
    "${diag:--}" "$code" "$pieces" "$rejected" "$seconds" "$message" >>"$table"
}

# Whether a failed run left its folder consistent: the stages before the
# failing one keep their results, the failing one wrote none (its main
# output absent, no pieces/ from a failed schedule), and no temporary file
# of an interrupted write is left.
consistent() {
  local dir=$1 failed=$2 stage
  local -A result=([cut]=cut.json [stitch-mesh]=stitch-mesh.smobj [schedule]=schedule.json)
  for stage in cut stitch-mesh schedule; do
    if [ "$stage" = "$failed" ]; then
      [ ! -e "$dir/${result[$stage]}" ] || return 1
      [ "$stage" != schedule ] || [ ! -e "$dir/pieces" ] || return 1
      break
    fi
    [ -s "$dir/${result[$stage]}" ] || return 1
  done
  [ -z "$(find "$dir" -name '*.tmp-*' -print -quit 2>/dev/null)" ]
}

# The knit branch of one mesh, seed and size.
knit_branch() {
  local mesh=$1 seed=$2 size=$3 start
  start=$(date +%s)
  local dir=$out/$mesh-s$seed-$size log=$out/$mesh-s$seed-$size.log
  local scale
  scale=$(python3 -c "print(repr($size / ${longest[$mesh]}))")
  rm -rf "$dir"
  local stage code=0
  for stage in cut stitch-mesh schedule; do
    case $stage in
      cut) "$wearknit" cut "$shared/meshes/$mesh.obj" --scale "$scale" --seed "$seed" -o "$dir" \
        -q --no-pictures >"$log" 2>&1 || code=$? ;;
      stitch-mesh) "$wearknit" stitch-mesh "$dir" -q --no-picture >"$log" 2>&1 || code=$? ;;
      schedule) "$wearknit" schedule "$dir" -q --seed "$seed" >"$log" 2>&1 || code=$? ;;
    esac
    if [ "$code" -ne 0 ]; then
      local result=failed
      grep -q 'internal error' "$log" && result=internal
      consistent "$dir" "$stage" || result=inconsistent
      record "$mesh" "$seed" "$size" "$result" "$stage" "$code" 0 0 "$start" "$log"
      return
    fi
  done
  local pieces=0 rejected=0 piece
  for piece in "$dir"/pieces/*.k; do
    pieces=$((pieces + 1))
    "$wearknit" validate "$piece" >/dev/null 2>&1 || rejected=$((rejected + 1))
  done
  record "$mesh" "$seed" "$size" ok - 0 "$pieces" "$rejected" "$start" /dev/null
  # Only the table is kept of a run that passed.
  rm -rf "$dir" "$log"
}

# The whole plan, the garment over itself, at 100 mm.
whole_plan() {
  local mesh=$1 start
  start=$(date +%s)
  local dir=$out/plan-$mesh log=$out/plan-$mesh.log code=0
  "$wearknit" plan "$shared/meshes/$mesh.obj" --wearer "$shared/meshes/$mesh.obj" --size-mm 100 \
    -o "$dir" -q --no-pictures >"$log" 2>&1 || code=$?
  local result=ok
  if [ "$code" -ne 0 ]; then
    result=failed
    grep -q 'internal error' "$log" && result=internal
  fi
  local pieces
  pieces=$(ls "$dir"/pieces/*.k 2>/dev/null | wc -l)
  record "$mesh" 1 100 "$result" plan "$code" "$pieces" 0 "$start" "$log"
}

runs=()
for mesh in $MESHES; do
  for seed in $SEEDS; do
    for size in $SIZES; do runs+=("knit_branch $mesh $seed $size"); done
  done
done
for mesh in $PLAN_MESHES; do runs+=("whole_plan $mesh"); done
echo "== $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); ${#runs[@]} runs, ${JOBS:-2} at once"
for run in "${runs[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "${JOBS:-2}" ]; do wait -n || true; done
  $run &
done
wait

bench/sweep_table.py "$table" >"$out/sweep.md"
python3 - "$table" <<'PY'
import collections, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
ok = [r for r in rows if r[3] == "ok"]
failed = [r for r in rows if r[3] != "ok"]
internal = [r for r in rows if r[3] == "internal"]
inconsistent = [r for r in rows if r[3] == "inconsistent"]
uncoded = [r for r in failed if r[5] == "-"]
rejected = sum(int(r[8]) for r in rows)
print(f"runs {len(rows)}, ok {len(ok)}, failed {len(failed)}, internal errors {len(internal)}, "
      f"failures without a code {len(uncoded)}, folders left inconsistent {len(inconsistent)}, pieces {sum(int(r[7]) for r in ok)}, "
      f"pieces the VM rejected {rejected}")
by = collections.Counter((r[4], r[5]) for r in failed)
for (stage, code), n in sorted(by.items()):
    print(f"  {stage} {code}: {n}")
for r in internal + uncoded + inconsistent:
    print("  " + " ".join(r[:3]) + ": " + r[10])
sys.exit(1 if internal or uncoded or inconsistent or rejected else 0)
PY
