#!/usr/bin/env bash
# bench/native.sh PORTABLE_BUILD NATIVE_BUILD [PAIRS]: the portable build (the default, run-time
# dispatch) against one configured with -DFIXPOINT_NATIVE=ON (-march=native), on the rows of
# bench/targets.sh, 1 thread, alternating runs; medians of PAIRS pairs (default 3). Issue 11
# asks the portable build to stay within 5% of the native one.
set -euo pipefail
portable=${1:?portable build folder}
native=${2:?native build folder}
pairs=${3:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh" # median, pair_medians
rate() { # build config [args] -> M samples/s from the summary line
    "$1/bin/fixpoint" render "$2" -o "$out/x.png" --force --threads 1 "${@:3}" 2>&1 | tail -1 |
        sed -n 's/.*(\([0-9.e+-]*\) [a-z ]*\/s, .*/\1/p' | awk '{printf "%.1f", $1 / 1e6}'; }
echo "$(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $pairs pairs"
echo
echo "| work | portable | native | portable / native |"
echo "|---|---|---|---|"
row() { # name config [args]
    local name=$1 cfg=$2
    shift 2
    portable_rate() { rate "$portable" "$cfg" "$@"; }
    native_rate() { rate "$native" "$cfg" "$@"; }
    local p n q
    read -r p n q < <(pair_medians "$pairs" portable_rate native_rate "$@")
    printf '| %s | %s | %s | %.2f |\n' "$name" "$p" "$n" "$q"
}
row "circles, density" bench/circles.yaml
row "circles, map-colour" bench/circles.yaml --set renderer.colourer.type=map-colour
row "Sierpinski, flame" bench/sierpinski.yaml
row "Barnsley fern, flame" bench/fern.yaml
row "Gumowski-Mira, many chains" bench/gm-chains.yaml
row "Gumowski-Mira, single orbit" bench/gm-orbit.yaml
row "default render (inversion/fig6a), 4e6 points" configs/inversion/fig6a.yaml --set renderer.points=4000000
row "superformula ring (inversion/fig6d), 1e6 points" configs/inversion/fig6d.yaml --set renderer.points=1000000
row "orbit-trap (orbit-trap/fig10a at 2400 x 2400)" configs/orbit-trap/fig10a.yaml --set renderer.width=2400 \
    --set renderer.height=2400
