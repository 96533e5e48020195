"""The private reflection primitive (impactsym.laws._reflection) states G_u(e) once for every
arithmetic the laws use; here it is evaluated in each (SymPy, fmpq, mpmath, float) against the
derivation's expression (derivations.reflection.printed_G) at random rationals."""

import random

import mpmath
import numpy as np
import sympy as sp
from flint import fmpq, fmpq_mat

from derivations.reflection import printed_G
from impactsym.laws import _reflection as r


def _scene(rng, n):
    L = sp.Matrix(n, n, lambda i, j: sp.Rational(rng.randint(-6, 6), rng.randint(1, 5)) if j <= i else 0)
    M = L * L.T + sp.Rational(rng.randint(1, 9), rng.randint(1, 9)) * sp.eye(n)
    u = sp.Matrix([[sp.Rational(rng.randint(-6, 6), rng.randint(1, 4)) for _ in range(n)]])
    if all(x == 0 for x in u):
        u[0] = 1
    v = sp.Matrix([sp.Rational(rng.randint(-9, 9), rng.randint(1, 7)) for _ in range(n)])
    e = sp.Rational(rng.randint(0, 12), 12)
    return M, u, v, e


def _fq(A):
    return fmpq_mat(A.rows, A.cols, [fmpq(int(x.p), int(x.q)) for x in A])


def _back(F):
    return sp.Matrix(F.nrows(), F.ncols(), [sp.Rational(int(F[i, j].p), int(F[i, j].q))
                                            for i in range(F.nrows()) for j in range(F.ncols())])


def test_primitive_equals_derivation_at_random_rationals():
    rng = random.Random(20261130)
    for trial in range(40):
        M, u, v, e = _scene(rng, rng.randint(1, 4))
        n = M.rows
        G = printed_G(M, u, e)
        # SymPy
        w, s = r.sympy_parts(M, u)
        g = r.gain(s, e)
        assert r.reflection_matrix(sp.eye(n), w, u, g) == G
        vp, p = r.reflect_along(v, w, (u * v)[0, 0], g)
        assert vp == G * v
        assert M * (vp - v) == u.T * p  # the impulse is the multiplier of M(v+ - v) = u^T p
        # fmpq
        wq, sq = r.fmpq_parts(_fq(M), _fq(u))
        gq = r.gain(sq, fmpq(int(e.p), int(e.q)))
        Gq = r.reflection_matrix(_fq(sp.eye(n)), wq, _fq(u), gq)
        assert _back(Gq) == G
        vq, pq = r.reflect_along(_fq(v), wq, (_fq(u) * _fq(v))[0, 0], gq)
        assert _back(vq) == G * v and sp.Rational(int(pq.p), int(pq.q)) == p
        # sparse form of the searches (rationals)
        wcol = [(j, wq[j, 0]) for j in range(n) if wq[j, 0] != 0]
        vs, ps = r.reflect_sparse(tuple(_fq(v)[j, 0] for j in range(n)), wcol, gq * (_fq(u) * _fq(v))[0, 0])
        assert [sp.Rational(int(x.p), int(x.q)) for x in vs] == list(G * v) and -ps == -pq
        # mpmath at 60 digits, against the exact value
        with mpmath.workdps(60):
            Mm = mpmath.matrix([[mpmath.mpf(int(x.p)) / int(x.q) for x in M.row(i)] for i in range(n)])
            um = mpmath.matrix([mpmath.mpf(int(x.p)) / int(x.q) for x in u])
            wm, sm = r.mpmath_parts(Mm, um)
            Gm = r.reflection_matrix(mpmath.eye(n), wm, um.T, r.gain(sm, mpmath.mpf(int(e.p)) / int(e.q)))
            for i in range(n):
                for j in range(n):
                    assert abs(Gm[i, j] - mpmath.mpf(sp.N(G[i, j], 70))) <= mpmath.mpf(10) ** -50 * (1 + abs(Gm[i, j]))


def test_float_searches_gain_is_the_elastic_gain():
    s = np.array([2.0, 0.5])
    assert list(r.gain(s, 1.0)) == [1.0, 4.0]


def test_float_search_step_agrees_with_the_generated_kernel():
    """The sequential float search reflects with the primitive on precomputed sparse columns (the
    kernel would re-solve M at every step); each step agrees with ``kernels.reflect``."""
    from impactsym import kernels
    from impactsym.laws.sequential.float_search import _FloatSystem

    rng = np.random.default_rng(11)
    for _ in range(20):
        n, k = int(rng.integers(2, 6)), int(rng.integers(1, 4))
        L = rng.normal(size=(n, n))
        M = L @ L.T + n * np.eye(n)
        H = rng.normal(size=(k, n))
        v = rng.normal(size=n)
        fs = _FloatSystem(M, H, v, 10)
        for i in range(k):
            wi, _ = fs.w_and_bound(tuple(v), i)
            got, p = fs.reflect(tuple(v), i, wi)
            want = kernels.reflect(M, H[i], v)
            assert np.allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(v).max())
            assert np.allclose(M @ (np.array(got) - v), H[i] * p, rtol=1e-10, atol=1e-10)
