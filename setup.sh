#!/usr/bin/env bash
# fixpoint's one setup script, for a fresh Debian 12 machine.
#
#   ./setup.sh         install the dependencies (Debian packages), build, render the default
#                      config to fixpoint.png
#   ./setup.sh test    the same, then run every test (this is what CI runs); then build again
#                      in build-asan with clang, ASan, UBSan and libFuzzer's coverage, run
#                      the unit, CLI and conformance tests there and fuzz the validate path
#                      for 40 s, serve's requests, the checkpoint and the histogram readers
#                      for 20 s each (tests/fuzz/run.sh). Under CI, warnings are errors in
#                      both builds; elsewhere the first command's build is reused as it is.
#                      FIXPOINT_QUICK=1 skips the build-asan stage (not under CI).
#
# Needs root or sudo only to install missing packages; does nothing to the system when they
# are all present.
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-render}
case "$mode" in
render | test) ;;
*)
    echo "usage: ./setup.sh [test]" >&2
    exit 2
    ;;
esac

packages=(
    build-essential cmake pkg-config git
    libboost-dev libboost-filesystem-dev libyaml-cpp-dev libopenimageio-dev
    libspdlog-dev libfmt-dev libtbb-dev libcli11-dev libpcg-cpp-dev
    libgtest-dev libgmock-dev libbenchmark-dev clang-format fonts-dejavu-core
    libcairo2-dev libhwy-dev
    zlib1g-dev # the checkpoints' CRC-32 (also pulled in by OpenImageIO)
    python3-dev pybind11-dev python3-numpy
    ffmpeg # fixpoint animate --video (and ffprobe for its test)
    libcpp-httplib-dev # fixpoint serve (a compiled library, linked with its pkg-config flags)
    nlohmann-json3-dev # fixpoint serve's JSON requests and answers (header-only)
    libssl-dev # the golden corpus's SHA-256 (tests/golden-recipes/; also pulled in by cpp-httplib)
    libopenmpi-dev openmpi-bin # mpirun -np N fixpoint render (FIXPOINT_MPI)
    libtinyxml2-dev # flam3's palette file (palette: flam3:N)
    ccache # the compiler cache of both builds (below)
)
quick=${FIXPOINT_QUICK:-}
if [ -n "$quick" ] && [ -n "${CI:-}" ]; then
    echo "setup: FIXPOINT_QUICK ignored under CI: every stage runs" >&2
    quick=
fi
sanitize=
# The Python tests: pytest, and Pillow to read the PNGs the CLI writes.
[ "$mode" = test ] && packages+=(python3-pytest python3-pil)
# The notebook (docs/notebook.ipynb), executed by tests/python/test_notebook.py as Jupyter runs
# it; interact()'s widgets and the progress bars of progress=True.
[ "$mode" = test ] && packages+=(python3-nbclient python3-nbformat python3-ipykernel python3-ipywidgets python3-tqdm)
# flam3's palettes, read where Debian installs them (a test reads palette 0 of the real file).
[ "$mode" = test ] && packages+=(flam3-palette)
# flam3 itself, the outside reference of the flam3 variations and genomes: libflam3 in a test
# only (tests/flam3), flam3-render and flam3-genome in the parity tests.
[ "$mode" = test ] && packages+=(libflam3-dev flam3-utils)
# The preview page's tests in a real browser: headless Chromium driven by Selenium.
[ "$mode" = test ] && packages+=(chromium chromium-driver python3-selenium)
# A one-node Slurm cluster that tests/cluster starts on localhost (auth/none, no munge): a job
# array of shards with a killed task, requeued, then merged.
[ "$mode" = test ] && packages+=(slurmctld slurmd slurm-client)
# The linters, run by CTest (tests/lint/): clang-tidy on the changed C++ files, ESLint on web/,
# flake8 on the Python (docs/testing.md).
[ "$mode" = test ] && packages+=(clang-tidy eslint flake8)
if [ "$mode" = test ] && [ -z "$quick" ]; then
    sanitize=1
    # The sanitizer build: clang 14 with its runtimes (ASan, UBSan, libFuzzer).
    packages+=(clang libclang-rt-14-dev lld)
fi
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]}" >&2
    sudo=()
    [ "$(id -u)" -eq 0 ] || sudo=(sudo)
    export DEBIAN_FRONTEND=noninteractive
    "${sudo[@]}" apt-get update -qq
    "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Each stage of `./setup.sh test` says how long it took.
stage() { echo "setup: $1: $((SECONDS - started)) s"; }
jobs=$(nproc 2>/dev/null || echo 2)
# Warnings are errors under CI (both builds). Elsewhere the flag is left as the build folder
# has it, so that `./setup.sh test` after `./setup.sh` reuses the build rather than rebuilding
# everything for a changed flag.
werror=()
[ -n "${CI:-}" ] && werror=(-DFIXPOINT_WERROR=ON)
# Both builds compile through ccache where it is installed. Its base directory is this checkout,
# so that the compile lines it hashes name paths relative to it (the tests take theirs from
# tests/support/cli.cpp alone): a clone elsewhere, as CI makes, is served what an earlier
# build compiled. The sanitizer build has debug information, which names the folder it was
# compiled in; it is left out of the hash there (NOHASHDIR), so a report's paths may name the
# folder of the build that filled the cache, with the right file and line.
launcher=()
# Debian's pcg_extras.hpp (included through the SDK's random streams) names __DATE__ and __TIME__
# in a seed fixpoint never uses; without time_macros sloppiness, ccache misses on every file
# that includes it, more than half of each build.
if command -v ccache >/dev/null 2>&1; then
    export CCACHE_BASEDIR="$PWD"
    export CCACHE_SLOPPINESS=time_macros
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
started=$SECONDS
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${werror[@]}" "${launcher[@]}" >/dev/null
cmake --build build -j"$jobs"
[ "$mode" = test ] && stage "Release build (build)"

build/bin/fixpoint render configs/inversion/fig6a.yaml -o fixpoint.png
echo "setup: rendered configs/inversion/fig6a.yaml to fixpoint.png"

# The Python module, importable by Debian's python3 from anywhere: a .pth file in the user's
# site-packages names the build's package folder (docs/python.md).
if [ -d build/lib/python3/dist-packages/fixpoint ]; then
    site=$(/usr/bin/python3 -c 'import site; print(site.getusersitepackages())')
    mkdir -p "$site"
    echo "$PWD/build/lib/python3/dist-packages" >"$site/fixpoint.pth"
    echo "setup: python3 can import fixpoint (through $site/fixpoint.pth)"
fi
[ "$mode" = test ] || exit 0

started=$SECONDS
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 900
stage "tests (Release)"
if [ -z "$sanitize" ]; then
    echo "setup: FIXPOINT_QUICK: no sanitizer build, no fuzzing"
    exit 0
fi

# LeakSanitizer stops the world with ptrace, which some containers refuse; there it would
# fail every sanitized program at exit (the build's test discovery too), so leaks go
# unchecked (said loudly) rather than the whole run failing. Probed with an empty program.
started=$SECONDS
mkdir -p build-asan
echo 'int main() { return 0; }' | clang -x c -fsanitize=address - -o build-asan/lsan-probe
leaks=1
lsan_probe=$(ASAN_OPTIONS=detect_leaks=1 build-asan/lsan-probe 2>&1 || true)
if [[ "$lsan_probe" == *"LeakSanitizer has encountered a fatal error"* ]]; then
    echo "setup: warning: LeakSanitizer does not work on this machine; leak checks are off" >&2
    leaks=0
fi
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=$leaks"

# Debug (asserts) at -O1 (CMakeLists.txt), so that the tests' renders stay quick enough.
# Without MPI: CI's build of that configuration (Open MPI's own allocations would also be
# reported by LeakSanitizer); the MPI tests then check only that it refuses to run as ranks.
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DFIXPOINT_SANITIZE=ON \
    -DFIXPOINT_FUZZ=ON -DFIXPOINT_WERROR=ON -DFIXPOINT_BUILD_TESTS=ON -DFIXPOINT_BUILD_BENCH=OFF \
    -DFIXPOINT_PYTHON=OFF -DFIXPOINT_MPI=OFF "${launcher[@]}" >/dev/null
CCACHE_NOHASHDIR=1 cmake --build build-asan -j"$jobs"
stage "sanitizer build (build-asan)"

# Every test but the style check, the out-of-tree plugins, the guide's code blocks, the
# preview page in the browser and the cluster (nothing sanitizer-specific in them: the page's
# JavaScript is the same, and the server under it is tested under the sanitizers by
# serve_requests, serve_access and serve_http; the cluster's shards, merges and checkpoints are
# the CLI's, tested here by the Shards and Checkpoint tests, and its Slurm flow would take
# minutes in this build).
# (No Python in this build: an interpreter not built with ASan under an ASan executable
# reports its own allocator's habits; the Release build runs the Python tests.)
started=$SECONDS
# The golden corpus records the Release build's pixels (GCC, -O2: what users run, on every
# instruction set alike); the sanitizer build is clang at -O1 with SSE4 alone, which gives other
# bytes for 2 of its 78 recipes (inversions in polygons, in float: docs/render-versions.md), so
# it is not run there.
ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 900 -E '^(clang_format|external_plugin|external_scheme|doc_code_blocks|browser_page|cluster_shards|golden_recipes|golden_recipes_refuse|golden_recipes_every_target)$'
stage "tests (build-asan)"
started=$SECONDS
# (Short runs from the seeds, within CI's 45 minutes: a longer search is
# tests/fuzz/run.sh by hand.)
tests/fuzz/run.sh build-asan 40 validate
tests/fuzz/run.sh build-asan 20 serve
tests/fuzz/run.sh build-asan 20 checkpoint
tests/fuzz/run.sh build-asan 20 histogram
stage "fuzzing (build-asan)"
