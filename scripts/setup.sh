#!/usr/bin/env bash
# Install silt's Debian 12 build dependencies (only those missing) and build it in Release.
# Usage: scripts/setup.sh [BUILD_DIR [CMAKE_OPTION...]]      (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}
shift $(( $# > 0 ? 1 : 0 ))

packages=(build-essential cmake pkg-config libtbb-dev libeigen3-dev libsuitesparse-dev libosmesa6-dev
          libopenblas-serial-dev libfftw3-dev libxxhash-dev libpng-dev doctest-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libfreetype-dev
          fonts-dejavu-core libreadline-dev clang libclang-rt-14-dev clang-format clang-tidy)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then sudo=sudo; else sudo=; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" > /dev/null
cmake --build "$build_dir" -j"$(nproc)"
