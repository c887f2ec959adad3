#!/usr/bin/env bash
# ESLint (Debian's eslint 6) on the preview page's script, with web/.eslintrc.json: the
# recommended rules, strict equality, const and let. (require-atomic-updates is off: it flags
# every assignment after an await that read the same property before it, which the page does on
# purpose, as the newest answer wins; ESLint 7 took it out of the recommended set for that.)
# Usage: eslint.sh ROOT
set -euo pipefail
cd "$1"
# Debian's eslint finds its modules in /usr/share/nodejs, which only Debian's own node searches
# by itself; a node from elsewhere (NodeSource) needs the path. The unix format needs no colour
# library (Debian's stylish needs node-chalk, a recommendation only).
export NODE_PATH=${NODE_PATH:+$NODE_PATH:}/usr/share/nodejs
eslint --format unix --max-warnings 0 web/
echo "eslint: web/ is clean"
