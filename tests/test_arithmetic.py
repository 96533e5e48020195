"""The exact-arithmetic layer (impactsym.arithmetic): its linear algebra agrees with SymPy's exact
``Matrix.rref`` on rational, algebraic and transcendental data, and its certified helpers decide
what they claim."""

from __future__ import annotations

import random

import pytest
import sympy as sp
from flint import arb, ctx, fmpq

from impactsym.arithmetic import (AlgebraicField, RationalField, certified_ceiling, exact_rank, field_of,
                                  in_row_space, nullspace, rank, rref, sign_surd, solve_columns)


def _rows(A: sp.Matrix, F):
    return [[F.num(x) for x in A.row(i)] for i in range(A.rows)]


def _sympy(rows, F, ncols):
    return sp.Matrix(len(rows), ncols, [F.to_sympy(x) for r in rows for x in r])


def _random_rational(rng, r, c, rank_at_most):
    B = sp.Matrix(r, rank_at_most, lambda i, j: sp.Rational(rng.randint(-5, 5), rng.randint(1, 4)))
    C = sp.Matrix(rank_at_most, c, lambda i, j: sp.Rational(rng.randint(-5, 5), rng.randint(1, 4)))
    return B * C


@pytest.mark.parametrize("seed", range(12))
def test_rational_rref_equals_sympy(seed):
    rng = random.Random(seed)
    A = _random_rational(rng, rng.randint(1, 5), rng.randint(1, 5), rng.randint(1, 3))
    R, piv = rref(_rows(A, RationalField), A.cols, RationalField)
    Rs, pivs = A.rref()
    assert list(piv) == list(pivs)
    assert _sympy(R, RationalField, A.cols) == Rs[:len(pivs), :]
    assert rank(_rows(A, RationalField), RationalField) == A.rank() == exact_rank(A)
    for x in nullspace(_rows(A, RationalField), A.cols, RationalField):
        assert A * sp.Matrix([RationalField.to_sympy(t) for t in x]) == sp.zeros(A.rows, 1)


def test_algebraic_rref_equals_sympy():
    s2, s3 = sp.sqrt(2), sp.sqrt(3)
    A = sp.Matrix([[s2, 1, s3], [2, s2, s2 * s3], [1, 0, s3 - 1]])
    assert field_of(A) is AlgebraicField
    R, piv = rref(_rows(A, AlgebraicField), 3, AlgebraicField)
    Rs, pivs = A.rref(simplify=True)
    assert list(piv) == list(pivs) == [0, 1]   # row 2 is sqrt(2) times row 1
    assert all(sp.simplify(a - b) == 0 for a, b in zip(_sympy(R, AlgebraicField, 3), Rs[:2, :]))


def test_transcendental_entries_use_the_certified_elimination():
    """No number field holds pi: the zero tests are certified signs, and 1/pi - 1/pi is decided 0."""
    A = [[sp.pi, 1], [1, 1 / sp.pi]]
    assert rank(A, AlgebraicField) == 1
    assert rank([[sp.pi, 1], [1, sp.E]], AlgebraicField) == 2
    sol = solve_columns([[sp.pi, 1], [1, sp.E]], [sp.pi + 1, 1 + sp.E], AlgebraicField)
    assert sol is not None and not sol[1]
    assert all(sp.simplify(z - 1) == 0 for z in sol[0])


def test_solve_and_row_space_decide_inconsistency():
    Q = RationalField
    one, two = Q.num(1), Q.num(2)
    assert solve_columns([[one, one]], [one, two], Q) is None          # x (1, 1) = (1, 2): no x
    z0, basis = solve_columns([[one, one], [two, two]], [one, one], Q)  # a (1,1) + b (2,2) = (1,1)
    assert len(basis) == 1 and z0[0] + 2 * z0[1] == 1
    assert in_row_space([[one, Q.num(0)], [Q.num(0), one]], [Q.num(3), Q.num(-7)], Q)
    assert not in_row_space([[one, one]], [one, Q.num(0)], Q)


def test_sign_surd_decides_near_ties_exactly():
    # 665857/470832 - sqrt(2) > 0 by about 1.6e-12; 470832/332929 - sqrt(2) < 0
    assert sign_surd(fmpq(665857, 470832), -1, 2) == 1
    assert sign_surd(fmpq(470832, 332929), -1, 2) == -1
    assert sign_surd(fmpq(-3), 1, 9) == 0
    with pytest.raises(ValueError, match="non-negative"):
        sign_surd(1, 1, -2)


def test_certified_ceiling_refines_and_ties():
    calls = []

    def ball_at(prec):  # 10 - 2^-200: its ceiling is 10, which 64 bits cannot see
        calls.append(prec)
        with ctx.workprec(prec):
            return arb(10) - arb(2) ** -200

    assert certified_ceiling(ball_at, lambda j: False) == (10, "arb", 256)
    assert calls == [64, 128, 256]
    assert certified_ceiling(lambda prec: arb(7), lambda j: j == 7) == (7, "exact_tie", 64)
    assert certified_ceiling(lambda prec: arb(7), lambda j: None, max_bits=256) is None


def _quadratic_surds(rng, count):
    """``r + q·√D`` built as the laws build ``p₁ = (−B + √D)/(2A)``: rationals of 1 to 8 digits."""
    def rat(digits):
        return sp.Rational(rng.randint(-10**digits, 10**digits), rng.randint(1, 10**rng.randint(1, 8)))
    out = [sp.sqrt(2), -sp.sqrt(3) / 7, 1 + sp.sqrt(5), sp.Rational(-3, 4) - sp.sqrt(10**20 + 7) / 9]
    while len(out) < count:
        r, q = rat(rng.randint(1, 8)), rat(rng.randint(1, 8))
        D = sp.Rational(rng.randint(1, 10**rng.randint(1, 12)), rng.randint(1, 10**rng.randint(1, 8)))
        x = (r if rng.random() < 0.8 else 0) + (q if rng.random() < 0.8 else 1) * sp.sqrt(D)
        if not x.is_Rational:
            out.append(x)
    return out


def test_tidy_keeps_a_quadratic_surd_as_the_generic_route_would():
    """``tidy`` returns ``r + q√n`` as it is without the generic route; the generic route (expand,
    sqrtdenest, radsimp, simplify, rational guess) gives the same expression, argument for argument
    (and so does ``radsimp``, which :meth:`AlgebraicField.norm` skips for them)."""
    from impactsym.arithmetic import closed_form

    for x in _quadratic_surds(random.Random(15), 40):
        assert closed_form._quadratic_surd(x), x
        assert closed_form._tidy(x) is x
        assert sp.srepr(closed_form._tidy_generic(x)) == sp.srepr(x), x
        # and AlgebraicField.norm, which skips radsimp for them, is radsimp's answer
        assert sp.srepr(sp.radsimp(x)) == sp.srepr(x) == sp.srepr(AlgebraicField.norm(x)), x
    # what the fast path must not take: sums of two surds, nested roots, symbols, other radicals
    for x in (sp.sqrt(2) + sp.sqrt(3), sp.sqrt(2 + sp.sqrt(3)), sp.sqrt(sp.Symbol("a")), sp.cbrt(2),
              1 + sp.sqrt(2) + sp.sqrt(3), sp.sqrt(2) * sp.sqrt(sp.Rational(1, 3) + sp.sqrt(2))):
        assert not closed_form._quadratic_surd(x), x


def _surd_sums(rng, count):
    """Sums of a rational and 2 to 6 rational multiples of square roots of square-free integers, in
    the forms the laws build them (a product by a surd, a common denominator, content factored)."""
    out = [sp.sqrt(3) * (sp.sqrt(2) + 3 * sp.sqrt(6)) / 34, -sp.sqrt(2) / 2 + (sp.sqrt(2) + sp.sqrt(6)) / 8,
           sp.sqrt(3) * (-sp.sqrt(6) + 5 * sp.sqrt(2)) / 34, sp.sqrt(2) + sp.sqrt(3)]
    while len(out) < count:
        big = rng.random() < 0.3
        terms = [sp.Rational(rng.randint(-10**6, 10**6) if big else rng.randint(-40, 40) or 1,
                             rng.randint(1, 10**6 if big else 60)) * sp.sqrt(n)
                 for n in rng.sample([2, 3, 5, 6, 7, 10, 11, 13, 14, 15, 21, 30, 105], rng.randint(2, 6))]
        if rng.random() < 0.6:
            terms.append(sp.Rational(rng.randint(-40, 40), rng.randint(1, 60)))
        y = sp.Add(*terms)
        out.append([y, sp.radsimp(y), sp.together(y), sp.factor_terms(y)][rng.randint(0, 3)])
    return out


def test_tidy_takes_a_sum_of_surds_as_the_generic_route_would():
    """``tidy`` of a number whose expansion is ``Σ qᵢ√nᵢ + r`` is ``radsimp`` of that expansion,
    without the generic route; the generic route (expand, sqrtdenest, radsimp, simplify, rational
    guess) gives the same expression, argument for argument."""
    from impactsym.arithmetic import closed_form

    for x in _surd_sums(random.Random(16), 12):
        assert closed_form._surd_sum(sp.expand(x)), x
        assert sp.srepr(closed_form._tidy(x)) == sp.srepr(closed_form._tidy_generic(x)), x
    # what the fast path must not take: nested roots, symbols, other radicals, rationals
    for x in (sp.sqrt(2 + sp.sqrt(3)) + sp.sqrt(2), sp.sqrt(sp.Symbol("a")) + sp.sqrt(2), sp.cbrt(2) + sp.sqrt(2),
              sp.sqrt(-2) + sp.sqrt(3), sp.pi + sp.sqrt(2), sp.Rational(1, 3)):
        assert not closed_form._surd_sum(sp.expand(x)), x
