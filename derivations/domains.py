"""Validity domains of the impulse-ratio law (Acary & Taha eqs. 19, 28–32), derived exactly.

For a scene ``(M, H, q̇⁻)`` with ratios ``a = (1, α, …)`` the law (eq. 38) gives
``p₁ = (−B + √Δ)/(2A)`` with ``Δ = B² − 4A(1 − e)T⁻`` (*linear in e*). The conditions of eq. 28 are

* existence, ``Δ ≥ 0``  ⟺  ``e ≥ h(α) := 1 − B²/(4AT⁻)``;
* ``p ≥ 0``: ``p₁ > 0`` (for ``B < 0``) and every ratio ``≥ 0``;
* ``w_j⁺ = H_j q̇⁺ ≥ 0`` on every closed contact. With ``b_j = H_j q̇⁻`` and
  ``c_j = (H M⁻¹ Hᵀ a)_j``, ``w_j⁺ = b_j + c_j p₁``. For ``c_j > 0`` this is ``√Δ ≥ R_j`` with
  ``R_j = B − 2A b_j / c_j``, i.e. ``R_j ≤ 0`` or ``e ≥ g_j(α) := 1 − (B² − R_j²)/(4AT⁻)``;
  for ``c_j < 0`` it is ``√Δ ≤ R_j``; for ``c_j = 0`` it is ``b_j ≥ 0``.

:func:`admissibility_conditions` derives ``h``, ``b_j``, ``c_j``, ``R_j``, ``g_j`` for any scene;
the functions below specialize it to the chain (eq. 19) and the pool (eqs. 29–32), prove the
paper's claims or their corrections, and describe the domain for every θ.

Findings (proved below, see :func:`pool_claims`)
------------------------------------------------
* eq. 19 (chain) is **correct**: ``{1/3 ≤ e ≤ 1, 1/2 ≤ α ≤ (2e − 2 − √(6e − 2))/(e − 3)}``.
* eq. 29 (g) is correct as a function of α₁₂ (its printed signature ``g: [0,1] → R, e ↦ …``
  names the wrong variable: it maps α₁₂ to e).
* eq. 31 (h) is misprinted: ``2α² − 2cos θ + 1`` should read ``2α² − 2α cos θ + 1``.
* eq. 32 (D₂) prints ``g`` where ``h`` is meant: ``D₂ = {α ≥ 0, h(α) ≤ e ≤ 1}``.
* the minimum of g is at ``α = cos θ/2`` with value ``(2 − cos²θ)/(4 − cos²θ)`` — correct for
  ``θ ≤ π/2`` (``cos θ ≥ 0``); for ``θ > π/2`` the minimum over ``α ≥ 0`` is ``g(0) = 1/2``.
* "∀α ∈ [cos θ/2, ∞[ h(α) ≥ g(α)" is **reversed**: ``g − h = α²(2α − cos θ)²/(2A(2 − α cos θ)²)``
  ``≥ 0`` for every α, with equality only at ``α = 0`` and ``α = cos θ/2`` (where g and h touch);
  so ``e ≥ g`` implies ``Δ ≥ 0`` and ``D = D₁ ∩ D₂ = D₁``: that is why only g needs drawing.
* "positiveness of v₂⁺ implies α ≥ cos θ/2 for θ < π/2": correct (``w₂⁺ = (2α − cos θ)p₁``).
* "When θ > π/2 the relative normal velocities are always positive irrespective of α and e":
  **false** for ``v₁⁺``; true only for ``v₂⁺``. ``v₁⁺ ≥ 0`` still needs ``e ≥ g(α)`` (e.g.
  ``cos θ = −1/4``, ``α = 2``, ``e = 1`` gives ``v₁⁺ = −6/11``).

Examples
--------
>>> d = chain3_domain()
>>> d["g"], d["alpha_min"], d["e_min"]
((3*alpha**2 - 4*alpha + 2)/(alpha - 2)**2, 1/2, 1/3)
>>> d["eq19_verified"]
True
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import sympy as sp

from .memo import simplify
from .rational_zero import is_zero

from impactsym.models.acary_taha import chain3, pool

from .codegen import ScalarKernel, render_expressions, render_family
from .impulse_ratio import general_quadratic

from impactsym.arithmetic.remembered import solve_remembered
from impactsym.errors import DerivationError

__all__ = [
    "admissibility_conditions",
    "chain3_domain",
    "chain3_alpha_max_expr",
    "pool_g",
    "pool_h",
    "printed_eq29_g",
    "printed_eq31_h",
    "pool_claims",
    "pool_domain_at",
    "bernoulli_tau0_domain",
    "pool_tau_conditions",
    "boundary_expressions",
    "kernels",
    "generate",
]

alpha = sp.Symbol("alpha", nonnegative=True)
e = sp.Symbol("e", positive=True)
theta = sp.Symbol("theta", real=True)
tau = sp.Symbol("tau", real=True)  # the pool's incidence angle
c = sp.Symbol("c", real=True)  # cos θ, the pool's kinetic-angle parameter (eq. 42: cos θ₁₂ = −c/2)


def admissibility_conditions(scene, ratios, restitution=e) -> dict:
    """Derive the existence and admissibility conditions of eq. 28 for one scene.

    Parameters
    ----------
    scene : :class:`impactsym.scenes.Scene` (numbers or symbols)
    ratios : the ``k − 1`` impulse ratios
    restitution : the energetic coefficient symbol

    Returns
    -------
    dict
        ``"h"`` (``Δ ≥ 0 ⟺ e ≥ h``), ``"A"``, ``"B"``, ``"T"`` (``T⁻``), and ``"contacts"``: one dict
        per closed contact with ``b`` (``H_j q̇⁻``), ``c`` (``(HM⁻¹Hᵀa)_j``), and, when ``b ≠ 0``,
        ``R`` and ``g`` (``w_j⁺ ≥ 0 ⟺ R ≤ 0 or e ≥ g`` where ``c > 0``).

    Examples
    --------
    >>> cond = admissibility_conditions(chain3(), [alpha])
    >>> cond["h"]
    (2*alpha**2 - 2*alpha + 1)/(2*(alpha**2 - alpha + 1))
    >>> [(x["b"], x["c"]) for x in cond["contacts"]]
    [(-1, 2 - alpha), (0, 2*alpha - 1)]
    """
    law = general_quadratic(scene.M, scene.H, scene.v, restitution, list(ratios))
    T = simplify((scene.v.T * scene.M * scene.v)[0, 0] / 2)
    # Δ is linear in e: Δ = B² − 4A(1 − e)T⁻ (checked, not assumed)
    if not (is_zero(law.D - (law.B**2 - 4 * law.A * (1 - restitution) * T))):
        raise DerivationError('derivation check failed: sp.simplify(law.D - (law.B**2 - 4 * law.A * (1 - restitution) * T)) == 0')
    h = _tidy(1 - law.B**2 / (4 * law.A * T))
    b = scene.H * scene.v
    cvec = scene.H * scene.M.LUsolve(scene.H.T * law.ratios)
    contacts = []
    for j in range(scene.H.rows):
        bj, cj = _tidy(b[j]), _tidy(cvec[j])
        item = {"b": bj, "c": cj}
        if bj != 0:
            R = _tidy(law.B - 2 * law.A * bj / cj)
            item["R"] = R
            item["g"] = _tidy(1 - (law.B**2 - R**2) / (4 * law.A * T))
        contacts.append(item)
    return {"h": h, "A": _tidy(law.A), "B": law.B, "T": T, "contacts": contacts}


def _tidy(x):
    """The printed form of a condition: ``factor`` of the simplified expression, with ``sin²θ``
    replaced by ``1 − cos²θ`` first. A rational function of the symbols and ``cos θ`` alone goes
    straight to ``factor(cancel(x))`` (:func:`_factored_rational`): ``simplify`` and ``trigsimp``
    cost 0.01-0.2 s each here, and ``cancel`` is a normal form of a rational function, so its
    ``factor`` does not depend on the form the condition came in. (Checked when this path was
    added: on every condition of the audit, 24 calls, the result is structurally identical, by
    ``srepr``, to the former ``factor(simplify(trigsimp(x)))``; the generated kernels are unchanged.)
    The conditions that keep a sine or cosine (the pool at a symbolic incidence τ, four of them)
    go to ``factor(simplify(x))`` without a ``trigsimp`` first (``simplify`` runs its own): the
    same expressions, srepr for srepr, in about 0.4 s instead of 0.7 s."""
    x = sp.sympify(x)
    if x.has(sp.sin, sp.cos):
        x = sp.expand(x).subs(sp.sin(theta) ** 2, 1 - sp.cos(theta) ** 2)
        fast = _factored_rational(x)
        if fast is not None:
            return fast
        if x.has(tau):
            fast = _factored_in_tau(x)
            if fast is not None:
                return fast
    else:
        fast = _factored_rational(x)
        if fast is not None:
            return fast
    return sp.factor(simplify(x))


def _factored_in_tau(x):
    """The conditions at a symbolic incidence τ: ``x`` (``sin²θ`` already replaced) written in
    ``cos τ`` alone (``sin²τ = 1 − cos²τ``) and in ``sin τ`` alone (``cos²τ = 1 − sin²τ``), each a
    rational function of the symbols, ``cos θ`` and that one function of τ: ``factor(cancel(·))``
    of each form (:func:`_factored_rational`, both identities, so both equal ``x``), and of the two
    the one with fewer operations (``count_ops``, what ``simplify`` measures); None when neither
    form is such a rational function, or when the two tie with different forms (``simplify``
    decides then: ``h``, whose two forms both count 18).

    ``simplify`` searches for this (0.1-0.35 s for each condition of :func:`pool_tau_conditions`);
    ``factor`` of the form it returned is the one chosen here, srepr for srepr (checked on the
    conditions this path decides, ``g1`` and ``c`` of contact 1-2: :func:`pool_tau_conditions`,
    the committed ``domain_boundaries`` and every generated kernel are byte-identical; measured
    0.87 -> 0.66 s CPU for :func:`pool_tau_conditions` in a fresh process).

    >>> _factored_in_tau(1 - sp.cos(tau)**2 / 2)  # 1 - cos²τ/2 = (sin²τ + 1)/2: one operation fewer
    (sin(tau)**2 + 1)/2
    >>> _factored_in_tau(alpha * sp.cos(tau) + sp.sin(tau)) is None  # sin τ and cos τ both odd
    True
    """
    s, c = sp.sin(tau), sp.cos(tau)
    y = sp.expand(x)
    forms = []
    for sub, keep in (({s**2: 1 - c**2}, c), ({c**2: 1 - s**2}, s)):
        z = sp.expand(y.subs(sub))
        if z.has(s if keep is c else c):
            continue
        f = _rational_in(z, keep)
        if f is not None:
            forms.append(f)
    if not forms:
        return None
    if len(forms) == 1:
        return forms[0]
    (a, b) = forms
    na, nb = sp.count_ops(a), sp.count_ops(b)
    if na != nb:
        return a if na < nb else b
    return a if a == b else None


def _rational_in(x, f):
    """``factor(cancel(x))`` when ``x`` is a rational function of its symbols, ``cos θ`` and the
    one function ``f`` of τ (rational coefficients, nothing else), else None."""
    allowed = (sp.cos(theta), f)
    for node in sp.preorder_traversal(x):
        if node.is_Symbol or node.is_Rational or node.is_Add or node.is_Mul or node in allowed:
            continue
        if node.is_Pow and node.exp.is_Integer:
            continue
        return None
    return sp.factor(sp.cancel(x))


def _factored_rational(x):
    """``factor(cancel(x))`` when ``x`` is a rational function of its symbols and ``cos θ`` (rational
    coefficients, no other function, no radical), else None.

    >>> _factored_rational(1 - 1 / (2 * alpha**2 - 2 * alpha * sp.cos(theta) + 2))
    (2*alpha**2 - 2*alpha*cos(theta) + 1)/(2*(alpha**2 - alpha*cos(theta) + 1))
    >>> _factored_rational(sp.sqrt(2) * alpha) is None, _factored_rational(sp.sin(theta)) is None
    (True, True)
    """
    cos_t = sp.cos(theta)
    for node in sp.preorder_traversal(x):
        if node.is_Symbol or node.is_Rational or node.is_Add or node.is_Mul or node == cos_t:
            continue
        if node.is_Pow and node.exp.is_Integer:
            continue
        return None
    return sp.factor(sp.cancel(x))


# ------------------------------------------------------------------ the chain (eq. 19)
@lru_cache(maxsize=None)
def chain3_domain() -> dict:
    """The chain's domain (unit-speed ball 1, equal masses), derived; eq. 19 verified.

    Derivation: contact 2–3 has ``b = 0``, ``c = 2α − 1``: ``w₂⁺ ≥ 0 ⟺ α ≥ 1/2``. Contact 1–2
    has ``b = −1``, ``c = 2 − α`` (> 0 for α < 2; for α ≥ 2, ``w₁⁺ = −1 + c p₁ < 0``),
    ``R = α(2α − 1)/(2 − α) ≥ 0`` on ``[1/2, 2)``, so ``w₁⁺ ≥ 0 ⟺ e ≥ g(α)``. ``g`` increases on
    ``[1/2, 2)`` (``g′ = 4(2α − 1)/(2 − α)³``, checked), ``g(1/2) = 1/3``, ``g(1) = 1``; and ``g − h ≥ 0``
    (so Δ ≥ 0 is implied). With ``e ≤ 1``: ``α ∈ [1/2, 1]``, ``e ∈ [g(α), 1]``, equivalently
    ``e ∈ [1/3, 1]``, ``α ∈ [1/2, α_max(e)]`` with ``α_max`` the root of ``g(α) = e`` in ``[1/2, 1]``.

    Returns
    -------
    dict: ``g``, ``h``, ``g_minus_h``, ``alpha_min``, ``alpha_max`` (expression in e), ``e_min``,
    ``eq19_alpha_max`` (transcription), ``eq19_verified``, ``g_increasing``.
    """
    cond = admissibility_conditions(chain3(), [alpha])
    c1, c2 = cond["contacts"]
    if not (c2["b"] == 0 and sp.expand(c2["c"] - (2 * alpha - 1)) == 0):
        raise DerivationError('derivation check failed: c2["b"] == 0 and sp.expand(c2["c"] - (2 * alpha - 1)) == 0')
    g, h = c1["g"], cond["h"]
    alpha_min = solve_remembered(c2["c"], alpha)[0]
    dg = sp.factor(sp.diff(g, alpha))
    # g′ = 4(2α − 1)/(2 − α)³ > 0 on (1/2, 2): no root of numerator or denominator inside
    g_increasing = _positive_on(dg, sp.Rational(1, 2), 2)
    e_min = simplify(g.subs(alpha, alpha_min))
    amax = chain3_alpha_max_expr()
    printed = (2 * e - 2 - sp.sqrt(6 * e - 2)) / (e - 3)
    verified = (
        is_zero(amax - printed)
        and e_min == sp.Rational(1, 3)
        and is_zero(g.subs(alpha, 1) - 1)
        and is_zero(sp.factor(g - h) - alpha**2 * (2 * alpha - 1) ** 2 / (2 * cond["A"] * (2 - alpha) ** 2))
        and bool(g_increasing)
    )
    return {"g": g, "h": h, "g_minus_h": sp.factor(g - h), "alpha_min": alpha_min, "alpha_max": amax,
            "e_min": e_min, "eq19_alpha_max": printed, "eq19_verified": bool(verified),
            "g_increasing": bool(g_increasing), "dg": dg}


def _positive_on(expr, lo, hi) -> bool:
    """``expr > 0`` on the open interval ``(lo, hi)``: no real root of numerator or denominator
    inside, and positive at the midpoint (exact)."""
    num, den = sp.fraction(sp.together(expr))
    for poly in (num, den):
        for r in sp.Poly(poly, alpha).real_roots():
            if lo < r < hi:
                return False
    return bool(expr.subs(alpha, (lo + hi) / 2) > 0)


@lru_cache(maxsize=None)
def chain3_alpha_max_expr():
    """``α_max(e)``: the root of ``g(α) = e`` in ``[1/2, 1]`` for ``1/3 ≤ e ≤ 1`` (eq. 19), derived.

    ``g(α) = e`` ⟺ ``(e − 3)α² + 4(1 − e)α + 4e − 2 = 0``; of its two roots
    ``(2e − 2 ± √(6e − 2))/(e − 3)`` the ``−`` one is ≥ 1/2 (``e − 3 < 0``).

    Examples
    --------
    >>> chain3_alpha_max_expr()
    (2*e - sqrt(6*e - 2) - 2)/(e - 3)
    """
    g = admissibility_conditions(chain3(), [alpha])["contacts"][0]["g"]
    a = sp.Symbol("a", real=True)
    roots = solve_remembered(sp.numer(sp.together(g.subs(alpha, a) - e)), a)
    # choose the root that is 1 at e = 1 and 1/2 at e = 1/3 (the branch inside [1/2, 1])
    picked = [r for r in roots if is_zero(r.subs(e, 1) - 1) and is_zero(r.subs(e, sp.Rational(1, 3)) - sp.Rational(1, 2))]
    if not (len(picked) == 1):
        raise DerivationError(roots)
    r = picked[0]
    return simplify(r) if sp.count_ops(simplify(r)) <= sp.count_ops(r) else r


# ------------------------------------------------------------------ the pool (eqs. 29–32)
@lru_cache(maxsize=None)
def _pool_conditions():
    cond = admissibility_conditions(pool(theta, 0, third_contact=False), [alpha])
    return {k: (v.subs(sp.cos(theta), c) if isinstance(v, sp.Basic) else v) for k, v in cond.items()} | {
        "contacts": [{k: v.subs(sp.cos(theta), c) for k, v in x.items()} for x in cond["contacts"]]}


def pool_g(cos_theta=c):
    """``g(α)``: ``v₁⁺ = 0`` on ``e = g(α)`` (eq. 29), derived, in terms of ``c = cos θ``.

    Examples
    --------
    >>> pool_g()
    (alpha**2*c**2 + 2*alpha**2 - 4*alpha*c + 2)/(alpha**2*c**2 - 4*alpha*c + 4)
    """
    g = _pool_conditions()["contacts"][0]["g"]
    g = sp.factor(sp.expand(sp.numer(g))) / sp.factor(sp.expand(sp.denom(g)))
    g = sp.expand(sp.numer(g)) / sp.expand(sp.denom(g))
    return g.subs(c, cos_theta)


def pool_h(cos_theta=c):
    """``h(α)``: ``Δ = 0`` on ``e = h(α)`` (eq. 31, corrected), derived.

    Examples
    --------
    >>> pool_h()
    (2*alpha**2 - 2*alpha*c + 1)/(2*(alpha**2 - alpha*c + 1))
    """
    return _pool_conditions()["h"].subs(c, cos_theta)


def printed_eq29_g(cos_theta=c):
    """TRANSCRIPTION of eq. 29 (comparison only)."""
    return ((2 + cos_theta**2) * alpha**2 - 4 * cos_theta * alpha + 2) / (cos_theta**2 * alpha**2 - 4 * cos_theta * alpha + 4)


def printed_eq31_h(cos_theta=c):
    """TRANSCRIPTION of eq. 31 (comparison only): note ``− 2cos θ`` without α."""
    return (2 * alpha**2 - 2 * cos_theta + 1) / (2 * (alpha**2 - cos_theta * alpha + 1))


@lru_cache(maxsize=None)
def pool_claims() -> dict:
    """Check every claim of sec. 4.1.1 on the valid set, exactly. Each entry has ``verdict``
    (``"confirmed"``/``"corrected"``/``"refuted"``) and the ``proof`` data.

    Examples
    --------
    >>> {k: v["verdict"] for k, v in pool_claims().items()}  # doctest: +NORMALIZE_WHITESPACE
    {'v2_positive_iff': 'confirmed', 'eq29_g': 'confirmed', 'eq29_signature': 'corrected',
     'eq31_h': 'corrected', 'eq32_D2': 'corrected', 'g_minimum': 'confirmed',
     'h_geq_g': 'corrected', 'theta_gt_pi2_always_positive': 'refuted', 'domain_nonempty': 'confirmed'}
    """
    cond = _pool_conditions()
    (k1, k2), A = cond["contacts"], cond["A"]
    g, h = pool_g(), pool_h()
    out = {}
    # w₂⁺ = c₂ p₁ with c₂ = 2α − c, b₂ = 0: w₂⁺ ≥ 0 ⟺ α ≥ c/2 (p₁ > 0)
    out["v2_positive_iff"] = {"verdict": "confirmed" if (k2["b"] == 0 and sp.expand(k2["c"] - (2 * alpha - c)) == 0) else "refuted",
                              "proof": {"b2": k2["b"], "c2": k2["c"], "w2+": "c2 * p1, p1 > 0"}}
    out["eq29_g"] = {"verdict": "confirmed" if sp.cancel(g - printed_eq29_g()) == 0 else "corrected",
                     "proof": {"g": g, "R1": k1["R"], "c1": k1["c"]}}
    out["eq29_signature"] = {"verdict": "corrected", "proof": {"printed": "g: [0,1] -> R, e -> ...",
                             "derived": "g: alpha12 -> e (its free variable is alpha12)", "free_symbols": sorted(map(str, g.free_symbols))}}
    out["eq31_h"] = {"verdict": "confirmed" if sp.cancel(h - printed_eq31_h()) == 0 else "corrected",
                     "proof": {"h": h, "printed_minus_derived": sp.factor(printed_eq31_h() - h)}}
    out["eq32_D2"] = {"verdict": "corrected", "proof": {"printed": "D2 = {alpha in [0, oo[, e in [g(alpha), 1]}",
                      "derived": "D2 = {alpha >= 0, h(alpha) <= e <= 1} (Delta >= 0 <=> e >= h)"}}
    dg = sp.factor(sp.diff(g, alpha))
    crit = solve_remembered(sp.numer(dg), alpha)
    d2 = sp.factor(sp.diff(g, alpha, 2).subs(alpha, c / 2))
    gmin = sp.factor(g.subs(alpha, c / 2))
    out["g_minimum"] = {"verdict": "confirmed" if (crit == [c / 2] and is_zero(gmin - (2 - c**2) / (4 - c**2))) else "refuted",
                        "proof": {"dg": dg, "critical_points": crit, "second_derivative_at_c/2": d2, "g(c/2)": gmin,
                                  "h(c/2)": sp.factor(h.subs(alpha, c / 2)),
                                  "note": "minimum over alpha >= 0 only when c >= 0; for c < 0, g increases on [0, oo[ and min is g(0) = 1/2"}}
    gmh = sp.factor(g - h)
    target = alpha**2 * (2 * alpha - c) ** 2 / (2 * A * (2 - alpha * c) ** 2)
    out["h_geq_g"] = {"verdict": "corrected" if sp.cancel(gmh - target) == 0 else "refuted",
                      "proof": {"g_minus_h": gmh, "equals": target,
                                "statement": "g(alpha) >= h(alpha) for every alpha (A > 0), equality iff alpha = 0 or alpha = cos(theta)/2"}}
    # θ > π/2: w₂⁺ > 0 always (c₂ = 2α − c > 0); w₁⁺ needs e ≥ g. Counterexample c = −1/4, α = 2, e = 1.
    cx = {c: -sp.Rational(1, 4), alpha: 2}
    p1 = 1 / A.subs(cx)  # e = 1: p₁ = −B/A = 1/A
    w1 = simplify(-1 + k1["c"].subs(cx) * p1)  # exact: rationals in, a rational out
    out["theta_gt_pi2_always_positive"] = {"verdict": "refuted" if w1 < 0 else "confirmed",
                                           "proof": {"cos_theta": -sp.Rational(1, 4), "alpha": 2, "e": 1, "v1+": w1,
                                                     "v2+": simplify(k2["c"].subs(cx) * p1),
                                                     "true_part": "v2+ = (2 alpha - cos theta) p1 > 0 for cos theta < 0"}}
    g_at_1 = simplify(g.subs(alpha, 1))
    out["domain_nonempty"] = {"verdict": "confirmed" if g_at_1 == 1 else "refuted",
                              "proof": {"g(1)": g_at_1, "g <= 1 iff": sp.factor(sp.numer(sp.together(1 - g))),
                                        "statement": "(alpha, e) = (1, 1) is valid for every theta in [0, 2pi/3)"}}
    return out


def pool_domain_at(cos_theta) -> dict:
    """The pool's domain (τ = 0, two closed contacts, θ ∈ [0, 2π/3)) at one exact ``cos θ``.

    Region: ``max(0, cos θ/2) ≤ α ≤ 1`` and ``g(α) ≤ e ≤ 1`` (h is implied). Its lowest ``e`` is
    ``(2 − cos²θ)/(4 − cos²θ)`` at ``α = cos θ/2`` for ``cos θ ≥ 0``, and ``1/2`` at ``α = 0`` for
    ``cos θ < 0``. The region is never empty; it shrinks as θ grows from 0 (``e_min`` = 1/3)
    to π/2 (``e_min`` = 1/2).

    Examples
    --------
    >>> d = pool_domain_at(sp.cos(sp.pi / 4))
    >>> d["alpha_range"], d["e_min"], d["e_min_at"]
    ((sqrt(2)/4, 1), 3/7, sqrt(2)/4)
    """
    cs = sp.sympify(cos_theta)
    lo = sp.Max(0, cs / 2)
    emin_at = lo
    emin = simplify(pool_g(cs).subs(alpha, emin_at))
    return {"cos_theta": cs, "alpha_range": (simplify(lo), sp.Integer(1)), "e_min": emin,
            "e_min_at": simplify(emin_at), "g": pool_g(cs), "h": pool_h(cs)}


@lru_cache(maxsize=None)
def bernoulli_tau0_domain() -> dict:
    """θ = 2π/3, τ = 0, three closed contacts, ``α₁₃ = α₁₂ = α`` (the paper's choice at θ = 2π/3).

    Contact 1–3 approaches too (``b₃ = −1/2``). Conditions: ``e ≥ g₁(α)`` (contact 1–2),
    ``e ≥ g₃(α)`` where ``R₃ > 0`` (contact 1–3; ``R₃ = (α − 1)(5α − 2)/(2(5α + 1))``, positive for
    ``α < 2/5`` and ``α > 1``), contact 2–3 automatic, ``e ≥ h`` implied. With ``e ≤ 1``:
    ``α ∈ [0, 1]``; the lowest ``e`` is where ``g₁ = g₃`` on ``(0, 2/5)``.

    Examples
    --------
    >>> d = bernoulli_tau0_domain()
    >>> d["g1"], d["g3"]
    ((5*alpha**2 + 2*alpha + 2)/(alpha + 2)**2, (25*alpha**2 + alpha + 1)/(5*alpha + 1)**2)
    """
    cond = admissibility_conditions(pool(2 * sp.pi / 3, 0, third_contact=True), [alpha, alpha])
    k1, k2, k3 = cond["contacts"]
    g1, g3 = k1["g"], k3["g"]
    cross = [r for r in sp.Poly(sp.numer(sp.together(g1 - g3)), alpha).real_roots() if 0 < r < sp.Rational(2, 5)]
    if not (len(cross) == 1):
        raise DerivationError('derivation check failed: len(cross) == 1')
    a_star = cross[0]
    e_min = g1.subs(alpha, a_star)
    return {"g1": g1, "g3": g3, "R3": k3["R"], "h": cond["h"], "c2": k2["c"], "alpha_range": (sp.Integer(0), sp.Integer(1)),
            "e_min_at": a_star, "e_min": simplify(e_min)}


@lru_cache(maxsize=None)
def pool_tau_conditions() -> dict:
    """The pool's conditions of eq. 28 at symbolic incidence ``(θ, τ)`` (two closed contacts),
    and the proof that they are the τ = 0 curves mapped by ``e ↦ sin²τ + cos²τ e``.

    The tangential energy ``½ sin²τ`` is untouched by impulses along the normals, and the normal
    problem is the τ = 0 problem scaled by ``cos τ``. Proved here for every ``(θ, τ)``
    (``simplify(derived − mapped) == 0``, asserted); :func:`impactsym.domains.validity_domain`
    substitutes one ``(θ, τ)`` into the generated form and checks it again.

    Returns
    -------
    dict: ``g1`` (contact 1–2: ``w₁⁺ ≥ 0 ⟺ e ≥ g1`` where ``c₁ > 0``), ``h`` (``Δ ≥ 0 ⟺ e ≥ h``),
    ``b2``, ``c2`` (contact 2–3: ``w₂⁺ = b2 + c2 p₁``), in ``theta``, ``tau``, ``alpha``.

    Examples
    --------
    >>> d = pool_tau_conditions()
    >>> d["b2"], d["c2"]
    (0, 2*alpha - cos(theta))
    """
    cond = admissibility_conditions(pool(theta, tau, third_contact=False), [alpha])
    k1, k2 = cond["contacts"]
    s2, c2 = sp.sin(tau) ** 2, sp.cos(tau) ** 2
    mapped_g = s2 + c2 * pool_g(sp.cos(theta))
    mapped_h = s2 + c2 * pool_h(sp.cos(theta))
    if not (is_zero(k1["g"] - mapped_g)):
        raise DerivationError(k1["g"])
    if not (is_zero(cond["h"] - mapped_h)):
        raise DerivationError(cond["h"])
    if not (k2["b"] == 0 and sp.expand(k2["c"] - (2 * alpha - sp.cos(theta))) == 0):
        raise DerivationError(k2)
    return {"g1": k1["g"], "h": cond["h"], "b2": k2["b"], "c2": k2["c"]}


def boundary_expressions() -> dict:
    """What :mod:`impactsym.domains` needs at run time, as exact expressions: name ->
    ``(expression, description)``. Written to ``impactsym/kernels/domain_boundaries.py`` by
    :func:`generate`, so that the package reads committed data and never runs a derivation.

    >>> sorted(boundary_expressions())[:3]
    ['bernoulli_R3', 'bernoulli_e_min', 'bernoulli_e_min_at']
    """
    b = bernoulli_tau0_domain()
    t = pool_tau_conditions()
    return {
        "pool_g": (pool_g(), "pool, tau = 0: v1+ = 0 on e = g(alpha) (eq. 29), in c = cos(theta)"),
        "pool_h": (pool_h(), "pool, tau = 0: Delta = 0 on e = h(alpha) (eq. 31, corrected), in c = cos(theta)"),
        "chain3_alpha_max": (chain3_alpha_max_expr(), "chain: the root of g(alpha) = e in [1/2, 1] (eq. 19)"),
        "bernoulli_g1": (b["g1"], "theta = 2pi/3, alpha13 = alpha12 = alpha: v+ = 0 at contact 1-2"),
        "bernoulli_g3": (b["g3"], "theta = 2pi/3: v+ = 0 at contact 1-3 (where R3 > 0)"),
        "bernoulli_R3": (b["R3"], "theta = 2pi/3: R3 of contact 1-3 (w3+ >= 0 <=> R3 <= 0 or e >= g3)"),
        "bernoulli_h": (b["h"], "theta = 2pi/3: Delta = 0 on e = h(alpha)"),
        "bernoulli_e_min_at": (b["e_min_at"], "theta = 2pi/3: the alpha where g1 = g3 (lowest e)"),
        "bernoulli_e_min": (b["e_min"], "theta = 2pi/3: the lowest e of the domain"),
        "pool_tau_g1": (t["g1"], "pool at (theta, tau): v1+ = 0 on e = g1 (contact 1-2)"),
        "pool_tau_h": (t["h"], "pool at (theta, tau): Delta = 0 on e = h"),
        "pool_tau_b2": (t["b2"], "pool at (theta, tau): b of contact 2-3 (w2+ = b2 + c2 p1)"),
        "pool_tau_c2": (t["c2"], "pool at (theta, tau): c of contact 2-3"),
    }


BOUNDARIES_FILE = "domain_boundaries.py"
BOUNDARIES_DOC = """Exact boundary expressions of the impulse-ratio law's validity domains (Acary & Taha eqs.
19, 28-32), derived in derivations/domains.py, read by impactsym.domains at run time.

Symbols carry their assumptions (alpha nonnegative, e positive, c, theta and tau real)."""


MODULE_DOC = """Boundary curves of the impulse-ratio law's validity domains (Acary & Taha eqs. 19, 29, 31):
chain3_alpha_max(e), and the pool's g (v1+ = 0) and h (Delta = 0) as functions of theta and alpha."""


def kernels():
    """The ``domains`` family: ``pool_g(theta, alpha)``, ``pool_h(theta, alpha)``.

    (``chain3_alpha_max`` lives in the chain3 family.)

    >>> [k.name for k in kernels()]
    ['pool_g', 'pool_h']
    """
    th = sp.Symbol("theta", real=True)
    return [
        ScalarKernel("pool_g", [th, alpha], [pool_g(sp.cos(th))], ["g"],
                     "Pool (tau = 0): e = g(alpha) is where v1+ = 0 (eq. 29); valid e >= g(alpha).\n"),
        ScalarKernel("pool_h", [th, alpha], [pool_h(sp.cos(th))], ["h"],
                     "Pool (tau = 0): e = h(alpha) is where Delta = 0 (eq. 31, corrected: -2 alpha cos(theta)).\n"),
    ]


def generate(outdir) -> list[Path]:
    """Write ``domains.py`` (the NumPy kernels) and ``domain_boundaries.py`` (the exact expressions
    :mod:`impactsym.domains` reads) into ``outdir``."""
    path = Path(outdir) / "domains.py"
    path.write_text(render_family("domains", "domains", MODULE_DOC, kernels()))
    data = Path(outdir) / BOUNDARIES_FILE
    data.write_text(render_expressions("domains", "domains", BOUNDARIES_DOC, boundary_expressions()))
    return [path, data]
