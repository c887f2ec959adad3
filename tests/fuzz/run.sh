#!/usr/bin/env bash
# Fuzz one of fixpoint's libFuzzer targets for a while.
#
#   tests/fuzz/run.sh [BUILD_DIR] [SECONDS] [TARGET]     defaults: build-asan 300 validate
#
# TARGET: validate (tests/fuzz/fuzz_validate.cpp: a config through the validate path), serve
# (tests/fuzz/fuzz_serve.cpp: a request through serve's checks and body parsing) or checkpoint
# (tests/fuzz/fuzz_checkpoint.cpp: a checkpoint file through --resume's checks and the resume)
# or histogram (tests/fuzz/fuzz_histogram.cpp: a histogram file, or its bins, through tone).
# BUILD_DIR is a build configured with FIXPOINT_SANITIZE=ON FIXPOINT_FUZZ=ON (clang) and
# built. Everything goes to BUILD_DIR/tests/fuzz/scratch/TARGET/, never to the source tree:
#   seeds/      validate: every config of the repository; serve: tests/fuzz/serve-seeds/;
#               checkpoint: checkpoints of tests/fuzz/checkpoint.yaml this build's CLI writes;
#               histogram: histogram files of tests/fuzz/histogram.yaml it writes;
#               made afresh at each run
#   corpus/     what libFuzzer found interesting; kept between runs, so runs add up
#               (delete it to start over)
#   artifacts/  the inputs of findings: crash-*, leak-*, timeout-*, oom-*
#   fuzz.log    libFuzzer's whole output of the last run
# Prints one summary line; exits non-zero on any finding (crash, sanitizer report, uncaught
# exception other than the refusals a user gets, leak, timeout, out of memory), naming the
# input and how to replay it. A finding's input belongs in tests/fuzz/regressions/ (validate)
# or tests/fuzz/serve-seeds/ (serve) once it is fixed.
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-build-asan}
secs=${2:-300}
target=${3:-validate}
[[ "$secs" =~ ^[0-9]+$ ]] && [[ "$target" =~ ^(validate|serve|checkpoint|histogram)$ ]] || {
    echo "usage: tests/fuzz/run.sh [BUILD_DIR] [SECONDS] [validate|serve|checkpoint|histogram]" >&2
    exit 2
}
[ -d "$build" ] || build="$src/$build" # relative to here, else to the source tree
fuzzer="$build/bin/fuzz_$target"
if [ ! -x "$fuzzer" ]; then
    echo "fuzz: no $fuzzer: configure $build with CC=clang CXX=clang++ -DFIXPOINT_SANITIZE=ON" \
        "-DFIXPOINT_FUZZ=ON and build it" >&2
    exit 2
fi
build=$(cd "$build" && pwd)
fuzzer="$build/bin/fuzz_$target"
scratch="$build/tests/fuzz/scratch/$target"
mkdir -p "$scratch/corpus" "$scratch/artifacts"
rm -rf "$scratch/seeds"
mkdir -p "$scratch/seeds"

# Seeds: validate: every config, named after its path (configs/mfs/fig4.yaml ->
# configs_mfs_fig4.yaml), and the inputs of past findings: they lie near paths that went wrong
# once. serve: requests as the page sends them, good and bad.
shopt -s globstar nullglob
if [ "$target" = validate ]; then
    seeds=("$src"/configs/**/*.yaml "$src"/bench/*.yaml "$src"/tests/external-plugin/config.yaml
        "$src"/tests/fuzz/regressions/*)
    dict=(-dict="$src/tests/fuzz/yaml.dict")
    max_len=8192
elif [ "$target" = serve ]; then
    seeds=("$src"/tests/fuzz/serve-seeds/*)
    dict=()
    max_len=8192
elif [ "$target" = histogram ]; then
    # Histogram files of the recipe, with 0 (a file) and 1 (its bins) as the first byte.
    seeds=()
    dict=()
    max_len=65536
    for points in 3000 300; do
        "$build/bin/fixpoint" render -q "$src/tests/fuzz/histogram.yaml" --set renderer.points=$points \
            -o "$scratch/seed.png" --force --histogram "$scratch/seed.fph"
        { printf '\0'; cat "$scratch/seed.fph"; } >"$scratch/seeds/file-$points"
        { printf '\1'; cat "$scratch/seed.fph"; } >"$scratch/seeds/bins-$points"
        rm -f "$scratch/seed.fph"
    done
    rm -f "$scratch/seed.png"
else
    # A finished render's checkpoint, and one of a third of its points (a resume continues it).
    seeds=()
    dict=()
    max_len=65536 # (the seeds are about 16 kB: the histogram)
    for points in 4000 1300; do
        "$build/bin/fixpoint" render -q "$src/tests/fuzz/checkpoint.yaml" --set renderer.points=$points \
            -o "$scratch/seed.png" --force --checkpoint "$scratch/seeds/points-$points.ck"
    done
    rm -f "$scratch/seed.png"
fi
for f in "${seeds[@]}"; do
    rel=${f#"$src"/}
    [ "${rel##*/}" = README.md ] && continue
    cp "$f" "$scratch/seeds/${rel//\//_}"
done

# One process: the machine this runs on in CI has two cores, and ctest may run beside it.
# -max_len: configs and requests are a few kB; longer inputs only slow the search down.
# -timeout: a validation taking 10 s is a finding (the CLI validates before every render).
# -rss_limit_mb: validating allocates little; 2 GiB is a runaway (and malloc_limit_mb,
#  which defaults to it, catches one huge allocation).
marker="$scratch/.started"
touch "$marker"
start=$(date +%s)
rc=0
(cd "$scratch" &&
    "$fuzzer" corpus seeds \
        "${dict[@]}" \
        -max_total_time="$secs" \
        -max_len="$max_len" \
        -timeout=10 \
        -rss_limit_mb=2048 \
        -print_final_stats=1 \
        -artifact_prefix="$scratch/artifacts/" \
        >"$scratch/fuzz.log" 2>&1) || rc=$?
elapsed=$(($(date +%s) - start))

final_stat() { sed -n "s/^stat::$1: *//p" "$scratch/fuzz.log" | tail -1; }
runs=$(final_stat number_of_executed_units)
rate=$(final_stat average_exec_per_sec)
added=$(final_stat new_units_added)
mapfile -t found < <(find "$scratch/artifacts" -type f -newer "$marker" \
    \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | sort)
corpus=$(find "$scratch/corpus" -type f | wc -l)
echo "fuzz: fuzz_$target: ${runs:-?} runs in ${elapsed} s (${rate:-?} exec/s), ${added:-?} new units" \
    "(corpus ${corpus}), ${#found[@]} new finding(s)"
if ((rc != 0 || ${#found[@]} > 0)); then
    # The report: from the sanitizer's or the harness's first line to libFuzzer's last.
    first=$(grep -n -m1 -E '^==[0-9]+==|^fuzz_[a-z]+: |ERROR: libFuzzer' "$scratch/fuzz.log" | cut -d: -f1 || true)
    if [ -n "$first" ]; then
        tail -n +"$first" "$scratch/fuzz.log" | head -60 >&2
    else
        tail -n 40 "$scratch/fuzz.log" >&2
    fi
    for f in "${found[@]}"; do
        echo "fuzz: finding: $f (replay: $fuzzer $f)" >&2
    done
    echo "fuzz: failed (libFuzzer exit code $rc); whole log: $scratch/fuzz.log" >&2
    exit 1
fi
