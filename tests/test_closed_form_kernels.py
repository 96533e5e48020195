"""Generated kernels of the chain3, pool and domains families against 50-digit references
computed from the exact closed forms (floats taken at their exact binary values)."""

import math
import mpmath

import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from derivations import chain3 as C
from derivations import domains as DD
from derivations import pool as P
from derivations.impulse_ratio import general_quadratic
from impactsym import kernels
from impactsym.models.acary_taha import chain3, pool
from impactsym.numbers import float_to_rational


def _ref_law(sc, ratios, ee):
    """Exact law at exact inputs, evaluated to 50 digits: (p, v+)."""
    law = general_quadratic(sc.M, sc.H, sc.v, ee, ratios)
    return [sp.N(x, 50) for x in law.p], [sp.N(x, 50) for x in law.vplus]


def _close(got, ref, scale, rtol=1e-12):
    return abs(float(got) - float(ref)) <= rtol * max(float(scale), 1e-300)


def test_codegen_names_match():
    for fam in ("chain3", "pool", "domains"):
        mod = getattr(kernels, fam)
        for kebab, snake in mod.CODEGEN_NAMES.items():
            assert kebab.replace("-", "_") == snake and callable(getattr(kernels, snake))
    assert kernels.CODEGEN_NAMES["chain3-impulse-ratio"] == ("chain3", "chain3_impulse_ratio")


# velocities inside the kernel's documented precondition: zero, or squares that are normal floats
_velocity = st.floats(-2.0, 2.0).filter(lambda x: x == 0.0 or abs(x) >= 1e-150)


@settings(max_examples=20, deadline=None)
@given(m=st.lists(st.floats(0.2, 5.0), min_size=3, max_size=3),
       v=st.lists(_velocity, min_size=3, max_size=3),
       ee=st.floats(0.5, 1.0), a=st.floats(0.0, 1.5))
@example(m=[1.0, 1.0, 1.0], v=[1.0, 0.0, 0.0], ee=1.0, a=0.95)
@example(m=[1.0, 2.0, 3.0], v=[-1.0, 0.5, 0.0], ee=0.9, a=0.5)  # B > 0 branch
def test_chain3_kernel_against_50_digit_reference(m, v, ee, a):
    ex = [float_to_rational(x) for x in (*m, *v, ee, a)]
    sc = chain3(ex[0:3], ex[3:6])
    law = general_quadratic(sc.M, sc.H, sc.v, ex[6], [ex[7]])
    D = law.D
    if D < 0:  # outside the domain the kernel returns NaN, as documented: the sqrt of D < 0 is expected
        with np.errstate(invalid="ignore", divide="ignore"):
            out = kernels.chain3_impulse_ratio(*m, *v, ee, a)
        assert np.isnan(out[0])
        return
    # numpy.select evaluates both branches of the kernel's Piecewise; the one not taken may be 0/0
    with np.errstate(invalid="ignore", divide="ignore"):
        out = kernels.chain3_impulse_ratio(*m, *v, ee, a)
    mpmath.mp.dps = 50
    p, w = [sp.N(x, 50) for x in law.p], [sp.N(x, 50) for x in law.vplus]
    # scale: the size of the terms combined (|v|, |p|, and the root's terms |B|/A, sqrt(D)/A)
    scale = max([abs(x) for x in (*v, 1.0)] + [abs(float(x)) for x in p] + [float(sp.sqrt(D) / law.A), float(abs(law.B) / law.A)])
    for got, ref in zip(out, [*p, *w]):
        assert _close(got, ref, scale * 1e2), (got, ref)


def test_chain3_kernel_paper_values():
    p1, p2, w1, w2, w3 = kernels.chain3_impulse_ratio(1, 1, 1, 1, 0, 0, 1, 0.95)
    assert abs(w1 + 19 / 381) < 1e-15 and abs(w2 - 20 / 381) < 1e-15 and abs(w3 - 380 / 381) < 1e-15
    # broadcasting
    out = kernels.chain3_impulse_ratio(1, 1, 1, 1, 0, 0, np.array([1.0, 0.9]), np.array([[0.6], [0.8]]))
    assert out[0].shape == (2, 2)


@pytest.mark.parametrize("theta,tau,ee,a", [
    (0.0, 0.0, 1.0, 0.95), (np.pi / 4, 0.0, 0.8, 0.6), (np.pi / 3, 0.3, 0.9, 0.4),
    (np.pi / 2, -0.5, 1.0, 0.2), (1.9, 0.1, 0.95, 0.0),
])
def test_pool_kernel_against_exact_law(theta, tau, ee, a):
    out = kernels.pool_impulse_ratio(theta, tau, ee, a)
    ex = [float_to_rational(x) for x in (theta, tau, ee, a)]
    sc = pool(ex[0], ex[1], third_contact=False)
    p, w = _ref_law(sc, [ex[3]], ex[2])
    for got, ref in zip(out, [*p, *w]):
        assert _close(got, ref, 10.0), (got, ref)


def test_pool_kernel_no_impact_when_cos_tau_negative():
    for ee in (1.0, 0.7):
        out = kernels.pool_impulse_ratio(np.pi / 4, 2.5, ee, 0.5)
        assert out[0] == 0 and out[1] == 0
        v1 = (np.cos(np.pi / 4 - 2.5), np.sin(np.pi / 4 - 2.5))
        assert np.allclose(out[2:4], v1, rtol=0, atol=1e-15) and all(x == 0 for x in out[4:])


def test_bernoulli_kernel_against_closed_form_eq37_derived():
    d = P.bernoulli_closed_form()
    for a in (0.0, 0.3, 1.0):
        out = kernels.bernoulli_impulse_ratio(-np.pi / 6, 1.0, a, a)
        ar = float_to_rational(a)
        refs = [d[k].subs(P.alpha, ar) for k in ("p1", "p2", "p3", *P.VELOCITY_NAMES)]
        for got, ref in zip(out, refs):
            assert _close(got, sp.N(ref, 50), 10.0, rtol=1e-13), (a, got, ref)


def test_bernoulli_kernel_independent_ratios_general_e():
    ta, ee, a, b = -0.4, 0.85, 0.3, 0.7
    out = kernels.bernoulli_impulse_ratio(ta, ee, a, b)
    ex = [float_to_rational(x) for x in (ta, ee, a, b)]
    sc = pool(2 * sp.pi / 3, ex[0], third_contact=True)
    p, w = _ref_law(sc, [ex[2], ex[3]], ex[1])
    for got, ref in zip(out, [*p, *w]):
        assert _close(got, ref, 10.0), (got, ref)
    # no contact approaching: no impact
    out = kernels.bernoulli_impulse_ratio(2.8, 0.9, 0.5, 0.5)
    assert out[0] == 0 and out[2] == 0


def test_pool_g_h_kernels_against_exact():
    g, h = DD.pool_g(), DD.pool_h()
    for th, a in ((0.3, 0.7), (np.pi / 4, 1.0), (1.8, 0.25)):
        cs = sp.cos(float_to_rational(th))
        ar = float_to_rational(a)
        assert _close(kernels.pool_g(th, a), sp.N(g.subs({DD.c: cs, DD.alpha: ar}), 50), 1.0, 1e-14)
        assert _close(kernels.pool_h(th, a), sp.N(h.subs({DD.c: cs, DD.alpha: ar}), 50), 1.0, 1e-14)


@pytest.mark.parametrize("km, kv", [(240, -240), (-240, 240), (-200, -280), (240, 240), (-470, 0), (0, -470)])
def test_chain3_kernel_scales_exactly_inside_its_precondition(km, kv):
    """The documented precondition (every |x| and |m_i v_j| zero or within about 1e±150, so that the
    squares are normal floats): masses times 2^km and velocities times 2^kv scale p by 2^(km+kv) and
    w by 2^kv, bit for bit. (With every mass and velocity at 1e-90 the outputs were 10% off: the
    precondition had named each number alone.)"""
    m, v, ee, a = [1.0, 2.0, 0.5], [1.0, -0.25, -0.5], 0.9, 0.5
    sm, sv = 2.0 ** km, 2.0 ** kv
    ref = kernels.chain3_impulse_ratio(*m, *v, ee, a)
    out = kernels.chain3_impulse_ratio(*(x * sm for x in m), *(x * sv for x in v), ee, a)
    assert [float(x) for x in out] == [ref[0] * sm * sv, ref[1] * sm * sv, ref[2] * sv, ref[3] * sv, ref[4] * sv]


@pytest.mark.parametrize("kh, km, kv", [(0, 0, 0), (0, -480, 480), (0, 480, -480), (0, 340, 340), (0, -340, -340),
                                       (-300, 0, 0), (300, 0, 0)])
def test_two_surface_kernel_scales_exactly_inside_its_precondition(kh, km, kv):
    """Inside the documented precondition (rows of H of order one; M and v of any scales within
    2^±480 for which v^T M v is a normal float), M times 2^km and v times 2^kv: the counts are the same and the exit velocities scale by
    2^kv, bit for bit; H alone scaled by 2^±300 changes nothing. (At 2^±360 on H the exit velocity
    was wrong: the precondition is needed.)"""
    b = (1.0, 0.2, 2.0, 1.0, 0.0, -1.0, 1.0, -1.0, -0.5)
    sh, sm, sv = 2.0 ** kh, 2.0 ** km, 2.0 ** kv
    ref = [float(x) for x in kernels.two_surface_resolution_2(*b)]
    out = [float(x) for x in kernels.two_surface_resolution_2(*(x * sm for x in b[:3]), *(x * sh for x in b[3:7]),
                                                              *(x * sv for x in b[7:]))]
    scale = [1.0, sv, sv, 1.0, sv, sv]
    assert all(o == r * c or (math.isnan(o) and math.isnan(r)) for o, r, c in zip(out, ref, scale)), (out, ref)
