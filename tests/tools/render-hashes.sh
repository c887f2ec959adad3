#!/usr/bin/env bash
# Renders every config under configs/ small, plus variants that take the renderers' other paths
# (double precision, generic kernels, strips, one thread, every SIMD target on a few), and prints
# the SHA-256 of each output's pixels (EXR: 32-bit floats, so the smallest change shows; the
# pixels only, since the recipe a file carries names each plugin binary's own hash). Run it with the
# binary before and after a change that must not change bytes, and diff the two lists:
#   tests/tools/render-hashes.sh build/bin/fixpoint /tmp/before > before.txt
# (ONLY=REGEX renders only the names that match.)
set -euo pipefail
bin=$(realpath "$1")
out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"

# render NAME CONFIG [ARGS...]: one render into $out/NAME.exr, its hash on stdout (only the
# names that match the regular expression $ONLY, when it is set).
render() {
    local name=$1 cfg=$2
    shift 2
    if [[ -n ${ONLY:-} && ! $name =~ $ONLY ]]; then return; fi
    local f="$out/$name.exr"
    if "$bin" render "$cfg" -o "$f" --force -q "$@" 2>"$out/$name.err"; then
        echo "$("$root/tests/tools/exr-pixels-sha256.py" "$f")  $name"
    else
        echo "FAILED($(tail -c 200 "$out/$name.err" | tr '\n' ' '))  $name"
    fi
}

# The keys that make a config small, by renderer.
small() {
    case $(grep -m1 -A3 '^renderer:' "$1" | grep -m1 'type:' | awk '{print $2}') in
    chaos-game) echo --set renderer.width=96 --set renderer.height=96 --set renderer.points=200000 ;;
    superfractal) echo --set renderer.width=96 --set renderer.height=96 --set renderer.points_per_buffer=20000 ;;
    orbit-trap) echo --set renderer.width=64 --set renderer.height=64 ;;
    mfs) echo --set renderer.width=96 --set renderer.height=96 ;;
    *) echo ;;
    esac
}

for cfg in "$root"/configs/*/*.yaml; do
    name=$(basename "$(dirname "$cfg")")-$(basename "$cfg" .yaml)
    # shellcheck disable=SC2046
    render "$name" "$cfg" $(small "$cfg") --threads 2
done

# The other paths of chaos-game and orbit-trap, on a few configs of each family.
cg="inversion/fig4a inversion/fig6d iterations/fig5b iterations/fig10a iterations/fig12a gumowski-mira/fig1b
    gumowski-mira/fig1b-chains gumowski-mira/fig5"
for c in $cg; do
    cfg=$root/configs/$c.yaml
    name=${c//\//-}
    # shellcheck disable=SC2046
    {
        render "$name-double" "$cfg" $(small "$cfg") --set renderer.precision=double
        render "$name-generic" "$cfg" $(small "$cfg") --set renderer.kernels=generic
        render "$name-generic-double" "$cfg" $(small "$cfg") --set renderer.kernels=generic \
            --set renderer.precision=double
        render "$name-1thread" "$cfg" $(small "$cfg") --threads 1
        render "$name-strips" "$cfg" --set renderer.width=400 --set renderer.height=400 \
            --set renderer.points=200000 --memory 12M
        render "$name-density" "$cfg" $(small "$cfg") --set 'renderer.colourer={type: density}'
        render "$name-rules-off" "$cfg" $(small "$cfg") --set renderer.inversion_rules=off
    }
done
ot="orbit-trap/fig5a orbit-trap/fig5a-hexagonal orbit-trap/fig7a orbit-trap/fig10a"
for c in $ot; do
    cfg=$root/configs/$c.yaml
    name=${c//\//-}
    # shellcheck disable=SC2046
    {
        render "$name-double" "$cfg" $(small "$cfg") --set renderer.precision=double
        render "$name-1thread" "$cfg" $(small "$cfg") --threads 1
        render "$name-strips" "$cfg" --set renderer.width=300 --set renderer.height=300 --memory 1M
        for red in none centred floor hexagonal; do
            render "$name-reduction-$red" "$cfg" $(small "$cfg") --set renderer.reduction=$red
        done
    }
done

# Every SIMD target this machine has, on one config of each kernel family.
targets=$("$bin" --help 2>/dev/null | grep -oE '\b(AVX3_SPR|AVX3_ZEN4|AVX3_DL|AVX3|AVX2|SSE4|SSSE3|EMU128|SCALAR|NEON|SVE2?)\b' | sort -u)
for t in $targets; do
    for c in inversion/fig4a iterations/fig5b gumowski-mira/fig1b gumowski-mira/fig5 orbit-trap/fig5a \
        orbit-trap/fig5a-hexagonal gumowski-mira/fig3; do
        cfg=$root/configs/$c.yaml
        # shellcheck disable=SC2046
        FIXPOINT_SIMD=$t render "${c//\//-}-simd-$t" "$cfg" $(small "$cfg")
    done
done
