#!/usr/bin/env bash
# fixpoint's one setup script, for a fresh Debian 12 machine.
#
#   ./setup.sh         install the dependencies (Debian packages), build, render the default
#                      config to fixpoint.png
#   ./setup.sh test    the same, then run every test (this is what CI runs)
#
# Needs root or sudo only to install missing packages; does nothing to the system when they
# are all present.
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-render}
case "$mode" in
render | test) ;;
*)
    echo "usage: ./setup.sh [test]" >&2
    exit 2
    ;;
esac

packages=(
    build-essential cmake pkg-config git
    libboost-dev libboost-filesystem-dev libyaml-cpp-dev libopenimageio-dev
    libspdlog-dev libfmt-dev libtbb-dev libcli11-dev libpcg-cpp-dev
    libgtest-dev libgmock-dev libbenchmark-dev clang-format fonts-dejavu-core
    libcairo2-dev
)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]}" >&2
    sudo=()
    [ "$(id -u)" -eq 0 ] || sudo=(sudo)
    export DEBIAN_FRONTEND=noninteractive
    "${sudo[@]}" apt-get update -qq
    "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$jobs"

build/bin/fixpoint render configs/inversion/fig6a.yaml -o fixpoint.png
echo "setup: rendered configs/inversion/fig6a.yaml to fixpoint.png"
if [ "$mode" = test ]; then
    ctest --test-dir build --output-on-failure -j"$jobs" --timeout 900
fi
