"""Every closed form of Acary & Taha secs. 3-4 against the general solver (exactly, symbolically),
and against the paper's print (transcriptions), with the proofs of each mismatch."""

import pytest
import sympy as sp

from derivations import chain3 as C
from derivations import pool as P
from derivations.impulse_ratio import general_quadratic
from impactsym.models.acary_taha import chain3, pool

al, e = C.alpha, C.e


def _zero(expr) -> bool:
    return sp.simplify(sp.cancel(sp.together(expr))) == 0


# ------------------------------------------------------------------ chain (eqs. 13-18)
def test_chain3_equal_masses_equals_general_solver():
    m = C.SYMBOLS["m"]
    sc = chain3((m, m, m), (1, 0, 0))
    law = general_quadratic(sc.M, sc.H, sc.v, e, [al])
    cf = C.chain3_equal_masses()
    assert _zero(cf["p1"] - law.p[0]) and _zero(cf["p2"] - law.p[1])
    for name, vp in zip(C.VELOCITY_NAMES, law.vplus):
        assert _zero(cf[name] - vp), name
    assert sp.expand(cf["Delta"] - law.D) == 0


def test_chain3_general_equals_general_solver():
    s = C.SYMBOLS
    sc = chain3((s["m1"], s["m2"], s["m3"]), (s["v1"], s["v2"], s["v3"]))
    law = general_quadratic(sc.M, sc.H, sc.v, e, [al])
    g = C.chain3_general()
    assert _zero(g["Delta"] - law.D)
    root = sp.Symbol("r")  # compare as affine functions of sqrt(Delta)
    for name, vp in zip(C.VELOCITY_NAMES, law.vplus):
        diff = (g[name] - vp).subs(sp.sqrt(law.D), root).subs(sp.sqrt(g["Delta"]), root)
        assert _zero(diff), name
    assert _zero((g["p1"] - law.p[0]).subs(sp.sqrt(law.D), root).subs(sp.sqrt(g["Delta"]), root))


def test_chain3_general_reduces_to_eq18():
    g, cf = C.chain3_general(), C.chain3_equal_masses()
    s = C.SYMBOLS
    sub = {s["m1"]: s["m"], s["m2"]: s["m"], s["m3"]: s["m"], s["v1"]: 1, s["v2"]: 0, s["v3"]: 0}
    for k in ("p1", "p2", *C.VELOCITY_NAMES):
        assert _zero(sp.simplify(g[k].subs(sub)) - cf[k]), k


def test_eq18_comparison_and_q3_sign_proof():
    assert C.compare_eq18() == {"p1": True, "p2": True, "q1+": True, "q2+": True, "q3+": False, "Delta": True}
    derived, printed = C.chain3_equal_masses(), C.printed_eq18()
    # derived q3+ = -printed q3+ exactly (sign misprint)
    assert _zero(derived["q3+"] + printed["q3+"])
    # momentum proves it: the derived state conserves it, the printed one does not
    assert C.momentum_energy_residuals(derived) == {"momentum": 0, "energy": 0}
    res = C.momentum_energy_residuals(printed)
    assert res["momentum"] != 0 and res["momentum"].subs({al: sp.Rational(1, 2), e: 1}) == -sp.Rational(4, 3) * C.SYMBOLS["m"]


def test_chain3_paper_numbers():
    cf = C.chain3_equal_masses()
    # alpha = 1, e = 1 gives (0, 0, 1) (sec. 3.3)
    at = {al: 1, e: 1}
    assert [sp.simplify(cf[k].subs(at)) for k in C.VELOCITY_NAMES] == [0, 0, 1]
    # alpha = 0.95, e = 1: exactly (-19/381, 20/381, 380/381) ~ (-0.0499, 0.0525, 0.9974); the paper prints
    # [-0.05, 0.05, 0.99] (0.99 is 0.9974 truncated; rounded it would be 1.00)
    at = {al: sp.Rational(19, 20), e: 1}
    vals = [sp.simplify(cf[k].subs(at)) for k in C.VELOCITY_NAMES]
    assert vals == [sp.Rational(-19, 381), sp.Rational(20, 381), sp.Rational(380, 381)]


def test_stable_root_branches_equal_the_physical_root():
    A, c, b = sp.symbols("A c b", positive=True)
    B = sp.Symbol("B", real=True)
    s = sp.Symbol("s", nonnegative=True)  # s = sqrt(D), s^2 = B^2 - 4AC
    pw = C.stable_root(A, B, c)
    assert isinstance(pw, sp.Piecewise) and len(pw.args) == 2
    assert pw.args[0][1] == (B <= 0) and pw.args[1][1] == sp.true
    for (expr, _cond), Bval in zip(pw.args, (-b, b)):  # each branch on its side: B = -b <= 0, B = b > 0
        D = Bval**2 - 4 * A * c
        diff = expr.subs(B, Bval).subs(sp.sqrt(D), s) - (-Bval + s) / (2 * A)
        num = sp.expand(sp.numer(sp.together(diff)))
        assert sp.expand(num.subs(s**2, D)) == 0
    # B = 0 (first branch): sqrt(D)/(2A)
    assert sp.simplify(pw.args[0][0].subs(B, 0) - sp.sqrt(-4 * A * c) / (2 * A)) == 0


# ------------------------------------------------------------------ pool (eqs. 27, 33-36)
def test_pool_tau0_equals_general_solver_and_eq27():
    sc, law = P.pool_law()
    cf = P.pool_tau0()
    for name, vp in zip(P.VELOCITY_NAMES, law.vplus):
        assert _zero(sp.expand_trig(cf[name] - vp)), name
    assert all(P.compare(cf, P.printed_eq27()).values())


def test_pool_tau0_at_theta0_is_the_chain():
    cf, ch = P.pool_tau0(), C.chain3_equal_masses()
    m = C.SYMBOLS["m"]
    for pk, ck in (("x1+", "q1+"), ("x2+", "q2+"), ("x3+", "q3+"), ("p1", "p1"), ("p2", "p2")):
        assert _zero(cf[pk].subs(P.theta, 0) - ch[ck].subs(m, 1)), pk
    assert cf["y1+"].subs(P.theta, 0) == 0 and cf["y2+"].subs(P.theta, 0) == 0


def test_eq33_is_theta_pi_over_3_with_two_misprints():
    r = P.eq33_theta()
    assert r["theta"] == [sp.pi / 3]
    assert r["misprinted"] == ["y1+", "x2+"]
    assert not any(v for k, v in r["at_pi_over_2"].items() if k != "y3+")
    derived = P.pool_at_theta(sp.pi / 3, 1)
    assert _zero(derived["y1+"] - sp.sqrt(3) * (2 * al**2 - al) / (2 * (2 * al**2 - al + 2)))
    assert _zero(derived["x2+"] - (1 - 2 * al) / (2 * al**2 - al + 2))
    # the printed state violates momentum in x and y (pre-impact (1/2, sqrt(3)/2))
    res = P.momentum_energy_residuals(P.printed_eq33(), (sp.Rational(1, 2), sp.sqrt(3) / 2))
    assert res["px"] != 0 and res["py"] != 0
    res = P.momentum_energy_residuals(derived, (sp.Rational(1, 2), sp.sqrt(3) / 2))
    assert res == {"px": 0, "py": 0, "energy": 0}


def test_eq34_and_eq36_match():
    assert all(P.compare(P.pool_at_theta(sp.pi / 2), P.printed_eq34()).values())
    assert all(P.compare(P.pool_any_tau(sp.pi / 2), P.printed_eq36()).values())


def test_eq35_x2_misprint_and_momentum_proof():
    d = P.pool_any_tau(0)
    assert P.compare(d, P.printed_eq35()) == {"x1+": True, "y1+": True, "x2+": False, "y2+": True,
                                               "x3+": True, "y3+": True}
    vm = (sp.cos(P.tau), -sp.sin(P.tau))
    for eps in (1, -1):
        res_d = P.momentum_energy_residuals({k: d[k].subs(P.eps, eps) for k in P.VELOCITY_NAMES}, vm)
        assert _zero(res_d["px"]) and _zero(res_d["py"])
    res_p = P.momentum_energy_residuals({k: v.subs(P.eps, 1) for k, v in P.printed_eq35().items()}, vm)
    assert _zero(res_p["px"] - 2 * al * sp.cos(P.tau) / (al**2 - al + 1))


def test_pool_any_tau_equals_solver_on_both_sides_of_cos_tau():
    sc, law = P.pool_law(sp.pi / 3, P.tau, 1)
    d = P.pool_any_tau(sp.pi / 3)
    for t, eps in ((sp.pi / 5, 1), (4 * sp.pi / 5, -1), (-sp.pi / 7, 1)):
        for name, vp in zip(P.VELOCITY_NAMES, law.vplus):
            assert _zero((d[name].subs(P.eps, eps) - vp).subs(P.tau, t)), (name, t)


def test_epsilon_device():
    r = P.epsilon_device()
    assert r["proven"] and r["selects_no_impact"] == 0
    # for cos(tau) < 0 the physical root gives v+ = v- (no impact)
    d = P.pool_any_tau(sp.pi / 4)
    sc = pool(sp.pi / 4, P.tau)
    for name, vm in zip(P.VELOCITY_NAMES, sc.v):
        assert _zero(sp.expand_trig(d[name].subs(P.eps, -1) - vm))


# ------------------------------------------------------------------ Bernoulli (eq. 37)
def test_bernoulli_equal_and_independent_ratios_equal_solver():
    a13 = P.alpha13
    for independent, ratios in ((False, (al, al)), (True, (al, a13))):
        sc = pool(2 * sp.pi / 3, -sp.pi / 6, third_contact=True)
        law = general_quadratic(sc.M, sc.H, sc.v, 1, list(ratios))
        d = P.bernoulli_closed_form(independent=independent)
        for name, vp in zip(P.VELOCITY_NAMES, law.vplus):
            assert _zero(sp.radsimp(d[name] - vp)), name
        for j, name in enumerate(("p1", "p2", "p3")):
            assert _zero(sp.radsimp(d[name] - law.p[j])), name
    d = P.bernoulli_closed_form()
    assert _zero(d["y2+"] - 3 / (2 * (5 * al**2 + 2 * al + 2)))
    assert _zero(d["x2+"] + sp.sqrt(3) * (1 + 2 * al) / (2 * (5 * al**2 + 2 * al + 2)))
    # energy and momentum of the derived state
    res = P.momentum_energy_residuals(d, (-sp.sqrt(3) / 2, sp.Rational(1, 2)))
    assert all(_zero(v) for v in res.values())


def test_bernoulli_general_e_and_tau_equals_solver_at_points():
    sc = pool(2 * sp.pi / 3, -sp.pi / 4, third_contact=True)
    a, b, ee = sp.Rational(1, 3), sp.Rational(1, 5), sp.Rational(9, 10)
    law = general_quadratic(sc.M, sc.H, sc.v, ee, [a, b])
    d = P.bernoulli_closed_form(-sp.pi / 4, ee, independent=True)
    for name, vp in zip(P.VELOCITY_NAMES, law.vplus):
        got = d[name].subs({al: a, P.alpha13: b})
        assert sp.N(got - vp, 60) == 0 or abs(sp.N(got - vp, 60)) < sp.Float("1e-55"), name


def test_eq37_no_reading_reproduces_the_print():
    r = P.eq37_analysis()
    assert r["matches"] == []
    assert len(r["readings"]) == 12
    # the print as printed violates x-momentum for every incidence: its x-sum depends on alpha
    assert sp.diff(r["px_printed"], al) != 0 and r["py_printed"] == sp.Rational(1, 2)
    # the momentum repair has ratios (alpha, alpha/2) and creates energy
    assert r["momentum_repaired"] == (0, 0)
    assert r["implied_ratios"] == (al, al / 2)
    assert _zero(r["energy_ratio"] - 1 - 12 * al * (al + 1) / (4 * al**2 + al + 4) ** 2)
    # the printed denominator appears only for alpha13 in {-1/2, -alpha/2} (negative impulses)
    A = P.bernoulli_closed_form(independent=True)["A"]  # velocity denominators are 4A
    b = sp.Symbol("b")  # unrestricted sign (alpha13 itself is declared nonnegative)
    sols = sp.solve(sp.expand(4 * A.subs(P.alpha13, b) - (4 * al**2 + al + 4)), b)
    assert set(sols) == {-sp.Rational(1, 2), -al / 2}
