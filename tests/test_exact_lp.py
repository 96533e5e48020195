"""The exact simplex (impactsym.arithmetic.exact_lp): optima certified by a dual point and equal to an
independent exact optimum on every ordering LP of the line scenes (HiGHS's float solution rounded to
an exact primal vertex and an exact dual point, both checked here; SymPy's linprog where the rounding
gives no certificate), exact on random small LPs (checked against brute-force vertex enumeration),
and the same realizability verdict as realize_ordering."""

from __future__ import annotations

import itertools
import random
from fractions import Fraction as F

import numpy as np
import pytest
import sympy as sp
from flint import fmpq, fmpq_mat

from impactsym.arithmetic.exact_lp import maximize
from impactsym.laws.sequential import resolve_sequential
from impactsym.scenes import balls_on_line
from impactsym.simulate import _ordering_lp, ordering_realizable, realize_ordering


def _fr(x) -> F:
    """A Fraction of an exact rational (int, Fraction, SymPy Rational, flint fmpq)."""
    if isinstance(x, (int, F)):
        return F(x)
    return F(int(x.p), int(x.q))


def _fmpq_mat(rows):
    return fmpq_mat([[fmpq(v.numerator, v.denominator) for v in r] for r in rows])


def _vertex_optimum(c, A_ub, b_ub, A_eq, b_eq):
    """max c.x over the polytope by enumerating its vertices (exact, flint fmpq_mat; for bounded
    feasible LPs): every choice of n tight constraints among A_ub, A_eq, x >= 0 with a unique solution
    that is feasible."""
    n = len(c)
    rows = [(r, b) for r, b in zip(A_ub, b_ub)] + [(r, b) for r, b in zip(A_eq, b_eq)]
    rows += [([F(int(i == j)) for j in range(n)], F(0)) for i in range(n)]
    best = None
    for pick in itertools.combinations(range(len(rows)), n):
        A = _fmpq_mat([rows[i][0] for i in pick])
        if A.det() == 0:
            continue
        sol = A.solve(_fmpq_mat([[rows[i][1]] for i in pick]))
        x = [_fr(sol[i, 0]) for i in range(n)]
        ok = all(v >= 0 for v in x) and all(sum(a * v for a, v in zip(r, x)) <= b for r, b in zip(A_ub, b_ub))
        ok = ok and all(sum(a * v for a, v in zip(r, x)) == b for r, b in zip(A_eq, b_eq))
        if ok:
            val = sum(a * v for a, v in zip(c, x))
            best = val if best is None else max(best, val)
    return best


def _unique_solution(rows, rhs, nvar):
    """The exact solution of ``rows · x = rhs`` when it is unique (full column rank and consistent),
    else None (flint: the normal equations, then the system itself checked)."""
    if not rows:
        return [] if nvar == 0 else None
    A, b = _fmpq_mat(rows), _fmpq_mat([[v] for v in rhs])
    At = A.transpose()
    try:
        x = (At * A).solve(At * b)
    except ZeroDivisionError:  # singular: not a unique solution
        return None
    if A * x != b:
        return None
    return [_fr(x[i, 0]) for i in range(nvar)]


def _highs_exact_optimum(c, A_ub, b_ub, A_eq, b_eq, tol=1e-9):
    """max c.x s.t. A_ub x <= b_ub, A_eq x = b_eq, x >= 0, exactly, independently of exact_lp: HiGHS
    (SciPy's float LP solver) picks the optimal vertex and the dual's support, the tight systems are
    solved exactly, and the exact primal and dual points are checked here (feasible, equal objectives:
    the optimum by weak duality). None when the rounding gives no such certificate."""
    from scipy.optimize import linprog as highs

    n, m1, m2 = len(c), len(A_ub), len(A_eq)
    fl = lambda rows: np.array([[float(v) for v in r] for r in rows]).reshape(len(rows), n)  # noqa: E731
    Aub, Aeq, cf = fl(A_ub), fl(A_eq), np.array([float(v) for v in c])
    res = highs(-cf, Aub if m1 else None, [float(v) for v in b_ub] if m1 else None, Aeq if m2 else None,
                [float(v) for v in b_eq] if m2 else None, method="highs")
    if res.status != 0:
        return None
    tight_ub = [i for i in range(m1) if abs(float(b_ub[i]) - Aub[i] @ res.x) <= tol]
    at_zero = [j for j in range(n) if abs(res.x[j]) <= tol]
    x = _unique_solution([A_ub[i] for i in tight_ub] + list(A_eq) + [[F(int(i == j)) for j in range(n)] for i in at_zero],
                         [b_ub[i] for i in tight_ub] + list(b_eq) + [F(0)] * len(at_zero), n)
    # the dual of the max problem: y_ub = -(HiGHS's ub marginals) >= 0, y_eq = -(eq marginals)
    yf = -res.ineqlin.marginals if m1 else np.zeros(0)
    zf = -res.eqlin.marginals if m2 else np.zeros(0)
    supp = [i for i in range(m1) if abs(yf[i]) > tol]
    reduced = (Aub.T @ yf if m1 else 0) + (Aeq.T @ zf if m2 else 0) - cf
    tight = [j for j in range(n) if abs(reduced[j]) <= tol]
    dual = _unique_solution([[A_ub[i][j] for i in supp] + [A_eq[i][j] for i in range(m2)] for j in tight],
                            [c[j] for j in tight], len(supp) + m2)
    if x is None or dual is None:
        return None
    y = [F(0)] * m1
    for i, v in zip(supp, dual):
        y[i] = v
    z = dual[len(supp):]
    ok = all(v >= 0 for v in x) and all(v >= 0 for v in y)
    ok = ok and all(sum(a * v for a, v in zip(r, x)) <= b for r, b in zip(A_ub, b_ub))
    ok = ok and all(sum(a * v for a, v in zip(r, x)) == b for r, b in zip(A_eq, b_eq))
    ok = ok and all(sum(A_ub[i][j] * y[i] for i in range(m1)) + sum(A_eq[i][j] * z[i] for i in range(m2)) >= c[j]
                    for j in range(n))
    value = sum(a * v for a, v in zip(c, x))
    ok = ok and sum(a * v for a, v in zip(b_ub, y)) + sum(a * v for a, v in zip(b_eq, z)) == value
    return value if ok else None


def _sympy_optimum(c, A_ub, b_ub, A_eq, b_eq):
    """max c.x by SymPy's exact linprog (the fallback reference)."""
    from sympy.solvers.simplex import linprog

    val, _z = linprog(sp.Matrix([[-v for v in c]]), sp.Matrix(A_ub), sp.Matrix(b_ub),
                      sp.Matrix(A_eq) if A_eq else None, sp.Matrix(b_eq) if b_eq else None)
    return -_fr(val)


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
def test_ordering_lps_agree_with_an_independent_exact_optimum(masses, velocities):
    """Every ordering of three balls against a wall: the exact simplex's optimum equals the optimum
    found without it (HiGHS rounded to a certificate checked here, or SymPy's linprog), and
    ordering_realizable agrees with realize_ordering."""
    sc = balls_on_line(masses, [1, 1, 1], [1, 3, 5], velocities, walls=[0])
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate", select=False)
    seen = set()
    for order, _ in r.iter_orderings(12):
        _, c, A_ub, b_ub, A_eq, b_eq = _ordering_lp(sc.M, sc.H, sc.v, order)
        lp = ([-_fr(x) for x in c], [[_fr(x) for x in row] for row in A_ub], [_fr(x) for x in b_ub],
              [[_fr(x) for x in row] for row in A_eq], [_fr(x) for x in b_eq])
        ref = _highs_exact_optimum(*lp)
        if ref is None:
            ref = _sympy_optimum(*lp)
        assert maximize([-x for x in c], A_ub, b_ub, A_eq, b_eq).value == ref
        ok = ordering_realizable(sc.M, sc.H, sc.v, order)
        assert ok == (realize_ordering(sc.M, sc.H, sc.v, order) is not None)
        seen.add(ok)
    assert seen == {True, False} or masses != [1, 3, 4]


def test_the_references_agree_with_sympy_linprog():
    """The two references of the ordering test agree where both answer (the LP of
    ordering_realizable's docstring, and a random bounded one), and vertex enumeration agrees."""
    sc_M, sc_H, v0 = sp.eye(2), sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-1, -2])
    for order in ([1, 0, 1, 0], [1, 1]):
        _, c, A_ub, b_ub, A_eq, b_eq = _ordering_lp(sc_M, sc_H, v0, order)
        lp = ([-_fr(x) for x in c], [[_fr(x) for x in row] for row in A_ub], [_fr(x) for x in b_ub],
              [[_fr(x) for x in row] for row in A_eq], [_fr(x) for x in b_eq])
        assert _highs_exact_optimum(*lp) == _sympy_optimum(*lp)
    lp = ([F(3, 2), F(-1), F(2)], [[F(1), F(2), F(-1)], [F(1), F(1), F(1)]], [F(3), F(4)], [[F(1), F(-1), F(0)]], [F(0)])
    assert _highs_exact_optimum(*lp) == _sympy_optimum(*lp) == _vertex_optimum(*lp) == 8
