"""The three numeric paths of G_u: exact, mpmath, float64 (generated kernel).

The float path's stated bound (impactsym.laws.reflection.FLOAT_ERROR_FACTOR):
    max|G_float - G| <= FLOAT_ERROR_FACTOR * n * cond(M) * eps * max|G|
against a 50-digit mpmath reference whose inputs are the floats' exact binary values, with a
precision-ladder self-check (the reference agrees with itself at 100 digits).
"""

import mpmath
import numpy as np
import pytest
import sympy as sp

from impactsym import kernels
from impactsym.laws.reflection import FLOAT_ERROR_FACTOR, reflect, reflection_map
from impactsym.numbers import float_to_rational

EPS = np.finfo(float).eps


def random_spd(rng, n, kappa):
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    M = (Q * np.logspace(0, np.log10(kappa), n)) @ Q.T
    return (M + M.T) / 2


def reference(M, u, e, dps):
    R = reflection_map(M, u, e, dps=dps)
    return np.array(R.tolist(), dtype=object)


@pytest.mark.parametrize("kappa", [1.0, 1e4, 1e8, 1e12])
@pytest.mark.parametrize("n", [2, 3, 6])
def test_float_path_within_stated_bound(n, kappa):
    rng = np.random.default_rng(int(n * 1000 + np.log10(kappa)))
    for _ in range(8):
        M, u, e = random_spd(rng, n, kappa), rng.standard_normal(n), rng.uniform()
        G = reflection_map(M, u, e)
        ref = reference(M, u, e, 50)
        ladder = reference(M, u, e, 100)
        with mpmath.workdps(50):
            assert max(abs(a - b) for a, b in zip(ref.ravel(), ladder.ravel())) < mpmath.mpf(10) ** -40
            err = max(abs(mpmath.mpf(float(g)) - r) for g, r in zip(G.ravel(), ref.ravel()))
            normG = max(abs(r) for r in ref.ravel())
        bound = FLOAT_ERROR_FACTOR * n * np.linalg.cond(M) * EPS * float(normG)
        assert float(err) <= bound, (float(err), bound)


def test_reference_inputs_are_exact_binary_values():
    """mpmath path with float input == exact path on the floats' binary values (no re-rounding)."""
    M = np.array([[1.1, 0.1], [0.1, 0.3]])
    u = np.array([0.1, -0.7])
    exact = reflection_map(sp.Matrix(2, 2, [float_to_rational(x) for x in M.ravel()]),
                           sp.Matrix([float_to_rational(x) for x in u]))
    mp = reference(M, u, 1, 60)
    with mpmath.workdps(60):
        for a, b in zip(exact, mp.ravel()):
            assert abs(mpmath.mpf(sp.N(a, 80)._mpf_) - b) < mpmath.mpf(10) ** -55


def test_kernel_broadcasts_over_leading_axes():
    rng = np.random.default_rng(7)
    Ms = np.stack([random_spd(rng, 3, 10.0) for _ in range(12)]).reshape(3, 4, 3, 3)
    us = rng.standard_normal((3, 4, 3))
    vs = rng.standard_normal((3, 4, 3))
    G = kernels.reflection_map(Ms, us, 0.5)
    assert G.shape == (3, 4, 3, 3)
    out = kernels.reflect(Ms, us, vs, 0.5)
    for i in range(3):
        for j in range(4):
            single = reflect(Ms[i, j], us[i, j], vs[i, j], 0.5)
            assert np.max(np.abs(out[i, j] - single)) <= 64 * EPS * (1 + np.max(np.abs(single)))
            assert np.max(np.abs(G[i, j] @ vs[i, j] - single)) <= 1e-12 * (1 + np.max(np.abs(single)))


@pytest.mark.parametrize("n", [2, 3])
def test_closed_form_kernels_agree_with_exact(n):
    """reflection_map_2/3 (adjugate closed forms) against the exact map on rational SPD input."""
    rng = np.random.default_rng(n)
    for _ in range(10):
        L = np.tril(rng.integers(-5, 6, (n, n))) + np.diag(rng.integers(1, 6, n) + 5)
        Mi = L @ L.T
        u = rng.integers(-4, 5, n)
        u[0] = u[0] or 1
        exact = reflection_map(sp.Matrix(Mi.tolist()), sp.Matrix(u.tolist()), sp.Rational(1, 3))
        upper = [float(Mi[i, j]) for i in range(n) for j in range(i, n)]
        f = getattr(kernels, f"reflection_map_{n}")(*upper, *map(float, u), 1 / 3)
        got = np.array(f, dtype=float).reshape(n, n)
        ref = np.array(exact.evalf(20).tolist(), dtype=float)
        assert np.max(np.abs(got - ref)) <= FLOAT_ERROR_FACTOR * n * np.linalg.cond(Mi) * EPS * np.max(np.abs(ref))


def test_mpmath_path_respects_dps_and_gives_it_back():
    before = mpmath.mp.dps
    G = reflection_map("11/10,0;0,1", "-1,1", dps=40)
    assert mpmath.mp.dps == before
    with mpmath.workdps(40):
        assert abs(G[0, 0] - mpmath.mpf(1) / 21) < mpmath.mpf(10) ** -38
