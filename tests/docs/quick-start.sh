#!/usr/bin/env bash
# The front page's first commands work as it says: the first sh block of README.md's "Five
# minutes" runs as it stands, in a scratch folder, with the build's CLI for build/bin/fixpoint,
# and the image rendered from fig4a.png's recipe has fig4a.png's bytes. (Three renders of 4e7
# points: a few seconds.)
# Usage: quick-start.sh FIXPOINT ROOT WORK
set -euo pipefail
bin=$1 root=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
ln -s "$root/configs" "$work/configs"
awk '/^## Five minutes/ { on = 1 } on && /^```sh$/ { inside = 1; next } inside && /^```$/ { exit }
     inside { print }' "$root/README.md" >"$work/block.sh"
grep -q 'fixpoint render fig4a.png -o again.png' "$work/block.sh" || {
    echo "README.md: no sh block under '## Five minutes' that renders fig4a.png's recipe" >&2
    exit 1
}
sed -i "s|build/bin/fixpoint|$bin|" "$work/block.sh"
cd "$work"
bash -euo pipefail block.sh
cmp fig4a.png again.png
grep -q "^renderer:" again.yaml
test -s fig4a-3.png
echo "README.md's five minutes: every command ran; again.png is fig4a.png, byte for byte"
