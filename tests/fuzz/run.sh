#!/usr/bin/env bash
# Fuzz the validate path (tests/fuzz/fuzz_validate.cpp) for a while.
#
#   tests/fuzz/run.sh [BUILD_DIR] [SECONDS]     defaults: build-asan 300
#
# BUILD_DIR is a build configured with FIXPOINT_SANITIZE=ON FIXPOINT_FUZZ=ON (clang) and
# built. Everything goes to BUILD_DIR/tests/fuzz/scratch/, never to the source tree:
#   seeds/      every config of the repository, copied afresh at each run
#   corpus/     what libFuzzer found interesting; kept between runs, so runs add up
#               (delete it to start over)
#   artifacts/  the inputs of findings: crash-*, leak-*, timeout-*, oom-*
#   fuzz.log    libFuzzer's whole output of the last run
# Prints one summary line; exits non-zero on any finding (crash, sanitizer report, uncaught
# exception other than fp::InputError, leak, timeout, out of memory), naming the input and
# how to replay it. A finding's input belongs in tests/fuzz/regressions/ once it is fixed.
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-build-asan}
secs=${2:-300}
[[ "$secs" =~ ^[0-9]+$ ]] || {
    echo "usage: tests/fuzz/run.sh [BUILD_DIR] [SECONDS]" >&2
    exit 2
}
[ -d "$build" ] || build="$src/$build" # relative to here, else to the source tree
fuzzer="$build/bin/fuzz_validate"
if [ ! -x "$fuzzer" ]; then
    echo "fuzz: no $fuzzer: configure $build with CC=clang CXX=clang++ -DFIXPOINT_SANITIZE=ON" \
        "-DFIXPOINT_FUZZ=ON and build it" >&2
    exit 2
fi
build=$(cd "$build" && pwd)
fuzzer="$build/bin/fuzz_validate"
scratch="$build/tests/fuzz/scratch"
mkdir -p "$scratch/corpus" "$scratch/artifacts"
rm -rf "$scratch/seeds"
mkdir -p "$scratch/seeds"

# Seeds: every config, named after its path (configs/mfs/fig4.yaml -> configs_mfs_fig4.yaml).
# Inputs of past findings too: they lie near paths that went wrong once.
shopt -s globstar nullglob
seeds=("$src"/configs/**/*.yaml "$src"/bench/*.yaml "$src"/tests/external-plugin/config.yaml
    "$src"/tests/fuzz/regressions/*)
for f in "${seeds[@]}"; do
    rel=${f#"$src"/}
    [ "$rel" = tests/fuzz/regressions/README.md ] && continue
    cp "$f" "$scratch/seeds/${rel//\//_}"
done

# One process: the machine this runs on in CI has two cores, and ctest may run beside it.
# -max_len: configs are a few kB; longer inputs only slow the search down.
# -timeout: a validation taking 10 s is a finding (the CLI validates before every render).
# -rss_limit_mb: validating allocates little; 2 GiB is a runaway (and malloc_limit_mb,
#  which defaults to it, catches one huge allocation).
marker="$scratch/.started"
touch "$marker"
start=$(date +%s)
rc=0
(cd "$scratch" &&
    "$fuzzer" corpus seeds \
        -dict="$src/tests/fuzz/yaml.dict" \
        -max_total_time="$secs" \
        -max_len=8192 \
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
echo "fuzz: fuzz_validate: ${runs:-?} runs in ${elapsed} s (${rate:-?} exec/s), ${added:-?} new units" \
    "(corpus ${corpus}), ${#found[@]} new finding(s)"
if ((rc != 0 || ${#found[@]} > 0)); then
    # The report: from the sanitizer's or the harness's first line to libFuzzer's last.
    first=$(grep -n -m1 -E '^==[0-9]+==|^fuzz_validate: |ERROR: libFuzzer' "$scratch/fuzz.log" | cut -d: -f1 || true)
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
