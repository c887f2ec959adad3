#!/usr/bin/env bash
# Runs fixpoint's benchmarks next to the reference kernel, in the same session (the machines
# drift by ~10% and more under other load, so only figures from one run are compared), and
# prints the ratios the performance targets are stated in.
#   bench/run.sh [BUILD_DIR]      (default: build; builds fixpoint_bench first)
#   bench/run.sh BUILD_DIR orbit-trap   (only the orbit-trap part, at the end)
# FIXPOINT_BENCH_POINTS=N sets the points of the fixpoint runs (default 1e8, the reference's).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
ref=../shared/perf-reference
out=$build/bench-ref
mkdir -p "$out"
if [ "${2:-}" != orbit-trap ]; then # (the orbit-trap part alone: see its comment below)
cmake --build "$build" --target fixpoint_bench -j"$(nproc)" >/dev/null
g++ -O3 -march=native -fopenmp -o "$out/circles" "$ref/circles.cpp"
echo "== $(date -u +%FT%TZ) $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
echo "== reference: $ref/circles.cpp (n=1e8, reps=5, median)"
declare -A rate
for variant in simd scalar; do
    for t in 1 2; do
        line=$("$out/circles" variant=$variant threads=$t n=1e8 reps=5 | grep '^SUMMARY')
        r=$(echo "$line" | tr ' ' '\n' | sed -n 's/^median_rate=//p')
        c=$(echo "$line" | tr ' ' '\n' | sed -n 's/^cpu_per_wall=//p')
        rate[ref_${variant}_$t]=$(awk -v r="$r" 'BEGIN {printf "%.1f", r / 1e6}')
        printf "reference %-6s threads=%d  %7.1f M points/s  (cpu/wall %s)\n" $variant $t "${rate[ref_${variant}_$t]}" "$c"
    done
done
echo "== fixpoint: $build/bin/fixpoint_bench (bench/circles.yaml; median of 3 repetitions of 3 renders)"
"$build/bin/fixpoint_bench" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true |
    tee "$out/fixpoint.txt"
while read -r name rest; do
    case $name in *_median | inline_scalar*) ;; *) continue ;; esac
    r=$(echo "$rest" | tr ' ' '\n' | sed -n 's/^items_per_second=\([0-9.]*\)\([kMG]\)\/s$/\1 \2/p')
    [ -n "$r" ] || continue
    key=$(echo "$name" | sed 's#/iterations.*##; s#/real_time.*##; s#_median$##')
    rate[$key]=$(echo "$r" | awk '{v = $1; if ($2 == "k") v /= 1000; if ($2 == "G") v *= 1000; printf "%.1f", v}')
done <"$out/fixpoint.txt"
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}'; }
echo "== ratios (targets: density float 1 thread >= 0.5 x reference simd 1 thread; 2 threads >= 1.9 x 1 thread)"
for c in density map_colour; do
    for p in float double; do
        one=${rate[chaos_game/${c}_$p/1]:-0} two=${rate[chaos_game/${c}_$p/2]:-0}
        printf "%-10s %-6s  1 thread %6.1f M/s = %s x ref simd 1;  2 threads %6.1f M/s = %s x ref simd 2;  2/1 = %s\n" \
            $c $p "$one" "$(ratio "$one" "${rate[ref_simd_1]}")" "$two" "$(ratio "$two" "${rate[ref_simd_2]}")" \
            "$(ratio "$two" "$one")"
    done
done
echo "reference simd 2/1 = $(ratio "${rate[ref_simd_2]}" "${rate[ref_simd_1]}"), scalar 2/1 = $(ratio "${rate[ref_scalar_2]}" "${rate[ref_scalar_1]}")"

# ---------------------------------------------------------------- orbit trap (paper 04, issue 6)
# The orbit-trap renderer on the work of ../shared/perf-reference/wallpaper.cpp (p4m-like map,
# four circle traps, 1024^2, M = 100), and a 1920x1080, 8-sample render of Fig. 8(d).
# The machine drifts by +-25% within minutes, so the reference (simd) and the renderer run in
# alternating pairs, FIXPOINT_OT_PAIRS of them (default 5) per thread count; the ratio is the
# median of the pairs' ratios. `bench/run.sh BUILD_DIR orbit-trap` runs this part alone.
fi
cmake --build "$build" --target fixpoint_bench_orbit_trap orbit-trap wallpaper circles lp colour-map picard \
    s-iteration complex real -j"$(nproc)" >/dev/null
g++ -O3 -march=native -fopenmp -o "$out/wallpaper" "$ref/wallpaper.cpp"
echo "== $(date -u +%FT%TZ) $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
echo "== reference: $ref/wallpaper.cpp (reps=3, median) vs $build/bin/fixpoint_bench_orbit_trap (mean of 3 renders); M useful pixel-iterations/s"
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
for t in 1 2; do
    : >"$out/ot_pairs_$t.txt"
    for i in $(seq "${FIXPOINT_OT_PAIRS:-5}"); do
        line=$("$out/wallpaper" variant=simd threads=$t reps=3 | grep '^SUMMARY')
        r=$(echo "$line" | tr ' ' '\n' | sed -n 's/^median_rate=//p' | awk '{printf "%.1f", $1 / 1e6}')
        c=$(echo "$line" | tr ' ' '\n' | sed -n 's/^cpu_per_wall=//p')
        o=$("$build/bin/fixpoint_bench_orbit_trap" --benchmark_filter="reference_work/$t/" 2>/dev/null |
            sed -n "s#^reference_work/$t/.*items_per_second=\([0-9.]*\)M/s.*#\1#p")
        q=$(awk -v a="$o" -v b="$r" 'BEGIN {printf "%.3f", a / b}')
        printf "threads=%d pair %d: reference simd %6.1f (cpu/wall %s)  orbit-trap %6.1f  ratio %s\n" $t $i "$r" "$c" "$o" "$q"
        echo "$r $o $q" >>"$out/ot_pairs_$t.txt"
    done
    printf "threads=%d MEDIAN: reference simd %s  orbit-trap %s  ratio %s\n" $t \
        "$(cut -d' ' -f1 "$out/ot_pairs_$t.txt" | median)" "$(cut -d' ' -f2 "$out/ot_pairs_$t.txt" | median)" \
        "$(cut -d' ' -f3 "$out/ot_pairs_$t.txt" | median)"
done
for t in 1 2; do
    line=$("$out/wallpaper" variant=scalar threads=$t reps=3 | grep '^SUMMARY')
    printf "reference scalar threads=%d  %s M it/s\n" $t \
        "$(echo "$line" | tr ' ' '\n' | sed -n 's/^median_rate=//p' | awk '{printf "%.1f", $1 / 1e6}')"
done
"$build/bin/fixpoint_bench_orbit_trap" --benchmark_filter='fig8d' 2>/dev/null | grep '^fig8d'
echo "(target: orbit-trap 1 thread >= 0.5 x reference simd 1 thread)"
