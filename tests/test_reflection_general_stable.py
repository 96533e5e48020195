"""Issue 15: the general-dimension ``reflect`` / ``reflection_map`` kernels (NumPy and C) emit the
closed forms' stable form, proved equal to ``I − (1+e) w u / s``, and hold the 64 eps (1 + cond) bound
at the points that broke the naive ``1 − (1+e) u_i w_i / s`` and the unequilibrated LU solve."""

from __future__ import annotations

import ctypes
import math
import shutil

import numpy as np
import pytest

import derivations.reflection as R
from impactsym import kernels as K
from impactsym.accuracy import _spd, accuracy_check, kernel_implementations, reference

HAVE_CC = bool(shutil.which("gcc") or shutil.which("cc"))
LANGS = ("numpy", "c") if HAVE_CC else ("numpy",)


def test_emitted_form_is_proved_equal_to_the_printed_map():
    r = R.general_emitted_proof()
    assert r["proven"]
    assert any(s.startswith("general n, diagonal") and s.endswith("True") for s in r["steps"])
    assert any(s.startswith("n = 6:") for s in r["steps"])


def test_proof_catches_a_wrong_emitted_form(monkeypatch):
    """The proof is not vacuous: a diagonal with the wrong sign of e t is refuted (general n and n = 1..2)."""
    g = R._GEN
    right = R._general_emitted()
    monkeypatch.setattr(R, "_general_emitted", lambda: (g["rest"] + g["e"] * g["t"], *right[1:]))
    r = R.general_emitted_proof.__wrapped__(2)
    assert not r["proven"]
    assert any(s.startswith("general n, diagonal") and s.endswith("False") for s in r["steps"])


def _check(kernel, x, langs=LANGS):
    return accuracy_check(kernel, x, kernel_implementations(kernel, langs), 64.0, reference(kernel), screen=False)


def test_reported_case_diagonal_at_e_zero():
    """1 − (1+e) u_i w_i / s cancelled to 5e10 eps at e = 0, M = diag(1, 1e-12)."""
    x = dict(m_00=1.0, m_01=0.0, m_11=1e-12, u_0=-1.0, u_1=1.0, e=0.0)
    v = _check("reflection_map_general_2", x)
    assert not v.problems and v.worst <= 4, v
    v = _check("reflect_general_2", dict(x, v_0=0.0, v_1=1.0))
    assert not v.problems and v.worst <= 4, v


def test_badly_scaled_mass_matrix_numpy_solve():
    """Found by a 400-point adversarial search (seed 15): LU with partial pivoting on the unscaled M
    gave g10 off by 1.3e17 eps (1 + cond); the kernel now solves on M equilibrated by powers of two."""
    x = {'m_00': 1.0, 'm_01': 0.0, 'm_02': 1.000000000000208e-12, 'm_11': 8.595404962848546e-11,
         'm_12': -3.7638109913557815e-10, 'm_22': 999999999999.9462, 'u_0': 461683411.4001449,
         'u_1': -3.7812922210436424e-05, 'u_2': 135261845662319.4, 'e': 0.0}
    v = _check("reflection_map_general_3", x)
    assert not v.problems and v.worst <= 4, v


@pytest.mark.parametrize("kappa", [1e12, 1e16])
def test_exact_zero_output_and_ill_conditioned_spd_mass_matrix(kappa):
    """u = e_0 at e = 0: G_00 and (G v)_0 are exactly 0 (the naive C form gave 1.1e-16: inf eps);
    an SPD M of condition 1e12 (the grid's) and 1e16 is accepted by the C Cholesky (no NaN)."""
    M = _spd(3, kappa, 5)
    u, v = np.array([1.0, 0.0, 0.0]), np.array([1.0, 0.5, -0.25])
    x = {f"m_{i}{j}": float(M[i, j]) for i in range(3) for j in range(i, 3)}
    x.update(u_0=1.0, u_1=0.0, u_2=0.0, e=0.0)
    for lang, f in kernel_implementations("reflection_map_general_3", LANGS).items():
        G = f(x)
        assert G[0] == 0.0 and not any(math.isnan(y) for y in G), (lang, G)
    xv = dict(x, **{f"v_{i}": float(v[i]) for i in range(3)})
    for lang, f in kernel_implementations("reflect_general_3", LANGS).items():
        out = f(xv)
        assert out[0] == 0.0 and not any(math.isnan(y) for y in out), (lang, out)
    assert K.reflection_map(M, u, 0.0)[0, 0] == 0.0 and K.reflect(M, u, v, 0.0)[0] == 0.0
    if kappa == 1e12:
        assert not _check("reflect_general_3", xv).problems


@pytest.mark.skipif(not HAVE_CC, reason="no C compiler (gcc/cc) on PATH")
def test_c_refuses_a_matrix_with_a_non_positive_pivot():
    """The documented refusal: an indefinite M (pivot 1 - 4 = -3) returns -1 and writes nothing."""
    from impactsym.accuracy import _c_library

    f = _c_library().reflection_map
    f.restype = ctypes.c_int
    dp = ctypes.POINTER(ctypes.c_double)
    M, u, G = np.array([[1.0, 2.0], [2.0, 1.0]]), np.array([1.0, 0.0]), np.full(4, 7.0)
    status = f(ctypes.c_size_t(2), M.ctypes.data_as(dp), u.ctypes.data_as(dp), ctypes.c_double(1.0),
               G.ctypes.data_as(dp))
    assert status == -1 and (G == 7.0).all()
    M = np.array([[1.0, 0.0], [0.0, 1e-300]])  # positive pivots: accepted
    status = f(ctypes.c_size_t(2), M.ctypes.data_as(dp), u.ctypes.data_as(dp), ctypes.c_double(1.0),
               G.ctypes.data_as(dp))
    assert status == 0 and list(G) == [-1.0, 0.0, 0.0, 1.0]


def test_batched_calls_agree_with_one_at_a_time():
    """The emitted form keeps the kernels' broadcasting: a batch of 4 equals 4 single calls, and a
    batch of restitutions against one (M, u) broadcasts."""
    rng = np.random.default_rng(15)
    A = rng.normal(size=(4, 3, 3))
    M = A @ A.transpose(0, 2, 1) + np.eye(3)
    u, v, e = rng.normal(size=(4, 3)), rng.normal(size=(4, 3)), rng.uniform(size=4)
    G, Gv = K.reflection_map(M, u, e), K.reflect(M, u, v, e)
    assert G.shape == (4, 3, 3) and Gv.shape == (4, 3)
    for b in range(4):
        assert (G[b] == K.reflection_map(M[b], u[b], e[b])).all()
        assert (Gv[b] == K.reflect(M[b], u[b], v[b], e[b])).all()
    assert (K.reflection_map(M[0], u[0], e)[2] == K.reflection_map(M[0], u[0], e[2])).all()
