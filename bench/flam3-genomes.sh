#!/usr/bin/env bash
# bench/flam3-genomes.sh [BUILD] [PAIRS] [QS]: flam3-render (Debian's flam3-utils) against
# fixpoint on random genomes of flam3-genome with their variations (tests/fixtures/flam3:
# genome-3, -7 and -19), each rendered from the same .flam3 file at twice its size (200 x 200)
# and QS times its quality (default 400: 16 M samples), one thread each, alternating; the
# medians of PAIRS pairs (default 3) of each command's whole wall time (start-up and PNG
# included), and their ratio.
set -euo pipefail
build=${1:-build}
pairs=${2:-3}
qs=${3:-400}
if ! command -v flam3-render >/dev/null; then
    echo "flam3-render not found (apt-get install flam3-utils)" >&2
    exit 1
fi
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
. "$here/lib.sh" # median
wall() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N); awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}'; }
echo "$(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $pairs pairs, qs $qs"
echo
echo "| genome (200^2, $((qs * 40)) k samples, 1 thread) | flam3-render | fixpoint | flam3 / fixpoint |"
echo "|---|---|---|---|"
for g in genome-3 genome-7 genome-19; do
    genome="$here/../tests/fixtures/flam3/$g.flam3"
    fl=() fx=()
    for _ in $(seq "$pairs"); do
        fl+=("$(cd "$out" && wall env ss=2 qs="$qs" nthreads=1 out="$out/flam3.png" flam3-render <"$genome")")
        fx+=("$(wall "$build/bin/fixpoint" render "$genome" -o "$out/fixpoint.png" --force --threads 1 \
            --set renderer.width=200 --set renderer.height=200 --set renderer.points=$((qs * 40000)))")
    done
    f=$(printf '%s\n' "${fl[@]}" | median) x=$(printf '%s\n' "${fx[@]}" | median)
    awk -v g="$g" -v f="$f" -v x="$x" 'BEGIN {printf "| %s | %.2f s | %.2f s | %.2f |\n", g, f, x, f / x}'
done
