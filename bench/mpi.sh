#!/usr/bin/env bash
# Ranks on one machine: the same render on 1, 2, 3 and 4 MPI ranks of one thread each, and what
# a rank costs beyond its share of the work (the histogram's reduction, the ranks' start):
#   bench/mpi.sh [BIN_DIR] [REPEATS]   (default build/bin, 3)
# Prints per work and rank count the median wall time of the whole command (mpirun's start
# included), its points or samples per second, the speed-up over one rank, and checks that
# every output has the same bytes. On this 2-core machine 3 and 4 ranks oversubscribe the
# cores: their figures show the cost of more ranks than cores, not more speed.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/bin}
repeats=${2:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
works=(
    "chaos-game fig6a 4e7 points|configs/inversion/fig6a.yaml|--set renderer.points=40000000"
    "chaos-game fig4a 1024^2 set-colour 4e7|configs/inversion/fig4a.yaml|"
    "orbit-trap fig5a 1024^2|configs/orbit-trap/fig5a.yaml|--set renderer.width=1024 --set renderer.height=1024"
    "superfractal fig2-F|configs/gumowski-mira/fig2-F.yaml|--set renderer.steps=10"
)
printf 'work\tranks\tseconds\trate/s\tspeed-up\n'
for w in "${works[@]}"; do
    IFS='|' read -r name config extra <<<"$w"
    base=
    for n in 1 2 3 4; do
        times=()
        for ((i = 0; i < repeats; i++)); do
            t0=$(date +%s.%N)
            # shellcheck disable=SC2086
            line=$(mpirun -np "$n" --oversubscribe "$bin/fixpoint" render "$config" -o "$out/np$n.png" --force \
                --threads 1 $extra 2>&1 | tail -1)
            t1=$(date +%s.%N)
            times+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')")
        done
        med=$(printf '%s\n' "${times[@]}" | sort -g | sed -n "$(((repeats + 1) / 2))p")
        samples=$(echo "$line" | sed -n 's/^[^:]*: \([0-9]*\) .*/\1/p')
        [ -z "$base" ] && base=$med
        if ! cmp -s "$out/np1.png" "$out/np$n.png"; then echo "$name: $n ranks: bytes differ" >&2; exit 1; fi
        awk -v w="$name" -v n="$n" -v t="$med" -v s="$samples" -v b="$base" \
            'BEGIN { printf "%s\t%d\t%.2f\t%.3g\t%.2fx\n", w, n, t, s / t, b / t }'
    done
done
