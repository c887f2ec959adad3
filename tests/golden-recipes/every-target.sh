#!/usr/bin/env bash
# The golden corpus on every instruction set this CPU has (the CLI's --help lists them): the
# same SHA256SUMS on each, which is the promise "the image is the same bytes on every one" made
# over every renderer, colour path, scheme and precision at once.
#   every-target.sh FIXPOINT FIXPOINT_GOLDEN CORPUS
set -euo pipefail
cli=$1 golden=$2 corpus=$3
targets=$("$cli" --help 2>/dev/null | grep -oE '\b(AVX3_SPR|AVX3_ZEN4|AVX3_DL|AVX3|AVX2|SSE4|SSSE3|EMU128|SCALAR|NEON|SVE2?)\b' | sort -u)
[ -n "$targets" ] || { echo "every-target.sh: no instruction set in $cli --help" >&2; exit 1; }
for t in $targets; do
    echo "== $t"
    FIXPOINT_SIMD=$t "$golden" "$corpus"
done
