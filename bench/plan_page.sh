#!/usr/bin/env bash
# bench/plan_page.sh DIR: writes the plan page of plan folder DIR
# (wearknit view DIR -> DIR/index.html) and reports its size and the time
# to write it; then, with browser_probe (tests/browser_probe.cpp, headless
# Chromium), the seconds until the page is interactive and the frames per
# second while the garment turns, with WebGL and with the 2D canvas (?gl=0).
#   WEARKNIT_BUILD  the build folder with apps/wearknit/wearknit and
#                   tests/browser_probe (default: build)
#   FRAMES          frames turned per measure (default 120)
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${WEARKNIT_BUILD:-$ROOT/build}
FRAMES=${FRAMES:-120}
DIR=${1:?usage: bench/plan_page.sh PLAN_DIR}
WEARKNIT=$BUILD/apps/wearknit/wearknit
PROBE=$BUILD/tests/browser_probe

start=$(date +%s.%N)
"$WEARKNIT" view "$DIR" -q
end=$(date +%s.%N)
bytes=$(stat -c %s "$DIR/index.html")
printf 'page: %s  %.2f MB  written in %.2f s\n' "$DIR/index.html" \
  "$(echo "$bytes / 1048576" | bc -l)" "$(echo "$end - $start" | bc -l)"

if [ ! -x "$PROBE" ]; then
  echo "no $PROBE: build the target browser_probe for the frame rates" >&2
  exit 0
fi
url="file://$(cd "$DIR" && pwd)/index.html"
for query in "" "?gl=0"; do
  "$PROBE" "$url$query" "wkPlan.renderer()" "wkPlan.bench(10)" "wkPlan.bench($FRAMES)" |
    python3 -c '
import json, sys
r = json.load(sys.stdin)
if "error" in r or r.get("ready") != "1":
    print("page failed:", r.get("error"), r.get("console_errors")); sys.exit(1)
v = r["values"]
print("%-7s interactive in %.2f s, %.1f frames/s while turning (%d frames)%s" % (
    v[0]["value"], r["interactive_s"], v[2]["value"], '"$FRAMES"',
    "" if not r["console_errors"] else ", console errors: %s" % r["console_errors"]))'
done
