#!/usr/bin/env bash
# bench/flam3.sh [BUILD] [PAIRS]: flam3-render (Debian's flam3-utils, when installed) against
# fixpoint on the same Sierpinski triangle (bench/sierpinski.flam3, bench/sierpinski.yaml:
# 1e8 points, 1024 x 1024, one thread), alternating; medians of PAIRS pairs (default 3) of
# each command's whole wall time (start-up and PNG included), as M points per second.
set -euo pipefail
build=${1:-build}
pairs=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
. "$here/lib.sh" # median, wall, need_flam3
need_flam3
fl=() fx=()
for _ in $(seq "$pairs"); do
    fl+=("$(cd "$out" && wall env in="$here/sierpinski.flam3" prefix="$out/flam3." nthreads=1 format=png flam3-render)")
    fx+=("$(wall "$build/bin/fixpoint" render "$here/sierpinski.yaml" -o "$out/fixpoint.png" --force --threads 1)")
done
f=$(printf '%s\n' "${fl[@]}" | median) x=$(printf '%s\n' "${fx[@]}" | median)
echo "$(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $pairs pairs"
echo
echo "| Sierpinski triangle, 1024^2, 1 thread | wall time | M points/s |"
echo "|---|---|---|"
awk -v t="$f" 'BEGIN {printf "| flam3-render 3.1.1 (99.6 M samples) | %.2f s | %.1f |\n", t, 99.6 / t}'
awk -v t="$x" 'BEGIN {printf "| fixpoint, flame colourer (100 M points) | %.2f s | %.1f |\n", t, 100 / t}'
