#!/usr/bin/env bash
# The knit branch of `wearknit plan` (cut, stitch mesh, schedule, then every
# piece through the VM) on meshes of ../shared/meshes scaled to a few sizes
# near 100 mm along the longest side: a change of size moves every level
# curve, lattice line and needle, so a stage that works at one size by luck
# fails at another. Prints one line per mesh and size: the stage that failed
# and its message, or "ok" with the scheduling cuts, the pieces, the pieces
# the VM rejected (there must be none) and the VM's warnings by code.
#   bench/sizes.sh [BUILD_DIR]               (default build)
# Environment: MESHES file names (default every mesh), FACTORS sizes as
# fractions of 100 mm (default "0.97 1.03"), SCHEDULE_OPTS options for
# `wearknit schedule` (e.g. "--max-shift 4 --pattern seed"), OUT the folder
# for the results (default a temporary one, removed).
source "$(dirname "$0")/plan_common.sh"
if [ -z "${MESHES:-}" ]; then
  MESHES=$(cd "$shared/meshes" && for f in *.obj; do echo "$f"; done)
fi
for mesh in $MESHES; do
  file=$shared/meshes/$mesh
  longest=$(python3 -c 'import sys
v = [list(map(float, l.split()[1:4])) for l in open(sys.argv[1]) if l.startswith("v ")]
print(max(max(p[i] for p in v) - min(p[i] for p in v) for i in range(3)))' "$file")
  for factor in ${FACTORS:-0.97 1.03}; do
    scale=$(python3 -c "print(100 / $longest * $factor)")
    dir=$out/${mesh%.obj}-$factor
    log=$dir.log
    rm -rf "$dir"
    if ! "$wearknit" cut "$file" --scale "$scale" -o "$dir" -q --no-pictures >"$log" 2>&1; then
      echo "$mesh $factor: cut failed: $(tail -1 "$log")"
      continue
    fi
    if ! "$wearknit" stitch-mesh "$dir" --no-picture -q >"$log" 2>&1; then
      echo "$mesh $factor: stitch-mesh failed: $(tail -1 "$log")"
      continue
    fi
    # shellcheck disable=SC2086
    if ! "$wearknit" schedule "$dir" -q ${SCHEDULE_OPTS:-} >"$log" 2>&1; then
      echo "$mesh $factor: schedule failed: $(tail -1 "$log")"
      continue
    fi
    rejected=0
    for piece in "$dir"/pieces/*.k; do
      "$wearknit" validate "$piece" --format json >"$piece.vm.json" 2>/dev/null ||
        rejected=$((rejected + 1))
    done
    summary=$(python3 - "$dir" <<'PY'
import collections, glob, json, os, sys
d = sys.argv[1]
r = json.load(open(os.path.join(d, "report.json")))["schedule"]
codes = collections.Counter()
for f in glob.glob(os.path.join(d, "pieces", "*.vm.json")):
    for diag in json.load(open(f)):
        if diag["severity"] == "warning":
            codes[diag["code"]] += 1
warn = ", ".join(f"{n} {c}" for c, n in sorted(codes.items())) or "none"
print(f"{r['cuts']} scheduling cuts, {len(r['pieces'])} pieces", end="")
print(f"; VM warnings: {warn}")
PY
)
    echo "$mesh $factor: ok, $summary; $rejected pieces rejected by the VM"
  done
done
