"""Lines of the text mesh formats (OBJ, OFF, ASCII PLY), split as their writers mean them.

Only "\\n", "\\r\\n" and "\\r" end a line: str.splitlines would also split at form feeds,
\\x1c-\\x1e and Latin-1's \\x85, which no mesh writer means as a line break.
"""

import re

_BREAK = re.compile(r"(?<=\n)|(?<=\r)(?!\n)")


def split_lines(text):
    """The lines of `text`, each with its line ending; "".join gives `text` back."""
    return [line for line in _BREAK.split(text) if line]


def line_ending(line):
    """The ending of `line` ("\\n" for the last line, which may have none)."""
    return line[len(line.rstrip("\r\n")):] or "\n"
