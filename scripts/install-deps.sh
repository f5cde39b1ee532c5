#!/usr/bin/env bash
# Installs every Debian package wearknit needs to build, test and benchmark.
# Idempotent: packages already present are left alone; `apt-get update` runs
# only when something is missing. Needs root (or sudo) on Debian 12.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ccache
  clang clang-format libclang-rt-dev
  libeigen3-dev libopenmesh-dev liblemon-dev
  libboost-program-options-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  libusb-1.0-0-dev libserialport-dev
  umockdev libumockdev-dev
  libfmt-dev nlohmann-json3-dev
  libcairo2-dev libpng-dev zlib1g-dev
  libssl-dev libtbb-dev
  nodejs
  chromium
  time
  # tests/slurm/cluster.sh's single-node Slurm; it runs its own daemons from
  # its own folder, not the packages' services (which do not start without
  # /etc/slurm/slurm.conf, or without an init here).
  slurmctld slurmd slurm-client munge
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
