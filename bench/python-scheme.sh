#!/usr/bin/env bash
# The cost of an iteration scheme written in Python against the same scheme in C++: paper 02
# Fig. 6(b) (the Mann iteration, alpha = 0.7, chaos-game, 1024^2, flame colour) rendered with
# `mann` and with a python-scheme computing the same steps (same bytes: tests/python), in
# alternating pairs on 1 and 2 threads; medians of the points per second of the summary lines.
# Usage: bench/python-scheme.sh [BUILD_DIR] [PAIRS] [POINTS]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build} pairs=${2:-5} points=${3:-3000000}
fixpoint=$(realpath "$build/bin/fixpoint")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/mann.py" <<'PY'
a = 0.7

def step(T, x, y, n):
    tx, ty = T(x, y)
    return (1 - a) * x + a * tx, (1 - a) * y + a * ty
PY
sed 's/iteration: {type: mann, alpha: 0.7}/iteration: {type: python-scheme, file: mann.py}/' \
    configs/iterations/fig6b.yaml >"$work/py.yaml"
rate() { # the points per second of a render's summary line
    "$fixpoint" render "$@" --force --set renderer.points="$points" 2>&1 |
        sed -n 's/.*(\([0-9.e+]*\) points\/s.*/\1/p'
}
. bench/lib.sh # median
echo "CPU: $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); $points points, $pairs pairs"
for threads in 1 2; do
    : >"$work/c" && : >"$work/p"
    for ((i = 0; i < pairs; i++)); do
        rate configs/iterations/fig6b.yaml -o "$work/c.png" --threads "$threads" >>"$work/c"
        (cd "$work" && rate py.yaml -o p.png --threads "$threads") >>"$work/p"
    done
    c=$(median <"$work/c") p=$(median <"$work/p")
    awk -v t="$threads" -v c="$c" -v p="$p" 'BEGIN {
        printf "%d thread(s): mann (C++) %.3g points/s, python-scheme %.3g points/s: Python at %.2fx of C++\n", t, c, p, p / c }'
done
