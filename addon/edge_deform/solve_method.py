"""Which method a solve asks the package for. With Acceleration "Automatic" (the default)
the add-on names none, so the package's own measured rule picks the method (docs/decisions/
0043 and 0070: L-BFGS where stiffness is 1 everywhere, else Anderson; a method named here
would override it); otherwise the artist's choice.
"""

from . import engine

AUTOMATIC = 'AUTO'


def requested(settings):
    """The package's name of the method the settings choose, or None: the package's
    measured rule decides."""
    return engine.acceleration(settings)
