#!/usr/bin/env bash
# Adds a recipe to the golden corpus: renders CONFIG (with the --set options given) through
# fixpoint, takes the recipe the image carries, less its `plugins:` (each plugin file's own
# hash, which every build changes; the render version covers them), and writes it to NAME.yaml
# here. Then record its hash: build/bin/fixpoint_golden tests/golden-recipes --record
#   tests/golden-recipes/add.sh build/bin/fixpoint NAME CONFIG [--set path=value ...]
# Keep recipes small (a second or less each): the corpus runs in every CI build, the
# sanitizers' included.
set -euo pipefail
bin=$1 name=$2 config=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
[ -e "$here/$name.yaml" ] && { echo "add.sh: $here/$name.yaml exists" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" render "$config" -o "$tmp/x.png" -q --allow-python "$@"
"$bin" recipe "$tmp/x.png" | awk '/^plugins:/ {skip = 1; next} skip && /^  / {next} {skip = 0; print}' \
    >"$here/$name.yaml"
echo "$here/$name.yaml"
