# Shared by the bench/*.sh scripts: a release build with the benchmarks, the
# generated 1M-line sheet, the reference backend, and timing helpers.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${WEARKNIT_BENCH_BUILD:-$ROOT/build-bench}
WORK=${WEARKNIT_BENCH_WORK:-/tmp/wearknit-bench}
SHARED=${WEARKNIT_SHARED:-$ROOT/../shared}
mkdir -p "$WORK"

bench_build() {
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DWEARKNIT_TESTS=OFF \
    -DWEARKNIT_BENCH=ON >/dev/null
  cmake --build "$BUILD" --parallel "$(nproc)" --target "$@" >/dev/null
}

# The 1,000,000-line plain sheet (500 needles x 2000 rows).
big_sheet() {
  local out=$WORK/sheet-500x2000.k
  [ -s "$out" ] || "$BUILD/bench/make_sheet" "$out" 500 2000 plain
  echo "$out"
}

# The reference backend knitout-to-dat.js: $KNITOUT_TO_DAT, if set. It is
# public code (CMU Textiles Lab, knitout-backend-swg, as vendored in
# mhofmann-Khoury/knit_script at commit ca672c6); the project never ships it.
reference() {
  if [ -n "${KNITOUT_TO_DAT:-}" ] && [ -f "$KNITOUT_TO_DAT" ] && command -v node >/dev/null; then
    echo "$KNITOUT_TO_DAT"
  fi
}

# median_run N CMD...: runs CMD N times; prints "median_seconds max_rss_kb".
median_run() {
  local n=$1; shift
  local times=() rss=0
  for _ in $(seq "$n"); do
    /usr/bin/time -f "%e %M" -o "$WORK/time.txt" "$@" >/dev/null 2>"$WORK/stderr.txt" || {
      echo "failed: $* (see $WORK/stderr.txt)" >&2; return 1; }
    read -r t m < "$WORK/time.txt"
    times+=("$t")
    (( m > rss )) && rss=$m
  done
  local median
  median=$(printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  echo "$median $rss"
}
