"""The pool/chain domain's factors (c2, A, w) and its text are read from the committed curves
(impactsym/kernels/domain_boundaries.py), not re-typed; here they are checked against the
derivation (derivations.domains) and the paper's printed forms."""

import sympy as sp

from derivations import domains as dd
from impactsym.domains import _c, _pool_factors, alpha, validity_domain


def test_factors_come_from_the_committed_curves_and_match_the_derivation():
    c2, A, w = _pool_factors()
    cond = dd._pool_conditions()  # the derivation's conditions for the pool at tau = 0, in c
    c = dd.c
    assert sp.simplify(c2.subs(_c, c) - cond["contacts"][1]["c"]) == 0  # w2+ = c2 p1
    assert sp.simplify(w.subs(_c, c) - cond["contacts"][0]["c"]) == 0  # w1+ = b1 + w p1
    assert sp.simplify(A.subs(_c, c) - cond["A"]) == 0
    assert cond["contacts"][0]["b"] == -1 and cond["contacts"][1]["b"] == 0


def test_domain_text_is_printed_from_the_factors():
    d = validity_domain("pool", "pi/5")
    h = next(b for b in d.boundaries if b.name == "h")
    assert "g - h = alpha^2 (2 alpha - cos(theta))^2 / (2 A (2 - alpha cos(theta))^2) >= 0" in h.condition
    d = validity_domain("chain3")
    h = next(b for b in d.boundaries if b.name == "h")
    assert "g - h = alpha^2 (2 alpha - 1)^2 / (2 A (2 - alpha)^2) >= 0" in h.condition


def test_bernoulli_prose_is_true_of_the_committed_curves():
    """The theta = 2pi/3 (Bernoulli) domain states two facts in words: R3 > 0 exactly for
    alpha < 2/5 or alpha > 1 (alpha >= 0), and e >= g1 implies Delta >= 0 (g1 >= h). Both are
    decided here from the committed expressions, exactly."""
    d = validity_domain("pool", "2*pi/3")
    by = {b.name: b for b in d.boundaries}
    assert "alpha < 2/5 or alpha > 1" in by["g3"].condition and "implied by e >= g1" in by["h"].condition
    a = sp.Symbol("a", real=True)
    R3 = sp.sympify(by["g3"].condition.split("(R3 = ")[1][:-1], locals={"alpha": alpha}).subs(alpha, a)
    positive = sp.solve_univariate_inequality(R3 > 0, a, relational=False).intersect(sp.Interval(0, sp.oo))
    assert positive == sp.Union(sp.Interval.Ropen(0, sp.Rational(2, 5)), sp.Interval.open(1, sp.oo))
    gap = sp.factor(sp.together((by["g1"].expression - by["h"].expression).subs(alpha, a)))
    below = sp.solve_univariate_inequality(gap < 0, a, relational=False).intersect(sp.Interval(0, sp.oo))
    assert below == sp.S.EmptySet, gap


def test_curves_are_simplified_as_simplify_does_with_the_nonnegative_alpha():
    """validity_domain simplifies g and h in an assumption-free alpha (the assumption only cost
    time); the form must stay simplify's own with alpha >= 0, which this pins for the chain and
    pi/3 (a SymPy whose simplify used alpha >= 0 on these curves would fail here)."""
    from impactsym.domains import _pool_g, _pool_h, _simplify_curve

    for cs in (sp.Integer(1), sp.Rational(1, 2)):
        for curve in (_pool_g(cs), _pool_h(cs)):
            assert sp.srepr(_simplify_curve(curve)) == sp.srepr(sp.simplify(curve))
