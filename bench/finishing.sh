#!/usr/bin/env bash
# bench/finishing.sh [BUILD] [SIZE]: what the finishing stage (docs/finishing.md, issue 42) buys.
#
#   anti-aliasing    bench/thin-strokes.yaml (paper 01's Fig. 4(a) circles, thin arcs) at 512 x 512,
#                    converged (1e8 points), raw and finished (supersample 2, flam3's gaussian),
#                    each against the same recipe rendered at 8x the size (4096 x 4096, 1e9 points)
#                    and box-filtered down: SSIM and PSNR over the lit pixels (bench/quality.py).
#   time to quality  the seconds until an image is within SSIM 0.95 (over the lit pixels) of the
#                    same recipe at 64x its points: fixpoint raw, fixpoint finished (supersample 2,
#                    gaussian 0.5, estimator_radius 3), and flam3-render (Debian's flam3-utils,
#                    its estimator radius 9 and filter 0.5) on the same triangle; SIZE x SIZE images
#                    (default 512), 2 threads. The points double from 1/4096 of the converged
#                    image's until the SSIM is reached; the time is that render's wall time.
#
# Prints Markdown tables (bench/README.md keeps the figures). Takes a few minutes.
set -euo pipefail
build=${1:-build}
size=${2:-512}
here=$(cd "$(dirname "$0")" && pwd)
fixpoint="$build/bin/fixpoint"
quality="$here/quality.py"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
. "$here/lib.sh" # wall
finish=(--set renderer.supersample=2 --set "renderer.filter={type: gaussian, radius: 0.5}")
# The finished setting of the time-to-quality rows: FINISH_SS (supersample, default 2),
# FINISH_DE (estimator_radius, default 3) and FINISH_Q (estimator_quality, default 0: flam3's
# kernels from the hits as they are), with flam3's gaussian of radius 0.5.
ss=${FINISH_SS:-2} de=${FINISH_DE:-3} q=${FINISH_Q:-0}
FINISH_LABEL="supersample $ss, gaussian 0.5, estimator_radius $de"
estimate=(--set renderer.supersample="$ss" --set renderer.estimator_radius="$de")
if [ "$q" != 0 ]; then
    FINISH_LABEL+=", estimator_quality $q"
    estimate+=(--set renderer.estimator_quality="$q")
fi
ssim_of() { /usr/bin/python3 "$quality" "$@" | sed 's/ssim=\([0-9.]*\).*/\1/'; }

echo "$(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo
echo "## Anti-aliasing: bench/thin-strokes.yaml at 512 x 512 against 4096 x 4096 box-filtered down"
echo
"$fixpoint" render --quiet "$here/thin-strokes.yaml" -o "$out/aa-8x.png" --set renderer.width=4096 \
    --set renderer.height=4096 --set renderer.points=1000000000
"$fixpoint" render --quiet "$here/thin-strokes.yaml" -o "$out/aa-raw.png"
"$fixpoint" render --quiet "$here/thin-strokes.yaml" -o "$out/aa-finished.png" "${finish[@]}"
"$fixpoint" render --quiet "$here/thin-strokes.yaml" -o "$out/aa-ss4.png" --set renderer.supersample=4 \
    --set "renderer.filter={type: gaussian, radius: 0.5}"
# The 8x render box-filtered in the histogram's linear densities rather than in display values:
# supersample 8 without a filter (the mean of each pixel's 64 bins' densities, then the gamma).
"$fixpoint" render --quiet "$here/thin-strokes.yaml" -o "$out/aa-ss8.png" --set renderer.supersample=8 \
    --set renderer.points=1000000000
echo "| image | the 8x render, its display values box-filtered | the 8x histogram box-filtered (supersample 8) |"
echo "|---|---|---|"
for img in raw:"raw (each point into one pixel)" finished:"supersample 2, gaussian 0.5" ss4:"supersample 4, gaussian 0.5"; do
    f=${img%%:*} label=${img#*:}
    echo "| $label | $(/usr/bin/python3 "$quality" "$out/aa-$f.png" "$out/aa-8x.png" --down 8) |" \
        "$(/usr/bin/python3 "$quality" "$out/aa-$f.png" "$out/aa-ss8.png") |"
done

# time_to NAME CONVERGED_POINTS CONFIG ARGS...: the first doubling of the points whose image is
# within SSIM 0.95 of the recipe at CONVERGED_POINTS; prints "points render-seconds wall-seconds
# ssim" (the render's own time from the summary line, and the whole command's with its start-up).
time_to() {
    local name=$1 conv=$2 config=$3
    shift 3
    "$fixpoint" render --quiet --threads 2 "$config" -o "$out/$name-conv.png" --set renderer.points="$conv" \
        --set renderer.width="$size" --set renderer.height="$size" "$@"
    local p=$((conv / 4096)) t0 t1 line s
    while [ "$p" -le "$conv" ]; do
        t0=$(date +%s.%N)
        line=$("$fixpoint" render --threads 2 "$config" -o "$out/$name.png" --force --set renderer.points="$p" \
            --set renderer.width="$size" --set renderer.height="$size" "$@" 2>&1 | tail -1)
        t1=$(date +%s.%N)
        s=$(ssim_of "$out/$name.png" "$out/$name-conv.png")
        if awk -v s="$s" 'BEGIN {exit !(s >= 0.95)}'; then
            echo "$p $(sed 's/.* in \([0-9.e+-]*\) s .*/\1/' <<<"$line") $(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f", b - a}') $s"
            return
        fi
        p=$((p * 2))
    done
    echo "- - - -"
}

row() {
    local label=$1 conv=$2 config=$3
    shift 3
    local raw fin
    raw=$(time_to "$label-raw" "$conv" "$config" "$@")
    fin=$(time_to "$label-fin" "$conv" "$config" "$@" "${finish[@]}" "${estimate[@]}")
    read -r rp rt rw rs <<<"$raw"
    read -r fp ft fw fs <<<"$fin"
    echo "| $label | $rp points, $rt s ($rw s wall), SSIM $rs | $fp points, $ft s ($fw s wall), SSIM $fs |" \
        "$(awk -v a="$rt" -v b="$ft" 'BEGIN {if (b > 0) printf "%.1fx", a / b}') |"
}

echo
echo "## Time to SSIM 0.95 over the lit pixels, ${size} x ${size}, 2 threads (converged: 64x the points)"
echo
# Paper 01's fig4a without its own finishing (the raw setting), and the other configs as they are.
grep -v 'supersample: 2\|filter: {type: gaussian' "$here/../configs/inversion/fig4a.yaml" >"$out/fig4a.yaml"
dense="$here/../configs/gumowski-mira/fig1b-dense.yaml"
echo "| config | raw | finished ($FINISH_LABEL) | raw / finished (render) |"
echo "|---|---|---|---|"
row fig4a 2560000000 "$out/fig4a.yaml"
row gm-fig1b-dense 200000000 "$dense"
row fern 6400000000 "$here/fern.yaml"
row sierpinski 6400000000 "$here/sierpinski.yaml"

if command -v flam3-render >/dev/null; then
    # flam3 on the triangle with its estimator and filter, its quality doubling from 1/4096 of the
    # converged image's (flam3's quality: samples per pixel).
    flam() {
        sed -e "s/size=\"1024 1024\"/size=\"$size $size\"/" -e "s/scale=\"1000\"/scale=\"$((size * 1000 / 1024))\"/" \
            -e "s/quality=\"95\"/quality=\"$1\"/" -e 's/filter="0"/filter="0.5" estimator_radius="9"/' \
            "$here/sierpinski.flam3" >"$out/s.flam3"
        (cd "$out" && wall env in="$out/s.flam3" prefix="$out/$2." nthreads=2 format=png flam3-render)
    }
    conv=6400
    flam "$conv" conv >/dev/null
    q=2
    while [ "$q" -le "$conv" ]; do
        t=$(flam "$q" run)
        s=$(ssim_of "$out/run.00000.png" "$out/conv.00000.png")
        if awk -v s="$s" 'BEGIN {exit !(s >= 0.95)}'; then break; fi
        q=$((q * 2))
    done
    echo "| sierpinski, flam3-render 3.1.1 (estimator 9, filter 0.5) | | quality $q, $t s wall, SSIM $s | |"
fi
