#!/usr/bin/env bash
# Virtual-machine speed and memory: `wearknit validate` on the generated
# 1,000,000-line plain sheet against the reference knitout-to-dat.js on the
# same file in the same run (wall and CPU time, peak RSS), peak RSS against
# input length, then the in-process Google Benchmark figures.
#   KNITOUT_TO_DAT=/path/to/knitout-to-dat.js bench/vm_bench.sh
#   RUNS=N (default 3) runs of wearknit per measurement, NODE_RUNS=N (default 1)
source "$(dirname "$0")/common.sh"
RUNS=${RUNS:-3}
NODE_RUNS=${NODE_RUNS:-1}
bench_build make_sheet wearknit vm_bench
WEARKNIT=$BUILD/apps/wearknit/wearknit
sheet=$(big_sheet)
quarter=$WORK/sheet-500x500.k
double=$WORK/sheet-500x4000.k
[ -s "$quarter" ] || "$BUILD/bench/make_sheet" "$quarter" 500 500 plain
[ -s "$double" ] || "$BUILD/bench/make_sheet" "$double" 500 4000 plain

# measure CMD...: prints "wall_s cpu_s max_rss_kb" of one run (/usr/bin/time -v).
measure() {
  /usr/bin/time -v "$@" >/dev/null 2>"$WORK/time-v.txt" || true
  awk -F': ' '
    /Elapsed \(wall clock\)/ { n = split($2, p, ":"); wall = (n == 3) ? p[1]*3600 + p[2]*60 + p[3] : p[1]*60 + p[2] }
    /User time/ { user = $2 } /System time/ { sys = $2 } /Maximum resident/ { rss = $2 }
    END { printf "%.3f %.3f %d\n", wall, user + sys, rss }' "$WORK/time-v.txt"
}
# median_of N CMD...: the median (by wall time) of N measurements.
median_of() {
  local n=$1; shift
  for _ in $(seq "$n"); do measure "$@"; done | sort -g | awk '{ a[NR] = $0 } END { print a[int((NR + 1) / 2)] }'
}

instructions=$("$WEARKNIT" validate "$sheet" 2>/dev/null | sed -n 's/.*(\([0-9]*\) instructions.*/\1/p')
echo "input: $(basename "$sheet"): $(wc -l <"$sheet") lines, $instructions instructions"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
read -r w_wall w_cpu w_rss < <(median_of "$RUNS" "$WEARKNIT" validate "$sheet")
printf '%-36s wall %7.3f s  cpu %7.3f s  max RSS %7d kB\n' "wearknit validate (median of $RUNS)" \
  "$w_wall" "$w_cpu" "$w_rss"
n_wall=0
n_cpu=0
ref=$(reference)
if [ -n "$ref" ]; then
  read -r n_wall n_cpu n_rss < <(median_of "$NODE_RUNS" node "$ref" "$sheet" "$WORK/vm-ref.dat")
  printf '%-36s wall %7.3f s  cpu %7.3f s  max RSS %7d kB\n' "node knitout-to-dat.js ($NODE_RUNS run)" \
    "$n_wall" "$n_cpu" "$n_rss"
else
  echo "reference: set KNITOUT_TO_DAT to knitout-to-dat.js to compare (not found)"
fi
awk -v n="$instructions" -v w="$w_wall" -v c="$w_cpu" -v nw="$n_wall" -v nc="$n_cpu" 'BEGIN {
  printf "wearknit validate: %.2f M instructions/s (wall), %.2f M instructions/s (cpu)\n", n / w / 1e6, n / c / 1e6
  if (nw > 0) printf "ratio over knitout-to-dat.js: %.1fx (wall), %.1fx (cpu)\n", nw / w, nc / c
}'
echo "== peak memory of wearknit validate against input length"
for f in "$quarter" "$sheet" "$double"; do
  read -r _ _ rss < <(measure "$WEARKNIT" validate "$f")
  printf '  %-22s %9d lines  max RSS %7d kB\n' "$(basename "$f")" "$(wc -l <"$f")" "$rss"
done
echo "== vm_bench (in-memory, one core)"
"$BUILD/bench/vm_bench" --benchmark_min_time=1
