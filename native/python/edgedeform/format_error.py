"""The one error every mesh-file reader and writer raises for a file it cannot take.

The format modules say the line and what is wrong ("line 14: ..."); mesh_files adds the
file and the format in front. Callers catch it by type, never by its text.
"""


class MeshFormatError(ValueError):
    """The file cannot be read or written as a polygon mesh."""


def at_line(line_no, what):
    """The error for 0-based line `line_no` of the file."""
    return MeshFormatError(f"line {line_no + 1}: {what}")


def parse_number(token, kind, line_no, what):
    """`kind(token)` (int or float), or MeshFormatError naming the line and `what` it is."""
    try:
        return kind(token)
    except ValueError:
        raise at_line(line_no, f"'{token}' is not {what}") from None


def require_count(token, line_no, what):
    """A count read from the file: a non-negative integer."""
    n = parse_number(token, int, line_no, f"a count of {what}")
    if n < 0:
        raise at_line(line_no, f"negative count of {what} ({n})")
    return n


def parse_index(token, line_no):
    """A vertex index as a file writes it: an integer that fits 64 bits (whether it names a
    vertex is checked once every vertex is known)."""
    k = parse_number(token, int, line_no, "a vertex index")
    if not -2**63 <= k < 2**63:
        raise at_line(line_no, f"vertex index {k} is out of range")
    return k
