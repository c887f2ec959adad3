#!/usr/bin/env bash
# clang-tidy (the checks of .clang-tidy) on the C++ lines changed since a base commit: cheap
# enough for every CI run, and a landing answers for what it wrote, not for older code.
#
# "Changed" is `git diff -M BASE` (committed and uncommitted changes against BASE; a file moved
# or renamed counts only for the lines that differ). BASE is FIXPOINT_TIDY_BASE when set, else
# HEAD's first parent: on CI's clone of main, where every branch lands as a merge, that is the
# whole landing (a plain commit: that commit). It depends only on the commit checked out, never
# on what ran before. A changed .cpp is checked as the build compiles it; a changed header
# through the first (sorted) source of the build that includes it; findings are reported on the
# changed lines only. At most FIXPOINT_TIDY_MAX (24) sources, the rest named as skipped, so that
# a landing that touches everything still costs minutes.
#
# Usage: clang-tidy-changed.sh ROOT BUILD   (BUILD holds compile_commands.json)
set -euo pipefail
root=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
cd "$root"
tidy=${CLANG_TIDY:-clang-tidy}
max=${FIXPOINT_TIDY_MAX:-24}

if ! git rev-parse --git-dir >/dev/null 2>&1; then
    echo "clang-tidy: $root is not a git checkout: nothing to compare, nothing checked"
    exit 0
fi
base=${FIXPOINT_TIDY_BASE:-HEAD^1}
if ! git rev-parse -q --verify "$base^{commit}" >/dev/null; then
    echo "clang-tidy: no commit $base here (a shallow clone?): nothing checked; set FIXPOINT_TIDY_BASE"
    exit 0
fi
[ -f "$build/compile_commands.json" ] || {
    echo "clang-tidy: no $build/compile_commands.json" >&2
    exit 1
}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
git diff -U0 -M --diff-filter=d --no-color "$base" -- '*.cpp' '*.hpp' '*.h' >"$tmp/diff"

# The build's database, less what clang does not know (GCC's -fno-gnu-unique), and the sources
# to check: changed sources it compiles, and for each changed header one source that includes it.
/usr/bin/python3 - "$build/compile_commands.json" "$tmp" "$root" "$max" <<'PY'
import json, os, re, sys
db_path, tmp, root, cap = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
gcc_only = {"-fno-gnu-unique", "-Wno-restrict"}
db = json.load(open(db_path))
for e in db:
    if "arguments" in e:
        e["arguments"] = [a for a in e["arguments"] if a not in gcc_only]
    else:
        e["command"] = " ".join(a for a in e["command"].split(" ") if a not in gcc_only)
json.dump(db, open(os.path.join(tmp, "compile_commands.json"), "w"))
sources = sorted({os.path.relpath(e["file"], root) for e in db
                  if os.path.realpath(e["file"]).startswith(root + "/")})
# The new side's lines of each hunk, by file ("@@ -a,b +c,d @@": d lines from c; d = 0 deletes).
lines, path = {}, None
for l in open(os.path.join(tmp, "diff"), errors="replace"):
    if l.startswith("+++ "):
        path = l[6:].rstrip("\n") if l.startswith("+++ b/") else None
    elif l.startswith("@@") and path:
        m = re.match(r"@@ -\S+ \+(\d+)(?:,(\d+))? @@", l)
        first, n = int(m.group(1)), int(m.group(2) or 1)
        if n:
            lines.setdefault(path, []).append([first, first + n - 1])
changed = sorted(lines)
todo = []
for f in changed:
    if f.endswith(".cpp"):
        if f in sources:
            todo.append(f)
        continue
    name = re.escape(os.path.basename(f))
    pat = re.compile(r'^\s*#\s*(include|define\s+HWY_TARGET_INCLUDE)\s*[<"](.*/)?' + name + r'[>"]', re.M)
    for s in sources:
        if pat.search(open(os.path.join(root, s), errors="replace").read()):
            todo.append(s)
            break
todo = sorted(set(todo))
with open(os.path.join(tmp, "todo"), "w") as out:
    out.write("".join(t + "\n" for t in todo[:cap]))
for t in todo[cap:]:
    print(f"clang-tidy: skipped {t} (more than FIXPOINT_TIDY_MAX={cap} sources)")
# Findings only on the changed lines.
json.dump([{"name": f, "lines": lines[f]} for f in changed], open(os.path.join(tmp, "filter.json"), "w"))
with open(os.path.join(tmp, "changed"), "w") as out:
    out.write("".join(f + "\n" for f in changed))
PY

n=$(wc -l <"$tmp/todo")
echo "clang-tidy: $(wc -l <"$tmp/changed") C++ files changed since $(git rev-parse --short "$base"), $n sources to check"
[ "$n" -gt 0 ] || exit 0
jobs=$(nproc 2>/dev/null || echo 2)
# One target of Highway's per-target code is enough to lint it (HWY_COMPILE_ONLY_STATIC), at a
# half the cost of all of them.
filter=$(cat "$tmp/filter.json")
status=0
xargs -a "$tmp/todo" -P "$jobs" -I{} sh -c '
    out=$("$0" -p "$1" --quiet --line-filter="$2" --extra-arg=-DHWY_COMPILE_ONLY_STATIC \
          --extra-arg=-Wno-unknown-warning-option "{}" 2>&1) && rc=0 || rc=$?
    found=$(printf "%s\n" "$out" | grep -E "(warning|error): " || true)
    if [ "$rc" -ne 0 ] || [ -n "$found" ]; then printf "%s\n" "$out" | grep -v "warnings\? generated\.$"; exit 1; fi
    echo "clang-tidy: {}: clean"' "$tidy" "$tmp" "$filter" || status=1
[ $status = 0 ] || echo "clang-tidy: findings above (the checks: .clang-tidy)" >&2
exit $status
