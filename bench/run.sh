#!/usr/bin/env bash
# Runs fixpoint's benchmarks next to the reference kernel, in the same session (the machines
# drift by ~10% and more under other load, so only figures from one run are compared), and
# prints the ratios the performance targets are stated in.
#   bench/run.sh [BUILD_DIR]      (default: build; builds fixpoint_bench first)
# FIXPOINT_BENCH_POINTS=N sets the points of the fixpoint runs (default 1e8, the reference's).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
ref=../shared/perf-reference
out=$build/bench-ref
mkdir -p "$out"
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
cmake --build "$build" --target fixpoint_bench_orbit_trap -j"$(nproc)" >/dev/null
g++ -O3 -march=native -fopenmp -o "$out/wallpaper" "$ref/wallpaper.cpp"
echo "== reference: $ref/wallpaper.cpp (reps=5, median; M useful pixel-iterations/s)"
for variant in simd scalar; do
    for t in 1 2; do
        line=$("$out/wallpaper" variant=$variant threads=$t reps=5 | grep '^SUMMARY')
        r=$(echo "$line" | tr ' ' '\n' | sed -n 's/^median_rate=//p')
        c=$(echo "$line" | tr ' ' '\n' | sed -n 's/^cpu_per_wall=//p')
        rate[wall_${variant}_$t]=$(awk -v r="$r" 'BEGIN {printf "%.1f", r / 1e6}')
        printf "reference %-6s threads=%d  %7.1f M it/s  (cpu/wall %s)\n" $variant $t "${rate[wall_${variant}_$t]}" "$c"
    done
done
echo "== fixpoint: $build/bin/fixpoint_bench_orbit_trap"
"$build/bin/fixpoint_bench_orbit_trap" | tee "$out/orbit_trap.txt"
for t in 1 2; do
    r=$(sed -n "s#^reference_work/$t/.*items_per_second=\([0-9.]*\)M/s.*#\1#p" "$out/orbit_trap.txt")
    printf "orbit-trap threads=%d  %7.1f M it/s = %s x reference simd %d thread(s)\n" $t "${r:-0}" \
        "$(ratio "${r:-0}" "${rate[wall_simd_$t]}")" $t
done
echo "(target: orbit-trap 1 thread >= 0.5 x reference simd 1 thread)"
