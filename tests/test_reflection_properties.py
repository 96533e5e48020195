"""Hypothesis property tests of G_u on random rational (exact) and float SPD matrices."""

import numpy as np
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from impactsym import kinetic_energy, reflect, reflection_map

small = st.integers(min_value=-6, max_value=6)


@st.composite
def rational_spd(draw, n=None):
    n = n or draw(st.integers(2, 4))
    # M = L L^T + d I with L rational: symmetric positive definite, exactly
    L = sp.Matrix(n, n, lambda i, j: sp.Rational(draw(small), draw(st.integers(1, 4))) if j <= i else 0)
    d = sp.Rational(draw(st.integers(1, 9)), draw(st.integers(1, 9)))
    return L * L.T + d * sp.eye(n)


@st.composite
def scene(draw):
    M = draw(rational_spd())
    n = M.rows
    u = sp.Matrix([draw(small) for _ in range(n)])
    if all(x == 0 for x in u):
        u[0] = 1
    v = sp.Matrix([sp.Rational(draw(small), draw(st.integers(1, 5))) for _ in range(n)])
    e = sp.Rational(draw(st.integers(0, 8)), 8)
    return M, u, v, e


@settings(max_examples=40, deadline=None)
@given(scene())
@example((sp.diag(sp.Rational(11, 10), 1), sp.Matrix([-1, 1]), sp.Matrix([1, 0]), sp.Integer(1)))
def test_exact_reflection_properties(data):
    M, u, v, e = data
    n = M.rows
    G = reflection_map(M, u)
    assert G * G == sp.eye(n)
    assert (G.T * M * G - M).applyfunc(sp.simplify) == sp.zeros(n, n)
    assert G.det() == -1
    assert reflection_map(M, 3 * u) == G and reflection_map(M, -u / 2) == G
    assert (u.T * reflect(M, u, v))[0, 0] == -(u.T * v)[0, 0]
    # restitution: u v+ = -e u v-, and T+ - T- = -(1 - e^2)(u v)^2 / (2 u M^-1 u^T)
    vp = reflect(M, u, v, e)
    assert (u.T * vp)[0, 0] == -e * (u.T * v)[0, 0]
    s = (u.T * M.LUsolve(u))[0, 0]
    assert kinetic_energy(M, vp) - kinetic_energy(M, v) == -(1 - e**2) * (u.T * v)[0, 0] ** 2 / (2 * s)
    # fixes ker u: x = u_j e_i - u_i e_j
    i = next(k for k in range(n) if u[k] != 0)
    for j in range(n):
        if j != i:
            x = sp.zeros(n, 1)
            x[i], x[j] = u[j], -u[i]
            assert G * x == x


@st.composite
def float_scene(draw):
    n = draw(st.integers(2, 6))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    M = A @ A.T + draw(st.floats(1e-3, 10.0)) * np.eye(n)
    return M, rng.standard_normal(n), rng.standard_normal(n)


@settings(max_examples=60, deadline=None)
@given(float_scene())
def test_float_reflection_properties(data):
    M, u, v = data
    n = M.shape[0]
    G = reflection_map(M, u)
    tol = 64 * n * np.linalg.cond(M) * np.finfo(float).eps
    scale = max(1.0, np.max(np.abs(G)) ** 2)
    assert np.max(np.abs(G @ G - np.eye(n))) <= tol * scale
    assert np.max(np.abs(G.T @ M @ G - M)) <= tol * scale * np.max(np.abs(M))
    assert abs(np.linalg.det(G) + 1) <= tol * scale ** (n / 2)
    w = reflect(M, u, v)
    assert abs(u @ w + u @ v) <= tol * (np.abs(u) @ (np.abs(v) + np.abs(w)) + 1e-300)
