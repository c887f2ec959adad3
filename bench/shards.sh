#!/usr/bin/env bash
# Shards (docs/cluster.md) at a cluster's image size: what a shard's file weighs, what a shard
# costs beyond its points, and how long merging takes, for the cost model in bench/README.md.
#   bench/shards.sh [BUILD] [N] [POINTS] [SIZE]
# Renders paper 01's fig. 6(a) (set-colour: bins with colour sums and last colours, the
# heaviest form) at SIZE² in N shards of POINTS in all, each on one thread, one after another;
# then the plain render on one thread; then merges the N shards into the image and into a
# histogram, and checks the image against the plain one.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
. "$here/lib.sh"
build=${1:-$here/../build}
n=${2:-8}
points=${3:-400000000}
size=${4:-4096}
cli=$build/bin/fixpoint
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cfg=$here/../configs/inversion/fig6a.yaml
set=(--set "renderer.points=$points" --set "renderer.width=$size" --set "renderer.height=$size")

echo "fig6a at ${size}², $points points in $n shards, one thread each ($(nproc) cores here)"
total=0
for k in $(seq "$n"); do
    t=$(wall "$cli" render -q "$cfg" "${set[@]}" --threads 1 --shard "$k/$n" --histogram "$work/part-$k.fph")
    total=$(awk -v a="$total" -v b="$t" 'BEGIN {print a + b}')
done
plain=$(wall "$cli" render -q "$cfg" "${set[@]}" --threads 1 -o "$work/plain.png")
one=$(stat -c %s "$work/part-1.fph")
raw=$(awk -v s="$size" 'BEGIN {print s * s * (32 + 6 + 16)}')
echo "shards: $total s in all, plain render: $plain s on one thread (overhead of sharding: $(awk -v a="$total" -v b="$plain" 'BEGIN {printf "%.2f", a / b}')x)"
echo "a shard's file: $one bytes ($(awk -v a="$one" -v b="$raw" 'BEGIN {printf "%.1f", b / a}')x smaller than its $raw bytes of bins)"
merge_png=$(wall "$cli" merge -q "$work"/part-*.fph -o "$work/merged.png" --threads 1)
merge_fph=$(wall "$cli" merge -q "$work"/part-*.fph -o "$work/merged.fph")
cmp -s "$work/merged.png" "$work/plain.png" && same=identical || same=DIFFERENT
echo "merge of $n into the image: $merge_png s (one thread; the image $same to the plain render's)"
echo "merge of $n into a histogram: $merge_fph s ($(stat -c %s "$work/merged.fph") bytes)"
