"""For two surfaces the resolver takes the O(1) closed form (impactsym.laws.two_surface); it must
agree exactly with the explicit iteration of sec. III-B."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from impactsym.errors import DomainError
from impactsym.laws.sequential import resolve_sequential
from impactsym.models.seghete_murphey import three_ball_cradle, two_balls_wall


def _pairs(r):
    return sorted((tuple(o), tuple(r.outcomes[i].velocity)) for o, i in r.iter_orderings())


@pytest.mark.parametrize("seed", range(40))
def test_closed_form_agrees_with_iteration_exactly(seed):
    rng = np.random.default_rng(1000 + seed)
    n = int(rng.integers(2, 5))
    A = rng.integers(-3, 4, size=(n, n))
    M = sp.Matrix(A.T @ A + 2 * np.eye(n, dtype=int))
    H = sp.Matrix(rng.integers(-4, 5, size=(2, n)))
    v = sp.Matrix(rng.integers(-4, 5, size=n))
    if H.rank() < 2:
        return
    rc = resolve_sequential(M, H, v, select=False, two_surface="closed-form")
    ri = resolve_sequential(M, H, v, select=False, two_surface="iterate")
    ra = resolve_sequential(M, H, v, select=False)  # auto: one of the two, the same answer
    assert rc.method == "two-surface closed form" and ri.method == "iteration"
    assert _pairs(rc) == _pairs(ri) == _pairs(ra) and rc.bound == ri.bound == ra.bound
    assert len(rc.outcomes) == len(ri.outcomes) <= 2
    for a, b in zip(rc.outcomes, ri.outcomes):
        assert a.impulse == b.impulse and a.reflections == b.reflections
    assert max(o.reflections for o in ri.outcomes) <= rc.bound


@pytest.mark.parametrize("seed", range(10))
def test_closed_form_agrees_with_iteration_in_float_mode(seed):
    rng = np.random.default_rng(2000 + seed)
    n = int(rng.integers(2, 5))
    A = rng.standard_normal((n, n))
    M = A.T @ A + n * np.eye(n)
    H = rng.standard_normal((2, n))
    v = rng.standard_normal(n)
    rc = resolve_sequential(M, H, v, select=False, two_surface="closed-form")
    ri = resolve_sequential(M, H, v, select=False, two_surface="iterate")
    assert [o for o, _ in rc.iter_orderings()] == [o for o, _ in ri.iter_orderings()]
    for a, b in zip(rc.outcomes, ri.outcomes):
        assert np.allclose(a.velocity, b.velocity, rtol=1e-10, atol=1e-12)


def test_selection_agrees_between_the_paths():
    sc = two_balls_wall(masses=(sp.Rational(11, 10), 1))
    for reading in ("energy", "cone"):
        a = resolve_sequential(sc.M, sc.H, sc.v, reading=reading)
        b = resolve_sequential(sc.M, sc.H, sc.v, reading=reading, two_surface="iterate")
        assert a.selected == b.selected


def test_canonical_scenes_take_the_closed_form_when_asked_and_auto_iterates_them():
    """The default ``two_surface="auto"`` chooses by the certified bound: the three-ball cradle
    (N = 3) is iterated, with the bound reported as the closed form reports it."""
    sc = three_ball_cradle()
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="closed-form")
    assert r.method == "two-surface closed form" and r.bound == 3
    assert list(r.outcomes[0].velocity) == [0, 0, 1]
    a = resolve_sequential(sc.M, sc.H, sc.v)
    assert a.method == "iteration" and a.bound == 3
    assert [list(o.velocity) for o in a.outcomes] == [[0, 0, 1]] and a.selected == r.selected


@pytest.mark.parametrize("q, method", [(1, "iteration"), (2, "iteration"), (3, "two-surface closed form"),
                                       (1000, "two-surface closed form")])
def test_auto_path_follows_the_certified_bound(q, method):
    """A wedge ``H = [1, 0; -q, 1]``, ``M = I``: ``N = ⌈π/atan(1/q)⌉`` (q = 2: N = 7; q = 3:
    N = 10 > AUTO_ITERATE_MAX_COUNT = 7). Both paths give the same outcomes, counts and selection."""
    import mpmath

    from impactsym.laws.sequential import AUTO_ITERATE_MAX_COUNT

    H, v = f"1,0;-{q},1", f"-1,-{q + 1}"
    with mpmath.workdps(50):
        bound = int(mpmath.ceil(mpmath.pi / mpmath.atan(mpmath.mpf(1) / q)))
    assert (bound <= AUTO_ITERATE_MAX_COUNT) == (method == "iteration")
    a = resolve_sequential("1,0;0,1", H, v)
    c = resolve_sequential("1,0;0,1", H, v, two_surface="closed-form")
    assert a.method == method and a.bound == c.bound == bound
    assert _pairs(a) == _pairs(c) if max(o.reflections for o in c.outcomes) < 200 else True
    assert [(list(o.velocity), o.reflections) for o in a.outcomes] == [(list(o.velocity), o.reflections)
                                                                      for o in c.outcomes]
    assert a.selected == c.selected


def test_parallel_rows_fall_back_to_iteration_and_refusal():
    with pytest.raises(DomainError, match="no non-zero velocity"):
        resolve_sequential("1", "1;-1", "1")
    r = resolve_sequential("1,0;0,1", "1,0;2,0", "-1,0")  # the same surface twice
    assert r.method == "iteration" and list(r.outcomes[0].velocity) == [1, 0]


@pytest.mark.parametrize("seed", range(12))
def test_auto_selection_equals_the_face_enumeration(seed):
    """``two_surface="auto"`` on a short wedge selects by comparing ``⟨o, v0⟩_M`` of the two
    outcomes; the forced iteration runs the general face enumeration: the same selection."""
    rng = np.random.default_rng(3000 + seed)
    n = int(rng.integers(2, 4))
    A = rng.integers(-2, 3, size=(n, n))
    M = sp.Matrix(A.T @ A + 2 * np.eye(n, dtype=int))
    H = sp.Matrix(rng.integers(-3, 4, size=(2, n)))
    v = sp.Matrix(rng.integers(-3, 4, size=n))
    if H.rank() < 2:
        return
    a = resolve_sequential(M, H, v)
    if a.method != "iteration":  # a long wedge: the closed form, compared elsewhere
        return
    b = resolve_sequential(M, H, v, two_surface="iterate")
    assert set(map(tuple, a.selected)) == set(map(tuple, b.selected))
