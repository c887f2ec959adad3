#!/usr/bin/env bash
# The corpus's checker fails as it should: a recipe whose pixels change (here: another seed)
# fails the check, and --record refuses it while no new render version touches it (the version
# is still the one it was recorded at, or no change since names its plugins and parameters),
# writing nothing.
#   refuses.sh FIXPOINT_GOLDEN CORPUS SCRATCH
set -euo pipefail
golden=$1 corpus=$2 d=$3
rm -rf "$d" && mkdir -p "$d"
cp "$corpus/inversion-fig4a.yaml" "$corpus/gm-fig1b.yaml" "$d/"
grep -E '  (inversion-fig4a|gm-fig1b)\.yaml$' "$corpus/SHA256SUMS" >"$d/SHA256SUMS"
"$golden" "$d" # as recorded
sed -i 's/^  seed: 1$/  seed: 2/' "$d/inversion-fig4a.yaml"
grep -q '^  seed: 2$' "$d/inversion-fig4a.yaml"
cp "$d/SHA256SUMS" "$d/before"
if "$golden" "$d" 2>"$d/check.err"; then
    echo "a changed recipe passed the check" >&2
    exit 1
fi
why='its pixels changed, but (the render version is still|no change after render version [0-9]* in framework/render-versions.yaml touches it)'
grep -Eq "^inversion-fig4a.yaml: pixels .* recorded .* at render version [0-9]*: $why" "$d/check.err"
! grep -q gm-fig1b "$d/check.err"
if "$golden" "$d" --record 2>"$d/record.err"; then
    echo "--record took a change without a new render version" >&2
    exit 1
fi
grep -Eq "$why" "$d/record.err"
cmp "$d/before" "$d/SHA256SUMS" # nothing written
echo "golden checker: a changed recipe fails, and is not recorded without a new version"
