#!/usr/bin/env bash
# Fails when a tracked C++ file does not match .clang-format.
set -euo pipefail
cd "$1"
files=$(git ls-files '*.cpp' '*.hpp' 2>/dev/null || find sdk framework plugins tests bench -name '*.[ch]pp')
[ -n "$files" ] || exit 0
bad=$(echo "$files" | xargs clang-format --dry-run 2>&1 | grep -c 'warning:' || true)
if [ "$bad" != 0 ]; then
    echo "$files" | xargs clang-format --dry-run 2>&1 | grep 'warning:' | head -20
    echo "clang-format: $bad differences; run clang-format -i on the files above" >&2
    exit 1
fi
echo "clang-format: all files match"
