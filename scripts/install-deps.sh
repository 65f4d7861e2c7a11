#!/usr/bin/env bash
# Installs every Debian package nearcap needs to build, test, fuzz, plot and
# measure (valgrind: the findings' instruction counts).
# Idempotent; run as root (or with sudo available). Debian 12 (bookworm).
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config git
  clang-14 libclang-rt-14-dev clang-format-14
  libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev
  libopenmesh-dev libglm-dev libceres-dev
  libcli11-dev nlohmann-json3-dev libstb-dev
  libgtest-dev libgmock-dev librapidcheck-dev libbenchmark-dev libtbb-dev
  libegl-dev libegl1-mesa-dev libgl1-mesa-dri libepoxy-dev
  libglfw3-dev xvfb xauth
  libembree-dev
  libopenmpi-dev openmpi-bin
  python3 python3-matplotlib
  chromium time valgrind
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
