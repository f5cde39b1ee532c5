#!/usr/bin/env bash
# `wearknit dat` against the reference backend `node knitout-to-dat.js` on the
# generated 1,000,000-line plain sheet (bench/make_sheet, 500 x 2000), in the
# same run: wall time, user+system CPU time and peak memory (max RSS) from
# /usr/bin/time -v, medians of RUNS interleaved runs, and the ratios. Also
# checks that both wrote the same bytes.
#
# usage: bench/dat_vs_reference.sh [BUILD_DIR] [RUNS]
#   BUILD_DIR  a build with the wearknit and make_sheet targets (default: build)
#   RUNS       runs of each program (default: 3)
#   KNITOUT_TO_DAT  path of knitout-to-dat.js (default: the extracted reference
#                   under /work/ref, see docs/dat.md)
set -euo pipefail

BUILD=${1:-build}
RUNS=${2:-3}
REF=${KNITOUT_TO_DAT:-/work/ref/interpreter/dat_compiler/dat-compiler/knitout-backend-swg-master/knitout-to-dat.js}
WEARKNIT=$BUILD/apps/wearknit/wearknit
MAKE_SHEET=$BUILD/bench/make_sheet

for f in "$WEARKNIT" "$MAKE_SHEET" "$REF" /usr/bin/time; do
  if [ ! -e "$f" ]; then echo "dat_vs_reference: missing $f" >&2; exit 2; fi
done
command -v node >/dev/null || { echo "dat_vs_reference: node not found" >&2; exit 2; }

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
"$MAKE_SHEET" "$TMP/sheet.k"
LINES=$(wc -l < "$TMP/sheet.k")

# measure NAME CMD... -> appends "wall cpu rss_kb" to $TMP/NAME
measure() {
  local name=$1; shift
  /usr/bin/time -v "$@" > /dev/null 2> "$TMP/time.txt"
  awk -F': ' '
    /Elapsed \(wall clock\)/ { n = split($2, p, ":"); w = 0; for (i = 1; i <= n; i++) w = w * 60 + p[i] }
    /User time/ { u = $2 } /System time/ { s = $2 } /Maximum resident/ { r = $2 }
    END { printf "%.3f %.3f %d\n", w, u + s, r }' "$TMP/time.txt" >> "$TMP/$name"
}

for _ in $(seq "$RUNS"); do
  measure reference node "$REF" "$TMP/sheet.k" "$TMP/reference.dat"
  measure wearknit "$WEARKNIT" dat "$TMP/sheet.k" -o "$TMP/wearknit.dat"
done

median() {  # column of file
  sort -n -k"$2" "$1" | awk -v c="$2" '{ v[NR] = $c } END { print v[int((NR + 1) / 2)] }'
}

if cmp -s "$TMP/reference.dat" "$TMP/wearknit.dat"; then same=yes; else same=NO; fi
rw=$(median "$TMP/reference" 1); rc=$(median "$TMP/reference" 2); rr=$(median "$TMP/reference" 3)
ww=$(median "$TMP/wearknit" 1); wc_=$(median "$TMP/wearknit" 2); wr=$(median "$TMP/wearknit" 3)

echo "input: bench/make_sheet 500 x 2000 plain, $LINES lines; $RUNS runs each, medians"
printf "%-24s %10s %12s %12s\n" "" "wall s" "user+sys s" "max RSS MB"
printf "%-24s %10.2f %12.2f %12.1f\n" "node knitout-to-dat.js" "$rw" "$rc" "$(awk -v r="$rr" 'BEGIN { print r / 1024 }')"
printf "%-24s %10.3f %12.3f %12.1f\n" "wearknit dat" "$ww" "$wc_" "$(awk -v r="$wr" 'BEGIN { print r / 1024 }')"
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b <= 0) b = 0.001; printf "%.0f", a / b }'; }
echo "speed-up: wall $(ratio "$rw" "$ww")x, cpu $(ratio "$rc" "$wc_")x; memory: $(awk -v a="$rr" -v b="$wr" 'BEGIN { printf "%.1f", a / b }')x less"
echo "same bytes: $same"
[ "$same" = yes ]
