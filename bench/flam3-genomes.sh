#!/usr/bin/env bash
# bench/flam3-genomes.sh [BUILD] [PAIRS] [QS]: flam3-render (Debian's flam3-utils) against
# fixpoint on random genomes of flam3-genome with their variations (tests/fixtures/flam3:
# genome-3, -7 and -19), each rendered from the same .flam3 file at twice its size (200 x 200)
# and QS times its quality (default 400: 16 M samples), one thread each, alternating; the
# medians of PAIRS pairs (default 3) of each command's whole wall time (start-up and PNG
# included), and the median of their ratios pair by pair.
set -euo pipefail
build=${1:-build}
pairs=${2:-3}
quality=${3:-400}
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
. "$here/lib.sh" # median, wall, need_flam3
need_flam3
echo "$(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $pairs pairs, qs $quality"
echo
echo "| genome (200^2, $((quality * 40)) k samples, 1 thread) | flam3-render | fixpoint | flam3 / fixpoint |"
echo "|---|---|---|---|"
flam3() { (cd "$out" && wall env ss=2 qs="$quality" nthreads=1 out="$out/flam3.png" flam3-render <"$1"); }
ours() {
    wall "$build/bin/fixpoint" render "$1" -o "$out/fixpoint.png" --force --threads 1 --set renderer.width=200 \
        --set renderer.height=200 --set renderer.points=$((quality * 40000))
}
for g in genome-3 genome-7 genome-19; do
    genome="$here/../tests/fixtures/flam3/$g.flam3"
    read -r f x q < <(pair_medians "$pairs" flam3 ours "$genome")
    awk -v g="$g" -v f="$f" -v x="$x" -v q="$q" 'BEGIN {printf "| %s | %.2f s | %.2f s | %.2f |\n", g, f, x, q}'
done
