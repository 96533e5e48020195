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
    rc = resolve_sequential(M, H, v, select=False)
    ri = resolve_sequential(M, H, v, select=False, two_surface="iterate")
    assert rc.method == "two-surface closed form" and ri.method == "iteration"
    assert _pairs(rc) == _pairs(ri)
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
    rc = resolve_sequential(M, H, v, select=False)
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


def test_canonical_scenes_take_the_closed_form():
    sc = three_ball_cradle()
    r = resolve_sequential(sc.M, sc.H, sc.v)
    assert r.method == "two-surface closed form" and r.bound == 3
    assert list(r.outcomes[0].velocity) == [0, 0, 1]


def test_parallel_rows_fall_back_to_iteration_and_refusal():
    with pytest.raises(DomainError, match="no non-zero velocity"):
        resolve_sequential("1", "1;-1", "1")
    r = resolve_sequential("1,0;0,1", "1,0;2,0", "-1,0")  # the same surface twice
    assert r.method == "iteration" and list(r.outcomes[0].velocity) == [1, 0]
