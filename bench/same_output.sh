#!/usr/bin/env bash
# Does a change keep what the planner computes? Records what one wearknit
# binary makes of the shared meshes, and compares two such records.
#
#   bench/same_output.sh run BUILD_DIR OUT       record into OUT/
#   bench/same_output.sh compare OUT_A OUT_B     exit 0 when the records agree
#
# `run` makes, with the binary BUILD_DIR/apps/wearknit/wearknit:
#   * the knit branch (`cut`, `stitch-mesh`, `schedule`, every option at its
#     default) of every mesh of ../shared/meshes scaled to 100 mm along its
#     longest side, in OUT/knit/NAME/;
#   * the whole plan (`plan --size-mm 100`, garment over itself) of the
#     small closed meshes in $PLAN_MESHES (default torus-quad-coarse,
#     3torus-quad), in OUT/plan/NAME/, and `wearknit demo` in OUT/demo/;
# and writes OUT/record.sha256: one line per output that decides the
# knitting (cut-mesh.obj, stitch-mesh.smobj, every pieces/*.k and .dat), and
# a line per stage that failed, with its exit code. `compare` prints the
# lines that differ, the knitout pieces first.
# Environment: MESHES file names instead of every mesh; WEARKNIT_SHARED.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
shared=${WEARKNIT_SHARED:-../shared}
source bench/mesh_helpers.sh

usage() {
  echo "usage: bench/same_output.sh run BUILD_DIR OUT | compare OUT_A OUT_B" >&2
  exit 2
}

# Appends the hashes of the files that decide the knitting under $1 to the record.
record_folder() {
  local dir=$1 label=$2 file
  for file in "$dir"/cut-mesh.obj "$dir"/stitch-mesh.smobj "$dir"/pieces/*.k "$dir"/pieces/*.dat; do
    [ -f "$file" ] || continue
    printf '%s  %s/%s\n' "$(sha256sum <"$file" | cut -d' ' -f1)" "$label" "${file#"$dir"/}"
  done
}

elapsed() { python3 -c "import time; print(time.time() - $1)"; }

run() {
  local build=$1 out=$2
  local wearknit=$build/apps/wearknit/wearknit
  [ -x "$wearknit" ] || { echo "no $wearknit: build it first" >&2; exit 2; }
  [ -d "$shared/meshes" ] || { echo "no $shared/meshes" >&2; exit 2; }
  rm -rf "$out"
  mkdir -p "$out/knit" "$out/plan"
  local record=$out/record.sha256 times=$out/times.txt
  : >"$record"
  : >"$times"
  local meshes=${MESHES:-$(cd "$shared/meshes" && ls ./*.obj | sed 's|^\./||')}
  local mesh name dir scale stage code start
  for mesh in $meshes; do
    name=${mesh%.obj}
    dir=$out/knit/$name
    scale=$(scale_to_100mm "$shared/meshes/$mesh")
    start=$(date +%s.%N)
    for stage in cut stitch-mesh schedule; do
      set +e
      case $stage in
        cut) "$wearknit" cut "$shared/meshes/$mesh" --scale "$scale" -o "$dir" -q --no-pictures ;;
        stitch-mesh) "$wearknit" stitch-mesh "$dir" -q --no-picture ;;
        schedule) "$wearknit" schedule "$dir" -q ;;
      esac >"$dir.$stage.log" 2>&1
      code=$?
      set -e
      if [ "$code" -ne 0 ]; then
        printf 'exit %d  knit/%s/%s\n' "$code" "$name" "$stage" >>"$record"
        break
      fi
    done
    record_folder "$dir" "knit/$name" >>"$record"
    printf 'knit/%s %.1f s\n' "$name" "$(elapsed "$start")" | tee -a "$times" >&2
  done
  for mesh in ${PLAN_MESHES:-torus-quad-coarse.obj 3torus-quad.obj}; do
    name=${mesh%.obj}
    start=$(date +%s.%N)
    set +e
    "$wearknit" plan "$shared/meshes/$mesh" --wearer "$shared/meshes/$mesh" --size-mm 100 \
      -o "$out/plan/$name" --quiet --no-pictures >"$out/plan/$name.log" 2>&1
    code=$?
    set -e
    [ "$code" -eq 0 ] || printf 'exit %d  plan/%s\n' "$code" "$name" >>"$record"
    record_folder "$out/plan/$name" "plan/$name" >>"$record"
    printf 'plan/%s %.1f s\n' "$name" "$(elapsed "$start")" | tee -a "$times" >&2
  done
  start=$(date +%s.%N)
  set +e
  "$wearknit" demo -o "$out/demo" >"$out/demo.log" 2>&1
  code=$?
  set -e
  [ "$code" -eq 0 ] || printf 'exit %d  demo\n' "$code" >>"$record"
  record_folder "$out/demo" demo >>"$record"
  printf 'demo %.1f s\n' "$(elapsed "$start")" | tee -a "$times" >&2
  echo "$(wc -l <"$record") lines in $record ($(grep -c '\.k$' "$record") knitout pieces)" >&2
}

compare() {
  local a=$1/record.sha256 b=$2/record.sha256
  [ -f "$a" ] && [ -f "$b" ] || { echo "need $a and $b" >&2; exit 2; }
  local pieces_a pieces_b
  pieces_a=$(grep -c '\.k$' "$a" || true)
  pieces_b=$(grep -c '\.k$' "$b" || true)
  if diff -q "$a" "$b" >/dev/null; then
    echo "same: $pieces_a knitout pieces and every other recorded output byte for byte"
    return 0
  fi
  echo "knitout pieces that differ or exist on one side only ($pieces_a and $pieces_b in all):"
  diff <(grep '\.k$' "$a") <(grep '\.k$' "$b") || true
  echo "other outputs and failures that differ:"
  diff <(grep -v '\.k$' "$a") <(grep -v '\.k$' "$b") || true
  return 1
}

case ${1:-} in
  run) [ $# -eq 3 ] || usage; run "$2" "$3" ;;
  compare) [ $# -eq 3 ] || usage; compare "$2" "$3" ;;
  *) usage ;;
esac
