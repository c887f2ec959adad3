#!/usr/bin/env bash
# The host reads by layer (issue #41): a file's folder says what it may include.
#
#   sdk/, plugins/          no host header at all (plugins see only the SDK)
#   host core/              core
#   host job/               core, job
#   host tools/             core, job, tools
#   host conformance/       core, conformance
#   host serve/             core, job, serve
#   python/ (the module)    core, job
#   framework/cli/          anything
#
# for framework/src/LAYER/ and framework/include/fixpoint/host/LAYER/ alike. Prints each include
# that crosses a rule, with its file and line, and fails if there is one.
set -u
root=${1:-$(dirname "$0")/..}
cd "$root" || exit 2
declare -A allowed=([core]="core" [job]="core job" [tools]="core job tools" [conformance]="core conformance"
                    [serve]="core job serve")
bad=0
check() { # FILE ALLOWED-LAYERS...
    local f=$1
    shift
    local allow=" $* " line text layer
    while IFS=: read -r line text; do
        layer=$(sed -E 's#.*<fixpoint/host/([a-z_]+)/.*#\1#' <<<"$text")
        if [[ "$allow" != *" $layer "* ]]; then
            echo "$f:$line: includes the $layer layer: $text" >&2
            bad=1
        fi
    done < <(grep -n '#include <fixpoint/host/' "$f")
}
for layer in "${!allowed[@]}"; do
    for f in $(find framework/src/$layer framework/include/fixpoint/host/$layer -name '*.[ch]pp' 2>/dev/null); do
        # shellcheck disable=SC2086
        check "$f" ${allowed[$layer]}
    done
done
for f in $(find python -name '*.cpp'); do check "$f" core job; done
for f in $(find sdk plugins -name '*.[ch]pp'); do check "$f"; done
# Nothing of the host outside its layer folders, but the image module and the CLI.
stray=$(find framework/src -maxdepth 1 -name '*.[ch]pp'; find framework/include/fixpoint/host -maxdepth 1 -name '*.hpp')
if [ -n "$stray" ]; then
    echo "host files outside a layer folder: $stray" >&2
    bad=1
fi
# No plugin folder includes another's files: a plugin's helpers stay in its kind's folder
# (plugins/renderers/...); what two kinds share goes to the SDK.
while IFS=: read -r f line text; do
    inc=$(sed -E 's#.*"(.*)".*#\1#' <<<"$text")
    kind=$(cut -d/ -f2 <<<"$f")
    target=$(realpath -m --relative-to=. "$(dirname "$f")/$inc")
    if [[ "$target" != plugins/$kind/* ]]; then
        echo "$f:$line: a plugin folder includes another's file: $text" >&2
        bad=1
    fi
done < <(grep -rn '#include "' plugins || true)
[ $bad = 0 ] && echo "layers: every include keeps to its layer"
exit $bad
