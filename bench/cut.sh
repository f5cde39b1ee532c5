#!/usr/bin/env bash
# Times the cutting stage against its targets (docs/cutting.md):
#   cutting bunny-qd (load + cut) under 1 s; remeshing and cutting the
#   52,000-face armadillo under 30 s. Prints the measured times and their
#   ratio to the target.
# usage: bench/cut.sh   (release build in $WEARKNIT_BENCH_BUILD, default build-bench; needs ../shared)
source "$(dirname "$0")/common.sh"
cd "$ROOT"
build="$BUILD"
bench_build cut_bench
json="$(mktemp)"
trap 'rm -f "$json"' EXIT
"$build/bench/cut_bench" --benchmark_format=json --benchmark_out="$json" --benchmark_out_format=json >/dev/null
python3 - "$json" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
targets = {"BM_CutBunnyQd": 1.0, "BM_RemeshAndCutArmadillo": 30.0}
scale = {"ms": 1e-3, "s": 1.0, "us": 1e-6, "ns": 1e-9}
print(f"{'benchmark':28} {'wall s':>8} {'cpu s':>8} {'target s':>8} {'wall/target':>11}")
for b in data["benchmarks"]:
    name = b["name"].split("/")[0]
    wall = b["real_time"] * scale[b["time_unit"]]
    cpu = b["cpu_time"] * scale[b["time_unit"]]
    t = targets.get(name)
    print(f"{name:28} {wall:8.3f} {cpu:8.3f} {t:8.1f} {wall / t:11.3f}")
    extra = {k: v for k, v in b.items() if k in ("faces", "input_faces", "proxy_faces", "extracted")}
    if extra:
        print("   ", ", ".join(f"{k}={v:g}" for k, v in extra.items()))
PY
