#!/usr/bin/env bash
# The performance targets of the portable-speed work (issue 11) in one run: each row is
# fixpoint's summary line on a bench/ config against its reference kernel in
# ../shared/perf-reference/, compiled here, in alternating pairs (the machines drift by 10% and
# more: only figures from one run are compared); the ratio is the median of the pairs' ratios.
#   bench/targets.sh [BUILD_DIR] [PAIRS]           (default: build, 3)
#   FIXPOINT_SIMD=AVX2 REF_FLAGS="-mavx2 -mfma" bench/targets.sh build
#       the same on an AVX2-class CPU: fixpoint pinned to AVX2, the references built for AVX2.
# Prints a Markdown table (M points/s, or M pixel-iterations/s for orbit-trap).
set -euo pipefail
# (set -e ends the script at a failed measurement without a word: say where.)
trap 'echo "bench/targets.sh: the command at line $LINENO failed" >&2' ERR
cd "$(dirname "$0")/.."
build=${1:-build}
pairs=${2:-3}
ref=../shared/perf-reference
out=$build/bench-ref/${FIXPOINT_SIMD:-best}
mkdir -p "$out"
flags=${REF_FLAGS:--march=native}
for k in circles ifs gm wallpaper; do
    # shellcheck disable=SC2086
    g++ -O3 $flags -fopenmp -o "$out/$k" "$ref/$k.cpp"
done
# The flame rows' whole work written by hand (bench/flame-ref.cpp): beside the targets, what
# the colour costs a kernel of the references' kind.
# shellcheck disable=SC2086
g++ -O3 $flags -o "$out/flame-ref" bench/flame-ref.cpp
. bench/lib.sh # median
ref_rate() { "$out/$1" "${@:2}" reps=3 | grep '^SUMMARY' | tr ' ' '\n' | sed -n 's/^median_rate=//p' |
    awk '{printf "%.1f", $1 / 1e6}'; }
fp_rate() { # config threads [args] -> M samples/s from the summary line
    "$build/bin/fixpoint" render "$1" -o "$out/x.png" --force --threads "$2" "${@:3}" 2>&1 | tail -1 |
        sed -n 's/.*(\([0-9.e+-]*\) [a-z ]*\/s, .*/\1/p' | awk '{printf "%.1f", $1 / 1e6}'; }
target=$("$build/bin/fixpoint" render bench/circles.yaml -o "$out/x.png" --force --threads 1 \
    --set renderer.points=1000 2>&1 | tail -1 | sed -n 's/.*thread[s]*, \([A-Z0-9_]*\)).*/\1/p')
echo "$(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores;" \
    "fixpoint dispatched to $target; references built with $flags; $pairs pairs"
echo
echo "| work | fixpoint | reference | ratio (median of pairs) | target |"
echo "|---|---|---|---|---|"
row() { # name target threads ref-args... -- config fp-args...
    local name=$1 goal=$2 t=$3
    shift 3
    local rargs=() fargs=()
    while [ "$1" != -- ]; do rargs+=("$1"); shift; done
    shift
    local cfg=$1
    shift
    fargs=("$@")
    local rs=() fs=() qs=()
    for _ in $(seq "$pairs"); do
        local r f
        r=$(ref_rate "${rargs[@]}" threads="$t")
        f=$(fp_rate "$cfg" "$t" "${fargs[@]}")
        rs+=("$r") fs+=("$f") qs+=("$(awk -v a="$f" -v b="$r" 'BEGIN {printf "%.3f", a / b}')")
    done
    printf '| %s | %s | %s %s | %.2fx | %s |\n' "$name" "$(printf '%s\n' "${fs[@]}" | median)" \
        "${rargs[0]}" "$(printf '%s\n' "${rs[@]}" | median)" "$(printf '%s\n' "${qs[@]}" | median)" "$goal"
}
row "circles, density, float" ">= 0.6x" 1 circles variant=simd n=1e8 -- bench/circles.yaml
row "circles, map-colour" ">= 0.45x" 1 circles variant=simd n=1e8 -- bench/circles.yaml \
    --set renderer.colourer.type=map-colour
row "Sierpinski, affine, flame" ">= 0.45x" 1 ifs map=sierpinski variant=simd n=1e8 -- bench/sierpinski.yaml
row "Barnsley fern, affine, flame" ">= 0.45x" 1 ifs map=fern variant=simd n=1e8 -- bench/fern.yaml
row "Sierpinski, flame, against flame-ref" "-" 1 flame-ref map=sierpinski n=1e8 -- bench/sierpinski.yaml
row "Barnsley fern, flame, against flame-ref" "-" 1 flame-ref map=fern n=1e8 -- bench/fern.yaml
# The ceiling of the flame rows: the same work written by hand (flame-ref, in its fastest
# layout, 2 x 2 bins to a cache line) against the flame target's yardstick. fixpoint's flame
# rows can reach their 0.45x only where this row reads well above it.
hand_row() { # name ifs-args... -- flame-ref-args...
    local name=$1
    shift
    local iargs=() hargs=()
    while [ "$1" != -- ]; do iargs+=("$1"); shift; done
    shift
    hargs=("$@")
    local rs=() hs=() qs=()
    for _ in $(seq "$pairs"); do
        local r h
        r=$(ref_rate "${iargs[@]}" threads=1)
        h=$(ref_rate "${hargs[@]}")
        rs+=("$r") hs+=("$h") qs+=("$(awk -v a="$h" -v b="$r" 'BEGIN {printf "%.3f", a / b}')")
    done
    printf '| %s | (by hand) %s | %s %s | %.2fx | - |\n' "$name" "$(printf '%s\n' "${hs[@]}" | median)" \
        "${iargs[0]}" "$(printf '%s\n' "${rs[@]}" | median)" "$(printf '%s\n' "${qs[@]}" | median)"
}
hand_row "Sierpinski, flame-ref layout=tiles" ifs map=sierpinski variant=simd n=1e8 -- \
    flame-ref map=sierpinski n=1e8 layout=tiles
hand_row "Barnsley fern, flame-ref layout=tiles" ifs map=fern variant=simd n=1e8 -- \
    flame-ref map=fern n=1e8 layout=tiles
row "Gumowski-Mira, many chains" ">= 0.5x" 1 gm variant=simd n=1e8 -- bench/gm-chains.yaml
row "Gumowski-Mira, single orbit (double)" ">= 0.7x" 1 gm variant=orbit1 n=5e7 -- bench/gm-orbit.yaml
row "circles, density, 2 threads" "-" 2 circles variant=simd n=1e8 -- bench/circles.yaml
# orbit-trap: the reference's work (p1 map, the traps of Fig. 3b, 1024^2, M = 100) through the
# renderer, from fixpoint_bench_orbit_trap (built with the tree).
if [ -x "$build/bin/fixpoint_bench_orbit_trap" ]; then
    rs=() fs=() qs=()
    for _ in $(seq "$pairs"); do
        r=$(ref_rate wallpaper variant=simd threads=1)
        f=$("$build/bin/fixpoint_bench_orbit_trap" --benchmark_filter='reference_work/1/' 2>/dev/null |
            sed -n 's#^reference_work/1/.*items_per_second=\([0-9.]*\)M/s.*#\1#p')
        rs+=("$r") fs+=("$f") qs+=("$(awk -v a="$f" -v b="$r" 'BEGIN {printf "%.3f", a / b}')")
    done
    printf '| orbit-trap, p1 map, 4 traps, M = 100 | %s | wallpaper %s | %.2fx | >= 0.6x |\n' \
        "$(printf '%s\n' "${fs[@]}" | median)" "$(printf '%s\n' "${rs[@]}" | median)" \
        "$(printf '%s\n' "${qs[@]}" | median)"
fi
