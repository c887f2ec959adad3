#!/usr/bin/env bash
# What a fixpoint process loads when it starts.
#   tests/startup.sh BUILD_DIR SOURCE_DIR [SANITIZE]
# 1. No binary of the build has an empty entry in its RUNPATH (or RPATH): the dynamic loader
#    reads one as the current folder, so the binary would load a library of a name it needs
#    from wherever it is run (CMake ends the build RUNPATH of a target it installs with ':').
# 2. OpenImageIO (about 260 libraries) is loaded only by a process that reads or writes a
#    raster image: not by --version, validate or a refused config; a render loads it (the
#    image module, framework/image/) and writes its image. (A sanitizer build, SANITIZE = 1,
#    links OpenImageIO at start: see framework/CMakeLists.txt. There only the render's PNG is
#    checked.)
# 3. Without the image module, a render to a raster image is refused before it starts (a
#    render of 1e11 points would outlast the timeout).
set -euo pipefail
build=$(cd "$1" && pwd)
src=$2
sanitize=${3:-0}
fail=0

checked=0
while IFS= read -r -d '' f; do
    head -c 4 "$f" 2>/dev/null | grep -q $'\x7fELF' || continue
    paths=$(readelf -dW "$f" 2>/dev/null | sed -n 's/.*(\(RUNPATH\|RPATH\)).*\[\(.*\)\]$/\2/p')
    checked=$((checked + 1))
    [ -z "$paths" ] && continue
    if [[ ":$paths:" == *"::"* ]]; then
        echo "FAIL: $f has an empty entry in its runpath: '$paths'"
        fail=1
    fi
done < <(find "$build/bin" "$build/lib" -type f -print0)
if [ "$checked" -lt 10 ]; then
    echo "FAIL: only $checked binaries found under $build/bin and $build/lib"
    fail=1
fi

fixpoint=$build/bin/fixpoint
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
loads_oiio() { grep -q 'file=libOpenImageIO\.so' "$@"; }

if [ "$sanitize" = 0 ]; then
    LD_DEBUG=files LD_DEBUG_OUTPUT=$tmp/version "$fixpoint" --version >/dev/null
    if loads_oiio "$tmp"/version.*; then
        echo "FAIL: fixpoint --version loads OpenImageIO"
        fail=1
    fi
    LD_DEBUG=files LD_DEBUG_OUTPUT=$tmp/validate "$fixpoint" validate "$src/configs/inversion/fig6a.yaml" \
        -o "$tmp/a.png" >/dev/null 2>&1
    if loads_oiio "$tmp"/validate.*; then
        echo "FAIL: fixpoint validate loads OpenImageIO"
        fail=1
    fi
    printf 'renderer:\n  type: chaos-game\n  wdth: 64\n' >"$tmp/bad.yaml"
    if LD_DEBUG=files LD_DEBUG_OUTPUT=$tmp/bad "$fixpoint" render "$tmp/bad.yaml" -o "$tmp/b.png" >/dev/null 2>&1; then
        echo "FAIL: a config with an unknown parameter rendered"
        fail=1
    fi
    if loads_oiio "$tmp"/bad.*; then
        echo "FAIL: a refused config loads OpenImageIO"
        fail=1
    fi
fi
LD_DEBUG=files LD_DEBUG_OUTPUT=$tmp/render "$fixpoint" render "$src/configs/inversion/fig6a.yaml" \
    -o "$tmp/c.png" --set renderer.points=10000 --set renderer.width=64 --set renderer.height=64 >/dev/null 2>&1
if [ "$sanitize" = 0 ] && ! loads_oiio "$tmp"/render.*; then
    echo "FAIL: a render does not load OpenImageIO"
    fail=1
fi
if [ "$(head -c 8 "$tmp/c.png" | od -An -tx1 | tr -d ' \n')" != 89504e470d0a1a0a ]; then
    echo "FAIL: the render wrote no PNG"
    fail=1
fi
# 3. A tree of the build's executable, SDK library and plugins, without the image module.
mkdir -p "$tmp/tree/bin" "$tmp/tree/lib/fixpoint"
cp "$fixpoint" "$tmp/tree/bin/fixpoint"
for f in "$build"/lib/libfixpoint_sdk.so*; do ln -s "$f" "$tmp/tree/lib/"; done
ln -s "$build/lib/fixpoint/plugins" "$tmp/tree/lib/fixpoint/plugins"
set +e
err=$(timeout 60 "$tmp/tree/bin/fixpoint" render "$src/configs/inversion/fig6a.yaml" -o "$tmp/d.png" \
    --set renderer.points=1e11 2>&1 >/dev/null)
rc=$?
set -e
want="cannot write '$tmp/d.png': fixpoint's image module '$tmp/tree/lib/fixpoint/fixpoint-image.so' is missing (reinstall fixpoint)"
if [ "$rc" -ne 2 ] || [ "$err" != "$want" ] || [ -e "$tmp/d.png" ]; then
    echo "FAIL: a render without the image module: exit $rc, '$err' (want exit 2, '$want', no file)"
    fail=1
fi

[ "$fail" -eq 0 ] && echo "startup: $checked binaries without an empty runpath entry; OpenImageIO loaded only to write" \
    "$([ "$sanitize" = 0 ] || echo "(not checked: a sanitizer build)")"
exit "$fail"
