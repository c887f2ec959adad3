#!/usr/bin/env bash
# docs/plugins.md is what `fixpoint describe --markdown` prints now: the reference of every
# plugin, from the plugins' own declarations. Fails with the difference, and the command that
# refreshes it, when a plugin's declaration changed and the file did not.
# Usage: plugin-reference.sh FIXPOINT ROOT
set -euo pipefail
bin=$1
root=$2
out=$(mktemp)
trap 'rm -f "$out"' EXIT
# The build's plugins only: none from the user's FIXPOINT_PLUGIN_PATH.
env -u FIXPOINT_PLUGIN_PATH "$bin" describe --markdown >"$out"
if ! diff -u "$root/docs/plugins.md" "$out" >"$out.diff"; then
    head -60 "$out.diff" >&2
    rm -f "$out.diff"
    echo "docs/plugins.md is stale (- the file, + the plugins now); refresh it:" >&2
    echo "    build/bin/fixpoint describe --markdown > docs/plugins.md" >&2
    exit 1
fi
rm -f "$out.diff"
echo "docs/plugins.md: $(grep -c '^### ' "$out") plugins, as they declare themselves"
