"""The exact simplex (impactsym.arithmetic.exact_lp): optima certified by a dual point and equal to
SymPy's linprog on every ordering LP of the line scenes, exact on random small LPs (checked against
brute-force vertex enumeration), and the same realizability verdict as realize_ordering."""

from __future__ import annotations

import itertools
import random
from fractions import Fraction as F

import pytest
import sympy as sp

from impactsym.arithmetic.exact_lp import maximize
from impactsym.laws.sequential import resolve_sequential
from impactsym.scenes import balls_on_line
from impactsym.simulate import _ordering_lp, ordering_realizable, realize_ordering


def _vertex_optimum(c, A_ub, b_ub, A_eq, b_eq):
    """max c.x over the polytope by enumerating its vertices (exact; for bounded feasible LPs): every
    choice of n tight constraints among A_ub, A_eq, x >= 0 with a unique solution that is feasible."""
    n = len(c)
    rows = [(r, b) for r, b in zip(A_ub, b_ub)] + [(r, b) for r, b in zip(A_eq, b_eq)]
    rows += [([F(int(i == j)) for j in range(n)], F(0)) for i in range(n)]
    best = None
    for pick in itertools.combinations(range(len(rows)), n):
        A = sp.Matrix([rows[i][0] for i in pick])
        if A.det() == 0:
            continue
        x = list(A.solve(sp.Matrix([rows[i][1] for i in pick])))
        ok = all(v >= 0 for v in x) and all(sum(a * v for a, v in zip(r, x)) <= b for r, b in zip(A_ub, b_ub))
        ok = ok and all(sum(a * v for a, v in zip(r, x)) == b for r, b in zip(A_eq, b_eq))
        if ok:
            val = sum(a * v for a, v in zip(c, x))
            best = val if best is None else max(best, val)
    return best


def test_random_bounded_lps_match_vertex_enumeration_and_carry_a_dual_certificate():
    rng = random.Random(7)
    checked = 0
    for _ in range(120):
        n = rng.randint(1, 3)
        A_ub = [[F(rng.randint(-4, 4), rng.randint(1, 3)) for _ in range(n)] for _ in range(rng.randint(0, 3))]
        b_ub = [F(rng.randint(-3, 5)) for _ in A_ub]
        A_ub.append([F(1)] * n)  # x >= 0 and sum x <= B: bounded
        b_ub.append(F(rng.randint(0, 4)))
        A_eq = [[F(rng.randint(-3, 3)) for _ in range(n)] for _ in range(rng.randint(0, 1))]
        b_eq = [F(rng.randint(-2, 2)) for _ in A_eq]
        c = [F(rng.randint(-5, 5), rng.randint(1, 2)) for _ in range(n)]
        r = maximize(c, A_ub, b_ub, A_eq, b_eq)
        ref = _vertex_optimum(c, A_ub, b_ub, A_eq, b_eq)
        if ref is None:
            assert r.status == "infeasible"
            continue
        assert r.status == "optimal" and r.value == ref
        assert all(y >= 0 for y in r.y_ub)
        assert sum(b * y for b, y in zip(b_ub, r.y_ub)) + sum(b * y for b, y in zip(b_eq, r.y_eq)) == r.value
        checked += 1
    assert checked > 60


def test_status_unbounded_and_infeasible_and_bad_entries():
    assert maximize([1, 1], [[1, -1]], [1]).status == "unbounded"
    assert maximize([1], [[1]], [1], [[1]], [2]).status == "infeasible"
    with pytest.raises(TypeError, match="exact rationals"):
        maximize([0.5], [[1]], [1])


@pytest.mark.parametrize("masses, velocities", [([1, 3, 4], [-1, -3, 0]), ([3, 2, 1], [-1, -3, 0]),
                                                 ([2, 5, 1], [-2, -1, -3])])
def test_ordering_lps_agree_with_sympy_linprog(masses, velocities):
    """Every ordering of three balls against a wall: the exact simplex's optimum equals SymPy's, and
    ordering_realizable agrees with realize_ordering."""
    from sympy.solvers.simplex import linprog

    sc = balls_on_line(masses, [1, 1, 1], [1, 3, 5], velocities, walls=[0])
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate", select=False)
    seen = set()
    for order, _ in r.iter_orderings(12):
        _, c, A_ub, b_ub, A_eq, b_eq = _ordering_lp(sc.M, sc.H, sc.v, order)
        val, _z = linprog(sp.Matrix([c]), sp.Matrix(A_ub), sp.Matrix(b_ub),
                          sp.Matrix(A_eq) if A_eq else None, sp.Matrix(b_eq) if b_eq else None)
        assert maximize([-x for x in c], A_ub, b_ub, A_eq, b_eq).value == -val
        ok = ordering_realizable(sc.M, sc.H, sc.v, order)
        assert ok == (realize_ordering(sc.M, sc.H, sc.v, order) is not None)
        seen.add(ok)
    assert seen == {True, False} or masses != [1, 3, 4]

