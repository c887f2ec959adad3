"""Every relative link of the Markdown docs leads somewhere: each link and image of README.md,
docs/**/*.md and bench/README.md names a file or folder of the repository, and a '#anchor'
names a heading of the page it points into (GitHub's anchors). Links inside code are not
links; web addresses are not checked (CI has no network).

Usage: check-links.py ROOT
"""

import os
import re
import sys

INLINE = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML = re.compile(r"<(?:img|a)\b[^>]*?\b(?:src|href)=\"([^\"]*)\"", re.I)
FENCE = re.compile(r"^\s*(```|~~~)")


def prose_lines(text):
    """(line number, line) outside fenced code blocks, with inline code spans blanked."""
    inside = False
    for n, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        if not inside:
            yield n, re.sub(r"`+[^`]*`+", "``", line)


def slug(heading):
    """GitHub's anchor of a heading: its text, lower case, without punctuation, spaces as '-'."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text
    text = text.replace("`", "").replace("*", "")
    text = re.sub(r"<[^>]+>", "", text).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


_anchors = {}


def anchors(path):
    """The anchors of a Markdown file's headings (a repeated one gets -1, -2, ...)."""
    cache = _anchors
    if path not in cache:
        seen, found = {}, set()
        inside = False
        for line in open(path, encoding="utf-8").read().splitlines():
            if FENCE.match(line):
                inside = not inside
                continue
            m = None if inside else re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                s = slug(m.group(1))
                k = seen.get(s, 0)
                seen[s] = k + 1
                found.add(s if k == 0 else f"{s}-{k}")
        cache[path] = found
    return cache[path]


def docs(root):
    yield os.path.join(root, "README.md")
    yield os.path.join(root, "bench", "README.md")
    for d, _, files in os.walk(os.path.join(root, "docs")):
        for f in sorted(files):
            if f.endswith(".md"):
                yield os.path.join(d, f)


def check(root):
    root = os.path.realpath(root)
    bad, count = [], 0
    for doc in docs(root):
        rel = os.path.relpath(doc, root)
        for n, line in prose_lines(open(doc, encoding="utf-8").read()):
            for target in INLINE.findall(line) + HTML.findall(line):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
                    continue  # https:, mailto:
                count += 1
                path, _, anchor = target.partition("#")
                dest = os.path.realpath(os.path.join(os.path.dirname(doc), path)) if path else doc
                where = f"{rel}:{n}: {target}"
                if not (dest == root or dest.startswith(root + os.sep)):
                    bad.append(f"{where}: leads out of the repository")
                elif not os.path.exists(dest):
                    bad.append(f"{where}: no such file or folder")
                elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                    bad.append(f"{where}: no heading '#{anchor}' in {os.path.relpath(dest, root)}")
    return bad, count


if __name__ == "__main__":
    bad, count = check(sys.argv[1])
    for b in bad:
        print(b, file=sys.stderr)
    if bad:
        sys.exit(1)
    print(f"docs: {count} relative links, every one resolves")
