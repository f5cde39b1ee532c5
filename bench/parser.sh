#!/usr/bin/env bash
# Parser speed: lines per second on the largest corpus file and on the
# generated 1M-line sheet, and the whole `wearknit fmt` run against the
# reference backend's whole run on the same file, in the same run.
#   KNITOUT_TO_DAT=/path/to/knitout-to-dat.js bench/parser.sh
source "$(dirname "$0")/common.sh"
bench_build make_sheet knitout_parser_bench wearknit
sheet=$(big_sheet)
largest=$SHARED/corpus/knitout/gen-plain-300x300.k
inputs=("$sheet")
[ -f "$largest" ] && inputs+=("$largest")
echo "== knitout_parser_bench (in-memory, one core)"
"$BUILD/bench/knitout_parser_bench" "${inputs[@]}" --benchmark_min_time=1 \
  --benchmark_out="$WORK/parser.json" --benchmark_out_format=json
reader_s=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print([b['real_time']/1000 for b in d['benchmarks'] if b['name']=='Reader/'+sys.argv[2]][0])" "$WORK/parser.json" "$(basename "$sheet")")
echo "== whole runs on $(wc -l < "$sheet") lines (median of 3, wall seconds, peak RSS)"
read -r fmt_s fmt_kb < <(median_run 3 "$BUILD/apps/wearknit/wearknit" fmt "$sheet" -o "$WORK/fmt.k")
printf 'wearknit fmt           %8.3f s  %7d KB\n' "$fmt_s" "$fmt_kb"
ref=$(reference)
if [ -n "$ref" ]; then
  read -r ref_s ref_kb < <(median_run 3 node "$ref" "$sheet" "$WORK/ref.dat")
  printf 'node knitout-to-dat.js %8.3f s  %7d KB\n' "$ref_s" "$ref_kb"
  awk -v a="$ref_s" -v b="$fmt_s" -v r="$reader_s" 'BEGIN {
    printf "ratio: the parser (Reader, %.3f s) is %.0fx faster than the reference whole run\n", r, a / r
    printf "ratio: the whole wearknit fmt run is %.0fx faster than the reference whole run\n", a / b }'
else
  echo "reference: set KNITOUT_TO_DAT to knitout-to-dat.js to compare (not found)"
fi
