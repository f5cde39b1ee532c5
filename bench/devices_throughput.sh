#!/usr/bin/env bash
# Throughput of the job protocol over TCP loopback and a pseudo-terminal,
# against sending the raw file over the same link, fault-free and at 1%
# frame corruption. Prints a table (docs/devices.md quotes it).
#   bench/devices_throughput.sh [BUILD_DIR] [WIDTH ROWS] [REPEATS]
set -euo pipefail
build=${1:-build}
width=${2:-500}
rows=${3:-2000}
repeats=${4:-3}
ninja -C "$build" make_sheet devices_throughput sp_pty_shim >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/bench/make_sheet" "$work/sheet.k" "$width" "$rows"
# libserialport opens a pty only with the test shim in front (docs/devices.md).
LD_PRELOAD="$(realpath "$build/tests/devices/libsp_pty_shim.so")" \
  "$build/bench/devices_throughput" "$work/sheet.k" "$repeats"
