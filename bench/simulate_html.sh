#!/usr/bin/env bash
# The HTML bed view (docs/vm.md, "Interactive bed view"): `wearknit simulate
# sheet.k --html out.html` on the generated 1,000,000-line plain sheet and on
# sheets two and four times as long: wall time, peak RSS and the page's size;
# then, when
# headless Chromium and the harness's browser_probe are there, the seconds
# until the page is interactive (document.body.dataset.ready) and a jump to
# the middle sweep.
#   bench/simulate_html.sh            RUNS=N (default 3) runs per measurement
# browser_probe is built from tests/ (a build with tests, WEARKNIT_TESTS=ON);
# set BROWSER_PROBE=/path/to/browser_probe to use another build's.
# BENCH_NO_BUILD=1 with WEARKNIT_BENCH_BUILD=DIR uses DIR's binaries as they are.
source "$(dirname "$0")/common.sh"
RUNS=${RUNS:-3}
[ "${BENCH_NO_BUILD:-0}" = 1 ] || bench_build make_sheet wearknit
WEARKNIT=$BUILD/apps/wearknit/wearknit
sheet=$(big_sheet)
double=$WORK/sheet-500x4000.k
[ -s "$double" ] || "$BUILD/bench/make_sheet" "$double" 500 4000 plain
quadruple=$WORK/sheet-500x8000.k
[ -s "$quadruple" ] || "$BUILD/bench/make_sheet" "$quadruple" 500 8000 plain
inputs=("$sheet" "$double" "$quadruple")

echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
printf '%-22s %10s %8s %10s %12s %10s\n' input lines MB wall_s peak_RSS_MB html_MB
for input in "${inputs[@]}"; do
  page=$WORK/$(basename "$input" .k).html
  read -r wall rss < <(median_run "$RUNS" "$WEARKNIT" simulate "$input" --html "$page")
  printf '%-22s %10d %8.1f %10.2f %12.1f %10.1f\n' "$(basename "$input")" "$(wc -l <"$input")" \
    "$(echo "$(stat -c %s "$input") / 1000000" | bc -l)" "$wall" "$(echo "$rss / 1024" | bc -l)" \
    "$(echo "$(stat -c %s "$page") / 1000000" | bc -l)"
done

# Page-interactive time in headless Chromium (tests/browser.hpp's harness):
# interactive_s from the start of loading to document.body.dataset.ready,
# wkBedTimings the page's own split (reading the data, building the view),
# then the whole bed redrawn and a jump to the middle sweep (ms in the page).
probe=${BROWSER_PROBE:-}
for candidate in "$BUILD/tests/browser_probe" "$ROOT/build/tests/browser_probe"; do
  [ -z "$probe" ] && [ -x "$candidate" ] && probe=$candidate
done
if [ -z "$probe" ]; then
  echo "browser_probe not built (ninja -C build browser_probe): page-interactive time not measured"
  exit 0
fi
echo "page                   interactive_s  data_s  view_s  sweeps  redraw_ms  go_to_sweep_ms"
for input in "${inputs[@]}"; do
  page=$WORK/$(basename "$input" .k).html
  "$probe" "file://$page" "wkBedTimings" "wkBedView.sweeps()" \
    "(() => { const t = performance.now(); wkBedView.redraw(); return performance.now() - t; })()" \
    "(() => { const t = performance.now(); wkBedView.goToSweep(Math.floor(wkBedView.sweeps() / 2)); return [wkBedView.currentLine(), wkBedView.currentSourceText(), performance.now() - t]; })()" \
    >"$WORK/probe.json" || { echo "browser_probe failed (exit $?)"; cat "$WORK/probe.json"; continue; }
  python3 - "$WORK/probe.json" "$(basename "$page")" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
if r.get("ready") != "1" or "error" in r or r["console_errors"]:
    print(sys.argv[2], "failed:", r.get("error"), r["console_errors"]); sys.exit(0)
t, sweeps, redraw, jump = (v["value"] for v in r["values"])
print(f"{sys.argv[2]:<22} {r['interactive_s']:13.2f} {t['data_ms'] / 1000:7.2f} {t['mount_ms'] / 1000:7.2f}"
      f" {sweeps:7d} {redraw:10.1f} {jump[2]:15.1f}")
PY
done
