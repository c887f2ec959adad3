#!/usr/bin/env bash
# The docs installed with the SDK (`cmake --install`, component docs) are whole: the front page,
# the manual, the benchmarks' page and the configs, with every relative link resolving there.
# Usage: install-check.sh BUILD WORK PYTHON CHECK_LINKS
set -euo pipefail
build=$1 work=$2 python=$3 check=$4
rm -rf "$work"
cmake --install "$build" --component docs --prefix "$work" >/dev/null
doc=$work/share/doc/fixpoint
for f in README.md docs/README.md docs/plugins.md bench/README.md configs/inversion/fig6a.yaml docs/gallery/fig6a.png; do
    [ -s "$doc/$f" ] || {
        echo "not installed: share/doc/fixpoint/$f" >&2
        exit 1
    }
done
"$python" "$check" "$doc"
