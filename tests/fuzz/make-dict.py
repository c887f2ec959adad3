#!/usr/bin/env python3
"""Writes tests/fuzz/yaml.dict, the libFuzzer dictionary of fuzz_validate.

Usage: tests/fuzz/make-dict.py [FIXPOINT_BIN]

Entries: YAML's syntax tokens, then every key and every `type:` value of the configs
(configs/**/*.yaml, bench/*.yaml, tests/external-plugin/config.yaml), and, when a built
`fixpoint` is given, every plugin's name, parameter names and the values of its enumerated
string parameters (from `fixpoint plugins` and `fixpoint describe`), so that plugins and
options no config uses yet are reached too. The mutator splices these whole words into
inputs, which random bytes would take long to spell. Run it again with a build's CLI
whenever a plugin, a parameter or a config is added: tests/fuzz/make-dict.py build/bin/fixpoint
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parents[2]

# YAML structure and scalars the guard and the schemas treat specially.
TOKENS = [
    "---", "...", ": ", "- ", "? ", "[", "]", "{", "}", ", ", "#", "\n", "\n  ", "\n    - ",
    "'", '"', "|", ">", "&a ", "*a", "!!str ", "!!int ", "!tag ", "<<: ", "%YAML 1.2\n",
    "null", "~", "true", "false", "on", "n", "yes", ".inf", "-.inf", ".nan", "0x1f", "0o17",
    "1e308", "-1e308", "4.9e-324", "-0", "1e+15", "18446744073709551616", "2147483648",
    "-2147483649", "0.5+0.5q", "#ff6b6b", "\\u0000", "\\x00",
]

words = set()
files = sorted(root.glob("configs/**/*.yaml")) + sorted(root.glob("bench/*.yaml"))
files.append(root / "tests/external-plugin/config.yaml")
for f in files:
    # Comments out (a '#' at a line's start or after a blank; colours are quoted).
    text = re.sub(r"(^|\s)#.*", "", f.read_text(encoding="utf-8"))
    words.update(m + ":" for m in re.findall(r"([A-Za-z_][A-Za-z0-9_-]*):(?=\s)", text))
    words.update("type: " + m for m in re.findall(r"\btype:\s*([A-Za-z0-9_-]+)", text))

if len(sys.argv) > 1:
    fixpoint = sys.argv[1]
    listing = subprocess.run([fixpoint, "plugins"], check=True, capture_output=True, text=True).stdout
    for line in listing.splitlines():
        name = line.split()[1]
        words.add("type: " + name)
        desc = subprocess.run([fixpoint, "describe", name], check=True, capture_output=True, text=True).stdout
        desc = desc.partition("\nparameters:\n")[2]  # one line per parameter, then its help
        words.update(m + ":" for m in re.findall(r"^  ([A-Za-z_][A-Za-z0-9_]*)\s{2,}\S", desc, re.M))
        # The values of enumerated strings: "  mode   string {fixed|level|ifs}; default fixed".
        for choices in re.findall(r"^  [A-Za-z_][A-Za-z0-9_]*\s{2,}string \{([^}]*)\}", desc, re.M):
            words.update(c for c in choices.split("|") if c)


def quote(s):
    out = ""
    for ch in s:
        if ch in '"\\':
            out += "\\" + ch
        elif " " <= ch <= "~":
            out += ch
        else:
            out += "\\x%02x" % ord(ch)
    return '"' + out + '"'


lines = ["# libFuzzer dictionary of fuzz_validate: written by tests/fuzz/make-dict.py; edit that, not this."]
lines += [quote(t) for t in TOKENS]
lines += [quote(w) for w in sorted(words - set(TOKENS))]
(root / "tests/fuzz/yaml.dict").write_text("\n".join(lines) + "\n", encoding="utf-8")
print(f"tests/fuzz/yaml.dict: {len(lines) - 1} entries")
