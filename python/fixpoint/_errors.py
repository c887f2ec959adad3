"""fixpoint's exception, raised for bad input (a config, a parameter, a path)."""

import re

# "FILE:LINE:COL: message", as the CLI prints its errors.
_WHERE = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<column>\d+): (?P<message>.*)$", re.S)


# The key path an error line starts with: renderer.maps[0].shape.radius
_KEYS = re.compile(r"^(?P<path>[A-Za-z_][\w-]*(?:\.[A-Za-z_][\w-]*|\[\d+\])*): (?P<rest>.*)$", re.S)
_PART = re.compile(r"[A-Za-z_][\w-]*|\[\d+\]")


class Error(Exception):
    """Bad input: the CLI's error line, with where it points split out.

    ``file``, ``line`` and ``column`` locate the error in the config (None when the error has
    no place, as for a missing plugin folder); ``message`` is the rest of the line; ``str()``
    is the whole line, the same text as the CLI's. ``keys`` is the key path the error names,
    as a tuple (``("renderer", "maps", 0, "shape", "radius")``), or None.

    For a config given as a dict, a line and column would point into text the user never saw
    (the dict as JSON): there ``str()`` names the key path as Python subscripts instead,
    ``config['renderer']['maps'][0]['shape']['radius']: must be > 0, got -0.9``, and ``file``,
    ``line`` and ``column`` are None.
    """

    def __init__(self, text, source=None, name="config"):
        m = _WHERE.match(text)
        if m:
            self.file = m["file"]
            self.line = int(m["line"])
            self.column = int(m["column"])
            self.message = m["message"]
        else:
            self.file = self.line = self.column = None
            self.message = text
        k = _KEYS.match(self.message)
        self.keys = tuple(int(p[1:-1]) if p.startswith("[") else p for p in _PART.findall(k["path"])) if k else None
        if source is not None and self.file == source:
            self.file = self.line = self.column = None
            if k:
                # (eval's transform= and scheme= dicts: their paths start with the argument's name)
                parts = self.keys[1:] if self.keys[0] == name else self.keys
                self.message = name + "".join(f"[{p!r}]" for p in parts) + ": " + k["rest"]
            text = self.message
        super().__init__(text)
