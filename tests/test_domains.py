"""Validity domains (Acary & Taha eqs. 19, 28-32): the derived inequalities, the paper's claims,
exact membership against brute-force evaluation of the law, kernels, and Fig. 3."""

from functools import lru_cache

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from derivations import domains as D
from derivations.impulse_ratio import general_quadratic
from impactsym.domains import validity_domain, plot_domain
from impactsym.errors import ImpactInputError
from impactsym.exact import certified_sign
from impactsym.models.acary_taha import chain3, pool
from impactsym.numbers import float_to_rational

al, e, c = D.alpha, D.e, D.c


# ------------------------------------------------------------------ derived claims
def test_eq19_verified():
    d = D.chain3_domain()
    assert d["eq19_verified"] and d["g_increasing"]
    assert d["alpha_min"] == sp.Rational(1, 2) and d["e_min"] == sp.Rational(1, 3)
    # alpha_max(e) solves g(alpha) = e and spans [1/2, 1]
    assert sp.simplify(d["g"].subs(al, d["alpha_max"]) - e) == 0
    assert d["alpha_max"].subs(e, sp.Rational(1, 3)) == sp.Rational(1, 2) and d["alpha_max"].subs(e, 1) == 1


def test_pool_claims_verdicts():
    v = {k: x["verdict"] for k, x in D.pool_claims().items()}
    assert v == {"v2_positive_iff": "confirmed", "eq29_g": "confirmed", "eq29_signature": "corrected",
                 "eq31_h": "corrected", "eq32_D2": "corrected", "g_minimum": "confirmed", "h_geq_g": "corrected",
                 "theta_gt_pi2_always_positive": "refuted", "domain_nonempty": "confirmed"}


def test_g_minus_h_identity_and_touching_points():
    g, h = D.pool_g(), D.pool_h()
    A = al**2 - al * c + 1
    assert sp.cancel(g - h - al**2 * (2 * al - c) ** 2 / (2 * A * (2 - al * c) ** 2)) == 0
    assert sp.simplify((g - h).subs(al, c / 2)) == 0 and sp.simplify((g - h).subs(al, 0)) == 0
    # the paper's spot check theta = pi/4, alpha = 1: g = 1 > h
    cs = sp.cos(sp.pi / 4)
    assert g.subs({c: cs, al: 1}) == 1 and certified_sign(h.subs({c: cs, al: 1}) - 1) < 0
    # the printed h differs from the derived one unless alpha = 1 or cos(theta) = 0
    assert sp.factor(D.printed_eq31_h() - h) == sp.factor(c * (al - 1) / (al**2 - al * c + 1))


def test_g_minimum_second_order():
    g = D.pool_g()
    d1 = sp.diff(g, al)
    assert sp.simplify(d1.subs(al, c / 2)) == 0
    d2 = sp.simplify(sp.diff(g, al, 2).subs(al, c / 2))
    for cs in (0, sp.Rational(1, 2), 1, -sp.Rational(1, 2)):
        assert d2.subs(c, cs) > 0
    assert sp.simplify(g.subs(al, c / 2) - (2 - c**2) / (4 - c**2)) == 0


def test_theta_beyond_pi_over_2_counterexample_with_the_law():
    # cos(theta) = -1/4, alpha = 2, e = 1: v1+ < 0 (the paper says "always positive")
    th = sp.acos(-sp.Rational(1, 4))
    sc = pool(th, 0, third_contact=False)
    law = general_quadratic(sc.M, sc.H, sc.v, 1, [2])
    w = (sc.H * law.vplus).applyfunc(sp.simplify)
    assert w[0] == -sp.Rational(6, 11) and w[1] > 0


# ------------------------------------------------------------------ brute force against the law
@lru_cache(maxsize=None)
def _symbolic_law(theta):
    if theta is None:
        sc, ratios = chain3(), [al]
    elif theta == 2 * sp.pi / 3:
        sc, ratios = pool(theta, 0, third_contact=True), [al, al]
    else:
        sc, ratios = pool(theta, 0, third_contact=False), [al]
    law = general_quadratic(sc.M, sc.H, sc.v, e, ratios)
    return law, sc.H * law.vplus


def law_is_valid(theta, a, ee) -> bool:
    """Brute force: evaluate the general law exactly at (alpha, e) and check eq. 28 directly."""
    if ee < 0 or ee > 1 or a < 0:
        return False
    law, w = _symbolic_law(theta)
    sub = {al: a, e: ee}
    if certified_sign(law.D.subs(sub)) < 0:
        return False
    if certified_sign(law.p1.subs(sub)) < 0:
        return False
    # certified_sign decides each sign exactly as substituted (interval enclosure, exact zero test
    # at a boundary point); rationalizing the denominators first (radsimp) gave the same verdicts at
    # three times the cost
    return all(certified_sign(x.subs(sub)) >= 0 for x in w)


THETAS = [None, sp.pi / 4, sp.pi / 3, sp.pi / 2, 2 * sp.pi / 3]
GRID_A = [sp.Rational(k, 8) for k in range(0, 11)]
GRID_E = [sp.Rational(k, 9) for k in range(0, 10)]


@pytest.mark.parametrize("theta", THETAS, ids=["chain3", "pi/4", "pi/3", "pi/2", "2pi/3"])
def test_domain_equals_brute_force_on_a_grid(theta):
    dom = validity_domain("chain3") if theta is None else validity_domain("pool", theta)
    mismatches = [(a, ee) for a in GRID_A for ee in GRID_E if dom.contains(a, ee) != law_is_valid(theta, a, ee)]
    assert mismatches == []
    assert any(dom.contains(a, ee) for a in GRID_A for ee in GRID_E)


def test_boundary_points_are_in_the_domain():
    # the corner of eq. 19 and points exactly on g
    dom = validity_domain("chain3")
    assert dom.contains("1/2", "1/3") and law_is_valid(None, sp.Rational(1, 2), sp.Rational(1, 3))
    assert dom.contains(1, 1) and law_is_valid(None, 1, 1)
    a = sp.Rational(3, 4)
    on_g = D.chain3_domain()["g"].subs(al, a)
    assert dom.contains(a, on_g) and law_is_valid(None, a, on_g)
    assert not dom.contains(a, on_g - sp.Rational(1, 10**6)) and not law_is_valid(None, a, on_g - sp.Rational(1, 10**6))


@settings(max_examples=15, deadline=None)
@given(a=st.fractions(0, 2, max_denominator=40), ee=st.fractions(0, 1, max_denominator=40),
       k=st.sampled_from([0, 1, 2]))
@example(a=__import__("fractions").Fraction(1, 2), ee=__import__("fractions").Fraction(1, 3), k=0)
def test_domain_membership_property(a, ee, k):
    theta = [None, sp.pi / 4, sp.pi / 2][k]
    dom = validity_domain("chain3") if theta is None else validity_domain("pool", theta)
    A, E = sp.Rational(a.numerator, a.denominator), sp.Rational(ee.numerator, ee.denominator)
    assert dom.contains(A, E) == law_is_valid(theta, A, E)


def test_domain_for_every_theta():
    for t, lo, emin in ((0, sp.Rational(1, 2), sp.Rational(1, 3)), (sp.pi / 3, sp.Rational(1, 4), sp.Rational(7, 15)),
                        (sp.pi / 2, 0, sp.Rational(1, 2)), (7 * sp.pi / 12, 0, sp.Rational(1, 2)),
                        (2 * sp.pi / 3, 0, sp.Rational(5, 9))):
        r = validity_domain("pool", t).region
        assert sp.simplify(r["alpha"][0] - lo) == 0 and r["alpha"][1] == 1, t
        assert sp.simplify(r["e"][0] - emin) == 0 and r["empty"] is False, t
    sym = validity_domain("pool")
    assert len(sym.sweep) == 7 and sym.as_json()["theta_sweep"][0]["e"] == ["1/3", "1"]


def test_bad_input():
    with pytest.raises(ImpactInputError, match="theta"):
        validity_domain("pool", "3")
    with pytest.raises(ImpactInputError, match="theta"):
        validity_domain("pool", "-1/10")
    with pytest.raises(ImpactInputError, match="scene"):
        validity_domain("bernoulli")
    with pytest.raises(ImpactInputError, match="theta"):
        validity_domain("chain3", "pi/4")
    with pytest.raises(ImpactInputError, match="theta"):
        validity_domain("pool", "nan")


# ------------------------------------------------------------------ kernels and Fig. 3
def test_chain3_alpha_max_kernel_against_mpmath():
    from impactsym.kernels import chain3_alpha_max

    es = np.array([1 / 3 + 1e-9, 0.4, 0.5, 0.75, 0.9, 1.0])
    got = chain3_alpha_max(es)
    mpmath.mp.dps = 60
    for x, y in zip(es, got):
        ex = mpmath.mpf(float_to_rational(x).p) / float_to_rational(x).q
        ref = (2 * ex - 2 - mpmath.sqrt(6 * ex - 2)) / (ex - 3)
        assert abs(mpmath.mpf(y) - ref) <= 1e-13 * abs(ref)


def test_plot_domain_writes_png_and_draws_the_derived_curves(tmp_path):
    out = plot_domain("pi/4", tmp_path / "fig3.png", points=101)
    data = (tmp_path / "fig3.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    g, h = D.pool_g(sp.cos(sp.pi / 4)), D.pool_h(sp.cos(sp.pi / 4))
    for i in (0, 17, 50, 73, 100):
        a = float_to_rational(out["alpha"][i])
        for curve, expr in (("g", g), ("h", h)):
            ref = sp.N(expr.subs(al, a), 50)
            # the kernel gets float(pi/4) and float alpha: a few ulps of the curve value
            assert abs(out[curve][i] - float(ref)) <= 1e-14 * max(1.0, abs(float(ref))), (curve, i)
    assert out["e_min"] == sp.Rational(3, 7)
    with pytest.raises(ImpactInputError):
        plot_domain("2*pi/3", tmp_path / "x.png")


@pytest.mark.parametrize("theta", [None, sp.pi / 3], ids=["chain3", "pi/3"])
def test_domain_agrees_with_the_impulse_ratio_law_validity(theta):
    """Cross-check against the package's general law (its own validity verdict)."""
    from impactsym.laws.impulse_ratio import impulse_ratio_law

    dom = validity_domain("chain3") if theta is None else validity_domain("pool", theta)
    sc = chain3() if theta is None else pool(theta, 0, third_contact=False)
    for a in GRID_A[::2]:
        for ee in GRID_E[1::2]:
            r = impulse_ratio_law(sc.M, sc.H, sc.v, ee, [a], allow_invalid=True)
            assert dom.contains(a, ee) == bool(r.valid), (a, ee, r.violations)
