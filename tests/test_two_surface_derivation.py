"""The two-surface derivation (Seghete & Murphey sec. III-C): plane reduction, frame, exact count,
the paper's bound, and the generated kernels against the certified law."""

from __future__ import annotations

import random
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from derivations import two_surface as ts
from impactsym import kernels
from impactsym.laws.two_surface import resolve_two_surfaces
from impactsym.mechanics import kinetic_angle_cos


def test_plane_reduction_any_dimension():
    r = ts.plane_reduction()
    assert r["proven"]
    s_A, g = ts.s_A, ts.g
    assert r["G_A_P"] == sp.Matrix([[-1, -2 * g / s_A], [0, 1]])
    assert r["G_B_P"] == sp.Matrix([[1, 0], [-2 * g / ts.s_B, -1]])


def test_plane_reduction_numerically_in_dimension_5():
    """Concrete check of the structural proof: a vector of ker H_A ∩ ker H_B is fixed, P is invariant."""
    rng = random.Random(1)
    n = 5
    L = sp.Matrix(n, n, lambda i, j: sp.Rational(rng.randint(-4, 4), rng.randint(1, 3)))
    M = L * L.T + sp.eye(n)
    H = sp.Matrix(2, n, lambda i, j: rng.randint(-3, 3))
    GA = sp.eye(n) - 2 * M.inv() * H[0, :].T * H[0, :] / (H[0, :] * M.inv() * H[0, :].T)[0]
    GB = sp.eye(n) - 2 * M.inv() * H[1, :].T * H[1, :] / (H[1, :] * M.inv() * H[1, :].T)[0]
    for x in H.nullspace():
        assert GA * x == x and GB * x == x
        assert (x.T * M * M.inv() * H.T) == sp.zeros(1, 2)  # M-orthogonal to w_A, w_B
    W = M.inv() * H.T
    P = W.columnspace()
    for G in (GA, GB):
        for w in P:
            assert sp.Matrix.hstack(W, G * w).rank() == 2


def test_frame_and_kinetic_angle():
    f = ts.plane_frame()
    assert f["proven"], f["checks"]
    # beta = pi - phi with impactsym's kinetic angle, on a concrete case
    M, HA, HB = sp.diag(sp.Rational(11, 10), 1), sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]])
    cphi = kinetic_angle_cos(M, HA, HB)
    sA = (HA * M.inv() * HA.T)[0]
    sB = (HB * M.inv() * HB.T)[0]
    g = (HA * M.inv() * HB.T)[0]
    vals = {ts.s_A: sA, ts.g: g, ts.Delta: sA * sB - g**2}
    assert sp.simplify(f["cos_beta"].subs(vals) + cphi) == 0


def test_count_derivation_proven():
    c = ts.reflection_count_derivation()
    assert c["proven"]
    assert c["count"] == sp.ceiling(ts.psi / ts.beta)


@pytest.mark.parametrize("m", range(1, 9))
def test_exit_angle_matches_products_of_reflections(m):
    """θ_f from the closed form equals the angle after m explicit reflections in the frame."""
    b, p = sp.Rational(3, 10), sp.Rational(27, 10)  # radians, arbitrary
    th = -p
    for k in range(m):
        th = -th if k % 2 == 0 else 2 * b - th
    assert sp.simplify(ts.exit_angle(m, p, b) - th) == 0


def _fraction(x) -> Fraction:
    return Fraction(int(x.p), int(x.q))


def test_exact_exit_closed_form_against_iteration():
    rng = random.Random(4)
    from test_two_surface_law import _random_case, _solve, iterate_fraction  # noqa: PLC0415
    checked = 0
    for _ in range(300):
        M, H, v = _random_case(rng, 2)
        ws = [[_fraction(x) for x in _solve(M, h)] for h in H]  # the reference solves in fmpq
        sA, sB = (sum(h[k] * w[k] for k in range(2)) for h, w in zip(H, ws))
        g = sum(H[0][k] * ws[1][k] for k in range(2))
        cA, cB = (sum(h[k] * v[k] for k in range(2)) for h in H)
        ref = iterate_fraction(M, H, v, 0)
        if ref is None or ref[0] == []:
            continue
        m = len(ref[0])
        ca, cb = ts.exact_exit_relative_velocity(sA, sB, g, cA, cB, m)
        assert (ca, cb) == tuple(sum(h[k] * _fraction(ref[1][k]) for k in range(2)) for h in H)
        checked += 1
    assert checked > 50


def test_lune_fraction_and_bound():
    b = ts.paper_bound()
    assert b["same_in_every_dimension"] and b["fraction"] == ts.beta / (2 * sp.pi)
    assert b["N"] == sp.ceiling(sp.pi / ts.beta)


@pytest.mark.parametrize("bp, N, both", [
    (sp.Rational(1, 4), 4, [4]), (sp.Rational(1, 3), 3, [3]), (sp.Rational(2, 7), 4, [3, 4]),
    (sp.Rational(2, 5), 3, [2, 3]), (sp.Rational(1, 2), 2, [2]), (sp.Rational(3, 4), 2, [1, 2]),
])
def test_bound_versus_count(bp, N, both):
    r = ts.bound_versus_count(bp)
    assert r["N"] == r["max_count"] == N and r["both_approaching"] == both


@pytest.mark.parametrize("den", [3, 4, 5, 7, 10])
def test_bound_versus_count_by_sampling_the_law(den):
    """M = I, n_A = (0, 1), n_B = (sin β, −cos β) (kinetic angle π − β), β = 2π/(2·den + 1) so that
    π/β = den + ½. Velocities all around the approaching half-plane of A: max count = N, never more."""
    beta = sp.pi * sp.Rational(2, 2 * den + 1)
    H = np.array([[0.0, 1.0], [float(sp.sin(beta)), float(-sp.cos(beta))]])
    counts = []
    for k in range(1, 400):
        ang = np.pi * (1 + k / 400.0)
        r = resolve_two_surfaces(np.eye(2), H, np.array([np.cos(ang), np.sin(ang)]))
        counts += [o.reflections for o in r.outcomes]
    N = int(sp.ceiling(sp.pi / beta))
    assert max(counts) == N == r.bound


def test_reachable_arcs_grow_by_two_wedges():
    for bp, k in ((sp.Rational(1, 5), 6), (sp.Rational(2, 7), 5)):
        arcs = ts.reachable_arc_lengths(bp, k)
        b = bp * sp.pi
        assert arcs[0] == b
        assert all(sp.simplify(a - sp.Min(2 * j * b, 2 * sp.pi)) == 0 for j, a in enumerate(arcs) if j >= 1)


def test_area_step_fails_for_general_connected_sets():
    r = ts.area_step_counterexample()
    assert r["fails"] and sp.simplify(r["union_area"] - 2 * r["two_max"]) == 0


def test_paper_example_counts():
    e = ts.paper_example_counts()
    t = sp.Symbol("t", real=True)
    assert e["N"] == 4
    assert e["G_u"] == sp.diag(-1, 1)  # the paper prints G_u = -I (misprint: det would be +1)
    assert e["v4a"] == sp.Matrix([[-439, -40], [44, -439]]) / 441
    assert e["ell_u"] == sp.Matrix([[-sp.Rational(23, 21), sp.Rational(19, 21)]])
    cu, cv = e["u_first_four_iff"], e["v_first_four_iff"]
    for x in (1, sp.Rational(23, 19), sp.Rational(23, 19) + sp.Rational(1, 10**9), 5, sp.Rational(439, 40), 11):
        assert bool(cu.subs(t, x)) == (x > sp.Rational(23, 19))
        assert bool(cv.subs(t, x)) == (x < sp.Rational(439, 40))


# --------------------------------------------------------------------------- generated kernels
def test_kernels_against_law_float():
    rng = np.random.default_rng(12)
    agree = 0
    for _ in range(300):
        n = int(rng.integers(2, 5))
        A = rng.normal(size=(n, n))
        M = A @ A.T + np.eye(n)
        H = rng.normal(size=(2, n))
        v = rng.normal(size=n)
        counts, exits = kernels.two_surface_exit_velocity(M, H, v)
        res = resolve_two_surfaces(M, H, v)
        for f in (0, 1):
            o = res.by_first[f]
            if o is None:
                assert counts[f] in (0, -1)
                continue
            assert counts[f] == o.reflections
            np.testing.assert_allclose(exits[f], o.velocity, rtol=0, atol=1e-12 * max(1, o.reflections) * np.abs(v).max() * 10)
            agree += 1
    assert agree > 200


def test_n2_closed_form_kernel():
    out = kernels.two_surface_resolution_2(1.1, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, -1.0, -2.0)
    v4a = np.array([[-439, -40], [44, -439]]) / 441 @ np.array([-1, -2])
    v4b = np.array([[-439, 40], [-44, -439]]) / 441 @ np.array([-1, -2])
    assert out[0] == 4 and out[3] == 4
    np.testing.assert_allclose(out[1:3], v4a, atol=1e-14)
    np.testing.assert_allclose(out[4:6], v4b, atol=1e-14)


def test_count_kernel_sentinels():
    # valid velocity: 0, 0; approaching only A: (count, -1)
    assert tuple(map(float, kernels.two_surface_reflection_count(1.0, 2.0, -1.0, 1.0, 1.0))) == (0.0, 0.0)
    ca, cb = kernels.two_surface_reflection_count(1.0, 2.0, -1.0, -1.0, 1.0)
    assert float(cb) == -1.0 and float(ca) == 2.0
