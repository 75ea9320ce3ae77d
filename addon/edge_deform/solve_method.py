"""Which method a solve asks the package for. With Acceleration "Automatic" (the default)
the add-on names none, so the package's own default rule picks the method it has found
fastest for the mesh (docs/decisions/0043: that rule may weigh the mesh's size and
stiffness, and a method named here would override it); otherwise the artist's choice.
"""

from . import engine

AUTOMATIC = 'AUTO'


def requested(settings):
    """The package's name of the method the settings choose, or None: the package's
    default rule decides."""
    if settings.acceleration == AUTOMATIC:
        return None
    return engine.acceleration(settings)
