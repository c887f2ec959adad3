#!/usr/bin/env bash
# The guide's test (docs/writing-a-scheme.md): install fixpoint from the build tree, build this
# folder's plugins (a scheme, a transform, a colourer) against the installed SDK as a researcher
# would, with no build type given, then check them: an optimised build, fixpoint eval on values
# computed by hand, the conformance suite, and the guide's renders.
# Usage: run.sh BUILD_DIR WORK_DIR SOURCE_DIR
set -euo pipefail
build=$1 work=$2 src=$3
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"

# No CMAKE_BUILD_TYPE: the SDK's CMake package makes it Release (optimised plugins).
cmake -S "$src" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
    >"$work/configure.log"
grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$work/build/CMakeCache.txt"
grep -q -- '-O3 .*m-iteration\.cpp' "$work/build/compile_commands.json"
# A build type given is kept.
cmake -S "$src" -B "$work/build-debug" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Debug \
    >"$work/configure-debug.log"
grep -q '^CMAKE_BUILD_TYPE:STRING=Debug$' "$work/build-debug/CMakeCache.txt"
cmake --build "$work/build" >"$work/build.log"

fixpoint=("$work/prefix/bin/fixpoint" --plugin-dir "$work/build")
# eval PROGRAM_ARGS... -- INPUT EXPECTED: fixpoint eval's output must be EXPECTED.
expect() {
    local input=$1 expected=$2
    shift 2
    local got
    got=$(printf '%s\n' "$input" | "${fixpoint[@]}" eval "$@")
    if [ "$got" != "$expected" ]; then
        echo "fixpoint eval $*: '$input' gave '$got', expected '$expected'" >&2
        exit 1
    fi
}
# The M-iteration with T(x, y) = (x / 2 + 1, y / 2) from p = (1, 2), T(p) = (1.5, 1), by hand:
#   reals, a = 1/2:           z = (1.25, 1.5),  y = T(z) = (1.625, 0.75),  p' = T(y) = (1.8125, 0.375);
#   complex, a = (1 + i)/2:   (1 - a) p = (1.5, 0.5), a T(p) = (0.25, 1.25), z = (1.75, 1.75),
#                             y = (1.875, 0.875), p' = (1.9375, 0.4375);
#   q-system A = 2, B = 1/2 (q^2 = 2 + q), a = (1 + q)/2: M(a) = [[a, A b], [b, a + 2 B b]] =
#                             [[0.5, 1], [0.5, 1]], (I - M(a)) p = (-1.5, -0.5), M(a) T(p) =
#                             (1.75, 1.75), z = (0.25, 1.25), y = (1.125, 0.625), p' = (1.5625, 0.3125);
#   reals, a_n = [1/2, 1/4], two steps: step 0 as above, then from (1.8125, 0.375):
#                             T(p) = (1.90625, 0.1875), z = (1.8359375, 0.328125),
#                             y = (1.91796875, 0.1640625), p' = (1.958984375, 0.08203125).
affine='{type: affine, coefficients: [0.5, 0, 0, 0.5, 1, 0]}'
expect '1 2' '1.8125 0.375' "$affine" --scheme '{type: m-iteration, a: 0.5}'
expect '1 2' '1.9375 0.4375' "$affine" --scheme '{type: m-iteration, a: 0.5+0.5q, numbers: {type: complex}}'
expect '1 2' '1.5625 0.3125' "$affine" \
    --scheme '{type: m-iteration, a: 0.5+0.5q, numbers: {type: q-system, A: 2, B: 0.5}}'
expect '1 2' '1.958984375 0.08203125' "$affine" --scheme '{type: m-iteration, a: [0.5, 0.25]}' --steps 2
# A q-number in the real numbers is refused, naming the parameter.
if out=$(printf '1 2\n' | "${fixpoint[@]}" eval "$affine" --scheme '{type: m-iteration, a: 0.5+0.3q}' 2>&1); then
    echo "a q-number in the real numbers was accepted: $out" >&2
    exit 1
fi
grep -q "scheme.a: 0.5+0.3q is a q-system number, but the scheme computes in the real numbers" <<<"$out"
# The transform: a quarter turn at distance 1 (strength pi/2): (2, 0) about (1, 0) -> (1, 1).
got=$(printf '2 0\n' | "${fixpoint[@]}" eval '{type: twirl, centre: [1, 0], strength: 1.5707963267948966}')
awk -v got="$got" 'BEGIN { split(got, v, " "); d = (v[1] - 1) ^ 2 + (v[2] - 1) ^ 2; exit !(d < 1e-24) }' ||
    { echo "twirl: (2, 0) gave '$got', expected (1, 1)" >&2; exit 1; }

"${fixpoint[@]}" conformance "$work/build/m-iteration.so" "$work/build/twirl.so" "$work/build/blend.so"

# A coefficient is found by its name when compiling: a name `params` does not declare, or a bare
# index, does not compile.
mkdir -p "$work/wrong"
sed 's/k\["a"\]/k["alpha"]/' "$src/m-iteration.cpp" >"$work/wrong/name.cpp"
sed 's/k\["a"\]/k[0]/' "$src/m-iteration.cpp" >"$work/wrong/index.cpp"
printf '%s\n' 'cmake_minimum_required(VERSION 3.25)' 'project(wrong LANGUAGES CXX)' \
    'find_package(fixpoint CONFIG REQUIRED)' 'fixpoint_add_plugin(name name.cpp)' \
    'fixpoint_add_plugin(index index.cpp)' >"$work/wrong/CMakeLists.txt"
cmake -S "$work/wrong" -B "$work/wrong/build" -DCMAKE_PREFIX_PATH="$work/prefix" >"$work/wrong/configure.log"
for t in name index; do
    if cmake --build "$work/wrong/build" --target "$t" >"$work/wrong/$t.log" 2>&1; then
        echo "k[...] with a wrong $t compiled" >&2
        exit 1
    fi
done
grep -q no_sequence_parameter_of_this_name_in_params "$work/wrong/name.log"
grep -q -i "deleted" "$work/wrong/index.log"

# The guide's renders, small: complex (the config), real, q-system; and the transform with the
# colourer. Each image must show something: not one or a few colours only.
small=(--set renderer.width=96 --set renderer.height=96 --set renderer.samples=1 --quiet)
"${fixpoint[@]}" render "$src/m-iteration.yaml" -o "$work/complex.png" "${small[@]}"
"${fixpoint[@]}" render "$src/m-iteration.yaml" -o "$work/real.png" "${small[@]}" \
    --set 'renderer.iteration.numbers={type: real}' --set renderer.iteration.a=0.05
"${fixpoint[@]}" render "$src/m-iteration.yaml" -o "$work/q-system.png" "${small[@]}" \
    --set 'renderer.iteration.numbers={type: q-system, A: -0.6, B: -0.2}'
"${fixpoint[@]}" render "$src/twirl.yaml" -o "$work/twirl.png" --quiet
python3 "$src/../support/png_colours.py" 16 "$work"/{complex,real,q-system,twirl}.png
"${fixpoint[@]}" recipe "$work/complex.png" | grep -q "type: m-iteration"
echo "external scheme: built optimised, eval as computed by hand, conformant, rendered"
