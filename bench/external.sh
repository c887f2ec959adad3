#!/usr/bin/env bash
# bench/external.sh [BUILD_DIR] [PAIRS]: third-party plugins against built-in ones (issue 11:
# "a plugin built against the installed SDK runs at the speed of a built-in one").
# Installs fixpoint from BUILD_DIR (default build) into a scratch prefix and builds copies of
# two built-in plugins out of tree against that installed SDK, with only the CMake a plugin
# author writes (find_package + fixpoint_add_plugin) and their registered names changed:
#   superformula -> superformula-ext   on configs/inversion/fig6d.yaml (five superformula sets:
#                                      their inside tests and ray exits take most of the time)
#   gumowski-mira -> gumowski-mira-ext on bench/gm-chains.yaml with `kernels: generic` (the
#                                      renderer calls the plugin's batch, not its fused step)
#   s-iteration -> s-iteration-ext     on bench/circles.yaml with that scheme: the chaos game's
#                                      fused step runs the program the copy's SchemeBase records
# Each is rendered with the built-in plugin and with the copy, 1 thread, in alternating runs;
# medians of PAIRS pairs (default 5). Each pair of images must hold the same image data.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
pairs=${2:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"
fixpoint=("$work/prefix/bin/fixpoint")
. bench/lib.sh # median, pair_medians
rate() { # config output [args] -> M points/s from the summary line
    "${fixpoint[@]}" --plugin-dir "$work/build" render "$1" -o "$2" --force --threads 1 "${@:3}" 2>&1 |
        tail -1 | sed -n 's/.*(\([0-9.e+-]*\) [a-z ]*\/s, .*/\1/p' | awk '{printf "%.3f", $1 / 1e6}'
}
# The image data of a PNG file (its IDAT chunks), not its text chunks, whose recipes differ
# in the plugin's name.
idat() {
    python3 - "$1" <<'PY'
import hashlib, struct, sys
data = open(sys.argv[1], "rb").read()
pos, h = 8, hashlib.sha256()
while pos < len(data):
    (n,) = struct.unpack(">I", data[pos:pos + 4])
    if data[pos + 4:pos + 8] == b"IDAT":
        h.update(data[pos + 8:pos + 8 + n])
    pos += 12 + n
print(h.hexdigest())
PY
}
# Copy plugin SOURCE (kind KIND, registered as NAME) out of tree as NAME-ext.
external() { # source kind name
    local src=$1 kind=$2 name=$3
    local file
    file=$(basename "$src")
    mkdir -p "$work/src/$name"
    sed "s/fp::Kind::$kind, \"$name\",/fp::Kind::$kind, \"$name-ext\",/" "$src" >"$work/src/$name/$file"
    grep -q "\"$name-ext\"" "$work/src/$name/$file" || {
        echo "bench/external.sh: $name's registration was not found to rename" >&2
        exit 1
    }
    printf '%s\n' 'cmake_minimum_required(VERSION 3.25)' "project($name-ext LANGUAGES CXX)" \
        'find_package(fixpoint CONFIG REQUIRED)' "fixpoint_add_plugin($name-ext $file)" \
        >"$work/src/$name/CMakeLists.txt"
    cmake -S "$work/src/$name" -B "$work/build-$name" -DCMAKE_PREFIX_PATH="$work/prefix" >"$work/configure.log"
    cmake --build "$work/build-$name" >"$work/build.log"
    mkdir -p "$work/build"
    cp "$work/build-$name/$name-ext.so" "$work/build/"
}
external plugins/shapes/superformula.cpp Shape superformula
external plugins/transforms/gumowski-mira.cpp Transform gumowski-mira
external plugins/iterations/s-iteration.cpp IterationScheme s-iteration
echo "$(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $pairs pairs, 1 thread"
echo
echo "| work | built in (M points/s) | out of tree | out of tree / built in | same image |"
echo "|---|---|---|---|---|"
row() { # label config name [args]
    local label=$1 cfg=$2 name=$3
    shift 3
    sed -E "s/type: $name([,}])/type: $name-ext\1/" "$cfg" >"$work/ext.yaml"
    ext_rate() { rate "$work/ext.yaml" "$work/ext.png" "$@"; }
    builtin_rate() { rate "$cfg" "$work/builtin.png" "$@"; }
    local e b q
    read -r e b q < <(pair_medians "$pairs" ext_rate builtin_rate "$@")
    local same=no
    [ "$(idat "$work/builtin.png")" = "$(idat "$work/ext.png")" ] && same=yes
    printf '| %s | %s | %s | %.2f | %s |\n' "$label" "$b" "$e" "$q" "$same"
    [ "$same" = yes ] || {
        echo "bench/external.sh: $name and $name-ext gave different images" >&2
        exit 1
    }
}
row "superformula ring (inversion/fig6d), 2e6 points" configs/inversion/fig6d.yaml superformula \
    --set renderer.points=2000000
row "Gumowski-Mira, many chains, kernels: generic, 2e7 points" bench/gm-chains.yaml gumowski-mira \
    --set renderer.kernels=generic --set renderer.points=20000000
sed 's/colourer: {type: density}/colourer: {type: density}\n  iteration: {type: s-iteration, alpha: 0.6, beta: 0.3}/' \
    bench/circles.yaml >"$work/circles-s.yaml"
row "S-iteration on bench/circles.yaml (fused step), 3e7 points" "$work/circles-s.yaml" s-iteration \
    --set renderer.points=30000000
