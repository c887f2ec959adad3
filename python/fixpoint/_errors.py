"""fixpoint's exception, raised for bad input (a config, a parameter, a path)."""

import re

# "FILE:LINE:COL: message", as the CLI prints its errors.
_WHERE = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<column>\d+): (?P<message>.*)$", re.S)


class Error(Exception):
    """Bad input: the CLI's error line, with where it points split out.

    ``file``, ``line`` and ``column`` locate the error in the config (None when the error has
    no place, as for a missing plugin folder); ``message`` is the rest of the line; ``str()``
    is the whole line, the same text as the CLI's.
    """

    def __init__(self, text):
        super().__init__(text)
        m = _WHERE.match(text)
        if m:
            self.file = m["file"]
            self.line = int(m["line"])
            self.column = int(m["column"])
            self.message = m["message"]
        else:
            self.file = self.line = self.column = None
            self.message = text
