#!/usr/bin/env bash
# Fails when a code block of a guide differs from the file it shows. In the Markdown, the line
#   <!-- file: tests/external-scheme/m-iteration.cpp -->
# just before a fenced block (```cpp ... ```) names the file, relative to the repository root,
# whose whole content the block must be.
# Usage: doc-blocks.sh ROOT DOC...
set -euo pipefail
root=$1
shift
status=0
for doc in "$@"; do
    tmp=$(mktemp -d)
    # Each marked block to $tmp/<n>, and "<n> <path>" per block to $tmp/list.
    awk -v dir="$tmp" '
        /^<!-- file: .* -->$/ { path = $3; want = 1; next }
        want && /^```/ && !inside { inside = 1; n++; out = dir "/" n; printf "" > out; print n, path > (dir "/list"); next }
        inside && /^```$/ { inside = 0; want = 0; close(out); next }
        inside { print > out; next }
        want && NF { print FILENAME ": no code block after the marker of " path > "/dev/stderr"; exit 1 }
    ' "$doc"
    if [ ! -s "$tmp/list" ]; then
        echo "$doc: no <!-- file: ... --> blocks" >&2
        status=1
    else
        while read -r n path; do
            if ! diff -u "$root/$path" "$tmp/$n" >"$tmp/diff"; then
                echo "$doc: the block of $path differs from the file (- file, + doc):" >&2
                head -40 "$tmp/diff" >&2
                status=1
            fi
        done <"$tmp/list"
        [ $status = 0 ] && echo "$doc: $(wc -l <"$tmp/list") code blocks equal their files"
    fi
    rm -rf "$tmp"
done
exit $status
