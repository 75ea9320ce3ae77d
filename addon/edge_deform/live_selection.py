"""What Live Deform changes around its mesh, and gives back (docs/decisions/0042).

- The selection. Started with the mesh active, Live makes the active handle's controller
  the active, only selected object, so that G/R/S and the gizmos move the controller, not
  the mesh object; the text over the view always names what G/R/S move now.
- Every object's transform. Inside Live, G/R/S push no undo step of their own (Live's
  one step holds the session), so Esc puts back the transform of every object moved
  during the session, the mesh object's too: after Esc the next Ctrl+Z reaches only the
  step before Live, never more.
Esc gives both back. Enter keeps the transforms (Live's undo step holds them) and gives
the selection back only if it is still the one Live made (the artist's own picks stay).
"""


def what_g_moves(layer, ob):
    """The words for what G/R/S move now, Live running on `ob`."""
    active = layer.objects.active
    if active is not None and active != ob and any(
            h.controller == active for h in ob.edge_deform.handles):
        return "G/R/S move '%s'" % active.name
    if active == ob:
        return "G/R/S would move the object '%s' itself: click a controller" % ob.name
    return "click a controller to move it with G/R/S"


def _selectable(layer, ob):
    return (ob is not None and layer.objects.get(ob.name) == ob
            and ob.visible_get(view_layer=layer))


class Surroundings:
    """The selection and the transforms as Live found them, for Esc and Enter."""

    def __init__(self, layer, ob):
        self.layer, self.ob = layer, ob
        self.active = layer.objects.active
        self.selected = [o for o in layer.objects if o.select_get()]
        self.transforms = [(o, o.matrix_basis.copy()) for o in layer.objects]
        self.made = None   # the controller Live made the active, only selected object

    def select_controller(self, controller):
        """With the mesh active, make `controller` the active, only selected object.
        Returns it, or None when Live leaves the selection alone (started from a
        controller or another object; no controller that can be selected)."""
        if self.active != self.ob or not _selectable(self.layer, controller):
            return None
        for other in self.layer.objects:
            other.select_set(other == controller)
        self.layer.objects.active = controller
        self.made = controller
        return controller

    def give_back(self, cancelled):
        """Esc (cancelled): every moved transform and the selection as before Live. Enter:
        the selection as before, if it is still Live's own."""
        if cancelled:
            for ob, matrix in self.transforms:
                try:
                    if ob.matrix_basis != matrix:
                        ob.matrix_basis = matrix
                except ReferenceError:   # deleted meanwhile
                    pass
        if cancelled or self._still_made():
            self._select_as_before()

    def _still_made(self):
        layer = self.layer
        return (self.made is not None and layer.objects.active == self.made
                and [o for o in layer.objects if o.select_get()] == [self.made])

    def _select_as_before(self):
        keep = set()
        for ob in self.selected:
            try:
                keep.add(ob.name_full)
            except ReferenceError:   # deleted meanwhile
                pass
        try:
            for other in self.layer.objects:
                if other.select_get() != (other.name_full in keep):
                    other.select_set(other.name_full in keep)
            if self.active is not None and self.layer.objects.get(self.active.name) \
                    == self.active:
                self.layer.objects.active = self.active
        except (ReferenceError, RuntimeError):   # an object went, or left the view layer
            pass
