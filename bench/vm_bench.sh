#!/usr/bin/env bash
# vm_bench.sh: speed and memory of `wearknit validate` on the generated
# 1,000,000-line plain sheet, against the reference knitout-to-dat.js on the
# same file in the same run. Prints a table; docs/vm.md quotes its figures.
#
#   bench/vm_bench.sh [BUILD_DIR]       (default build; needs make_sheet,
#                                        wearknit and vm_bench built there)
#   RUNS=N   runs per measurement (median; default 3 for wearknit, 1 for node)
#   K2D=...  path of knitout-to-dat.js (default: the extracted reference)
set -euo pipefail

BUILD=${1:-build}
RUNS=${RUNS:-3}
NODE_RUNS=${NODE_RUNS:-1}
K2D=${K2D:-/work/ref/interpreter/dat_compiler/dat-compiler/knitout-backend-swg-master/knitout-to-dat.js}
WEARKNIT=$BUILD/apps/wearknit/wearknit
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

"$BUILD/bench/make_sheet" "$TMP/sheet.k"                   # 500 x 2000: ~1,000,000 lines
"$BUILD/bench/make_sheet" "$TMP/sheet-quarter.k" 500 500   # ~250,000 lines
"$BUILD/bench/make_sheet" "$TMP/sheet-double.k" 500 4000   # ~2,000,000 lines

# measure OUT_PREFIX CMD...: runs CMD under /usr/bin/time -v, prints
# "wall_s cpu_s max_rss_kb".
measure() {
  /usr/bin/time -v "$@" >"$TMP/out" 2>"$TMP/time" || true
  awk -F': ' '
    /Elapsed \(wall clock\)/ { n = split($2, p, ":"); wall = (n == 3) ? p[1]*3600 + p[2]*60 + p[3] : p[1]*60 + p[2] }
    /User time/ { user = $2 } /System time/ { sys = $2 } /Maximum resident/ { rss = $2 }
    END { printf "%.3f %.3f %d\n", wall, user + sys, rss }' "$TMP/time"
}

# median_of N CMD...: median (by wall time) of N measurements.
median_of() {
  local n=$1; shift
  for _ in $(seq "$n"); do measure "$@"; done | sort -n | awk '{ a[NR] = $0 } END { print a[int((NR + 1) / 2)] }'
}

lines=$(wc -l <"$TMP/sheet.k")
"$WEARKNIT" validate "$TMP/sheet.k" >"$TMP/summary" 2>/dev/null
instructions=$(sed -n 's/.*(\([0-9]*\) instructions.*/\1/p' "$TMP/summary")
echo "input: make_sheet 500 x 2000 plain: $lines lines, $instructions instructions"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
echo

read -r w_wall w_cpu w_rss < <(median_of "$RUNS" "$WEARKNIT" validate "$TMP/sheet.k")
printf '%-34s wall %7.3f s  cpu %7.3f s  max RSS %7d kB\n' "wearknit validate (median of $RUNS)" "$w_wall" "$w_cpu" "$w_rss"
if command -v node >/dev/null && [ -f "$K2D" ]; then
  read -r n_wall n_cpu n_rss < <(median_of "$NODE_RUNS" node "$K2D" "$TMP/sheet.k" "$TMP/sheet.dat")
  printf '%-34s wall %7.3f s  cpu %7.3f s  max RSS %7d kB\n' "node knitout-to-dat.js ($NODE_RUNS run)" "$n_wall" "$n_cpu" "$n_rss"
else
  echo "node or $K2D missing: no reference comparison"
  n_wall=0; n_cpu=0
fi
echo
awk -v n="$instructions" -v w="$w_wall" -v c="$w_cpu" -v nw="$n_wall" -v nc="$n_cpu" 'BEGIN {
  printf "wearknit: %.2f M instructions/s (wall), %.2f M instructions/s (cpu)\n", n / w / 1e6, n / c / 1e6
  if (nw > 0) printf "speed-up over knitout-to-dat.js: %.1fx (wall), %.1fx (cpu)\n", nw / w, nc / c
}'
echo

echo "peak memory of wearknit validate against input length:"
for f in sheet-quarter sheet sheet-double; do
  read -r _ _ rss < <(measure "$WEARKNIT" validate "$TMP/$f.k")
  printf '  %-14s %9d lines  max RSS %7d kB\n' "$f" "$(wc -l <"$TMP/$f.k")" "$rss"
done
echo

if [ -x "$BUILD/bench/vm_bench" ]; then
  "$BUILD/bench/vm_bench" --benchmark_min_time=1
fi
