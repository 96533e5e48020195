"""The impulse-ratio law restates A, B, C (fmpq / SymPy / float) and takes its float root from the
generated kernel ``impulse_ratio_root``; here both are evaluated against the derivation
(``derivations.impulse_ratio.general_quadratic`` and ``derivations.impulse_ratio_root``) at random
rationals."""

import random

import numpy as np
import pytest
import sympy as sp

from derivations.impulse_ratio import general_quadratic
from derivations.impulse_ratio_root import stable_roots, coefficients
from impactsym.laws.impulse_ratio import energy_balance_along


def _scene(rng):
    n = rng.randint(2, 4)
    k = rng.randint(1, n)
    L = sp.Matrix(n, n, lambda i, j: sp.Rational(rng.randint(-5, 5), rng.randint(1, 4)) if j <= i else 0)
    M = L * L.T + sp.Rational(rng.randint(1, 9), rng.randint(1, 9)) * sp.eye(n)
    while True:
        H = sp.Matrix(k, n, lambda i, j: sp.Rational(rng.randint(-4, 4), rng.randint(1, 3)))
        if H.rank() == k:
            break
    v = sp.Matrix([sp.Rational(rng.randint(-7, 7), rng.randint(1, 5)) for _ in range(n)])
    e = sp.Rational(rng.randint(0, 10), 10)
    alphas = [sp.Rational(rng.randint(0, 9), rng.randint(1, 5)) for _ in range(k - 1)]
    return M, H, v, e, alphas


def test_exact_and_float_coefficients_equal_the_derivation():
    rng = random.Random(1130)
    for _ in range(25):
        M, H, v, e, alphas = _scene(rng)
        law = general_quadratic(M, H, v, e, alphas)
        a = [sp.Integer(1)] + alphas
        r = energy_balance_along(M, H, v, e, a, exact=True, allow_invalid=True)
        assert tuple(r.coefficients) == (law.A, law.B, law.C)
        assert r.delta == law.D
        if r.impulses is not None:
            assert sp.simplify(r.impulses[0] - law.p1) == 0
        Mf, Hf, vf = (np.array(X.tolist(), dtype=float) for X in (M, H, v))
        rf = energy_balance_along(Mf, Hf, vf.reshape(-1), float(e), [float(x) for x in a], exact=False,
                                  allow_invalid=True)
        for got, want in zip(rf.coefficients, (law.A, law.B, law.C)):
            assert abs(got - float(want)) <= 1e-12 * (1 + abs(float(want)))
        if rf.impulses is not None and law.D != 0:
            p1 = float(law.p1)
            assert abs(float(rf.impulses[0]) - p1) <= 1e-10 * (1 + abs(p1))


def test_float_root_is_the_generated_stable_kernel():
    """The kernel the float path calls is the derivation's stable root (not a re-typed formula)."""
    from impactsym import kernels

    A, B, C = coefficients()
    phys = stable_roots()[0]
    rng = random.Random(7)
    for _ in range(40):
        a, b, c = (sp.Rational(rng.randint(1, 50), rng.randint(1, 9)), sp.Rational(rng.randint(-50, 50), rng.randint(1, 9)),
                   sp.Rational(rng.randint(0, 20), rng.randint(1, 9)))
        if b * b - 4 * a * c < 0 or (b >= 0 and b * b - 4 * a * c == 0 and b == 0):
            continue
        want = phys.subs({A: a, B: b, C: c})
        got = float(kernels.impulse_ratio_root(float(a), float(b), float(c))[0])
        assert abs(got - float(want)) <= 1e-12 * (1 + abs(float(want)))


def test_rational_data_derive_in_qq_as_the_sympy_balance_does():
    """Rational data take general_quadratic's QQ[p₁] route; the same scene with e a symbol takes
    the SymPy route (expand, coefficients, simplify). Put e in afterwards, every field is the same
    exact number: the two routes are one derivation."""
    rng = random.Random(11)
    x = sp.Symbol("x")
    real = 0
    for _ in range(10):
        M, H, v, e, alphas = _scene(rng)
        fast = general_quadratic(M, H, v, e, alphas)
        slow = general_quadratic(M, H, v, x, alphas)
        for f, s in [(fast.A, slow.A), (fast.B, slow.B), (fast.C, slow.C), (fast.D, slow.D)]:
            assert f.is_Rational and sp.expand(s.subs(x, e)) == f
        if fast.D >= 0:
            real += 1
            assert fast.p1 == (-fast.B + sp.sqrt(fast.D)) / (2 * fast.A)
            assert slow.p1.subs(x, e) == fast.p1
            assert list(fast.vplus) == list(v + fast.p1 * M.LUsolve(H.T * sp.Matrix([1, *alphas])))
    assert real >= 3  # the roots and v+ compared on scenes with a real solution (4 of these 10)


def test_a_singular_mass_matrix_raises_the_same_error_on_both_routes():
    from sympy.matrices.exceptions import NonInvertibleMatrixError

    M, H, v = sp.Matrix([[1, 1], [1, 1]]), sp.Matrix([[-1, 1]]), sp.Matrix([1, 0])
    for e in (1, sp.Symbol("x")):  # the QQ route, the SymPy route
        with pytest.raises(NonInvertibleMatrixError, match="not invertible"):
            general_quadratic(M, H, v, e, [])
