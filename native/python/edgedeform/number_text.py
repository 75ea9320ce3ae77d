"""Numbers as the text mesh files hold.

`repr(float(x))`: the shortest text that reads back as the same double. Never `repr(x)` or
`f"{x!r}"` on a NumPy scalar: since NumPy 2 that gives `np.float64(0.13)`, which no mesh
reader (ours included) can parse.
"""


def float_text(x):
    return repr(float(x))


def floats_text(values):
    """'x y z' for a row of coordinates."""
    return " ".join(float_text(x) for x in values)
