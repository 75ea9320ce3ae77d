"""The states of the modal tools, Live Deform and Grab Deform, and their transitions: one
state enum and one transition function per tool. No bpy: the operators
(operators_live.py, operators_grab.py) observe Blender and act, then ask here where that
leaves them; a pair that is not listed is a bug and raises (the operator then ends
cleanly, never in a state nobody designed). tests/blender/test_unit_settle.py walks them.
"""

import enum


class IllegalTransition(RuntimeError):
    pass


def _next(table, tool, state, event):
    try:
        return table[state][event]
    except KeyError:
        raise IllegalTransition("%s: %s in state %s" % (tool, event.value, state.value))


class Live(enum.Enum):
    HOLDING = "holding"        # started on a Grab edit no handle holds: nothing is solved
                               # (nothing moves) until a controller or a setting changes
    SOLVING = "solving"        # the targets or settings changed, not settled yet: iterate
    AT_REST = "at rest"        # settled, or gave up settling: watch for changes only
    PAUSED = "paused"          # the object is in another mode (Blender's tools own it)
    REFUSED = "refused"        # a check or solve failed: wait until the user changes a fix
    REBINDING = "rebinding"    # check and read the settings and groups again before solving
                               # (after a pause or a refusal, a change of the groups or of
                               # Output, a deleted controller); Live holds no solver until
                               # it is done
    SWITCHING = "switching"    # building the new domain's graph, one stage per tick


class LiveEvent(enum.Enum):
    CHANGED = "changed"              # targets or settings differ from the last solve
    ITERATED = "iterated"            # a tick iterated and has not settled
    SETTLED = "settled"              # settled, or reached the give-up limit
    MODE_LEFT = "mode left"          # the object left Object Mode
    MODE_BACK = "mode back"          # ... and came back
    FAILED = "failed"                # a refusal or a solver error
    RETRY = "retry"                  # what the user can fix changed since the refusal
    REBIND = "rebind"                # groups, Output or a controller changed: bind again
    BOUND = "bound"                  # the rebind's checks passed: a new solver is ready
    SWITCH = "switch"                # the domain setting differs from the graph's
    SWITCH_ENDED = "switch ended"    # the new graph is ready, or the switch stopped


_LIVE = {
    Live.HOLDING: {LiveEvent.CHANGED: Live.SOLVING, LiveEvent.MODE_LEFT: Live.PAUSED,
                   LiveEvent.FAILED: Live.REFUSED, LiveEvent.SWITCH: Live.SWITCHING,
                   LiveEvent.REBIND: Live.REBINDING},
    Live.SOLVING: {LiveEvent.CHANGED: Live.SOLVING, LiveEvent.ITERATED: Live.SOLVING,
                   LiveEvent.SETTLED: Live.AT_REST, LiveEvent.MODE_LEFT: Live.PAUSED,
                   LiveEvent.FAILED: Live.REFUSED, LiveEvent.SWITCH: Live.SWITCHING,
                   LiveEvent.REBIND: Live.REBINDING},
    Live.AT_REST: {LiveEvent.CHANGED: Live.SOLVING, LiveEvent.MODE_LEFT: Live.PAUSED,
                   LiveEvent.FAILED: Live.REFUSED, LiveEvent.SWITCH: Live.SWITCHING,
                   LiveEvent.REBIND: Live.REBINDING},
    # The topology may have changed in another mode: bind again.
    Live.PAUSED: {LiveEvent.MODE_BACK: Live.REBINDING},
    Live.REFUSED: {LiveEvent.RETRY: Live.REBINDING, LiveEvent.MODE_LEFT: Live.PAUSED},
    Live.REBINDING: {LiveEvent.BOUND: Live.SOLVING, LiveEvent.FAILED: Live.REFUSED},
    Live.SWITCHING: {LiveEvent.SWITCH_ENDED: Live.SOLVING},
}


def live_next(state, event):
    """Live Deform's transition function."""
    return _next(_LIVE, "Live Deform", state, event)


class Grab(enum.Enum):
    WAITING = "waiting"        # nothing moves (nothing is solved) before the pointer moves
                               # in the viewport (its motion counts from where it first is
                               # there: from the panel's button, where it enters the view)
    DRAGGING = "dragging"      # the pointer (or the axis) changed: solve for it
    SETTLING = "settling"      # the pointer stands still, not settled: iterate
    AT_REST = "at rest"        # settled, gave up, or the solve failed: wait for the pointer


class GrabEvent(enum.Enum):
    STARTED = "started"        # the pointer moved in the viewport
    MOVED = "moved"            # the pointer moved or the axis changed
    ITERATED = "iterated"
    SETTLED = "settled"        # settled, or reached the give-up limit
    FAILED = "failed"


_GRAB = {
    Grab.WAITING: {GrabEvent.STARTED: Grab.DRAGGING},
    Grab.DRAGGING: {GrabEvent.MOVED: Grab.DRAGGING, GrabEvent.ITERATED: Grab.SETTLING,
                    GrabEvent.SETTLED: Grab.AT_REST, GrabEvent.FAILED: Grab.AT_REST},
    Grab.SETTLING: {GrabEvent.MOVED: Grab.DRAGGING, GrabEvent.ITERATED: Grab.SETTLING,
                    GrabEvent.SETTLED: Grab.AT_REST, GrabEvent.FAILED: Grab.AT_REST},
    Grab.AT_REST: {GrabEvent.MOVED: Grab.DRAGGING},
}


def grab_next(state, event):
    """Grab Deform's transition function."""
    return _next(_GRAB, "Grab Deform", state, event)
