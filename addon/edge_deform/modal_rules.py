"""What the modal tools decide without bpy: Live's and Grab's states and transitions
(one state enum and one transition function per tool), then the settle policy. No bpy and
no imports from the add-on, so tests/blender/test_unit_settle.py and
bench/bench_live_settle.py load this file by its path.

The operators (live.py, grab.py) observe Blender and act, then ask here where that
leaves them; a pair that is not listed is a bug and raises (the operator then ends
cleanly, never in a state nobody designed). tests/blender/test_unit_settle.py walks them.
"""

import enum
import math
import time


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


# ------------------------------------------------------------------ the settle policy
# The settle policy of the modal tools (Live, Grab) and of Solve's chunks: how long a tick
# iterates, when a solve counts as settled, when the tools give up. No bpy and no imports
# from the add-on, so bench/bench_live_settle.py replays exactly this policy outside Blender
# and tests/blender/test_unit_settle.py checks it with plain Python (both load this file by
# its path).
#
# A tick spends a TIME budget on solver iterations, not a fixed count: TICK_BUDGET_MS, or,
# when Blender took longer than that between two ticks (a software-GL redraw of a big mesh
# takes 0.6-1.9 s), as long as Blender took, up to a cap. So slow redraws do not throttle
# the solve: the solver gets at least half of the wall time. The cap is lower while the
# targets move (the artist waits for the next frame) than while they stand still.
#
# The speed a tick is sized from is measured on the system the solver iterates on now: after
# any change of it (a region to the whole mesh, the whole mesh to a region, λ, the domain, a
# rebind: engine.Binding.system changes) the first call asks for LEAST_ITERATIONS and
# measures. Sized from a 40-vertex region's speed, the first whole-mesh tick after O asked
# for 609 iterations, 14 s of a frozen window (record 0067).
#
# "Settled" needs a claim made in a call that asked for the check: a tick whose targets stand
# still asks the solver to check a convergence claim against J_G's slowest mode first (the
# core's verify_claims, for every method: without it Live called the 50k koala settled
# 4.7e-3 of its size away, docs/decisions/0025). A tick whose targets move does not ask (the check costs about
# 30 iterations: a drag would stutter), so its claim stays "settling…" until the next still
# tick has asked. A claim after no iteration at all (nothing free to move) is exact.

TICK_BUDGET_MS = 30.0          # solve time per tick on a machine that redraws quickly
MOVING_CAP_MS = 100.0          # the most a tick iterates while the targets move
SETTLING_CAP_MS = 400.0        # ... and while they stand still (Esc still answers)
# Some shapes never report convergence (a mode that does not contract, or tolerance 0):
# past this many iterations since the last change the tools stop and say so, as a cold
# solve stops at its max_iterations, so an idle tool does not keep a core busy for ever.
SETTLE_LIMIT = 2000
# Warm solve calls of one iteration each follow the same iterates as longer calls but may
# never report convergence (measured on the plane, a shear-and-bend at λ 0.5: still
# unconverged after 1500 one-iteration calls, where calls of 2 or more stop at iteration
# 1519, as one long call does). So no call asks for fewer than this.
LEAST_ITERATIONS = 2
# A settle still running after this long (the artist waiting) is worth a word: on a big
# mesh a proportional radius makes it local and quick (the tools say so once).
LONG_WAIT_MS = 3000.0


def is_settled(result):
    """The solver's own distance estimate says converged (Settle.settled also needs the
    call to have asked for the claim's check)."""
    return bool(result.converged)


def iterations_within(budget_ms, ms_per_iteration, most=None):
    """How many iterations fit in `budget_ms` at `ms_per_iteration` (None: not measured
    yet), never fewer than LEAST_ITERATIONS nor more than `most`."""
    if not ms_per_iteration:
        n = LEAST_ITERATIONS
    else:
        n = max(LEAST_ITERATIONS, int(budget_ms / ms_per_iteration + 1e-6))
    if most is not None:
        n = min(n, int(most))
        if 0 < int(most) - n < LEAST_ITERATIONS:
            n = int(most)      # no one-iteration call left at the end
    return max(1, n)


class Settle:
    """One tool's settle bookkeeping: the solver's measured speed, the time Blender takes
    between ticks, and the iterations and wall time since the last change of the targets.

    Each tick: `tick(solve, moving)` with solve(n, check_claims) -> a SolveResult of n
    more warm iterations. It calls solve in chunks until the tick's budget is spent, the solve
    settled, or the give-up limit is reached, and returns the last result."""

    def __init__(self, limit=None, clock=time.perf_counter):
        self._limit = limit          # None: SETTLE_LIMIT as it is now (tests lower it)
        self.clock = clock
        self.ms_per_iteration = None
        self.system = None           # what ms_per_iteration was measured on
        self.last_tick_end = None
        self.changed()

    # ---------------------------------------------------------------- bookkeeping

    def changed(self):
        """The targets or the settings changed: a new settle starts."""
        self.iterations = 0          # since the change
        self.started = None          # when the first tick after the change began
        self.waited_ms = 0.0         # wall time from that tick to the last result
        self.result = None
        self.check_requested = False  # the last result's solve call asked to check a claim

    @property
    def limit(self):
        return SETTLE_LIMIT if self._limit is None else self._limit

    @property
    def settled(self):
        return self.result is not None and self.check_requested and is_settled(self.result)

    @property
    def claim_unchecked(self):
        """Converged in a call that did not ask for the check: one more call must ask."""
        return self.result is not None and is_settled(self.result) and not self.check_requested

    @property
    def gave_up(self):
        return not self.settled and not self.claim_unchecked and self.iterations >= self.limit

    @property
    def at_rest(self):
        """Settled or given up: nothing to do until something changes."""
        return self.settled or self.gave_up

    @property
    def runs_long(self):
        """Still settling after LONG_WAIT_MS of the artist's wait."""
        return not self.at_rest and self.waited_ms >= LONG_WAIT_MS

    def budget_ms(self, moving, now):
        """This tick's time budget (see the module's docstring)."""
        gap = 0.0 if self.last_tick_end is None else (now - self.last_tick_end) * 1e3
        cap = MOVING_CAP_MS if moving else SETTLING_CAP_MS
        return min(cap, max(TICK_BUDGET_MS, gap))

    # ---------------------------------------------------------------- one tick

    def tick(self, solve, moving, system=None):
        """`system`: what the solver iterates on (engine.Binding.system); another than the
        last tick's drops the speed measured on that one."""
        if system != self.system:
            self.system, self.ms_per_iteration = system, None
        now = self.clock()
        if self.started is None:
            self.started = now
        budget = self.budget_ms(moving, now)
        check = not moving
        spent, result = 0.0, None
        while True:
            n = iterations_within(budget - spent, self.ms_per_iteration,
                                  most=max(1, self.limit - self.iterations))
            t0 = self.clock()
            result = solve(n, check)
            ms = (self.clock() - t0) * 1e3
            if not getattr(result, "claim_checks", 0):   # a check's time is not an iteration's
                # (nor is a factorization the call made first, after new constraints)
                iterating = ms - float(getattr(result, "factor_ms", 0.0))
                self.ms_per_iteration = max(iterating, 0.0) / max(1, int(result.iterations))
            spent += ms
            self.iterations += int(result.iterations)
            self.result = result
            self.check_requested = check or int(result.iterations) == 0
            if self.at_rest or result.iterations < n or is_settled(result):
                break
            if budget - spent < LEAST_ITERATIONS * (self.ms_per_iteration or 0.0):
                break
        self.last_tick_end = self.clock()
        self.waited_ms = (self.last_tick_end - self.started) * 1e3
        return result

    def rested(self):
        """A tick that did not iterate (nothing changed): Blender's time until the next
        tick must not count as a slow redraw."""
        self.last_tick_end = None


def describe(settle, resume_hint):
    """The words a modal tool shows for its settle. "settled" only by is_settled; the
    time is the wall time the artist has waited since the last change, not the solver's."""
    if settle.gave_up:
        estimate = float(settle.result.distance_estimate)
        how_far = ("estimated %.0e of the size away" % estimate if math.isfinite(estimate)
                   else "distance unknown")
        return ("stopped after %d iterations, not converged (%s); %s to go on"
                % (settle.iterations, how_far, resume_hint))
    return "%s, %d iterations, %.1f s" % ("settled" if settle.settled else "settling…",
                                          settle.iterations, settle.waited_ms / 1e3)
