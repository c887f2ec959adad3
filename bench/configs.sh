#!/usr/bin/env bash
# Throughput of every config in configs/, for the before/after table of bench/README.md:
#   bench/configs.sh BIN_DIR [THREADS] > table.tsv
# Each config is rendered once to a scratch folder with the CLI of BIN_DIR (points of chaos-game
# configs capped at 2e7, so the whole run takes minutes), and its summary line's samples per
# second printed as "config <TAB> samples/s <TAB> unit". Run two builds alternately in one
# session to compare them (the machines drift).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:?usage: bench/configs.sh BIN_DIR [THREADS]}
threads=${2:-2}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for f in $(find configs -name '*.yaml' | sort); do
    set_args=()
    if grep -q 'type: chaos-game' "$f"; then
        pts=$(grep -m1 -E '^\s*points:' "$f" | awk '{print $2}')
        if [ -n "$pts" ] && [ "$pts" -gt 20000000 ] 2>/dev/null; then set_args=(--set renderer.points=20000000); fi
    fi
    line=$("$bin/fixpoint" render "$f" -o "$out/x.png" --force --threads "$threads" "${set_args[@]}" 2>&1 | tail -1)
    rate=$(echo "$line" | sed -n 's/.*(\([0-9.e+-]*\) \(.*\)\/s, .*/\1/p')
    unit=$(echo "$line" | sed -n 's/.*(\([0-9.e+-]*\) \(.*\)\/s, .*/\2/p')
    printf '%s\t%s\t%s\n' "$f" "${rate:-?}" "${unit:-?}"
done
