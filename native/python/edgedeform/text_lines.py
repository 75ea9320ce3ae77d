"""Lines of the text mesh formats (OBJ, OFF, ASCII PLY), split as their writers mean them.

Only "\\n", "\\r\\n" and "\\r" end a line: str.splitlines would also split at form feeds,
\\x1c-\\x1e and Latin-1's \\x85, which no mesh writer means as a line break.
"""

import re

_BREAK = re.compile(r"(?<=\n)|(?<=\r)(?!\n)")
_LINE = re.compile(r"[^\r\n]*(?:\r\n|\n|\r)|[^\r\n]+\Z")


def split_lines(text):
    """The lines of `text`, each with its line ending; "".join gives `text` back."""
    return [line for line in _BREAK.split(text) if line]


def iter_lines(text, start=0):
    """(line with its ending, offset after it) from `start` on, one at a time: a reader that
    stops early never splits the rest of a large file."""
    for match in _LINE.finditer(text, start):
        yield match.group(), match.end()


def lines_at_most(text, start=0):
    """An upper bound of the lines from `start` on, without splitting them."""
    return text.count("\n", start) + text.count("\r", start) + 1


def line_ending(line):
    """The ending of `line` ("\\n" for the last line, which may have none)."""
    return line[len(line.rstrip("\r\n")):] or "\n"
