"""The small-gap simulator agrees with every ordering the sequential resolver reports, exactly."""

from __future__ import annotations

import pytest
import sympy as sp

from impactsym.errors import DomainError, ImpactInputError
from impactsym.laws.sequential import resolve_sequential
from impactsym.models.seghete_murphey import balls_against_wall, cradle, three_ball_cradle, two_balls_wall
from impactsym.scenes import balls_on_line, full_velocity
from impactsym.simulate import perturbed_scene_positions, realize_ordering, simulate_line

R = sp.Rational

SCENES = [
    ("two-balls-wall equal", lambda: two_balls_wall()),
    ("two-balls-wall 1.1:1", lambda: two_balls_wall(masses=(R(11, 10), 1))),
    ("two-balls-wall 1.1:1 (-1,-10)", lambda: two_balls_wall(masses=(R(11, 10), 1), velocities=(-1, -10))),
    ("two-balls-wall 1.1:1 3-4 sector", lambda: two_balls_wall(masses=(R(11, 10), 1), velocities=(-20, -21))),
    ("three-ball cradle [1,0,0]", lambda: three_ball_cradle()),
    ("three-ball cradle [1,1,0]", lambda: three_ball_cradle(velocities=(1, 1, 0))),
    ("three-ball cradle [1,0,-1]", lambda: three_ball_cradle(velocities=(1, 0, -1))),
    ("three-ball cradle masses 1,2,3", lambda: three_ball_cradle(velocities=(2, 0, -1), masses=(1, 2, 3))),
    ("cradle 4 balls 2 strikers", lambda: cradle(4, 2)),
    ("cradle 5 balls 2 strikers", lambda: cradle(5, 2)),
    ("cradle 4 balls unequal", lambda: cradle(4, 1, masses=[2, 1, 3, 1])),
    ("balls against wall 3", lambda: balls_against_wall(3)),
    ("balls against wall 3 unequal", lambda: balls_against_wall(3, masses=[3, 2, 1], velocities=[0, -1, -2]),
     [(0, 1, 0, 2, 0, 1, 2), (0, 1, 2, 0, 1, 2)]),
]


def _check_scene(sc, limit=None, unrealizable=()):
    """Every realizable ordering is simulated and must agree exactly; the orderings no gaps realize
    must be exactly ``unrealizable``, and every outcome must be reached by a realizable ordering."""
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate", select=False)
    n_checked = 0
    missing = []
    reached = set()
    for order, idx in r.iter_orderings(limit):
        gaps = realize_ordering(sc.M, sc.H, sc.v, order)
        if gaps is None:
            missing.append(order)
            continue
        reached.add(idx)
        assert all(g > 0 for g in gaps)
        pos = perturbed_scene_positions(sc, gaps)
        meta = sc.meta
        sim = simulate_line(meta["masses"], meta["radii"], pos, list(meta["all_velocities"]), meta["walls"])
        assert [name for _, name in sim.events] == [sc.contacts[i] for i in order]
        assert sim.velocities == full_velocity(sc, r.outcomes[idx].velocity)
        n_checked += 1
    assert missing == list(unrealizable)
    if limit is None:
        assert reached == set(range(len(r.outcomes)))
    return n_checked


@pytest.mark.parametrize("case", SCENES, ids=[s[0] for s in SCENES])
def test_simulator_realizes_every_ordering(case):
    """Finding (k >= 3): the branching rule of sec. III-B also produces orderings that no gaps
    realize (balls against a wall, masses 3:2:1: 2 of 10 orderings; 3000 random gap draws never
    produce them either); their outcomes are reached by realizable orderings too."""
    name, build, *unrealizable = case
    assert _check_scene(build(), unrealizable=unrealizable[0] if unrealizable else ()) >= 1


def test_branching_rule_can_produce_outcomes_no_small_gaps_give():
    """Finding: for three surfaces the rule of sec. III-B ("every violated surface opens a branch")
    over-generates. Masses 1, 3, 4 against a wall, v0 = (-1, -3, 0): 15 orderings, 5 distinct
    outcomes, but the exact LP realizes only orderings ending at (1/7, 5/7, 18/7), and so do gap
    draws over several scales (a random sweep of 524 line scenes found 37 such scenes)."""
    sc = balls_on_line([1, 3, 4], [1, 1, 1], [1, 3, 5], [-1, -3, 0], walls=[0])
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate", select=False)
    assert r.orderings == 15 and len(r.outcomes) == 5
    realized = {idx for order, idx in r.iter_orderings() if realize_ordering(sc.M, sc.H, sc.v, order) is not None}
    assert [list(r.outcomes[i].velocity) for i in realized] == [[R(1, 7), R(5, 7), R(18, 7)]]
    for gaps in ([1, 2, 3], [3, 2, 1], [1, 1000, 7], [500, 1, 3], [2, 5, 1000]):
        pos = perturbed_scene_positions(sc, [R(g, 10**9) for g in gaps])
        sim = simulate_line(sc.meta["masses"], sc.meta["radii"], pos, list(sc.meta["all_velocities"]), [0])
        assert sim.velocities == [R(1, 7), R(5, 7), R(18, 7)]


def test_uninvolved_ball_keeps_its_velocity_in_simulation():
    sc = balls_on_line([1, 1, 1, 1], [1, 1, 1, 1], [0, 2, 4, 100], [1, 0, 0, 5])
    assert _check_scene(sc) == 1


@pytest.mark.slow
def test_simulator_on_larger_cradles():
    """6 balls struck by 3: 42 orderings, one outcome; 6 of the orderings are realized by no small
    gaps (exact LP), the sec. III-B over-generation again, and every outcome is still reached."""
    unrealizable = [(2, 1, 3, 2, 4, 0, 1, 3, 2), (2, 1, 3, 4, 0, 2, 1, 3, 2), (2, 1, 3, 4, 2, 0, 1, 3, 2),
                    (2, 3, 1, 0, 2, 4, 3, 1, 2), (2, 3, 1, 0, 4, 2, 3, 1, 2), (2, 3, 1, 2, 0, 4, 3, 1, 2)]
    assert _check_scene(cradle(6, 3), unrealizable=unrealizable) == 42 - len(unrealizable)
    assert _check_scene(cradle(5, 1)) >= 1


def test_simultaneous_collision_is_refused():
    with pytest.raises(DomainError, match="same instant"):
        simulate_line([1, 1, 1], [1, 1, 1], [0, "21/10", "42/10"], [1, 0, -1])


def test_float_and_overlap_input_refused():
    with pytest.raises(ImpactInputError, match="exact"):
        simulate_line([1.0, 1.0], [1, 1], [0, 3], [1, 0])
    with pytest.raises(ImpactInputError, match="overlap"):
        simulate_line([1, 1], [1, 1], [0, 1], [1, 0])


def test_simulator_conserves_momentum_and_energy():
    m = [1, 2, R(1, 3)]
    res = simulate_line(m, [1, 1, 1], [0, "2001/1000", "4003/1000"], [3, 0, -1])
    e0 = sum(mi * vi**2 for mi, vi in zip(m, [3, 0, -1]))
    assert sum(mi * vi**2 for mi, vi in zip(m, res.velocities)) == e0
    assert sum(mi * vi for mi, vi in zip(m, res.velocities)) == sum(mi * vi for mi, vi in zip(m, [3, 0, -1]))
    assert len(res.events) >= 2
    # a ball between two walls bounces for ever: the event cap refuses it
    with pytest.raises(DomainError, match="max_events"):
        simulate_line([1], [1], [0], [1], walls=[-2, 2], max_events=50)


# --------------------------------------------------------------------------- restitution (Newton's law)
def test_pair_restitution_by_hand():
    """m = (2, 3), v = (5, -1), e = 1/3: w = -6, mu = 6/5, P = (4/3)(6)(6/5) = 48/5, so
    v' = (5 - 48/10, -1 + 48/15) = (1/5, 11/5); w' = 2 = -e w; momentum 7 kept; loss (1-e^2)/2 mu w^2."""
    res = simulate_line([2, 3], [1, 1], [0, 2], [5, -1], restitution="1/3")
    assert res.velocities == [R(1, 5), R(11, 5)]
    assert res.events == [(0, "1-2")]
    assert res.impulses == {"1-2": R(48, 5)}
    assert res.energy_loss == R(8, 9) / 2 * R(6, 5) * 36


def test_wall_restitution_and_per_contact_mapping():
    res = simulate_line([3], [1], [2], [-3], walls=[0], restitution="2/5")
    assert res.velocities == [R(6, 5)] and res.impulses == {"wall@0-1": R(63, 5)}
    # per contact: only the wall contact is inelastic, the pair stays elastic
    res = simulate_line([1, 1], [1, 1], [1, 3], [0, -2], walls=[0], restitution={"wall@0-1": "1/2"})
    # 1-2 at t=0: (0,-2) -> (-2, 0); wall at t=0: -2 -> 1; then 1-2 again: (1, 0) -> (0, 1)
    assert res.events == [(0, "1-2"), (0, "wall@0-1"), (0, "1-2")]
    assert res.velocities == [0, 1]
    assert res.energy_loss == R(3, 2)


@pytest.mark.parametrize("e", [R(1, 2), R(7, 10), 1])
def test_restitution_agrees_with_the_reflection_map(e):
    """The simulator's first-principles Newton law equals G_u(e) (impactsym.laws.reflection),
    collision by collision, on a 3-ball line with a wall (unequal masses, exact)."""
    from impactsym.laws.reflection import reflect

    m, pos, v0 = [2, 1, 3], [1, "31/10", "27/5"], [0, -1, -3]
    res = simulate_line(m, [1, 1, 1], pos, v0, walls=[0], restitution=e)
    assert len(res.events) >= 3
    rows = {"wall@0-1": [1, 0, 0], "1-2": [-1, 1, 0], "2-3": [0, -1, 1]}
    v = sp.Matrix(v0)
    p = {}
    for _, name in res.events:
        u = sp.Matrix([rows[name]])
        new = reflect(sp.diag(*m), u, v, e)
        j = rows[name].index(1)  # M (v' - v) = u^T p: read p on the ball whose row entry is +1
        p[name] = p.get(name, 0) + m[j] * (new[j] - v[j])
        v = new
    assert res.impulses == p
    assert res.velocities == list(v)
    # kinetic energy: initial minus the reported loss, exactly
    ke = lambda vel: R(1, 2) * sum(mi * vi**2 for mi, vi in zip(m, vel))  # noqa: E731
    assert ke(res.velocities) == ke(v0) - res.energy_loss
    assert (res.energy_loss == 0) == (e == 1)


def test_restitution_bad_input():
    with pytest.raises(ImpactInputError, match=r"restitution: must satisfy 0 <= e <= 1, got 3/2"):
        simulate_line([1, 1], [1, 1], [0, 3], [1, 0], restitution="3/2")
    with pytest.raises(ImpactInputError, match="restitution"):
        simulate_line([1, 1], [1, 1], [0, 3], [1, 0], restitution=-1)
    with pytest.raises(ImpactInputError, match="exact"):
        simulate_line([1, 1], [1, 1], [0, 3], [1, 0], restitution=0.5)
    with pytest.raises(ImpactInputError, match="rational"):
        simulate_line([1, 1], [1, 1], [0, 3], [1, 0], restitution="sqrt(2)/2")
    with pytest.raises(ImpactInputError, match=r"restitution: names no contact of this line: '1-3'"):
        simulate_line([1, 1, 1], [1, 1, 1], [0, 3, 6], [1, 0, 0], restitution={"1-3": "1/2"})
    with pytest.raises(ImpactInputError, match=r"restitution\['1-2'\]: must satisfy"):
        simulate_line([1, 1, 1], [1, 1, 1], [0, 3, 6], [1, 0, 0], restitution={"1-2": 2})
    with pytest.raises(ImpactInputError, match="max_events"):
        simulate_line([1, 1], [1, 1], [0, 3], [1, 0], max_events=0)


def test_inelastic_collapse_is_refused_not_capped():
    """Three equal balls, e = 1/20 (below 7 - 4 sqrt 3): the middle ball rattles between the outer
    two with ever shorter intervals. The run is refused at the cap and says why; with e = 1/10 the
    same start ends after finitely many collisions."""
    start = ([1, 1, 1], [1, 1, 1], [0, "21/10", "42/10"], [1, 0, "-1/2"])
    with pytest.raises(DomainError, match="max_events: inelastic collapse: 300 collisions and the collision times converge"):
        simulate_line(*start, restitution="1/20", max_events=300)
    res = simulate_line(*start, restitution="1/10")
    assert 3 <= len(res.events) < 300
    assert sum(res.velocities) == R(1, 2)
    # sticking (e = 0) with three balls: infinitely many collisions at one instant (t = 0)
    with pytest.raises(DomainError, match=r"inelastic collapse.*the last at t = 0\)"):
        simulate_line([1, 1, 1], [1, 1, 1], [0, 2, 4], [0, 0, -1], restitution=0, max_events=200)
    # a ball between two walls, e = 1/2: never ends, but the times spread out: not a collapse
    with pytest.raises(DomainError, match="max_events: more than 60 collisions .*do not converge"):
        simulate_line([1], [1], [0], [1], walls=[-2, 2], restitution="1/2", max_events=60)


def test_two_sticking_balls_move_together():
    res = simulate_line([1, 3], [1, 1], [0, 3], [2, 0], restitution=0)
    assert res.velocities == [R(1, 2), R(1, 2)] and res.events == [(R(1, 2), "1-2")]


# --------------------------------------------------------------------------- same instant, t = 0
def test_independent_impacts_at_one_instant_are_resolved():
    res = simulate_line([1, 1, 1, 1], [1, 1, 1, 1], [0, "21/10", 10, "121/10"], [0, -1, 1, 0])
    assert res.events == [(R(1, 10), "1-2"), (R(1, 10), "3-4")]
    assert res.velocities == [-1, 0, 0, 1]
    # a wall and a pair that share no ball, at one instant
    res = simulate_line([1, 1, 1], [1, 1, 1], [2, 10, 13], [-1, 1, 0], walls=[0], restitution={"wall@0-1": 0})
    assert res.events == [(1, "2-3"), (1, "wall@0-1")]
    assert res.velocities == [0, 0, 1]


def test_touching_and_approaching_at_t0():
    """Cradle of four touching balls struck from both ends: 1-2 and 3-4 touch and approach at t = 0
    (independent), then 2-3, then 1-2 and 3-4 again, all at t = 0."""
    res = simulate_line([1, 1, 1, 1], [1, 1, 1, 1], [0, 2, 4, 6], [1, 0, 0, -1])
    assert res.events == [(0, "1-2"), (0, "3-4"), (0, "2-3"), (0, "1-2"), (0, "3-4")]
    assert res.velocities == [-1, 0, 0, 1] and res.time == 0
    # three touching balls struck from both ends: 1-2 and 2-3 share ball 2 at t = 0
    with pytest.raises(DomainError, match=r"1-2, 2-3 close at the same instant t = 0 \(touching and approaching at "
                                          r"t = 0\) and share ball 2"):
        simulate_line([1, 1, 1], [1, 1, 1], [0, 2, 4], [1, 0, -1])
    # touching and approaching, with an open gap elsewhere: resolved first, then the rest
    res = simulate_line([1, 1, 1], [1, 1, 1], [0, 2, "41/10"], [1, 0, 0])
    assert res.events == [(0, "1-2"), (R(1, 10), "2-3")] and res.velocities == [0, 0, 1]


def test_only_the_named_contacts_collide_and_the_others_must_stay_open():
    res = simulate_line([1, 1, 1], [1, 1, 1], [0, "21/10", 10], [1, 0, 0], contacts=["1-2"])
    assert res.events == [(R(1, 10), "1-2")] and res.velocities == [0, 1, 0]  # 2-3 closes later: not simulated
    with pytest.raises(DomainError, match=r"contact 2-3, which is not simulated, closes at t = 1/20, before"):
        simulate_line([1, 1, 1], [1, 1, 1], [0, "21/10", "42/10"], [1, 0, -2], contacts=["1-2"])
    with pytest.raises(ImpactInputError, match=r"contacts: names no contact of this line: '1-3'"):
        simulate_line([1, 1, 1], [1, 1, 1], [0, 3, 6], [1, 0, 0], contacts=["1-3"])


def test_fmpq_simplex_is_sympys_linprog_pivot_for_pivot():
    """realize_ordering's simplex in fmpq returns SymPy's linprog vertex and value exactly: on the
    ordering LPs of a scene (phase 2 only) and on random LPs whose right-hand sides have negative
    entries (phase 1, infeasible ones included)."""
    import random

    from sympy.solvers.simplex import InfeasibleLPError, linprog  # the sum row bounds every LP here

    from impactsym.simulate import _linprog_fmpq, _linprog_sympy, _ordering_lp

    sc = balls_against_wall(3, masses=[3, 2, 1], velocities=[0, -1, -2])
    margins = []
    for order in [(0, 1, 2, 0, 1, 2), (0, 1, 2, 0, 2, 1)]:  # margin 0 and 2/25
        _, c, A_ub, b_ub, A_eq, b_eq = _ordering_lp(sp.Matrix(sc.M), sp.Matrix(sc.H), sp.Matrix(sc.v), order)
        got, want = _linprog_fmpq(c, A_ub, b_ub, A_eq, b_eq), _linprog_sympy(c, A_ub, b_ub, A_eq, b_eq)
        assert got == (want[0], list(want[1])) and [type(x) for x in got[1]] == [type(x) for x in want[1]]
        margins.append(-got[0])
    assert margins == [0, R(2, 25)]
    rng = random.Random(7)
    seen = set()
    for _ in range(40):
        n, m = rng.randint(2, 4), rng.randint(2, 5)
        c = [R(rng.randint(-4, 4), rng.randint(1, 3)) for _ in range(n)]
        A_ub = [[R(rng.randint(-4, 4), rng.randint(1, 3)) for _ in range(n)] for _ in range(m)] + [[1] * n]
        b_ub = [R(rng.randint(-3, 4), rng.randint(1, 2)) for _ in range(m)] + [5]
        A_ub = [[sp.sympify(x) for x in row] for row in A_ub]
        b_ub = [sp.sympify(x) for x in b_ub]
        A_eq, b_eq = ([], [])
        if rng.random() < 0.5:
            A_eq, b_eq = [[R(rng.randint(-2, 2)) for _ in range(n)]], [R(rng.randint(-1, 1))]
        try:
            want = linprog(sp.Matrix([c]), sp.Matrix(A_ub), sp.Matrix(b_ub),
                           sp.Matrix(A_eq) if A_eq else None, sp.Matrix(b_eq) if b_eq else None)
        except InfeasibleLPError:
            want = None
        got = _linprog_fmpq(c, A_ub, b_ub, A_eq, b_eq)
        assert got == (None if want is None else (want[0], list(want[1])))
        assert want is None or [type(x) for x in got[1]] == [type(x) for x in want[1]]  # int 0 off the basis
        seen.add(want is None)
        seen.add(("phase 1", any(b < 0 for b in b_ub + b_eq)))
    assert seen >= {True, False, ("phase 1", True)}  # both verdicts and the phase-1 path were exercised
