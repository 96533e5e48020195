"""``impactsym.compliant._dop853`` is SciPy's ``solve_ivp(..., method="DOP853")`` step for step.

The compliant and LZB laws integrate with ``_dop853``, which repeats SciPy's DOP853 arithmetic
without the Python around it. Its promise is bit-identity: the same accepted steps, states, event
roots and evaluation counts as ``solve_ivp``. These tests hold it to that, on a plain ODE with
terminal and non-terminal events and on whole runs of both laws, where every returned number is
compared byte for byte with a run that integrates through ``solve_ivp`` itself.
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.integrate import DOP853, solve_ivp

import impactsym.compliant as compliant
import impactsym.lzb as lzb
from impactsym.compliant import _dop853, chain_impact, compliant_impact
from impactsym.lzb import lzb_chain


def _via_solve_ivp(fun, t0, t_bound, y0, rtol, atol, events, keep_states=True, into=False, values=None,
                   stage=None, turns=(), crossings=(), first_step=None):
    # SciPy calls fun(t, y) and copies what it returns: `into` (write into the stage table) does not apply;
    # nor do `values` (the events' values in one call: SciPy calls the events themselves) and `stage`;
    # nor `turns` (a crossing there and back inside one step, which SciPy does not see: the scenes below
    # have none, and where one is found the bytes differ, as they should); nor `crossings` (steps ended
    # at a non-integer exponent's crossings: the fast runs below are made with that switched off)
    # (`first_step`, capped at the span as _dop853 caps it, is solve_ivp's own option; the step size the
    # controller would try next, which the compliant law starts its next window with, is read off the
    # solver solve_ivp made)
    made = []

    class Recorded(DOP853):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            made.append(self)

    first = None if first_step is None else min(float(first_step), float(t_bound) - float(t0))
    sol = solve_ivp(fun, (t0, t_bound), y0, method=Recorded, rtol=rtol, atol=atol, events=events, first_step=first)
    run = compliant._Run()
    run.h_abs = float(made[0].h_abs)
    run.t, run.y, run.steps, run.y_last = sol.t, sol.y, len(sol.t) - 1, sol.y[:, -1]
    prev = max(len(sol.t) - 2, 0)  # the last step's start
    run.t_prev, run.y_prev = sol.t[prev], sol.y[:, prev]
    run.t_events, run.y_events, run.status, run.message, run.nfev = (sol.t_events, sol.y_events, sol.status,
                                                                     sol.message, sol.nfev)
    return run


def _same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def test_dop853_repeats_solve_ivp_bit_for_bit_with_events():
    # a damped Duffing oscillator: a non-terminal event (each upward zero of x) and a terminal one
    # (the energy falls below a level); plus a run that ends at the end of its span
    def fun(_t, y):
        return np.array([y[1], -y[0] - 0.3 * y[0] ** 3 - 0.05 * y[1]])

    def up(_t, y):
        return y[0]

    up.direction = 1

    def low(_t, y):
        return 0.5 * y[1] ** 2 + 0.5 * y[0] ** 2 - 0.05

    low.terminal = True
    low.direction = -1
    atol = np.array([1e-12, 1e-12])
    for t_bound, events, status in ((100.0, [up, low], 1), (7.5, [up], 0)):
        ref = solve_ivp(fun, (0.0, t_bound), np.array([1.0, 0.0]), method="DOP853", rtol=1e-10, atol=atol,
                        events=events)
        run = _dop853(fun, 0.0, t_bound, np.array([1.0, 0.0]), 1e-10, atol, events)
        assert run.status == ref.status == status and run.nfev == ref.nfev and run.steps == len(ref.t) - 1
        assert _same(run.t, ref.t) and _same(run.y, ref.y) and _same(run.y_last, ref.y[:, -1])
        assert run.t_prev == ref.t[-2] and _same(run.y_prev, ref.y[:, -2])  # the last step's start
        assert len(ref.t_events[0]) >= 1
        for te, tr, ye, yr in zip(run.t_events, ref.t_events, run.y_events, ref.y_events):
            assert _same(te, tr) and _same(ye, yr)
    assert len(ref.t_events[0]) == 1 and len(run.t_events[0]) == 1
    first = _dop853(fun, 0.0, 100.0, np.array([1.0, 0.0]), 1e-10, atol, [up, low])
    assert len(first.t_events[0]) == 8 and len(first.t_events[1]) == 1  # 8 upward zeros, then the energy stop


M_EXTREME = [0.02973812642706829, 40.84152907608479, 0.01862294907359638, 97.19613777916885,
             0.0023785239862465124, 89.72777123474523]
K_EXTREME = [0.04550185120183626, 0.3166561928765105, 0.18490670781039542, 5.825700330709063, 0.051794961274602765]

RUNS = {
    "hertz-chain": lambda: chain_impact(M_EXTREME[:3], [1, 0, 0], K_EXTREME[:2]),
    "linear-gaps": lambda: compliant_impact(np.diag([1.0, 2.0, 1.5]), [[-1, 1, 0], [0, -1, 1]], [1.0, 0.2, -0.5],
                                            [1.0, 3.0], 1, gaps=[0.0, 0.01]),
    "damped": lambda: chain_impact([1, 2, 3], [1, 0, -1], 1.0, damping=0.3),
    "hunt-crossley": lambda: chain_impact([1, 2, 3], [1, 0, -1], 1.0, hunt_crossley=0.3),
    "rest": lambda: chain_impact([1], [1], 1.0, [0.3, 0.3], walls=("left", "right"), model="linear", rest_tol=3e-2),
    "lzb-elastic": lambda: lzb_chain(M_EXTREME[:3], [1, 0, 0], K_EXTREME[:2]),
    "lzb-restitution": lambda: lzb_chain([1, 2, 3], [1, 0, -1], 1.0, restitution=[0.7, 0.9], track_time=True),
}


@pytest.mark.parametrize("name", sorted(RUNS))
def test_both_laws_return_the_same_bytes_as_through_solve_ivp(name, monkeypatch):
    # no step ended at a crossing (the hertz chain's contacts, exponent 1.5, have them): SciPy's steps
    monkeypatch.setattr(compliant, "_cut_at_crossing", lambda *args: None)
    fast = RUNS[name]()
    monkeypatch.setattr(compliant, "_dop853", _via_solve_ivp)
    monkeypatch.setattr(lzb, "_dop853", _via_solve_ivp)
    ref = RUNS[name]()
    for f in dataclasses.fields(fast):
        a, b = getattr(fast, f.name), getattr(ref, f.name)
        if isinstance(a, (np.ndarray, float)):
            assert _same(a, b), f.name
        elif f.name != "certificate":
            assert a == b, f.name
    assert fast.steps > 0 and fast.nfev > 12 * fast.steps
    if name == "rest":
        assert fast.outcome == "rest"  # the rest event ended it


def test_dop853_fails_where_solve_ivp_fails():
    # y' = y², y(0) = 1 blows up at t = 1: the step size underflows before, at the same step
    def fun(_t, y):
        return y * y

    atol = np.array([1e-12])
    ref = solve_ivp(fun, (0.0, 2.0), np.array([1.0]), method="DOP853", rtol=1e-10, atol=atol)
    run = _dop853(fun, 0.0, 2.0, np.array([1.0]), 1e-10, atol, [])
    assert ref.status == run.status == -1 and run.message == ref.message and run.nfev == ref.nfev
    assert _same(run.t, ref.t) and _same(run.y, ref.y) and abs(run.t[-1] - 1) < 1e-6 and run.y[0, -1] > 1e12


def test_dop853_finds_a_crossing_there_and_back_inside_one_step_only_with_turns():
    # x = −sin t: the event x − 0.9999 rises through 0 and falls back within ±0.014 of t = 3π/2, far
    # inside one step at rtol = 1e-6 (steps of ~1); SciPy (and the driver without turns) never sees it
    def fun(_t, y):
        return np.array([y[1], -y[0]])

    def peak(_t, y):
        return y[0] - 0.9999

    peak.terminal = True
    peak.direction = 1
    atol = np.array([1e-9, 1e-9])
    y0 = np.array([0.0, -1.0])
    ref = solve_ivp(fun, (0.0, 6.0), y0, method="DOP853", rtol=1e-6, atol=atol, events=[peak])
    i = np.searchsorted(ref.t, 1.5 * np.pi)
    assert ref.status == 0 and len(ref.t_events[0]) == 0 and ref.t[i] - ref.t[i - 1] > 0.5
    assert peak(0, ref.y[:, i - 1]) < 0 and peak(0, ref.y[:, i]) < 0
    plain = _dop853(fun, 0.0, 6.0, y0, 1e-6, atol, [peak])
    assert plain.status == 0 and _same(plain.y, ref.y)
    run = _dop853(fun, 0.0, 6.0, y0, 1e-6, atol, [peak], turns=[(0, lambda f: float(f[0]))])
    assert run.status == 1 and len(run.t_events[0]) == 1
    t_root = run.t_events[0][0]
    # the first crossing, on the way up (to the dense output's accuracy over a step of ~1: the
    # crossing is grazing, x' = 0.014 there, so 1e-6 in x is 7e-5 in t)
    assert 1.5 * np.pi - 0.0143 < t_root < 1.5 * np.pi - 0.014 and abs(-np.sin(t_root) - 0.9999) < 2e-6
    assert abs(run.y_last[0] - 0.9999) < 1e-12 and run.y_last[1] > 0
    # the slope given as a component of the state derivative (f[0]: every turn read in one pass,
    # _excursions' columns) finds the same root, bit for bit
    col = _dop853(fun, 0.0, 6.0, y0, 1e-6, atol, [peak], turns=[(0, 0)])
    assert col.status == 1 and _same(col.t_events[0], run.t_events[0]) and _same(col.y_last, run.y_last)
    # a turn whose extremum stays short of 0 is no crossing: the event x − 1.0001 is never reached
    def beyond(_t, y):
        return y[0] - 1.0001

    beyond.terminal = True
    beyond.direction = 1
    run = _dop853(fun, 0.0, 6.0, y0, 1e-6, atol, [beyond], turns=[(0, lambda f: float(f[0]))])
    assert run.status == 0 and len(run.t_events[0]) == 0 and _same(run.y_last, ref.y[:, -1])
    col = _dop853(fun, 0.0, 6.0, y0, 1e-6, atol, [beyond], turns=[(0, 0)])
    assert col.status == 0 and len(col.t_events[0]) == 0 and _same(col.y_last, ref.y[:, -1])


def _between_two_walls(p):
    # a unit mass between two walls 1 apart, each a force K δ^p with K = 1: the state (g1, g2, v), the
    # gaps to the left and the right wall; it starts touching the left one at speed 1
    def fun(_t, y):
        return np.array([y[2], -y[2], max(-y[0], 0.0) ** p - max(-y[1], 0.0) ** p])

    return fun, np.array([0.0, 1.0, -1.0])


def test_dop853_ends_a_step_at_every_armed_crossing():
    """With ``crossings`` no accepted step has an armed gap's crossing inside it: every opening and
    closing after the first contact is a step boundary, where the gap is exactly 0. Without them
    (SciPy's steps) the steps cross the points where the force ``δ^1.5`` starts and stops."""
    fun, y0 = _between_two_walls(1.5)
    atol = np.full(3, 1e-14)
    # each contact lasts 2 δ_m B(1/2.5, 1/2) / 2.5 = 3.218 (δ_m = 1.25^0.4), each flight 1: over
    # [0, 16.4] four openings (at 3.218, 7.436, 11.654, 15.872) and three closings, ending in a flight
    plain = _dop853(fun, 0.0, 16.4, y0, 1e-11, atol, [])
    cut = _dop853(fun, 0.0, 16.4, y0, 1e-11, atol, [], crossings=[(0, 1e-14), (1, 1e-14)])
    for run in (plain, cut):
        assert run.status == 0 and abs(abs(run.y_last[2]) - 1) < 1e-9  # the speed is 1 in every flight
    g = cut.y[:2]
    across = (g[:, 1:] * g[:, :-1]) < 0  # a gap of opposite strict signs at a step's two ends
    assert not across.any() and np.count_nonzero(g[:, 1:] == 0.0) == 7
    assert np.count_nonzero(plain.y[:2, 1:] * plain.y[:2, :-1] < 0) == 7
    # the finer runs' steps are counted, and the run still ends where it should
    assert cut.steps > plain.steps and cut.t[-1] == 16.4


def test_dop853_a_terminal_event_before_a_crossing_in_the_same_step_ends_the_run_there():
    """The step taken again to a crossing's root carries the events: a terminal event whose root lies
    in that step before the crossing ends the run at its own root (not at the crossing's, and not
    missed because the step was cut)."""
    fun, y0 = _between_two_walls(1.5)
    atol = np.full(3, 1e-14)
    cut = _dop853(fun, 0.0, 16.4, y0, 1e-11, atol, [], crossings=[(0, 1e-14), (1, 1e-14)])
    t_open = next(t for t, g in zip(cut.t, cut.y[0]) if t > 0 and g == 0.0)  # the first opening
    i = int(np.searchsorted(cut.t, t_open))
    # a time just before that opening, inside the step that crossed it in a run without crossings
    plain = _dop853(fun, 0.0, 16.4, y0, 1e-11, atol, [])
    j = int(np.searchsorted(plain.t, t_open))
    t_ev = t_open - 1e-3 * (t_open - plain.t[j - 1])
    assert cut.t[i - 1] < t_ev < t_open and plain.t[j - 1] < t_ev < plain.t[j]

    def clock(t, _y):
        return t - t_ev

    clock.terminal = True
    clock.direction = 1
    run = _dop853(fun, 0.0, 16.4, y0, 1e-11, atol, [clock], crossings=[(0, 1e-14), (1, 1e-14)])
    assert run.status == 1 and len(run.t_events[0]) == 1 and abs(run.t_events[0][0] - t_ev) < 1e-12
    assert run.t[-1] == run.t_events[0][0] and run.y_last[0] < 0  # still compressed there


def test_dop853_ends_a_step_where_a_gated_linear_function_crosses_0():
    """A crossing ``(row, floor, gate)`` ends a step where ``row · y`` crosses 0 while the gap
    ``y[gate]`` is closed: a ball against a wall with eq. 20's damping, ``f = max(K δ^1.5 + C δ^0.5
    δ̇, 0)``, whose force stops where ``φ = K δ + C δ̇ = −K g − C v`` falls through 0, before the gap
    opens. With the crossing an accepted state sits on that root (and the gap is still closed
    there); without it the root lies inside a step."""
    K, C = 1.0, 0.5

    def fun(_t, y):
        d, dd = max(-y[0], 0.0), -y[1]
        return np.array([y[1], max(K * d**1.5 + C * d**0.5 * dd, 0.0) if d > 0 else 0.0])

    y0, atol = np.array([0.0, -1.0]), np.full(2, 1e-14)
    phi = np.array([-K, -C])
    plain = _dop853(fun, 0.0, 5.0, y0, 1e-11, atol, [])
    cut = _dop853(fun, 0.0, 5.0, y0, 1e-11, atol, [], crossings=[(0, 1e-14), (phi, 1e-14, 0)])
    for run, on_root in ((cut, True), (plain, False)):
        values = phi @ run.y
        closed = run.y[0] < 0
        falls = np.flatnonzero((values[:-1] > 0) & (values[1:] <= 0) & closed[1:])
        assert len(falls) == 1  # φ falls through 0 once while the gap is closed
        i = falls[0]
        # on the root: the state there (either end of the step) is 0 to the integration's error (the
        # root is placed on the step's dense output, the state is the finer run's: 1.8e-12 measured)
        assert (min(abs(values[i]), abs(values[i + 1])) < 1e-9) == on_root, (values[i:i + 2], on_root)
    assert cut.y[1, -1] > 0 and abs(cut.y[1, -1] - plain.y[1, -1]) < 1e-8  # it leaves the wall, slower
