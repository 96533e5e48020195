"""The flint-backed replacements of SymPy's slow paths (issue 15, ``impactsym reproduce`` speed):
``cancel`` returns SymPy's own normal form term for term, ``is_zero_algebraic`` proves identities
over Q(√q, i) with cos/sin and √P generators and never calls a non-identity zero, the flint
Bareiss determinant agrees with SymPy's, and the exact rational momentum solve of
``paper_checks.framework.conservation`` agrees with ``sympy.solve``."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from derivations.memo import simplify
from derivations.rational_zero import cancel, factored_numerator, is_zero, is_zero_algebraic
from derivations.reflection import _bareiss_det_plus_is_zero, symbolic_covector, symbolic_mass_matrix
from paper_checks.framework import _rational_unique_solution
from random_expressions import random_rational



@pytest.mark.parametrize("seed", range(16))
def test_cancel_is_sympys_normal_form_term_for_term(seed):
    rng = random.Random(seed)
    syms = sp.symbols("x y z")
    f = random_rational(rng, syms) + random_rational(rng, syms)
    assert sp.srepr(cancel(f)) == sp.srepr(sp.cancel(f))


def test_cancel_of_the_3x3_reflection_entries():
    M, u = symbolic_mass_matrix(3), symbolic_covector(3)
    qm = sp.Matrix(sp.symbols("qm_0:3", real=True))
    w = M.inv() * u.T
    for x in (qm - 2 * (u * qm)[0, 0] * w / (u * w)[0, 0]):
        assert sp.srepr(cancel(x)) == sp.srepr(sp.cancel(x))


def test_algebraic_zero_test_proves_identities_and_declines_perturbations():
    x, y, t = sp.symbols("x y t", real=True)
    r = sp.sqrt(x**2 + y * sp.cos(t) + 3)
    identities = [
        (sp.sqrt(3) * x + 1) * (sp.sqrt(3) * x - 1) - 3 * x**2 + 1,
        sp.cos(t) ** 2 + sp.sin(t) ** 2 - 1,
        (sp.cos(t) + sp.I * sp.sin(t)) * (sp.cos(t) - sp.I * sp.sin(t)) - 1,
        (1 + r) ** 2 - 1 - 2 * r - r**2,
        1 / (sp.sqrt(2) + 1) - sp.sqrt(2) + 1,
    ]
    for e in identities:
        assert is_zero_algebraic(e) is True, e
        assert is_zero_algebraic(e + sp.Rational(1, 10**30)) is None, e  # never a false zero
        assert is_zero_algebraic(e + x * sp.sin(t) / 97) is None, e
        assert is_zero(e) is True


def test_algebraic_zero_test_uses_the_relations_between_square_roots():
    """Square roots of rationals are products of prime roots (√6 = √2·√3, √(2/3) = √6/3) and a
    root of an expression is split off its rational content (√(10 + 10√2) = √2·√5·√(1 + √2)):
    the identities of Q(√2, √3) and the pool's nested radicals are proved, perturbations are not."""
    x = sp.Symbol("x", real=True)
    s = sp.sqrt
    identities = [
        s(6) - s(2) * s(3),
        (s(2) + s(3)) ** 2 - 5 - 2 * s(6),
        s(6) * x / 3 - s(sp.Rational(2, 3)) * x,
        1 / s(6) - s(6) / 6,
        s(10 + 10 * s(2)) - s(2) * s(5 + 5 * s(2)),
        s(x**2 + 1) * s(2 * x**2 + 2) - s(2) * (x**2 + 1),
        s(sp.Integer(2) ** 101 * 15) - 2**50 * s(30),
    ]
    for e in identities:
        assert is_zero_algebraic(e) is True, e
        assert is_zero_algebraic(e + sp.Rational(1, 10**30)) is None, e
        assert is_zero_algebraic(e + s(6) / 10**30) is None, e
    assert is_zero_algebraic(s(6) - s(2)) is None and is_zero_algebraic(s(3) ** 3 - 9 * s(3)) is None


@pytest.mark.parametrize("expr", ["sqrt(x**2) - x", "sqrt(sqrt(x) + 1)", "exp(x) - 1", "cos(x + y) - 1"])
def test_algebraic_zero_test_declines_what_it_does_not_handle(expr):
    assert is_zero_algebraic(sp.sympify(expr)) is None


def test_is_zero_matches_simplify_on_non_rational_input():
    x = sp.Symbol("x", positive=True)
    assert is_zero(sp.sqrt(x**2) - x) is True  # decided by SymPy's simplify (assumptions)
    assert is_zero(x**2 - x) is False  # a non-zero rational function, decided by flint


def test_factored_numerator_has_the_roots_and_refuses_a_lambda_denominator():
    lam, a, b = sp.symbols("lambda a b")
    expr = lam * (lam * a - b) / (a**2 + 1)
    assert set(sp.solve(factored_numerator(expr, free_of=[lam]), lam)) == {0, b / a}
    with pytest.raises(ValueError, match="involves lambda"):
        factored_numerator(1 / lam + a, free_of=[lam])


@pytest.mark.parametrize("n", [1, 2, 3])
def test_flint_bareiss_determinant_agrees_with_sympy(n):
    M = symbolic_mass_matrix(n)
    assert _bareiss_det_plus_is_zero(M, -M.det(method="bareiss"))
    assert not _bareiss_det_plus_is_zero(M, -M.det(method="bareiss") + M[0, 0])
    P = sp.Matrix(n, n, lambda i, j: 1 if i + j == n - 1 else 0)  # zero pivots: row swaps
    assert _bareiss_det_plus_is_zero(P, -P.det())


@pytest.mark.parametrize("seed", range(8))
def test_rational_momentum_solve_agrees_with_sympy_solve(seed):
    rng = random.Random(seed)
    n, k = rng.randint(2, 4), rng.randint(1, 3)
    A = sp.Matrix(n, k, lambda i, j: sp.Rational(rng.randint(-4, 4), rng.randint(1, 3)))
    x = sp.Matrix(k, 1, lambda i, j: sp.Rational(rng.randint(-4, 4), rng.randint(1, 3)))
    b = A * x if rng.random() < 0.7 else A * x + sp.Matrix(n, 1, lambda i, j: sp.Rational(1, 7) if i == 0 else 0)
    p = sp.symbols(f"p0:{k}")
    sol = sp.solve(list(A * sp.Matrix(p) - b), p, dict=True)
    mine = _rational_unique_solution(A, b)
    if mine is None:  # rank-deficient: left to sympy.solve
        assert A.rank() < k
    elif mine is False:
        assert sol == []
    else:
        assert len(sol) == 1 and [sol[0][s] for s in p] == mine


def test_memoized_simplify_is_simplify():
    x = sp.Symbol("x")
    e = (x**2 - 1) / (x - 1)
    assert simplify(e) == sp.simplify(e) and simplify(e) is simplify(e)
    M = sp.Matrix([[e]])  # unhashable: simplified directly
    assert simplify(M) == sp.Matrix([[x + 1]])


def test_nonzero_at_a_point_never_claims_an_identity_and_respects_assumptions():
    """nonzero_at_a_point is a proof of 'not identically zero': it is never True for an identity
    (including ones that hold only under the symbols' assumptions), True for perturbations, and
    undecided where its point would leave the symbols' domain."""
    x, y = sp.symbols("x y", positive=True)
    t = sp.Symbol("t", real=True)
    from derivations.rational_zero import nonzero_at_a_point

    identities = [sp.sqrt(x**2) - x, sp.cos(t) ** 2 + sp.sin(t) ** 2 - 1, sp.log(x * y) - sp.log(x) - sp.log(y),
                  (x**2 - y**2) / (x - y) - x - y, sp.Abs(x) - x, sp.exp(sp.log(x)) - x]
    for e in identities:
        assert nonzero_at_a_point(e) is False, e
        assert nonzero_at_a_point(e + sp.Rational(1, 10**25)) is True, e
        assert is_zero(e) is True
    n = sp.Symbol("n", integer=True)
    assert nonzero_at_a_point(sp.sin(sp.pi * n)) is False  # would need a non-integer n: undecided
    assert nonzero_at_a_point(1 / (x - sp.Rational(2, 3))) is False  # undefined at its point
    rng = random.Random(3)
    syms = sp.symbols("a b c", positive=True)
    for _ in range(30):
        f = random_rational(rng, list(syms))
        if nonzero_at_a_point(f):
            assert sp.cancel(f) != 0  # f is a rational function of a, b, c: its normal form decides zero exactly
