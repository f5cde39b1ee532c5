#!/usr/bin/env bash
# The pictures of docs/viewer.md, taken in headless Chromium by the test
# harness's browser_probe (tests/browser.hpp): the demo's plan page (3D,
# pieces laid flat, a piece's bed view) and the bed view page of a corpus
# knitout file.
#   scripts/viewer-pictures.sh [BUILD_DIR]   (default build; needs ../shared)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
wearknit=$build/apps/wearknit/wearknit
probe=$build/tests/browser_probe
shared=${WEARKNIT_SHARED:-../shared}
out=docs/figures
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$wearknit" demo -q -o "$work/demo" >/dev/null
page="file://$work/demo/index.html"
shot() {  # shot NAME WIDTHxHEIGHT URL [EXPRESSION...]
  local name=$1 size=$2
  shift 2
  "$probe" --size "$size" --shot "$out/$name" "$@" >"$work/probe.json" ||
    { cat "$work/probe.json" >&2; exit 1; }
  echo "$out/$name"
}
# The first lace seam selected, in 3D and laid flat.
lace='wkPlan.selectSeam((wkPlan.seams().find(s => s.label === "lace") || wkPlan.seams()[0]).number)'
settle='new Promise(r => setTimeout(r, 300))'
shot viewer-3d.png 1200x760 "$page" "$lace" "wkPlan.frame()" "$settle"
shot viewer-flat.png 1200x760 "$page#flat" "$lace" "$settle"
# Piece 1 on the needle bed, scrubbed halfway.
bed='new Promise(r => { const t = () => window.wkPlanBedView ?
  r(wkPlanBedView.goToSweep(Math.floor(wkPlanBedView.sweeps() / 2))) : setTimeout(t, 50); t(); })'
shot viewer-pieces.png 1200x900 "$page#pieces" "$bed" "$settle"
# simulate --html on a corpus file, the pointer over the third carrier's block.
"$wearknit" simulate "$shared/corpus/knitout/gen-intarsia-4color-200x200.k" --html "$work/bed.html"
point='(() => { const c = document.querySelector(".bv-stage canvas");
  const r = c.getBoundingClientRect();
  c.dispatchEvent(new MouseEvent("mousemove", { clientX: r.left + 0.3 * r.width,
    clientY: r.top + 0.45 * r.height, bubbles: true }));
  return document.querySelector(".bv-hover").textContent; })()'
shot viewer-simulate.png 1200x820 "file://$work/bed.html" \
  "wkBedView.goToSweep(Math.floor(wkBedView.sweeps() * 0.6))" "$point" "$settle"
