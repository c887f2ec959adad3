#!/usr/bin/env bash
# Runs fixpoint's benchmarks next to the reference kernels, in the same session (the
# machines drift by ~10%, so only figures from one run are compared).
#   bench/run.sh [BUILD_DIR]      (default: build; builds fixpoint_bench first)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
ref=../shared/perf-reference
out=$build/bench-ref
mkdir -p "$out"
cmake --build "$build" --target fixpoint_bench -j"$(nproc)" >/dev/null
g++ -O3 -march=native -fopenmp -o "$out/circles" "$ref/circles.cpp"
echo "== reference: $ref/circles.cpp (n=1e8, reps=5)"
for variant in simd scalar; do
    for t in 1 2; do
        "$out/circles" variant=$variant threads=$t n=1e8 reps=5 | grep '^SUMMARY' |
            awk -v v=$variant -v t=$t '{for(i=1;i<=NF;i++) if($i ~ /^median_rate=/){split($i,a,"="); printf "reference %-6s threads=%d  %.1f M points/s\n", v, t, a[2]/1e6}}'
    done
done
echo "== fixpoint: $build/bin/fixpoint_bench (bench/circles.yaml)"
"$build/bin/fixpoint_bench" --benchmark_counters_tabular=true
