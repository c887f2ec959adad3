#!/usr/bin/env bash
# The out-of-tree plugin test: install fixpoint from the build tree, build this folder's
# plugin against the installed SDK with find_package(fixpoint CONFIG), then load it and
# render with it through the installed CLI, and run the conformance suite on it.
# Usage: run.sh BUILD_DIR WORK_DIR SOURCE_DIR
set -euo pipefail
build=$1 work=$2 src=$3
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"
cmake -S "$src" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release >"$work/configure.log"
cmake --build "$work/build" >"$work/build.log"
fixpoint=("$work/prefix/bin/fixpoint" --plugin-dir "$work/build")
"${fixpoint[@]}" describe ellipse
"${fixpoint[@]}" render "$src/config.yaml" -o "$work/out.png" --quiet
test -s "$work/out.png"
"${fixpoint[@]}" recipe "$work/out.png" | grep -q "type: ellipse"
"${fixpoint[@]}" conformance "$work/build/ellipse.so"
# Through FIXPOINT_PLUGIN_PATH as well.
FIXPOINT_PLUGIN_PATH="$work/build" "$work/prefix/bin/fixpoint" plugins --kind shape | grep -q "^shape  *ellipse"
echo "external plugin: built, loaded, rendered, conformant"
