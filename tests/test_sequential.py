"""The sequential resolver (Seghete & Murphey sec. III-B): branching, exactness, refusals, float mode."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from impactsym.errors import DomainError, ImpactInputError, NonTermination
from impactsym.laws.reflection import reflection_map
from impactsym.laws.sequential import (
    READINGS,
    resolve_sequential,
    termination_bound,
    valid_velocity_witness,
)
from impactsym.mechanics import kinetic_energy
from impactsym.models.seghete_murphey import cradle, three_ball_cradle, two_balls_wall

R = sp.Rational


def _G(M, H, order):
    P = sp.eye(M.shape[0])
    for i in order:
        P = reflection_map(M, H[i, :]) * P
    return P


def test_every_outcome_is_the_product_of_its_reflections():
    sc = two_balls_wall(masses=(R(11, 10), 1), velocities=(-1, -3))
    r = resolve_sequential(sc.M, sc.H, sc.v)
    for order, idx in r.iter_orderings():
        assert _G(sc.M, sc.H, order) * sc.v == r.outcomes[idx].velocity
    assert sum(o.orderings for o in r.outcomes) == r.orderings == len(list(r.iter_orderings()))


def test_branching_rule_every_violated_surface_opens_a_branch():
    # 3 surfaces, all violated at v0: every first surface appears
    M, H = sp.eye(3), sp.Matrix([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    r = resolve_sequential(M, H, sp.Matrix([-1, -2, -3]))
    orders = sorted(o for o, _ in r.iter_orderings())
    assert len(orders) == 6 and {o[0] for o in orders} == {0, 1, 2}
    assert [list(o.velocity) for o in r.outcomes] == [[1, 2, 3]]


def test_valid_velocity_gives_no_reflection():
    r = resolve_sequential("1,0;0,1", "1,0;-1,1", "1,2")
    assert r.outcomes[0].order == () and list(r.outcomes[0].velocity) == [1, 2]
    assert r.approaching == (False, False)


def test_grazing_contact_does_not_branch():
    r = resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-1")  # ball-ball relative velocity 0
    assert [o for o, _ in r.iter_orderings()] == [(0, 1, 0)]
    assert r.approaching == (True, False)


def test_impulses_are_nonnegative_and_give_the_momentum_jump():
    sc = cradle(5, 2, masses=[1, 2, 3, 2, 1])
    r = resolve_sequential(sc.M, sc.H, sc.v)
    for o in r.outcomes:
        assert all(p >= 0 for p in o.impulse)
        assert sc.M * (o.velocity - sc.v) == sc.H.T * o.impulse
        assert kinetic_energy(sc.M, o.velocity) == kinetic_energy(sc.M, sc.v)
        assert all(w >= 0 for w in sc.H * o.velocity)


def test_memoized_dag_counts_orderings_without_enumerating_them():
    sc = cradle(8, 4)
    r = resolve_sequential(sc.M, sc.H, sc.v)
    # the strikers' velocities are sorted by adjacent swaps: states = C(8, 4) permutations
    assert r.states_visited == 70
    # orderings = standard Young tableaux of the 4x4 rectangle (hook length formula)
    assert r.orderings == 24024
    assert [list(o.velocity) for o in r.outcomes] == [[0, 0, 0, 0, 1, 1, 1, 1]]


def test_refusal_when_no_nonzero_velocity_is_valid():
    with pytest.raises(DomainError, match="no non-zero velocity"):
        resolve_sequential("1", "1;-1", "1")
    with pytest.raises(DomainError, match="gradients"):
        resolve_sequential("1,0;0,1", "1,0;0,1;-1,-1", "-1,-1")
    assert valid_velocity_witness("1,0;0,1;-1,-1") is None
    w = valid_velocity_witness("1,0;0,1;-1,1")
    assert w is not None and any(w) and all(x >= 0 for x in sp.Matrix([[1, 0], [0, 1], [-1, 1]]) * w)


def test_refusal_is_decided_exactly_in_float_mode_too():
    with pytest.raises(DomainError, match="no non-zero velocity"):
        resolve_sequential(np.array([[1.0]]), np.array([[1.0], [-1.0]]), np.array([1.0]))
    # 1e-300 keeps the cone open: decided on the exact binary value, not on rounding
    r = resolve_sequential(np.eye(2), np.array([[1.0, 0.0], [-1.0, 1e-300]]), np.array([-1.0, 0.0]), select=False)
    assert r.witness is not None


def test_cycle_is_reported_as_nontermination():
    # a ball between two walls (x) on a floor (y): it bounces between the walls for ever
    with pytest.raises(NonTermination, match="max_reflections"):
        resolve_sequential("1,0;0,1", "1,0;-1,0;0,1", "1,-1")


def test_reflection_cap_names_the_cap():
    # narrow wedge: the valid lune has angle ~0.0997, the paper's bound is 32
    H = sp.Matrix([[0, 1], [-1, -10]])
    v0 = sp.Matrix([11, -1])
    r = resolve_sequential(sp.eye(2), H, v0, two_surface="iterate")
    need = r.max_reflections_used
    assert need > 3
    with pytest.raises(NonTermination, match=f"max_reflections={need - 1}"):
        resolve_sequential(sp.eye(2), H, v0, max_reflections=need - 1, two_surface="iterate")
    assert resolve_sequential(sp.eye(2), H, v0, max_reflections=need, two_surface="iterate").max_reflections_used == need
    # the closed form iterates nothing: the cap does not apply
    assert resolve_sequential(sp.eye(2), H, v0, max_reflections=1).max_reflections_used == need


@pytest.mark.parametrize("kw, arg", [({"reading": "sphere"}, "reading"), ({"max_reflections": 0}, "max_reflections"),
                                      ({"max_reflections": 2.5}, "max_reflections")])
def test_bad_options(kw, arg):
    with pytest.raises(ImpactInputError, match=arg):
        resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2", **kw)


def test_bad_shapes_are_refused():
    with pytest.raises(ImpactInputError, match="gradients"):
        resolve_sequential("1,0;0,1", "1,0,0", "-1,-2")
    with pytest.raises(ImpactInputError, match="velocity"):
        resolve_sequential("1,0;0,1", "1,0", "-1,-2,3")
    with pytest.raises(ImpactInputError, match="mass_matrix"):
        resolve_sequential("1,2;2,1", "1,0", "-1,-2")


def test_algebraic_entries_use_certified_signs():
    # contact normals at 60 degrees: sqrt(3) in the rows
    h = sp.sqrt(3) / 2
    H = sp.Matrix([[1, 0], [-R(1, 2), h]])
    v0 = sp.Matrix([-1, -1])
    r = resolve_sequential(sp.eye(2), H, v0)
    assert r.backend == "algebraic"
    for o in r.outcomes:
        assert sp.simplify(kinetic_energy(sp.eye(2), o.velocity) - 1) == 0
        assert all(sp.simplify(w).is_nonnegative for w in H * o.velocity)
    # same problem in rational form (rows scaled by 2/sqrt(3) do not change G): compare counts
    assert r.orderings == len(list(r.iter_orderings()))


def test_termination_bound_of_the_paper_examples():
    assert termination_bound("1,0;0,1", "1,0;-1,1") == 4
    assert termination_bound("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1") == 3
    with pytest.raises(ImpactInputError, match="two surfaces"):
        termination_bound("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1;1,0,0")


# ------------------------------------------------------------------ float mode
def test_float_mode_matches_exact_and_counts_fallbacks():
    sc = three_ball_cradle()
    rf = resolve_sequential(np.eye(3), np.array(sc.H, dtype=float), np.array([1.0, 0, 0]), two_surface="iterate")
    assert not rf.exact and rf.backend == "float" and rf.exact_fallbacks > 0
    assert rf.outcomes[0].velocity.tolist() == [0.0, 0.0, 1.0]
    re = resolve_sequential(sc.M, sc.H, sc.v)
    assert re.exact_fallbacks == 0 and re.exact


def test_float_mode_decides_a_near_grazing_sign_exactly():
    # v0 grazes contact 2 up to one ulp: the float bound straddles zero, the exact binary value decides
    eps = 2.0**-52
    for v2, expect_branches in ((1.0 + eps, 2), (1.0, 1), (1.0 - eps, 1)):
        r = resolve_sequential(np.eye(2), np.array([[1.0, 0.0], [-1.0, 1.0]]), np.array([-1.0, -v2]),
                               two_surface="iterate")
        first = {o[0] for o, _ in r.iter_orderings()}
        assert len(first) == expect_branches, v2
        assert r.exact_fallbacks >= 1
        rx = resolve_sequential(np.eye(2), np.array([[1.0, 0.0], [-1.0, 1.0]]), np.array([-1.0, -v2]), exact=True,
                                two_surface="iterate")
        assert {o[0] for o, _ in rx.iter_orderings()} == first


@pytest.mark.parametrize("seed", range(12))
def test_float_mode_agrees_with_exact_on_random_cases(seed):
    rng = np.random.default_rng(seed)
    n, k = int(rng.integers(2, 4)), int(rng.integers(2, 4))
    A = rng.integers(-3, 4, size=(n, n))
    Mq = sp.Matrix(A.T @ A + np.eye(n, dtype=int) * 2)
    Hq = sp.Matrix(rng.integers(-3, 4, size=(k, n)))
    if any(all(x == 0 for x in Hq[i, :]) for i in range(k)):
        return
    vq = sp.Matrix(rng.integers(-3, 4, size=n))
    try:
        re = resolve_sequential(Mq, Hq, vq, max_reflections=200, select=False)
    except (DomainError, NonTermination):
        return
    rf = resolve_sequential(np.array(Mq, dtype=float), np.array(Hq, dtype=float), np.array(vq, dtype=float),
                            max_reflections=200, select=False)
    assert sorted(o for o, _ in re.iter_orderings()) == sorted(o for o, _ in rf.iter_orderings())
    assert len(re.outcomes) == len(rf.outcomes)
    for a, b in zip(re.outcomes, rf.outcomes):
        assert np.allclose(np.array(a.velocity, dtype=float).ravel(), b.velocity, rtol=1e-9, atol=1e-9)


def test_readings_listed():
    assert READINGS == ("energy", "cone")
