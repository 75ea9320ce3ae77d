"""Unit tests (pytest, no Blender) of the modal tools' settle policy (addon/edge_deform/
modal_rules.py) and state machines (the same file). It is bpy-free and loaded by its
path, as bench/bench_live_settle.py loads the policy.

    /usr/bin/python3 -m pytest tests/blender/test_unit_settle.py
"""

import importlib.util
import os
from types import SimpleNamespace

import pytest

ADDON = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))), "addon", "edge_deform")


def load(name):
    spec = importlib.util.spec_from_file_location("edge_deform_" + name,
                                                  os.path.join(ADDON, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


settle = states = load("modal_rules")


class Clock:
    """A clock the fake solver and the "redraws" advance."""

    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


class Solver:
    """solve(n, check_claims): n iterations at ms_per_iteration each; converges after
    `converge_at` iterations in all (None: never). Records the calls and whether each
    asked for its claim to be checked."""

    def __init__(self, clock, ms_per_iteration, converge_at=None, estimate=0.01):
        self.clock, self.ms = clock, ms_per_iteration
        self.converge_at, self.estimate = converge_at, estimate
        self.done, self.calls, self.checks = 0, [], []

    def __call__(self, n, check_claims):
        self.calls.append(n)
        self.checks.append(check_claims)
        if self.converge_at is not None:
            n = max(0, min(n, self.converge_at - self.done))
        self.done += n
        self.clock.now += n * self.ms / 1e3
        converged = self.converge_at is not None and self.done >= self.converge_at
        return SimpleNamespace(iterations=n, converged=converged,
                               distance_estimate=0.0 if converged else self.estimate)


def test_iterations_within_the_budget():
    assert settle.iterations_within(30.0, None) == settle.LEAST_ITERATIONS   # measure
    assert settle.iterations_within(30.0, 3.0) == 10
    assert settle.iterations_within(30.0, 50.0) == settle.LEAST_ITERATIONS   # never one
    assert settle.iterations_within(30.0, 3.0, most=4) == 4
    assert settle.iterations_within(30.0, 3.0, most=11) == 11   # no 1-iteration call left
    assert settle.iterations_within(30.0, 3.0, most=1) == 1


def test_a_tick_spends_its_time_budget_not_a_count():
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0)
    s.tick(solver, moving=True)
    # The first call measures (2 iterations); the rest of the 30 ms goes on iterating.
    assert solver.calls[0] == settle.LEAST_ITERATIONS
    assert 27 <= s.iterations <= 30, s.iterations
    spent = (clock.now - 100.0) * 1e3
    assert spent <= settle.TICK_BUDGET_MS + 1e-9, spent


def test_slow_redraws_do_not_throttle_the_solve():
    """A software-GL redraw of 1.5 s between ticks: each tick then iterates up to its cap
    (the solver gets at least as long as the redraw, up to the cap), where a fixed count
    gave two iterations a redraw."""
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=10.0)
    s.tick(solver, moving=False)
    first = s.iterations
    clock.now += 1.5                      # Blender redraws for 1.5 s
    s.tick(solver, moving=False)
    assert s.iterations - first == settle.SETTLING_CAP_MS / 10.0, s.iterations - first
    clock.now += 1.5
    before = s.iterations
    s.tick(solver, moving=True)           # while the targets move: the lower cap
    assert s.iterations - before == settle.MOVING_CAP_MS / 10.0
    assert settle.MOVING_CAP_MS < settle.SETTLING_CAP_MS
    clock.now += 0.005                    # a quick redraw: the base budget
    before = s.iterations
    s.tick(solver, moving=False)
    assert s.iterations - before == settle.TICK_BUDGET_MS / 10.0


def test_idle_time_is_not_a_slow_redraw():
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0)
    s.tick(solver, moving=False)
    s.rested()                            # ticks that did not iterate
    clock.now += 60.0
    before = s.iterations
    s.tick(solver, moving=False)
    assert s.iterations - before <= settle.TICK_BUDGET_MS


def test_settled_only_when_the_solver_says_converged():
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0, converge_at=45)
    s.tick(solver, moving=True)
    assert not s.settled and not s.at_rest
    assert settle.describe(s, "move").startswith("settling…, 30 iterations"), \
        settle.describe(s, "move")
    clock.now += 0.02
    s.tick(solver, moving=False)
    assert s.settled and s.at_rest and s.iterations == 45
    text = settle.describe(s, "move")
    assert text.startswith("settled, 45 iterations"), text
    # The time shown is the artist's wait since the change (redraws included), not the
    # solver's 45 ms.
    assert text.endswith("0.1 s"), text
    s.changed()
    assert not s.settled and s.iterations == 0


def test_a_claim_while_the_targets_move_is_checked_before_settled():
    """A drag tick does not pay for the claim check; its claim is only "settling…" until
    the next still tick, whose call asks for the check, makes it "settled"."""
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0, converge_at=12)
    s.tick(solver, moving=True)
    assert solver.checks and not any(solver.checks), solver.checks   # no check while moving
    assert s.result.converged and not s.settled and not s.at_rest
    assert settle.describe(s, "move").startswith("settling…"), settle.describe(s, "move")
    clock.now += 0.02
    calls = len(solver.calls)
    s.tick(solver, moving=False)
    assert solver.checks[calls:] == [True] * (len(solver.calls) - calls)
    assert s.settled and s.at_rest
    assert settle.describe(s, "move").startswith("settled"), settle.describe(s, "move")
    s.changed()                           # the targets move again: unchecked once more
    s.tick(Solver(clock, ms_per_iteration=1.0, converge_at=5), moving=True)
    assert s.result.converged and not s.settled


def test_nothing_to_move_is_settled_at_once():
    """No free vertex: the core answers converged after 0 iterations, an exact claim with
    nothing to check; a drag tick must not leave it "settling…" for ever."""
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0, converge_at=0)
    s.tick(solver, moving=True)
    assert s.settled and s.at_rest and s.iterations == 0


def test_an_unchecked_claim_at_the_limit_is_checked_not_given_up():
    clock = Clock()
    s = settle.Settle(limit=12, clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0, converge_at=12)
    s.tick(solver, moving=True)           # converges exactly at the limit, unchecked
    assert s.iterations == 12 and s.result.converged
    assert not s.gave_up and not s.at_rest, settle.describe(s, "move")
    s.tick(solver, moving=False)          # one call that asks for the check
    assert solver.checks[-1] and s.settled and not s.gave_up


def test_a_claim_check_does_not_count_as_slow_iterations():
    """A call that ran the core's claim check (about 30 back-substitutions) is not a
    measure of the iterations' speed: the next ticks still get their full count."""
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0)
    s.tick(solver, moving=False)
    speed = s.ms_per_iteration

    def checking(n, check_claims):
        clock.now += 0.5                  # the check: 0.5 s for 2 iterations
        return SimpleNamespace(iterations=2, converged=False, distance_estimate=0.01,
                               claim_checks=1)
    s.tick(checking, moving=False)
    assert s.ms_per_iteration == speed


def test_a_new_system_is_measured_before_a_tick_is_sized():
    """Settled on a small region (0.05 ms an iteration), then the whole mesh (24 ms: O
    off, record 0067): the first call on the new system asks for LEAST_ITERATIONS, and no
    tick iterates past its cap; before, it asked for 400 / 0.05 iterations (the limit)."""
    clock = Clock()
    s = settle.Settle(clock=clock)
    region = Solver(clock, ms_per_iteration=0.05)
    s.tick(region, moving=False, system=1)
    s.tick(region, moving=False, system=1)
    assert s.ms_per_iteration == pytest.approx(0.05)
    whole = Solver(clock, ms_per_iteration=24.0)
    clock.now += 1.0                     # a slow redraw: the tick may use its cap
    s.changed()
    start = clock.now
    s.tick(whole, moving=False, system=2)
    assert whole.calls[0] == settle.LEAST_ITERATIONS, whole.calls
    assert (clock.now - start) * 1e3 <= settle.SETTLING_CAP_MS + 1e-9
    assert s.ms_per_iteration == pytest.approx(24.0)
    s.tick(Solver(clock, ms_per_iteration=24.0), moving=False, system=2)   # same system
    assert s.ms_per_iteration == pytest.approx(24.0)


def test_a_factorization_is_not_an_iterations_time():
    """The core factors lazily, in the first solve after new constraints (factor_ms): that
    call's speed is its iterations' alone, so the next call is not sized too small."""
    clock = Clock()
    s = settle.Settle(clock=clock)

    def first(n, check_claims):
        clock.now += (200.0 + n * 1.0) / 1e3
        return SimpleNamespace(iterations=n, converged=False, distance_estimate=0.01,
                               factor_ms=200.0)
    s.tick(first, moving=True, system=1)
    assert s.ms_per_iteration == pytest.approx(1.0)


def test_runs_long_after_the_long_wait():
    clock = Clock()
    s = settle.Settle(clock=clock)
    solver = Solver(clock, ms_per_iteration=10.0)
    s.tick(solver, moving=False)
    assert not s.runs_long
    while s.waited_ms < settle.LONG_WAIT_MS:
        clock.now += 0.5
        s.tick(solver, moving=False)
    assert s.runs_long
    s.changed()
    assert not s.runs_long


def test_give_up_at_the_limit_and_say_so():
    clock = Clock()
    s = settle.Settle(limit=50, clock=clock)
    solver = Solver(clock, ms_per_iteration=1.0, estimate=float("inf"))
    while not s.at_rest:
        s.tick(solver, moving=False)
        clock.now += 0.01
    assert s.gave_up and not s.settled and s.iterations == 50   # never past the limit
    text = settle.describe(s, "move a controller")
    assert text == ("stopped after 50 iterations, not converged (distance unknown); "
                    "move a controller to go on"), text
    s.result.distance_estimate = 0.02
    assert "estimated 2e-02 of the size away" in settle.describe(s, "x")


def test_the_limit_follows_the_module_constant(monkeypatch):
    s = settle.Settle()
    monkeypatch.setattr(settle, "SETTLE_LIMIT", 7)
    assert s.limit == 7


def test_is_settled_reads_converged():
    assert settle.is_settled(SimpleNamespace(converged=True))
    assert not settle.is_settled(SimpleNamespace(converged=False))


def test_live_transitions():
    L, E = states.Live, states.LiveEvent
    go = states.live_next
    s = L.SOLVING
    s = go(s, E.ITERATED)
    assert s == L.SOLVING
    s = go(s, E.SETTLED)
    assert s == L.AT_REST
    assert go(s, E.CHANGED) == L.SOLVING
    assert go(s, E.MODE_LEFT) == L.PAUSED
    # Back from another mode, or retrying a refusal: bind again, then solve.
    assert go(L.PAUSED, E.MODE_BACK) == L.REBINDING
    assert go(go(L.SOLVING, E.FAILED), E.RETRY) == L.REBINDING
    assert go(L.REBINDING, E.BOUND) == L.SOLVING
    assert go(L.REBINDING, E.FAILED) == L.REFUSED
    for state in (L.HOLDING, L.SOLVING, L.AT_REST):
        assert go(state, E.REBIND) == L.REBINDING     # groups, Output or a controller
    with pytest.raises(states.IllegalTransition):
        go(L.REBINDING, E.ITERATED)       # no solve before the new solver is ready
    assert go(go(L.AT_REST, E.SWITCH), E.SWITCH_ENDED) == L.SOLVING
    with pytest.raises(states.IllegalTransition):
        go(L.PAUSED, E.ITERATED)          # a paused Live never solves
    with pytest.raises(states.IllegalTransition):
        go(L.SWITCHING, E.CHANGED)        # nothing else happens during a switch
    # Started on a Grab edit no handle holds: nothing is solved until something changes.
    assert go(L.HOLDING, E.CHANGED) == L.SOLVING
    assert go(L.HOLDING, E.MODE_LEFT) == L.PAUSED
    for event in (E.ITERATED, E.SETTLED):
        with pytest.raises(states.IllegalTransition):
            go(L.HOLDING, event)          # holding never iterates
    # Every state can be left (no dead end but the tool's own end).
    for state in L:
        assert any(True for e in E if _legal(go, state, e))


def _legal(go, state, event):
    try:
        go(state, event)
        return True
    except states.IllegalTransition:
        return False


def test_grab_transitions():
    G, E = states.Grab, states.GrabEvent
    go = states.grab_next
    assert go(G.WAITING, E.STARTED) == G.DRAGGING
    with pytest.raises(states.IllegalTransition):
        go(G.WAITING, E.MOVED)            # before the pointer moved in the view: nothing
    assert go(G.DRAGGING, E.ITERATED) == G.SETTLING
    assert go(G.SETTLING, E.SETTLED) == G.AT_REST
    assert go(G.SETTLING, E.MOVED) == G.DRAGGING
    assert go(G.DRAGGING, E.FAILED) == G.AT_REST
    assert go(G.AT_REST, E.MOVED) == G.DRAGGING
    with pytest.raises(states.IllegalTransition):
        go(G.AT_REST, E.ITERATED)
