"""Acary & Taha, *Concurrent Multiple Impacts in Rigid Bodies: Formulation and Simulation*:
every equation (1–45), display, example and statement, one claim function each.

Derived values come from impactsym: the general impulse-ratio quadratic
(:mod:`derivations.impulse_ratio`), the closed forms (:mod:`derivations.chain3`,
:mod:`derivations.pool`), the domains (:mod:`derivations.domains`), the classical laws
(:mod:`impactsym.laws.classical`), the impulse-ratio law (:mod:`impactsym.laws.impulse_ratio`),
the coupling criteria (:mod:`impactsym.laws.coupling`) and the scenes of
:mod:`impactsym.models.acary_taha`. Published forms are transcriptions, misprints included (the
closed-form modules hold the long transcriptions, ``printed_eq18`` ... ``printed_eq37``).

The unnumbered τ = 0 solution display of sec. 4.1.1 is eq. 27 (the numbering runs 26, display, 28).

Every verdict other than ``definition`` and ``not-checkable`` is chosen by a computation, and each
such claim declares the mutations (``paper_checks/mutants_acary_taha.py``) under which it must
change verdict or raise. Law results a verdict rests on are first checked against the impact
equations with their own impulses (:func:`_consistent`); derived closed forms must conserve
momentum and energy before a print is called a misprint (:func:`_derived_state_holds`). Agreement
shown at a few angles, points or integrations is ``supported-by-samples`` (the note gives the
count). Four verdicts are readings of typography (``judgment``): the summation index of eq. 5, the
case labels of sec. 4.2, the component labels of eq. 37 and the ``q⁺`` of eq. 38.

>>> from paper_checks.framework import evaluate
>>> evaluate("at-eq18-Delta").verdict
'exact-match'
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

from derivations.memo import simplify
from derivations.rational_zero import is_zero, is_zero_algebraic

from impactsym.arithmetic.remembered import solveset_remembered
from impactsym.exact import certified_sign
from impactsym.mechanics import kinetic_angle_cos, m_normal
from impactsym.models.acary_taha import bernoulli, chain3, pool

from .framework import Finding, claim, compare_decimal, conservation, extremum, identical

P = "acary-taha"


def _cl(id, ref, quantity, expect, mutations=()):
    return claim(id, paper=P, ref=ref, quantity=quantity, expect=expect, mutations=tuple(mutations))


#: mutation names (paper_checks/mutants_acary_taha.py), one place to spell them
IRL, GQ, CHAIN, POOL, POS = "at.impulse_ratio_law", "at.general_quadratic", "at.chain3_scene", "at.pool_scene", "at.pool_positions"
NEWTON, POISSON, HG, DEL, KCOS = "at.newton_moreau", "at.poisson", "at.han_gilmore", "at.delassus", "at.kinetic_angle_cos"
DOM, COMPLIANT, INC = "at.validity_domain", "at.chain_impact", "at.pool_incidence"


def _definition(id, ref, quantity, published, note=""):
    @_cl(id, ref, quantity, "definition")
    def _f():
        return Finding("definition", published=published, note=note)

    _f.__name__ = id.replace("-", "_")
    return _f


# --------------------------------------------------------------------------- cached derivations
@lru_cache(maxsize=None)
def _chain():
    from derivations import chain3 as c3
    return c3.chain3_equal_masses(), c3.printed_eq18(), c3.compare_eq18()


@lru_cache(maxsize=None)
def _chain_domain():
    from derivations.domains import chain3_domain
    return chain3_domain()


@lru_cache(maxsize=None)
def _pool_claims():
    from derivations.domains import pool_claims
    return pool_claims()


@lru_cache(maxsize=None)
def _pool(name: str):
    from derivations import pool as pl
    if name == "tau0":
        d = pl.pool_tau0()
        return d, pl.printed_eq27(), pl.compare(d, pl.printed_eq27())
    if name == "eq33":
        d = pl.pool_at_theta(sp.pi / 3, 1)
        return d, pl.printed_eq33(), pl.compare(d, pl.printed_eq33())
    if name == "eq34":
        d = pl.pool_at_theta(sp.pi / 2)
        return d, pl.printed_eq34(), pl.compare(d, pl.printed_eq34())
    if name == "eq35":
        d = pl.pool_any_tau(0)
        return d, pl.printed_eq35(), pl.compare(d, pl.printed_eq35())
    if name == "eq36":
        d = pl.pool_any_tau(sp.pi / 2)
        return d, pl.printed_eq36(), pl.compare(d, pl.printed_eq36())
    if name == "eq37":
        d = pl.bernoulli_closed_form()
        return d, pl.printed_eq37(), None
    raise KeyError(name)


@lru_cache(maxsize=None)
def _eq33_theta():
    from derivations.pool import eq33_theta
    return eq33_theta()


@lru_cache(maxsize=None)
def _eq37():
    from derivations.pool import eq37_analysis
    return eq37_analysis()


def _classical():
    from impactsym.laws import classical
    return classical


def _consistent(M, H, v, r, law: str):
    """Raise unless a law's returned impulses and velocity satisfy ``M(v⁺ − v⁻) = Hᵀp`` exactly: a
    law whose outputs disagree with each other is no baseline for any verdict."""
    if r.velocity is None:
        return r
    if r.impulses is None:
        raise ValueError(f"{law} returned a velocity without impulses")
    M_, H_, v_ = sp.Matrix(M), sp.Matrix(H), sp.Matrix(v)
    resid = M_ * (sp.Matrix(r.velocity) - v_) - H_.T * sp.Matrix(r.impulses)
    # an entry proved zero exactly (flint, milliseconds) needs no certified sign
    resid = [sp.Integer(0) if is_zero_algebraic(x) else sp.radsimp(x) for x in resid]
    if any(certified_sign(x) != 0 for x in resid):
        raise ValueError(f"{law}'s impulses {list(r.impulses)} and velocity {list(r.velocity)} violate "
                         f"M(v+ - v-) = H^T p: {list(resid)}")
    return r


def _expanded_number(x):
    """A number of the pool's numeric scenes (rationals and square roots of rationals, products of
    cosines and sines of multiples of π/12) written as its expanded sum of surds: the same value,
    in the form ``simplify`` gives these numbers, without simplify's search (display form; every
    sign is decided on it by :func:`certified_sign`)."""
    if x.free_symbols:
        raise ValueError(f"x: a number is expected, got {x}")
    return sp.expand(x)


def _law(M, H, v, e, ratios, **kw):
    """``impactsym.laws.impulse_ratio.impulse_ratio_law``, its result checked by :func:`_consistent`."""
    from impactsym.laws.impulse_ratio import impulse_ratio_law
    return _consistent(M, H, v, impulse_ratio_law(M, H, v, e, ratios, **kw), "impulse_ratio_law")


def _conserves_energy(M, H, v, r, e, law: str, where: str):
    """Raise unless a law's state (if it has one) satisfies ``T⁺ = e T⁻`` exactly: a state that
    breaks the energy line of eq. 38 is no state of the law, valid or not, and no verdict may rest
    on it. Decided by the exact zero test, else a certified sign (no simplification)."""
    if r.velocity is None:
        return r
    M_, v_, vp = sp.Matrix(M), sp.Matrix(v), sp.Matrix(r.velocity)
    balance = (vp.T * M_ * vp)[0, 0] / 2 - sp.sympify(e) * (v_.T * M_ * v_)[0, 0] / 2
    if not (is_zero_algebraic(balance) or certified_sign(balance) == 0):
        raise ValueError(f"{law}'s state {where} violates T+ = e T- (e = {e}): T+ - e T- = {balance}; "
                         "no verdict can rest on it")
    return r


def _chain_args():
    sc = chain3()
    return sc.M, sc.H, sc.v


# =========================================================================== sec. 2.1
_definition("at-eq1", "eq. 1", "h_α(q, t) ≥ 0", r"h_\alpha(q,t)\ge0,\ \alpha = 1\dots\nu")
_definition("at-eq2", "eq. 2", "admissible set 𝒞", r"\mathcal C(t) = \{q\in\mathcal M(t)\,|\,h_\alpha(q,t)\ge0\}")
_definition("at-eq3", "eq. 3", "Lagrange equations", r"M(q)\ddot q + F(q,\dot q,t) = \sum_{\alpha=1}^{\nu}\nabla h_\alpha(q)\lambda_\alpha")
_definition("at-eq4", "eq. 4", "complementarity", r"0\le h_\alpha(q,t)\perp\lambda_\alpha\ge0")


@_cl("at-eq5", "eq. 5", "measure differential equation, summation index", "erratum")
def eq5():
    i, m, a = sp.symbols("i m alpha", integer=True, positive=True)
    f = sp.Function("f")  # stands for ∇h_α λ_α
    printed = sp.Sum(f(a), (i, 1, m)).doit()
    return Finding("erratum",
                   judgment="a reading of the summation index: the printed Σ_{i=1}^{m} runs over an index that its "
                            "summand ∇h_α λ_α does not contain; that the sum is meant over the ν constraints α (as in "
                            "eq. 3) is a reading of the notation, not something impactsym computes",
                   published=r"M(q)du + F(q,u,t)dt = \sum_{i=1}^{m}\nabla h_\alpha(q)\lambda_\alpha",
                   derived={"printed sum evaluates to": printed},
                   corrected=r"M(q)\,du + F(q,u,t)\,dt = \sum_{\alpha=1}^{\nu}\nabla h_\alpha(q)\,d\lambda_\alpha",
                   note="The summation index i does not occur in the summand, so the printed sum is m·∇h_α λ_α "
                        f"(SymPy: {printed}); the sum runs over the ν constraints α as in eq. 3 (the text then speaks of "
                        "λ_i). As a measure equation the impulsive term is the measure dλ_α.")


_definition("at-eq6", "eq. 6", "impact equations", r"M\Delta\dot q = P,\ v = H\dot q,\ P = H^Tp,\ H = \nabla h",
            "H stacks the gradient rows (impactsym: rows H_i = Dh_i), so P = Hᵀp.")


@_cl("at-eq7", "eq. 7", "Δv = HM⁻¹Hᵀp", "exact-match", [DEL])
def eq7():
    from derivations.reflection import symbolic_mass_matrix
    M = symbolic_mass_matrix(2)
    H = sp.Matrix(2, 2, lambda i, j: sp.Symbol(f"h_{i}{j}"))
    p = sp.Matrix(sp.symbols("p1 p2"))
    dq = M.LUsolve(H.T * p)  # eq. 6: M Δq̇ = Hᵀp
    from impactsym.laws.delassus import delassus
    W = delassus(M, H)  # the package's eq. 7 operator
    package = identical(W * p, H * dq)
    if not package.equal:
        raise ValueError(f"impactsym.laws.delassus.delassus disagrees with eq. 6 ({package.method}): no baseline")
    r = identical(H * dq, H * M.inv() * H.T * p)
    # printed: rational functions with rational coefficients, whose simplest form is the lowest-terms
    # quotient sympy.cancel gives (flint's cancel: the same form, without simplify's search)
    from derivations.rational_zero import cancel
    return Finding(r.decide("exact-match", "erratum"), published=r"\Delta v = HM(q_{t_k})^{-1}H^Tp",
                   derived=(H * dq).applyfunc(cancel), corrected=None if r.equal else W * p,
                   note=f"From eq. 6 with symbolic M (SPD) and H: {r.method}; impactsym.laws.delassus.delassus gives the "
                        f"same W p ({package.method}).")


_definition("at-eq8", "eq. 8", "perfect unilateral constraints", r"h_\alpha = 0 \Rightarrow p_\alpha\ge0,\ v_\alpha(t_k^+)\ge0")


# =========================================================================== sec. 2.2
_definition("at-eq9", "eq. 9", "Newton's law", r"v_\alpha(t^+) = -e\,v_\alpha(t^-)")
_definition("at-eq10", "eq. 10", "Moreau's law", r"0\le v(t^+) + e\,v(t^-)\perp p\ge0")
_definition("at-eq11", "eq. 11", "Poisson's coefficient", r"e_p = p_{r_\alpha}/p_{c_\alpha}")


@_cl("at-eq12", "eq. 12", "global energetic coefficient", "erratum", [IRL])
def eq12():
    # the chain at e = 1 (perfectly elastic, sec. 3.3) and at e = 1/2: which reading does the law's state satisfy?
    M, H, v = _chain_args()
    Tm = (v.T * M * v)[0, 0] / 2
    readings = {}
    for e_ in (sp.Integer(1), sp.Rational(1, 2)):
        res = _law(M, H, v, e_, [1], allow_invalid=True)
        if res.velocity is None:
            raise ValueError(f"impulse_ratio_law(chain, e = {e_}, alpha = 1) has no state to test eq. 12 on")
        c = conservation(M, H, v, res.velocity, e_)
        if not c["momentum"]:
            raise ValueError(f"impulse_ratio_law(chain, e = {e_}) violates momentum: no baseline for eq. 12")
        Tp = (res.velocity.T * M * res.velocity)[0, 0] / 2
        readings[e_] = {"T+": Tp, "with 1/2 (T+ = e T-)": Tp == e_ * Tm, "as printed (T+ = 2e T-)": Tp == 2 * e_ * Tm}
    half = all(r["with 1/2 (T+ = e T-)"] for r in readings.values())
    literal = all(r["as printed (T+ = 2e T-)"] for r in readings.values())
    if half == literal:
        raise ValueError(f"the law's states fit neither or both readings of eq. 12: {readings}")
    Tp = readings[1]["T+"]
    literal_rhs = 1 * (v.T * M * v)[0, 0]  # e q̇⁻ᵀMq̇⁻ without ½
    return Finding("erratum" if half else "exact-match", published=r"\frac12\dot q(t^+)^TM\dot q(t^+) = e\,\dot q(t^-)^TM\dot q(t^-)",
                   derived={"T-": Tm, "T+ (e=1, alpha=1)": Tp, "printed right side at e=1": literal_rhs,
                            "readings": readings},
                   corrected=r"\frac12\dot q(t^+)^TM\dot q(t^+) = e\,\frac12\dot q(t^-)^TM\dot q(t^-)",
                   note="Read literally, e = 1 ('perfect elastic impact', sec. 3.3) would demand T⁺ = 2T⁻: the "
                        f"elastic chain outcome [0, 0, 1] has ½q̇⁺ᵀMq̇⁺ = {Tp} but the printed right side is {literal_rhs}. "
                        "impulse_ratio_law's states (chain, α = 1, e ∈ {1, 1/2}) satisfy T⁺ = eT⁻ exactly and not T⁺ = 2eT⁻. "
                        "Eqs. 17 and 25 use the ratio with ½ on both sides (T⁺ = e T⁻, CONVENTIONS.md).")


# =========================================================================== sec. 3.2
@_cl("at-eq13", "eq. 13", "chain impact dynamics", "exact-match", [CHAIN])
def eq13():
    m, p1, p2 = sp.symbols("m p1 p2", positive=True)
    sc = chain3((m, m, m))
    lhs_over = sc.H.T * sp.Matrix([p1, p2])  # M Δq̇ = Hᵀp
    printed = sp.Matrix([-p1, -p2 + p1, p2])
    r = identical(lhs_over, printed)
    return Finding(r.decide("exact-match", "erratum"), corrected=None if r.equal else lhs_over,
                   published=r"m(\dot q_1^+ - \dot q_1) = -p_1,\ m(\dot q_2^+ - \dot q_2) = -p_2 + p_1,\ m(\dot q_3^+ - \dot q_3) = p_2",
                   derived=lhs_over, note="Hᵀp with the gradient rows of h₁ = q₂ − q₁ − 2r, h₂ = q₃ − q₂ − 2r (impactsym.models.acary_taha.chain3).")


@_cl("at-eq14", "eq. 14", "chain unilateral constraints", "exact-match", [CHAIN])
def eq14():
    sc = chain3()
    q = sp.Matrix(sp.symbols("qd1 qd2 qd3", real=True))
    w = sc.H * q
    ok = list(w) == [q[1] - q[0], q[2] - q[1]]
    return Finding("exact-match" if ok else "erratum", corrected=None if ok else w,
                   published=r"\dot q_1^+\le\dot q_2^+\le\dot q_3^+,\ p_1\ge0,\ p_2\ge0",
                   derived=w, note="H q̇⁺ ≥ 0 with the chain's rows is q̇₂⁺ − q̇₁⁺ ≥ 0, q̇₃⁺ − q̇₂⁺ ≥ 0.")


@_cl("at-sec3.2-newton", "sec. 3.2", "Newton: q̇⁺ = [−1/3, 2/3, 2/3], p = [4/3, 2/3]", "exact-match", [NEWTON])
def newton():
    M, H, v = _chain_args()
    r = _consistent(M, H, v, _classical().newton_moreau(M, H, v, 1), "newton_moreau")
    ok = list(r.velocity) == [-sp.Rational(1, 3), sp.Rational(2, 3), sp.Rational(2, 3)] and \
        list(r.impulses) == [sp.Rational(4, 3), sp.Rational(2, 3)]
    return Finding("exact-match" if ok else "erratum", corrected=None if ok else {"velocity": r.velocity, "impulses": r.impulses},
                   published="[q̇1+, q̇2+, q̇3+] = [-1/3, 2/3, 2/3], [p1, p2] = [4/3, 2/3]",
                   derived={"velocity": r.velocity, "impulses": r.impulses},
                   note="impactsym.laws.classical.newton_moreau on the chain, e1 = e2 = 1, exact.")


@_cl("at-sec3.2-newton-energy", "sec. 3.2", "Newton state conserves momentum and energy", "exact-match", [CHAIN])
def newton_energy():
    M, H, v = _chain_args()
    c = conservation(M, H, v, sp.Matrix([-sp.Rational(1, 3), sp.Rational(2, 3), sp.Rational(2, 3)]), 1)
    ok = c["holds"] and c["p"] == [sp.Rational(4, 3), sp.Rational(2, 3)]
    return Finding("exact-match" if ok else "refuted", published="[-1/3, 2/3, 2/3] (published state)",
                   derived=c, note="Momentum exactly (impulses p = (4/3, 2/3) ≥ 0), and T⁺ = T⁻ = 1/2 exactly: the Newton "
                   "state with e = 1 conserves energy (1/9 + 4/9 + 4/9 = 1), so its rejection in the paper is on "
                   "qualitative grounds, not energy.", evidence=c)


@_cl("at-sec3.2-poisson", "sec. 3.2", "Poisson: same solution as Newton", "exact-match", [POISSON])
def poisson_():
    M, H, v = _chain_args()
    r = _consistent(M, H, v, _classical().poisson(M, H, v, 1), "poisson")
    ok = list(r.velocity) == [-sp.Rational(1, 3), sp.Rational(2, 3), sp.Rational(2, 3)]
    return Finding("exact-match" if ok else "erratum", corrected=None if ok else r.velocity,
                   published="[q̇1+, q̇2+, q̇3+] = [-1/3, 2/3, 2/3] ...",
                   derived={"velocity": r.velocity, "impulses": r.impulses,
                            "compression impulses": r.details.get("compression_impulses")},
                   note="impactsym.laws.classical.poisson (paper variant, e_p = 1): compression to q̇₁ = q̇₂ = q̇₃, then p = 2 p_c.")


@lru_cache(maxsize=None)
def _hg():
    M, H, v = _chain_args()
    r = _classical().han_gilmore(M, H, v, 1)
    for o in r.outcomes:
        _consistent(M, H, v, o, "han_gilmore")
    return r


@_cl("at-eq15", "eq. 15", "Han & Gilmore outcome 1", "exact-match", [HG])
def eq15():
    r = _hg()
    vs = [list(o.velocity) for o in r.outcomes]
    target = [-sp.Rational(1, 3), sp.Rational(2, 3), sp.Rational(2, 3)]
    M, H, v = _chain_args()
    c = conservation(M, H, v, sp.Matrix(target), 1)
    return Finding("exact-match" if target in vs else "refuted", published="(q̇1+, q̇2+, q̇3+) = (-1/3, 2/3, 2/3)",
                   derived={"outcomes": vs}, evidence=c,
                   note="impactsym.laws.classical.han_gilmore: the stage {1,2} (contact 2–3 grazing joins) gives it. "
                        "It is not a sequence of single impacts (those all give (0, 0, 1), Seghete & Murphey eq. 4).")


@_cl("at-eq16", "eq. 16", "Han & Gilmore outcome 2", "exact-match", [HG, "reflection_map"])
def eq16():
    r = _hg()
    vs = [list(o.velocity) for o in r.outcomes]
    from impactsym.laws.reflection import reflection_map
    Gu, Gv = reflection_map(sp.eye(3), "-1,1,0"), reflection_map(sp.eye(3), "0,-1,1")
    seq = Gv * Gu * sp.Matrix([1, 0, 0])
    ok = [0, 0, 1] in vs and list(seq) == [0, 0, 1]
    return Finding("exact-match" if ok else "refuted", published="(q̇1+, q̇2+, q̇3+) = (0, 0, 1)",
                   derived={"outcomes": vs, "single impacts 1-2 then 2-3": seq},
                   note="Han & Gilmore's sequence (1), (2); also the sequential single-impact outcome G_vG_u v⁻.")


@_cl("at-eq17", "eq. 17", "energy balance and α = p₂/p₁", "definition")
def eq17():
    return Finding("definition", published=r"(\dot q_1^+)^2 + (\dot q_2^+)^2 + (\dot q_3^+)^2 = e(\dot q_1^2 + \dot q_2^2 + \dot q_3^2),\ \alpha = p_2/p_1",
                   note="Equal masses: eq. 12 with ½ on both sides (T⁺ = eT⁻); the ratio against the primary contact 1–2.")


# =========================================================================== sec. 3.3, eq. 18
def _eq18_claim(key: str, quantity: str):
    derived, printed, cmp = _chain()
    from derivations.chain3 import momentum_energy_residuals
    ok = cmp[key]
    note = f"derivations.chain3.chain3_equal_masses (general quadratic on the chain scene); exact identity: {ok}."
    if ok:
        return Finding("exact-match", published=str(printed[key]), published_expr=printed[key], derived=derived[key],
                       note=note)
    res_p = momentum_energy_residuals(printed)
    res_d = momentum_energy_residuals(derived)
    if any(not is_zero(x) for x in res_d.values()):
        raise ValueError(f"the derived eq. 18 state violates momentum or energy ({res_d}): no baseline for an erratum")
    if is_zero(res_p["momentum"]):
        raise ValueError(f"the printed {quantity} differs from the derived one yet conserves momentum: not a sign misprint")
    return Finding("erratum", published=str(printed[key]), published_expr=printed[key], derived=derived[key],
                   corrected=derived[key],
                   note=note + f" Sign misprint: with the printed {quantity} momentum fails, Σm q̇⁺ − m = "
                               f"{sp.factor(res_p['momentum'])} ≠ 0 for α > 0; with the derived one momentum and energy "
                               f"residuals are {res_d['momentum']}, {res_d['energy']}. Eq. 13's third line, m q̇₃⁺ = p₂ ≥ 0, "
                               "also forbids the printed sign.",
                   evidence={"printed residuals": res_p, "derived residuals": res_d})


@_cl("at-eq18-p1", "eq. 18", "p1", "exact-match", [GQ])
def eq18_p1():
    return _eq18_claim("p1", "p1")


@_cl("at-eq18-p2", "eq. 18", "p2", "exact-match", [GQ])
def eq18_p2():
    return _eq18_claim("p2", "p2")


@_cl("at-eq18-q1", "eq. 18", "q1+", "exact-match", [GQ])
def eq18_q1():
    return _eq18_claim("q1+", "q̇₁⁺")


@_cl("at-eq18-q2", "eq. 18", "q2+", "exact-match", [GQ])
def eq18_q2():
    return _eq18_claim("q2+", "q̇₂⁺")


@_cl("at-eq18-q3", "eq. 18", "q3+", "erratum", [GQ])
def eq18_q3():
    return _eq18_claim("q3+", "q̇₃⁺")


@_cl("at-eq18-Delta", "eq. 18", "Delta", "exact-match", [GQ])
def eq18_Delta():
    return _eq18_claim("Delta", "Δ")


@_cl("at-eq19", "eq. 19", "domain of (α, e) for the chain", "exact-match", [GQ])
def eq19():
    d = _chain_domain()
    ok = d["eq19_verified"] and d["e_min"] == sp.Rational(1, 3) and d["alpha_min"] == sp.Rational(1, 2)
    return Finding("exact-match" if ok else "erratum", corrected=None if ok else d["alpha_max"],
                   published=r"\frac13\le e\le1,\quad \frac12\le\alpha\le\frac{2e - 2 - \sqrt{6e-2}}{e-3}",
                   published_expr=d["eq19_alpha_max"], derived={"alpha_max(e)": d["alpha_max"], "g": d["g"], "h": d["h"],
                                                               "g - h": d["g_minus_h"]},
                   note="derivations.domains.chain3_domain: w₂⁺ ≥ 0 ⇔ α ≥ 1/2; w₁⁺ ≥ 0 ⇔ e ≥ g(α) with g increasing on "
                        "[1/2, 2), g(1/2) = 1/3, g(1) = 1; g ≥ h so Δ ≥ 0 is implied; α_max(e) is the root of g = e, identical "
                        "to the print. (The transcription shows the two lines of the display as a fraction: a layout artefact.)")


@_cl("at-sec3.3-alpha1-e1", "sec. 3.3", "α = 1, e = 1 gives [0, 0, 1]", "exact-match", [IRL])
def alpha1():
    M, H, v = _chain_args()
    r = _law(M, H, v, 1, [1])
    ok = list(r.velocity) == [0, 0, 1]
    return Finding("exact-match" if ok else "refuted", published="[q̇1+, q̇2+, q̇3+] = [0, 0, 1] for α = 1, e = 1",
                   derived=r.velocity, note="impactsym.laws.impulse_ratio.impulse_ratio_law, exact.")


@lru_cache(maxsize=None)
def _alpha095():
    M, H, v = _chain_args()
    return _law(M, H, v, 1, ["19/20"])


def _alpha095_claim(i: int, printed: str):
    r = _alpha095()
    val = r.velocity[i]
    cmpd = compare_decimal(val, printed)
    kind = cmpd["agreement"]
    verdict = "match-at-published-precision" if kind != "neither" else "erratum"
    others = [compare_decimal(r.velocity[j], p)["agreement"] for j, p in enumerate(["-0.05", "0.05", "0.99"])]
    return Finding(verdict, published=printed, derived=val, digits=50, corrected=None if verdict != "erratum" else sp.N(val, 3),
                   note=f"impulse_ratio_law(chain, e = 1, α = 19/20) exact: {val} = {cmpd['value'][:22]}…; printed to "
                        f"{cmpd['places']} decimals by {kind}. Across the example the print is inconsistent: "
                        f"q̇₁⁺ {others[0]}, q̇₂⁺ {others[1]}, q̇₃⁺ {others[2]} (consistently rounded: "
                        f"[{compare_decimal(r.velocity[0], '-0.05')['rounded']}, {compare_decimal(r.velocity[1], '0.05')['rounded']}, "
                        f"{compare_decimal(r.velocity[2], '0.99')['rounded']}]).",
                   evidence=cmpd)


@_cl("at-sec3.3-alpha095-q1", "sec. 3.3", "q1+ (α = 0.95, e = 1)", "match-at-published-precision", [IRL])
def a095_q1():
    return _alpha095_claim(0, "-0.05")


@_cl("at-sec3.3-alpha095-q2", "sec. 3.3", "q2+ (α = 0.95, e = 1)", "match-at-published-precision", [IRL])
def a095_q2():
    return _alpha095_claim(1, "0.05")


@_cl("at-sec3.3-alpha095-q3", "sec. 3.3", "q3+ (α = 0.95, e = 1)", "match-at-published-precision", [IRL])
def a095_q3():
    return _alpha095_claim(2, "0.99")


@_cl("at-sec3.3-alpha095-conservation", "sec. 3.3", "α = 0.95 state: momentum and energy", "exact-match", [IRL])
def a095_cons():
    r = _alpha095()
    M, H, v = _chain_args()
    c = conservation(M, H, v, r.velocity, 1)
    ok = c["holds"] and c["p"][0] != 0 and c["p"][1] / c["p"][0] == sp.Rational(19, 20)
    printed = [sp.Rational(-5, 100), sp.Rational(5, 100), sp.Rational(99, 100)]
    pm = sum(printed) - 1
    return Finding("exact-match" if ok else "refuted", published="[-0.05, 0.05, 0.99]",
                   derived=c, evidence=c,
                   note=f"The exact state conserves momentum and T (p = {c['p']}, ratio 19/20). The printed decimals "
                        f"carry a momentum defect {pm} (within 3 × 0.01 of the printed precision), from the truncated 0.99.")


@_cl("at-sec3.3-alpha095-interpretation", "sec. 3.3", "balls 1 and 2 move slightly, ball 3 ≈ initial velocity of 1", "exact-match", [IRL])
def a095_interp():
    r = _alpha095()
    v = r.velocity
    M, H, vm = _chain_args()
    if not conservation(M, H, vm, v, 1)["holds"]:
        raise ValueError(f"impulse_ratio_law's α = 0.95 state {list(v)} violates the impact equations: nothing to interpret")
    ok = v[0] < 0 and v[1] > 0 and abs(v[0]) < sp.Rational(1, 10) and abs(v[1]) < sp.Rational(1, 10) and abs(v[2] - 1) < sp.Rational(1, 100)
    return Finding("exact-match" if ok else "refuted", published="the ball 1 and 2 are no longer stationary ... ball 3 moves with almost the same velocity as the initial velocity of ball 1",
                   derived=v, note="|q̇₁⁺|, |q̇₂⁺| < 0.1 and non-zero; |q̇₃⁺ − 1| < 0.01.")


# =========================================================================== sec. 3.4
_definition("at-eq20", "eq. 20", "Hertz visco-elastic contact", r"f = K\delta^n + C\delta^{n-1}\dot\delta")
_definition("at-eq21", "eq. 21", "impulse ratio from forces", r"\alpha_{\gamma\beta} = \int_0^{t_f}f_\gamma\,dt / \int_0^{t_f}f_\beta\,dt")
_definition("at-eq22", "eq. 22", "attractive set E", r"E = \{\delta\ge0,\ \dot\delta\ge0\}")
_definition("at-eq23", "eq. 23", "linear contact", r"f = K\delta")


@lru_cache(maxsize=None)
def _compliant_alpha(masses: tuple, velocity: tuple, stiffness: tuple, damping, model: str) -> float:
    """α₁₂ of one compliant chain run (:func:`impactsym.compliant.chain_impact`); the equal chain
    (1, 1, 1; K 1, 1; v⁻ = (1, 0, 0)) is a run of both :func:`_ratio_spread` and
    :func:`_ratio_dependence`, integrated once."""
    from impactsym.compliant import chain_impact
    return float(chain_impact(list(masses), list(velocity), list(stiffness), damping, model=model).ratios[1])


def _ratio_spread(model: str, damping=None):
    runs = []
    for masses, stiff, vel in (([1, 1, 1], [1, 1], [1, 0, 0]), ([3, 3, 3], [10, 10], [1, 0, 0]),
                               ([3, 3, 3], [10, 10], [2, 0, 0]), ([1, 1, 1], [1000, 1000], [1, 0, 0])):
        alpha = _compliant_alpha(tuple(masses), tuple(vel), tuple(stiff), damping, model)
        runs.append({"masses": masses, "stiffness": stiff, "velocity": vel, "alpha": alpha})
    alphas = [x["alpha"] for x in runs]
    return runs, max(alphas) - min(alphas)


#: agreement required between compliant runs (the integrator runs at rtol 1e-11)
COMPLIANT_TOL = 1e-8


def _ratio_dependence(model: str):
    """Claim 2(b)'s second half, "only function of the ratio of stiffness and mass": a chain with
    unequal masses and stiffnesses (1, 2, 1; K 1, 3), the same chain with every mass ×4, every K ×5
    and |v⁻| ×3 (same ratios: α must not move), and how far α₁₂ is from the equal chain's (the
    ratios do change with the mass and stiffness ratios)."""
    runs = []
    for masses, stiff, vel in (([1, 2, 1], [1, 3], [1, 0, 0]), ([4, 8, 4], [5, 15], [3, 0, 0]),
                               ([1, 1, 1], [1, 1], [1, 0, 0])):
        alpha = _compliant_alpha(tuple(masses), tuple(vel), tuple(stiff), None, model)
        runs.append({"masses": masses, "stiffness": stiff, "velocity": vel, "alpha": alpha})
    same_ratios = abs(runs[0]["alpha"] - runs[1]["alpha"])
    shift = abs(runs[0]["alpha"] - runs[2]["alpha"])
    return runs[:2], same_ratios, shift


#: how far α₁₂ must move with the mass and stiffness ratios to count as depending on them
RATIO_SHIFT_MIN = 1e-3


@_cl("at-sec3.4-claim2b", "sec. 3.4", "Hertz: ratios independent of absolute stiffness and mass", "supported-by-samples",
     [COMPLIANT])
def sec34_2b():
    runs, spread = _ratio_spread("hertz")
    uneven, same, shift = _ratio_dependence("hertz")
    ok = spread < COMPLIANT_TOL and same < COMPLIANT_TOL and shift > RATIO_SHIFT_MIN
    return Finding("supported-by-samples" if ok else "refuted",
                   published="(b) The impulse ratios are independent of the absolute value of stiffness and masses but only "
                             "function of the ratio of stiffness and mass.",
                   derived={"scalings": runs, "same_ratios": uneven, "shift_with_ratios": shift},
                   evidence_kind="samples",
                   note=f"Sampled, not proved: {len(runs) + 3} integrations. "
                        f"impactsym.compliant.chain_impact (undamped Hertz, eq. 20), 3 equal balls: scaling K by 10 and 1000, "
                        f"m by 3 and |v⁻| by 2 changes α₁₂ by {spread:.1e}; masses 1, 2, 1 with K 1, 3 against the same "
                        f"chain with m ×4, K ×5, |v⁻| ×3: {same:.1e} (both < {COMPLIANT_TOL:g}; numerical, DOP853 at rtol "
                        f"1e-11). What changes with the ratios: α₁₂ moves by {shift:.3g} from the equal chain's "
                        f"(> {RATIO_SHIFT_MIN:g}). "
                        "With damping the invariance needs C scaled with K and m (dimensional analysis in impactsym.compliant); "
                        "the paper does not say so.")


@_cl("at-sec3.4-claim3", "sec. 3.4", "linear contacts: ratios independent of k and m", "supported-by-samples", [COMPLIANT])
def sec34_3():
    runs, spread = _ratio_spread("linear")
    uneven, same, shift = _ratio_dependence("linear")
    ok = spread < COMPLIANT_TOL and same < COMPLIANT_TOL
    return Finding("supported-by-samples" if ok else "refuted",
                   published="the ratio of impulses, α, do not depend on the absolute values of stiffness k and mass m",
                   derived={"scalings": runs, "same_ratios": uneven, "shift_with_ratios": shift},
                   evidence_kind="samples",
                   note=f"Sampled, not proved: {len(runs) + 3} integrations. "
                        f"impactsym.compliant.chain_impact (linear contacts, eq. 23): α₁₂ varies by {spread:.1e} across the "
                        f"same scalings, and by {same:.1e} between masses 1, 2, 1 with k 1, 3 and the same chain scaled "
                        f"(m ×4, k ×5, |v⁻| ×3) (both < {COMPLIANT_TOL:g}); also independent of |v⁻| (the model is linear "
                        f"between events). The mass and stiffness ratios move α₁₂ by {shift:.3g}.")


@_cl("at-sec3.4-claim1-2a", "sec. 3.4", "well-posedness with (12); attractivity of E", "not-checkable")
def sec34_rest():
    return Finding("not-checkable", published="1. The post-impact velocity ... is provided in a unique way ... 2.(a) The ratio of "
                                              "impulse is finite and the subspace E = {δ ≥ 0, δ̇ ≥ 0} is globally attractive.",
                   note="Recalled from Acary & Brogliato without a statement precise enough to test (no system class, no "
                        "rate); uniqueness of the rigid law's root is covered by at-eq38-law, finiteness of the ratios by the "
                        "compliant runs of at-sec3.4-claim2b.")


# =========================================================================== sec. 4.1
@_cl("at-eq24", "eq. 24", "constraints h_1, h_2, h_3", "erratum", [POS])
def eq24():
    th = sp.Symbol("theta", real=True)
    q = sp.symbols("x1 y1 x2 y2 x3 y3", real=True)
    x1, y1, x2, y2, x3, y3 = q
    printed = [(x2 - x1)**2 + (y2 - y1)**2 - 2, (x2 - x3)**2 + (y3 - y2)**2 - 2, (x3 - x1)**2 + (y3 - y1)**2 - 2]
    corrected = [expr + 2 - 4 for expr in printed]
    from impactsym.models.acary_taha import pool_positions
    G = pool_positions(2 * sp.pi / 3)
    at = dict(zip(q, [*G[0], *G[1], *G[2]]))
    pv = [simplify(h.subs(at)) for h in printed]
    cv = [simplify(h.subs(at)) for h in corrected]
    sq, di = pool(th, constraint="squared"), pool(th, constraint="distance")
    ratio = [simplify(sq.H[i, j] / di.H[i, j]) for i in range(2) for j in range(6) if di.H[i, j] != 0]
    ok = all(x == 2 for x in pv) and all(x == 0 for x in cv) and set(ratio) == {4}
    return Finding("erratum" if ok else "exact-match", published="h_i = (Δx)² + (Δy)² − 2 ≥ 0",
                   derived={"printed h at contact (theta=2pi/3)": pv, "corrected h at contact": cv,
                            "squared/distance gradient ratio": sorted(set(ratio))},
                   corrected=r"h_i(q) = (x_j - x_i)^2 + (y_j - y_i)^2 - 4 \ge 0 \quad(a = 1)",
                   note="With radius a = 1 the centres of touching balls are 2 apart: the squared distance is 4, so the "
                        "printed h = … − 2 equals 2 (not 0) at contact. With the corrected squared form the gradient rows "
                        "are 4× the unit normals of the distance form ‖G_j − G_i‖ − 2 that eq. 27's impulses refer to: "
                        "impulses differ by the factor 4, ratios α are the same.")


@_cl("at-eq25", "eq. 25", "energy balance for the pool", "exact-match", [POOL])
def eq25():
    th, tau = sp.symbols("theta tau", real=True)
    sc = pool(th, tau)
    two_T = simplify((sc.v.T * sc.M * sc.v)[0, 0])
    return Finding("exact-match" if two_T == 1 else "erratum", corrected=None if two_T == 1 else two_T,
                   published=r"\sum_{i=1}^6(\dot q_i^+)^2 = e((\dot q_1^-)^2 + (\dot q_2^-)^2) = e",
                   derived={"q̇⁻ᵀMq̇⁻": two_T},
                   note="Eq. 12 with ½ on both sides, unit masses; ball 1's speed is 1, so the right side is e.")


_definition("at-eq26", "eq. 26", "impulse ratios α12, α13", r"\alpha_{12} = p_2/p_1,\ \alpha_{13} = p_3/p_1")


@_cl("at-sec4.1-incidence", "sec. 4.1", "pre-impact velocity q̇⁻", "erratum", [GQ])
def incidence():
    th, tau = sp.symbols("theta tau", real=True)
    pr = pool(th, 0, incidence="printed")
    w = simplify((pr.H * pr.v)[0])
    d35 = _pool("eq35")[2]
    from derivations import pool as pl
    plus = pl.compare(_plus_tau_eq35(), pl.printed_eq35())
    printed_approaches = identical(w, -1).equal  # the printed q̇⁻ drives ball 1 into ball 2 (as eq. 27 needs)
    printed_recedes = identical(w, 1).equal
    n_minus, n_plus = sum(map(bool, d35.values())), sum(map(bool, plus.values()))
    if printed_approaches:
        verdict = "exact-match"
    elif printed_recedes and n_minus > n_plus and n_minus >= len(d35) - 1:
        verdict = "erratum"  # the printed q̇⁻ gives no impact; θ − τ reproduces eq. 35 up to its one misprint
    else:
        raise ValueError(f"no incidence reading is supported: H₁q̇⁻ = {w}, eq. 35 matches θ − τ: {d35}, θ + τ: {plus}")
    return Finding(verdict, published=r"\dot q^- = [-\cos(\theta+\tau), -\sin(\theta+\tau), 0, 0, 0, 0]",
                   derived={"H_1 q̇⁻ (printed reading, tau = 0)": w, "eq. 35 vs theta-minus-tau": d35,
                            "eq. 35 vs theta-plus-tau": plus},
                   corrected=r"\dot q^- = [\cos(\theta-\tau), \sin(\theta-\tau), 0, 0, 0, 0]",
                   note="Readings compared: the printed velocity has H₁q̇⁻ = +1 at τ = 0 (ball 1 moves away from ball 2: "
                        "no impact), contradicting eq. 27. Eqs. 27, 35 and 36 are reproduced by (cos(θ−τ), sin(θ−τ)) "
                        "(eq. 35's ẏ₁⁺ = −sin τ fixes the sign of τ; (cos(θ+τ), sin(θ+τ)) gives +sin τ). The mathematics "
                        "supports θ − τ.")


def _plus_tau_eq35():
    """Eq. 35's setting (θ = 0, e = 1) derived with the other incidence reading, (cos(θ+τ), sin(θ+τ))."""
    from derivations.chain3 import closed_form
    from derivations.impulse_ratio import general_quadratic, on_energy_line
    from derivations.pool import VELOCITY_NAMES, eps, tau
    sc = pool(0, tau, incidence="theta-plus-tau")
    law = on_energy_line(general_quadratic(sc.M, sc.H, sc.v, 1, [sp.Symbol("alpha", positive=True)]), sc.M, sc.v, 1)
    cf = closed_form(sc, law, VELOCITY_NAMES)
    # θ = 0: rational functions of α, ε, cos τ, sin τ and surds, whose printed form factor gives
    # directly (derivations.pool._factored: simplify first only for a symbolic θ)
    return {k: sp.factor(v.subs(sp.Abs(sp.cos(tau)), eps * sp.cos(tau))) for k, v in cf.items()}


@_cl("at-sec4.1-two-contacts", "sec. 4.1", "θ ∈ [0, 2π/3[: only two closed contacts; three at 2π/3", "exact-match", [POS])
def two_contacts():
    from impactsym.models.acary_taha import pool_positions
    th = sp.Symbol("theta", real=True)
    G1, _G2, G3 = pool_positions(th)
    d2 = simplify(sp.expand((G3 - G1).dot(G3 - G1)))
    gap = sp.factor(simplify(d2 - 4))  # squared distance minus (2a)^2
    # a proof on the whole interval: the gap's only zero in [0, π] is 2π/3, and it is positive at θ = 0
    zeros = solveset_remembered(gap, th, sp.Interval(0, sp.pi))
    ok = zeros == sp.FiniteSet(2 * sp.pi / 3) and certified_sign(gap.subs(th, 0)) > 0
    ok &= identical(gap, 8 * sp.cos(th) + 4).equal
    return Finding("exact-match" if ok else "refuted",
                   published="for θ ∈ [0, 2π/3[, we have only two closed contacts ... When θ = 2π/3, there are three closed contacts",
                   derived={"|G3 - G1|^2 - 4": gap, "zeros in [0, pi]": zeros, "at theta = 0": gap.subs(th, 0)},
                   note="impactsym.models.acary_taha.pool_positions: |G₃ − G₁|² − 4 = 8cos θ + 4; its only zero in [0, π] "
                        "is 2π/3 (solveset) and it is 12 > 0 at θ = 0, so by continuity > 0 on [0, 2π/3[.")


_definition("at-sec4.1-alpha13-zero", "sec. 4.1", "α13 = 0 unless θ = 2π/3", r"\alpha_{13} = 0\ \text{for}\ \theta\ne\frac{2\pi}{3}",
            "Contact 1–3 is open for θ < 2π/3 (impactsym.models.acary_taha.pool closes it exactly at θ = 2π/3).")


def _eq27_claim(key: str):
    d, pr, cmp = _pool("tau0")
    th = sp.Symbol("theta", real=True)
    _baseline("tau0", (sp.cos(th), sp.sin(th)), restitution=sp.Symbol("e", positive=True))
    ok = cmp[key]
    return Finding("exact-match" if ok else "erratum", published=str(pr[key]), published_expr=pr[key], derived=d[key],
                   corrected=None if ok else d[key],
                   note="derivations.pool.pool_tau0 (general quadratic on the pool scene, τ = 0, any θ, e, α₁₂); exact "
                        f"identity after √Δ → symbol: {ok}.")


for _k in ("p1", "p2", "x1+", "y1+", "x2+", "y2+", "x3+", "y3+", "Delta"):
    def _mk(k=_k):
        @_cl(f"at-eq27-{k.replace('+', 'p')}", "eq. 27", k, "exact-match", [GQ])
        def _f():
            return _eq27_claim(k)
        return _f
    _mk()


_definition("at-eq28", "eq. 28", "validity conditions", r"\Delta\ge0,\ p\ge0,\ v_i^+\ge0")


def _pc(key):
    return _pool_claims()[key]


@_cl("at-sec4.1.1-v2-alpha", "sec. 4.1.1", "v2+ ≥ 0 ⇔ α12 ≥ cos θ/2 (θ < π/2)", "exact-match", [GQ])
def v2_alpha():
    r = _pc("v2_positive_iff")
    return Finding("exact-match" if r["verdict"] == "confirmed" else "refuted",
                   published=r"\forall\theta<\frac\pi2,\ \alpha_{12}\in[\frac{\cos\theta}{2},\infty)", derived=r["proof"],
                   note="derivations.domains.pool_claims: w₂⁺ = (2α − cos θ) p₁ with p₁ > 0.")


@_cl("at-eq29", "eq. 29", "g (v1+ = 0 on e = g(α12))", "exact-match", [GQ])
def eq29():
    from derivations.domains import pool_g, printed_eq29_g
    r = _pc("eq29_g")
    ok = r["verdict"] == "confirmed"
    return Finding("exact-match" if ok else "erratum", corrected=None if ok else pool_g(),
                   published=r"\frac{(2+\cos^2\theta)\alpha_{12}^2 - 4\cos\theta\,\alpha_{12} + 2}{\cos^2\theta\,\alpha_{12}^2 - 4\cos\theta\,\alpha_{12} + 4}",
                   published_expr=printed_eq29_g(), derived=pool_g(),
                   note="derivations.domains.pool_g: the e at which w₁⁺ = 0 (c = cos θ); identical to the print.")


@_cl("at-eq29-signature", "eq. 29", "signature of g", "erratum", [GQ])
def eq29_sig():
    from derivations.domains import pool_g
    r = _pc("eq29_signature")
    g = pool_g()
    a, e_ = sp.Symbol("alpha", nonnegative=True), sp.Symbol("e", positive=True)
    names = {str(x) for x in g.free_symbols}
    limit = sp.limit(g, a, sp.oo)
    # the printed signature g: [0,1] -> R, e -> ... is right only if g is a function of e; the derived g is the
    # e at which w1+ = 0, a function of alpha (and c = cos θ), and not [0,1]-valued on alpha >= cos θ/2
    if "e" in names:
        verdict = "exact-match"
    elif "alpha" in names and certified_sign(limit.subs(sp.Symbol("c", real=True), sp.cos(sp.pi / 4)) - 1) > 0:
        verdict = "erratum"
    else:
        raise ValueError(f"g has neither e nor alpha as its variable: {names}")
    return Finding(verdict, published=r"g: [0,1]\longmapsto\mathbb R,\quad e\longmapsto \dots(\alpha_{12})",
                   derived={"free symbols of g": sorted(map(str, g.free_symbols)), "g(oo)": limit},
                   corrected=r"g: [\tfrac{\cos\theta}{2}, \infty[\ \to\mathbb R,\quad \alpha_{12}\mapsto g(\alpha_{12})",
                   note="The printed map takes e to an expression in α₁₂: the variable is α₁₂ and the value is an e. "
                        f"g is not [0,1]-valued on the whole half-line (g → {limit} > 1 as α₁₂ → ∞; g ≤ 1 ⇔ α₁₂ ≤ 1), so D₁ "
                        "is empty beyond α₁₂ = 1.", evidence=r["proof"])


@_cl("at-eq30", "eq. 30", "D1 (valid set is the part above g)", "supported-by-samples", [DOM])
def eq30():
    from impactsym.domains import validity_domain
    dom = validity_domain("pool", sp.pi / 4)
    from derivations.domains import pool_g
    c = sp.cos(sp.pi / 4)
    g = pool_g(c)
    a = sp.Symbol("alpha", nonnegative=True)
    pts = [(sp.Rational(1, 2), 1), (sp.Rational(3, 4), sp.Rational(9, 10)), (sp.Rational(9, 10), sp.Rational(99, 100))]
    rows = []
    ok = True
    for al, ee in pts:
        gv = g.subs(a, al)
        above = certified_sign(ee - gv) > 0
        member = dom.contains(al, ee)
        below = dom.contains(al, gv - sp.Rational(1, 100))
        ok &= above == member and not below
        rows.append({"alpha": al, "e": ee, "g": gv, "in D": member, "just below g in D": below})
    return Finding("supported-by-samples" if ok else "refuted",
                   published=r"\mathcal D_1 = \{(\alpha_{12},e)\in[\frac{\cos\theta}2,+\infty[\times[g(\alpha_{12}),1]\}",
                   derived=rows, note=f"Sampled, not proved: {2 * len(pts)} exact memberships at θ = π/4. "
                   "impactsym.domains.validity_domain('pool', π/4): points above g are valid, points "
                   "just below g are not (exact membership).")


@_cl("at-sec4.1.1-theta-gt-pi2", "sec. 4.1.1", "θ > π/2: relative velocities positive irrespective of α12, e", "refuted", [GQ])
def theta_gt():
    r = _pc("theta_gt_pi2_always_positive")
    return Finding("refuted" if r["verdict"] == "refuted" else "exact-match",
                   published="When θ > π/2 the relative normal velocities are always positive irrespective of α12 and e.",
                   derived=r["proof"],
                   note="Counterexample (derivations.domains.pool_claims): cos θ = −1/4, α₁₂ = 2, e = 1 gives "
                        f"v₁⁺ = {r['proof']['v1+']} < 0. True only for v₂⁺ = (2α − cos θ) p₁.")


@_cl("at-eq31", "eq. 31", "h (Δ = 0 on e = h(α12))", "erratum", [GQ])
def eq31():
    from derivations.domains import pool_h, printed_eq31_h
    r = _pc("eq31_h")
    return Finding("erratum" if r["verdict"] == "corrected" else "exact-match",
                   published=r"h(\alpha_{12}) = \frac{2\alpha_{12}^2 - 2\cos\theta + 1}{2(\alpha_{12}^2 - \cos\theta\,\alpha_{12} + 1)}",
                   published_expr=printed_eq31_h(), derived=pool_h(),
                   corrected=pool_h(sp.cos(sp.Symbol("theta", real=True))),
                   note="Δ ≥ 0 ⇔ e ≥ h(α) = 1 − 1/(2A), A = α² − α cos θ + 1 (derivations.domains.pool_h); the numerator "
                        f"lacks the α of −2α cos θ (printed − derived = {r['proof']['printed_minus_derived']}).")


@_cl("at-eq32", "eq. 32", "D2 (uses g where h is meant)", "erratum", [GQ, IRL])
def eq32():
    from derivations.domains import pool_g, pool_h
    c = sp.cos(sp.pi / 4)
    a = sp.Symbol("alpha", nonnegative=True)
    al = sp.Integer(1)
    gv, hv = sp.radsimp(pool_g(c).subs(a, al)), sp.radsimp(pool_h(c).subs(a, al))
    e_mid, e_low = sp.Rational(4, 5), sp.Rational(3, 5)  # at θ = π/4, α = 1: e_low < h(1) < e_mid < g(1) = 1
    if not (certified_sign(e_low - hv) < 0 < certified_sign(e_mid - hv) and certified_sign(gv - e_mid) > 0):
        raise ValueError(f"the test points do not straddle h(1) = {hv} and g(1) = {gv}")
    sc = pool(sp.pi / 4, 0)
    disc = {}
    for e_ in (e_low, e_mid):  # the law's own discriminant decides Δ ≥ 0
        # a state the law returns must lie on its energy line T⁺ = eT⁻ (checked exactly), or its
        # discriminant decides nothing about eq. 38
        r = _conserves_energy(sc.M, sc.H, sc.v, _law(sc.M, sc.H, sc.v, e_, [al], allow_invalid=True), e_,
                              "impulse_ratio_law", f"at theta = pi/4, alpha = {al}, e = {e_}")
        disc[e_] = "negative-discriminant" not in [x.condition for x in r.violations]
    if disc[e_low] or not disc[e_mid]:
        raise ValueError(f"impulse_ratio_law's Δ ≥ 0 disagrees with e ≥ h(α) (derivations.domains.pool_h): {disc}")
    # (α, e) = (1, 4/5) has Δ ≥ 0 (in D₂ as defined: the Δ ≥ 0 set) but e < g(1): the printed set excludes it
    excluded_by_print = certified_sign(e_mid - gv) < 0
    return Finding("erratum" if excluded_by_print else "exact-match",
                   published=r"\mathcal D_2 = \{(\alpha_{12},e)\in[0,+\infty[\times[g(\alpha),1]\}",
                   derived={"alpha": al, "g": gv, "h": hv, "e between": e_mid, "law: Delta >= 0 at e": disc},
                   corrected=r"\mathcal D_2 = \{(\alpha_{12},e)\in[0,+\infty[\times[h(\alpha_{12}),1]\}",
                   note="D₂ is where Δ ≥ 0, i.e. e ≥ h(α₁₂) (eq. 31 corrected). The printed set uses g: at θ = π/4, "
                        f"α₁₂ = 1 the pair e = 4/5 (h = {sp.N(hv, 6)} < e < g = {sp.N(gv, 6)}, exact signs) has Δ ≥ 0 but is "
                        "excluded by the print. impulse_ratio_law agrees: Δ ≥ 0 at e = 4/5, Δ < 0 at e = 3/5 < h.")


@_cl("at-sec4.1.1-h-geq-g", "sec. 4.1.1", "h(α12) ≥ g(α12) on [cos θ/2, ∞[", "erratum", [GQ])
def h_geq_g():
    r = _pc("h_geq_g")
    return Finding("erratum" if r["verdict"] == "corrected" else "exact-match",
                   published=r"\forall\alpha_{12}\in[\frac{\cos\theta}2,+\infty[,\ h(\alpha_{12})\ge g(\alpha_{12})",
                   derived={"g - h": r["proof"]["g_minus_h"]},
                   corrected=r"g(\alpha_{12}) - h(\alpha_{12}) = \frac{\alpha_{12}^2(2\alpha_{12}-\cos\theta)^2}{2A(2-\alpha_{12}\cos\theta)^2}\ge0,"
                             r"\ \text{equality only at}\ \alpha_{12}\in\{0, \tfrac{\cos\theta}2\}",
                   note="The inequality is reversed: g ≥ h (A = α² − α cos θ + 1 > 0), touching at α = cos θ/2. The paper's "
                        "conclusion survives: e ≥ g implies Δ ≥ 0, so D = D₁ ∩ D₂ = D₁ and only g needs drawing.")


@_cl("at-sec4.1.1-g-minimum", "sec. 4.1.1", "min g at α = cos θ/2, value (2 − cos²θ)/(4 − cos²θ)", "exact-match", [GQ])
def g_min():
    from derivations.domains import pool_g
    c = sp.Symbol("c", real=True)
    a = sp.Symbol("alpha", nonnegative=True)
    g = pool_g()
    # for every c = cos θ ∈ [0, 1]: g' = 0 only at α = c/2 (pool_claims), g'' there = 64/(4 − c²)³ > 0
    # (4 − c² ≥ 3 on [0, 1]), and g(c/2) equals the print (symbolic identities, not samples)
    ex = extremum(g, a, c / 2, kind="min")
    d2 = sp.factor(ex["f''(x0)"])
    d2_form = identical(d2, 64 / (4 - c**2) ** 3).equal
    positive = solveset_remembered(4 - c**2 <= 0, c, sp.Interval(0, 1)) == sp.S.EmptySet
    value = identical(g.subs(a, c / 2), (2 - c**2) / (4 - c**2)).equal
    r = _pc("g_minimum")
    ok = ex["stationary"] and d2_form and positive and value and r["verdict"] == "confirmed"
    return Finding("exact-match" if ok else "refuted",
                   published=r"\min g = g(\tfrac{\cos\theta}2) = \frac{2-\cos^2\theta}{4-\cos^2\theta}",
                   derived={"g'(c/2)": ex["f'(x0)"], "g''(c/2)": d2, "critical points": r["proof"]["critical_points"],
                            "dg": r["proof"]["dg"]},
                   note="g′ = 4(c − 2α)/(αc − 2)³ vanishes at α = c/2 only; g″(c/2) = 64/(4 − c²)³ > 0 for c ∈ [0, 1] "
                        "(proved for symbolic c); value identical to the print. Valid for θ ≤ π/2 (c ≥ 0); for c < 0 the "
                        "minimum over α ≥ 0 is g(0) = 1/2.")


@_cl("at-fig3", "sec. 4.1.1", "Figure 3: valid domain for θ = π/4", "exact-match", [DOM])
def fig3():
    # the figure's content is the domain impactsym.domains.plot_domain shades and marks
    # (validity_domain at θ = π/4, its lowest e); the PNG itself is drawn by `reproduce --report`
    # into the report's folder (drawing it here cost matplotlib's import and left a temporary
    # folder behind on every run)
    from impactsym.domains import validity_domain
    dom = validity_domain("pool", sp.pi / 4)
    emin = dom.region["e"][0]
    if not isinstance(emin, sp.Basic):
        raise TypeError(f"validity_domain's lowest e must be exact, got {type(emin).__name__} {emin!r}")
    ok = identical(emin, sp.Rational(3, 7)).equal
    figure = "fig3.png of `impactsym reproduce --report DIR` (impactsym.domains.plot_domain)"
    return Finding("exact-match" if ok else "refuted", published="Figure 3. Valid domain of e and α for θ = π/4 (image)",
                   derived={"e_min": emin, "figure": figure},
                   note="impactsym.domains.plot_domain(π/4): region above g, below e = 1; lowest e = (2 − 1/2)/(4 − 1/2) = 3/7 "
                        "at α = √2/4. The figure's printed image is not machine-readable; `impactsym reproduce --report` "
                        "embeds the regenerated one.", evidence={"figure_path": figure})


@_cl("at-sec4.1.1-case1-theta0", "sec. 4.1.1", "θ = 0 recovers the 1-D chain", "exact-match", [CHAIN])
def theta0():
    d, _, _ = _pool("tau0")
    chain, _, _ = _chain()
    th = sp.Symbol("theta", real=True)
    al = sp.Symbol("alpha", positive=True)
    m = sp.Symbol("m", positive=True)
    ok = True
    for pk, ck in (("x1+", "q1+"), ("x2+", "q2+"), ("x3+", "q3+")):
        ok &= bool(identical(d[pk].subs(th, 0), chain[ck]))
    ok &= all(is_zero(d[k].subs(th, 0)) for k in ("y1+", "y2+", "y3+"))
    return Finding("exact-match" if ok else "refuted", published="the solution of the monodimensional 3-ball chain is found again when we set θ = 0",
                   derived={k: simplify(d[k].subs(th, 0)) for k in ("x1+", "x2+", "x3+")},
                   note="derivations.pool.pool_tau0 at θ = 0 against derivations.chain3 (x-components equal, y-components 0).")


# --------------------------------------------------------------------------- eq. 33
@_cl("at-eq33-label", "eq. 33", "θ of eq. 33 (labelled π/2)", "erratum", [GQ])
def eq33_label():
    r = _eq33_theta()
    at_pi2 = r["at_pi_over_2"]
    thetas = r["theta"]
    if not thetas:
        raise ValueError("no θ in [0, 2π/3] reproduces eq. 33's entries: the label cannot be decided")
    label_ok = any(is_zero(t - sp.pi / 2) for t in thetas)
    return Finding("exact-match" if label_ok else "erratum", published="Case 2. θ = π/2. For e = 1, we have the following solution ... (33)",
                   derived={"theta solving the correctly printed entries": r["theta"], "misprinted at that theta": r["misprinted"],
                            "entries matching at theta = pi/2": [k for k, v in at_pi2.items() if v]},
                   corrected=None if label_ok else rf"\theta = {sp.latex(thetas[0])}\ (e = 1,\ \tau = 0)",
                   note="derivations.pool.eq33_theta: the denominators and ẋ₁⁺, ẏ₂⁺, ẋ₃⁺ hold only at θ = π/3; at the "
                        f"labelled θ = π/2 only {[k for k, v in at_pi2.items() if v]} agree. The text says π/2; the mathematics "
                        f"says {thetas}.")


def _derived_state_holds(d: dict, vminus, eps=None, restitution=1) -> None:
    """Raise unless the derived pool state ``d`` conserves momentum and energy (``T⁺ = eT⁻``) for
    ball 1's pre-impact velocity ``vminus``: a comparison with a print needs a sound baseline.
    ``eps`` (ε = sign cos τ) is checked at both signs."""
    from derivations.pool import momentum_energy_residuals
    res = momentum_energy_residuals(d, vminus, restitution, simplified=False)  # decided by is_zero below
    vals = [res["px"], res["py"], res["energy"]]
    if eps is not None:
        vals = [x.subs(eps, sgn) for x in vals for sgn in (1, -1)]
    bad = [x for x in vals if not is_zero(x)]
    if bad:
        raise ValueError(f"the derived state violates momentum or energy ({res}): no baseline to compare the print with")


@lru_cache(maxsize=None)
def _baseline_failure(name: str, vminus: tuple, eps=None, restitution=1) -> str | None:
    """:func:`_derived_state_holds` for the derived state of ``_pool(name)``, decided once per
    process and shared by the claims of one equation: None when it holds, else its message (an
    ``lru_cache``, which the mutation tests clear with every other cache, so a mutant's state is
    checked afresh; a failure is cached too, so that every claim of the equation raises it without
    simplifying the same non-zero residual again)."""
    try:
        _derived_state_holds(_pool(name)[0], vminus, eps, restitution)
    except ValueError as exc:
        return str(exc)
    return None


def _baseline(name: str, vminus: tuple, eps=None, restitution=1) -> None:
    """Raise ``ValueError`` unless the derived state of ``_pool(name)`` conserves momentum and
    energy (:func:`_derived_state_holds`, decided once per process)."""
    failure = _baseline_failure(name, vminus, eps, restitution)
    if failure is not None:
        raise ValueError(failure)


def _eq33_claim(key: str):
    d, pr, cmp = _pool("eq33")
    from derivations.pool import momentum_energy_residuals
    ok = cmp[key]
    _baseline("eq33", (sp.Rational(1, 2), sp.sqrt(3) / 2))
    # printed factored: the residuals as they stand (factor gives the form it gave after simplify)
    res = None if ok else momentum_energy_residuals(pr, (sp.Rational(1, 2), sp.sqrt(3) / 2), energy=False,
                                                    simplified=False)
    return Finding("exact-match" if ok else "erratum", published=str(pr[key]), published_expr=pr[key], derived=d[key],
                   corrected=None if ok else d[key],
                   note="Compared with the derived e = 1 solution at θ = π/3 (what eq. 33 is, see at-eq33-label); "
                        + ("identical." if ok else f"misprint; the printed state fails momentum: Δp_x = {sp.factor(res['px'])}, "
                                                   f"Δp_y = {sp.factor(res['py'])}."))


for _k, _exp in (("x1+", "exact-match"), ("y1+", "erratum"), ("x2+", "erratum"), ("y2+", "exact-match"),
                 ("x3+", "exact-match"), ("y3+", "exact-match")):
    def _mk33(k=_k, ex=_exp):
        @_cl(f"at-eq33-{k.replace('+', 'p')}", "eq. 33", k, ex, [GQ])
        def _f():
            return _eq33_claim(k)
        return _f
    _mk33()


def _eq34_claim(key: str):
    d, pr, cmp = _pool("eq34")
    ok = cmp[key]
    return Finding("exact-match" if ok else "erratum", published=str(pr[key]), published_expr=pr[key], derived=d[key],
                   corrected=None if ok else d[key],
                   note="derivations.pool.pool_at_theta(π/2) (τ = 0, any e): eq. 34 belongs to θ = π/2, unlike eq. 33.")


@_cl("at-eq34-p1", "eq. 34", "p1 (θ = π/2)", "exact-match", [GQ])
def eq34_p1():
    return _eq34_claim("p1")


@_cl("at-eq34-p2", "eq. 34", "p2 (θ = π/2)", "exact-match", [GQ])
def eq34_p2():
    return _eq34_claim("p2")


def _coupling_at(theta_value):
    from impactsym.laws.coupling import coupling_decision
    sc = pool(theta_value, 0)
    return coupling_decision(sc.M, sc.H, sc.v)


def _coupling_proof():
    """Criterion 43 on the pool for symbolic θ: the sign of W₁₂ (``impactsym.laws.delassus.delassus``)
    against the sign of cos θ. Returns ``(W₁₂, k)`` with ``W₁₂ = k cos θ``; raises when ``W₁₂`` is no
    constant multiple of cos θ (then no sign rule can be read off)."""
    from impactsym.laws.delassus import delassus
    th = sp.Symbol("theta", real=True)
    sc = pool(th, 0)
    w12 = simplify(delassus(sc.M, sc.H)[0, 1])
    k = simplify(w12 / sp.cos(th))
    if not (k.is_number and k != 0):
        raise ValueError(f"W_12 = {w12} is not a constant multiple of cos(theta)")
    return w12, k


def _coupling_samples(angles, expect_coupled):
    """The package's decision (``coupling_decision``) at sample angles, checked against the symbolic
    rule; a disagreement is a bug in one of them (raises)."""
    rows = {}
    for t in angles:
        d = _coupling_at(t)
        rows[str(t)] = {"cos theta12": d.cosines[(0, 1)], "coupled": d.coupled[(0, 1)]}
        if d.coupled[(0, 1)] != expect_coupled(t):
            raise ValueError(f"coupling_decision at theta = {t} disagrees with the sign of W_12: {rows[str(t)]}")
    return rows


@_cl("at-sec4.1.1-pi2-alpha0", "sec. 4.1.1", "θ = π/2 and θ ∈ ]π/2, 2π/3[: enforce α12 = 0", "exact-match", [DEL])
def pi2_alpha0():
    th = sp.Symbol("theta", real=True)
    w12, k = _coupling_proof()
    # coupled ⇔ W₁₂ = k cos θ < 0; on [π/2, 2π/3[ cos θ ≤ 0 (solveset), so with k < 0 never coupled
    cos_pos = solveset_remembered(sp.cos(th) > 0, th, sp.Interval.Ropen(sp.pi / 2, 2 * sp.pi / 3))
    ok = certified_sign(k) < 0 and cos_pos == sp.S.EmptySet
    rows = _coupling_samples((sp.pi / 2, 3 * sp.pi / 5, 5 * sp.pi / 8),
                             lambda t: certified_sign(k * sp.cos(t)) < 0)
    rows["W_12(theta)"] = w12
    return Finding("exact-match" if ok else "refuted",
                   published="In this particular position, the ball 3 must remain stationary. Hence ... α12 = 0 (and for θ ∈ ]π/2, 2π/3[)",
                   derived=rows, note=f"impactsym.laws.delassus.delassus on the pool, symbolic θ: W₁₂ = {w12}, and cos θ ≤ 0 on "
                   "[π/2, 2π/3[ (solveset), so cos θ₁₂ = −½cos θ ≥ 0: contacts 1–2 and 2–3 are not coupled (criterion 43) "
                   "and α₁₂ = 0 (proved for every θ; coupling_decision agrees at π/2, 3π/5, 5π/8).")


@_cl("at-sec4.1.1-well-posed", "sec. 4.1.1", "well posed on [0, 2π/3[ with α12 = 0 on [π/2, 2π/3[",
     "supported-by-samples", [IRL])
def well_posed():
    rows = []
    ok = True
    for t, al in ((0, 1), (sp.pi / 4, sp.Rational(1, 2)), (sp.pi / 3, sp.Rational(3, 4)), (sp.pi / 2, 0),
                  (3 * sp.pi / 5, 0), (5 * sp.pi / 8, 0)):
        sc = pool(t, 0)
        r = _law(sc.M, sc.H, sc.v, 1, [al], allow_invalid=True)
        # valid by the law's own account and by an independent exact check of the impact equations
        holds = r.velocity is not None and conservation(sc.M, sc.H, sc.v, r.velocity, 1, values=False)["holds"]
        rows.append({"theta": t, "alpha12": al, "valid": r.valid, "impact equations hold": holds})
        ok &= r.valid and holds
        if not ok:  # one sampled pair where the law fails is the counterexample: the rest cannot restore it
            break
    return Finding("supported-by-samples" if ok else "refuted",
                   published="our model is well posed for θ ∈ [0, 2π/3[ and τ = 0 if we set α12 = 0 for all θ ∈ [π/2, 2π/3[",
                   derived=rows, note=f"Sampled, not proved: {len(rows)} (θ, α₁₂) pairs. "
                   "impactsym.laws.impulse_ratio.impulse_ratio_law, e = 1, exact: every sampled (θ, α₁₂) "
                   "is valid (p ≥ 0, H v⁺ ≥ 0, Δ ≥ 0) and its state satisfies momentum, T⁺ = T⁻, p ≥ 0, H v⁺ ≥ 0 exactly "
                   "(framework.conservation). The domain of α for θ < π/2 is at-eq30 / at-fig3.")


# =========================================================================== sec. 4.2
@_cl("at-sec4.2-tau-ge-pi2", "sec. 4.2", "τ ≥ π/2: only simple impact occurs", "refuted", [POOL])
def tau_ge():
    rows = []
    for t in (sp.pi / 2, 2 * sp.pi / 3, 3 * sp.pi / 4):
        for th in (0, sp.pi / 4):
            sc = pool(th, t)
            w = [_expanded_number(x) for x in sc.H * sc.v]
            rows.append({"theta": th, "tau": t, "H v-": w, "approaching": [certified_sign(x) < 0 for x in w]})
    # for symbolic θ, τ: H q̇⁻ = (w₁(τ), 0); if w₁ is free of θ, solveset decides its sign on [π/2, π] (a proof)
    th_, tau_ = sp.symbols("theta tau", real=True)
    sc = pool(th_, tau_)
    w_sym = [simplify(x) for x in sc.H * sc.v]
    if w_sym[1] == 0 and not w_sym[0].has(th_):
        none = solveset_remembered(w_sym[0] < 0, tau_, sp.Interval(sp.pi / 2, sp.pi)) == sp.S.EmptySet
        how = f"proved for every θ and τ ∈ [π/2, π]: H q̇⁻ = {w_sym}"
    else:  # the samples decide (a non-approaching sample is still an exact counterexample)
        none = all(not any(r["approaching"]) for r in rows)
        how = f"decided at {len(rows)} exact samples: H q̇⁻ = {w_sym}"
    return Finding("refuted" if none else "exact-match", published="We can state obviously that for τ ≥ π/2 only simple impact occurs.",
                   derived={"H v- (symbolic)": w_sym, "samples": rows},
                   note=f"{how}. For τ ≥ π/2, H₁q̇⁻ = −cos τ ≥ 0 and H₂q̇⁻ = 0: no contact approaches, so there is no "
                   "impact at all (τ = π/2 grazing). The text itself says so two paragraphs later ('the case with no impact "
                   "(τ ≥ π/2)', the ε device); the mathematics supports 'no impact'.")


@_cl("at-sec4.2-epsilon", "sec. 4.2", "ε = sign(cos τ) device", "exact-match", [GQ])
def epsilon():
    from derivations.pool import epsilon_device
    r = epsilon_device()
    return Finding("exact-match" if r["proven"] else "refuted", published=r"\epsilon = \mathrm{sign}(\cos\tau),\ 1\ \text{for}\ \tau\le\frac\pi2,\ -1\ \text{otherwise}",
                   derived={"roots at e=1": r["roots"], "physical root": r["physical_root"]},
                   note="derivations.pool.epsilon_device: at e = 1, √Δ = |cos τ| = ε cos τ and the physical root is "
                        "(1 + ε)cos τ/(2A): p = 0 for cos τ < 0. (At τ = π/2, sign(cos τ) = 0, not 1; every entry carries a "
                        "factor cos τ, so the value is unaffected.)")


def _eq3536_claim(name: str, key: str, theta_label: str):
    d, pr, cmp = _pool(name)
    from derivations.pool import momentum_energy_residuals
    ok = cmp[key]
    th_, tau_ = (0 if name == "eq35" else sp.pi / 2), sp.Symbol("tau", real=True)
    _baseline(name, (sp.cos(th_ - tau_), sp.sin(th_ - tau_)), eps=sp.Symbol("epsilon", real=True))
    note = f"derivations.pool.pool_any_tau({theta_label}) (e = 1, any τ, ε = sign(cos τ), incidence θ − τ); identical: {ok}."
    if not ok:
        tau = sp.Symbol("tau", real=True)
        eps = sp.Symbol("epsilon", real=True)
        th = 0 if name == "eq35" else sp.pi / 2
        vm = (sp.cos(th - tau), sp.sin(th - tau))
        res = momentum_energy_residuals(pr, vm, energy=False, simplified=False)  # factored at ε = 1 below
        # a rational function of α and cos τ: factor is its factored normal form, the same with or
        # without a simplify first (srepr for srepr; 0.08 s of simplify's search spared)
        note += f" The printed state fails x-momentum: Δp_x = {sp.factor(res['px'].subs(eps, 1))} at ε = 1."
    return Finding("exact-match" if ok else "erratum", published=str(pr[key]), published_expr=pr[key], derived=d[key],
                   corrected=None if ok else d[key], note=note)


for _k, _exp in (("x1+", "exact-match"), ("y1+", "exact-match"), ("x2+", "erratum"), ("y2+", "exact-match"),
                 ("x3+", "exact-match"), ("y3+", "exact-match")):
    def _mk35(k=_k, ex=_exp):
        @_cl(f"at-eq35-{k.replace('+', 'p')}", "eq. 35", k, ex, [GQ])
        def _f():
            return _eq3536_claim("eq35", k, "0")
        return _f
    _mk35()

for _k in ("x1+", "y1+", "x2+", "y2+", "x3+", "y3+"):
    def _mk36(k=_k):
        @_cl(f"at-eq36-{k.replace('+', 'p')}", "eq. 36", k, "exact-match", [GQ])
        def _f():
            return _eq3536_claim("eq36", k, "π/2")
        return _f
    _mk36()


@_cl("at-sec4.2-case-labels", "sec. 4.2", "case numbering (two 'Case 2')", "erratum")
def case_labels():
    return Finding("erratum", judgment="a reading of the section's labels: 'Case 2' is printed twice; which one is "
                                       "misnumbered is typography, with nothing for impactsym to compute", published="Case 1. θ ∈ [0, π/2[ ... Case 2. θ = π/2 ... Case 2. θ ∈ [π/2, 2π/3[ ... Case 3. θ = 2π/3",
                   derived={"labels": ["Case 1", "Case 2", "Case 2", "Case 3"]},
                   corrected="Case 1, Case 2 (θ = π/2), Case 3 (θ ∈ ]π/2, 2π/3[), Case 4 (θ = 2π/3)",
                   note="Sec. 4.2 uses the label 'Case 2' twice (sec. 4.1.1 numbers the same θ ranges 1–4); the second "
                        "range overlaps the first at θ = π/2.")


# --------------------------------------------------------------------------- eq. 37
@_cl("at-eq37-labels", "eq. 37", "component labels (ẏ3⁺ twice)", "erratum")
def eq37_labels():
    r = _eq37()
    return Finding("erratum", judgment="a reading of the component labels: ẏ₃⁺ is printed twice and ẋ₃⁺ not at all; "
                                       "reading the first as ẋ₃⁺ is supported (the y-sum is then the pre-impact 1/2) but "
                                       "remains a reading of the typesetting", published="... ẏ3+ = 5α12√3/(4α12²+α12+4), ẏ3+ = 3α12/(2(4α12²+α12+4))",
                   derived={"y-momentum of the print (reading the first ẏ3⁺ as ẋ3⁺)": r["py_printed"]},
                   corrected=r"\dot x_3^+ = \dots,\ \dot y_3^+ = \dots",
                   note="Six components, ẏ₃⁺ listed twice and ẋ₃⁺ missing. Reading the first as ẋ₃⁺, the y-components sum to "
                        f"the pre-impact 1/2 ({r['py_printed']}), which supports that reading.")


def _eq37_claim(key: str):
    d, pr, _ = _pool("eq37")
    r = _eq37()
    sc = bernoulli()
    _baseline("eq37", (sc.v[0], sc.v[1]))
    idn = identical(d[key], pr[key], domain={sp.Symbol("alpha", positive=True): (sp.Rational(1, 5), 3)})
    verdict = idn.decide("exact-match", "refuted")
    return Finding(verdict, published=str(pr[key]), published_expr=pr[key], derived=d[key],
                   note="derivations.pool.bernoulli_closed_form (θ = 2π/3, τ = −π/6, e = 1, α₁₃ = α₁₂; denominator "
                        "2(5α² + 2α + 2)). No reading reproduces the print (derivations.pool.eq37_analysis: 3 incidences × 2 "
                        f"constraint scalings × 2 ratio assignments, matches = {r['matches']}). The printed state violates "
                        f"x-momentum (Σẋ⁺ = {r['px_printed']} ≠ −√3/2 for α > 0); its momentum repair (ẋ₃⁺ halved) has "
                        f"α₁₃ = α₁₂/2 and gains energy, T⁺/T⁻ − 1 = {sp.factor(r['energy_ratio'] - 1)}. Difference: {idn.method}.",
                   evidence={"readings": r["readings"]})


for _k, _exp in (("x1+", "refuted"), ("y1+", "refuted"), ("x2+", "refuted"), ("y2+", "refuted"),
                 ("x3+", "refuted"), ("y3+", "refuted")):
    def _mk37(k=_k, ex=_exp):
        @_cl(f"at-eq37-{k.replace('+', 'p')}", "eq. 37", k, ex, [GQ])
        def _f():
            return _eq37_claim(k)
        return _f
    _mk37()


@_cl("at-eq37-conservation", "eq. 37", "printed state: momentum and energy", "refuted", [GQ])
def eq37_cons():
    r = _eq37()
    sc = bernoulli()
    d, _, _ = _pool("eq37")
    _baseline("eq37", (sc.v[0], sc.v[1]))  # the law's state conserves both: the baseline
    from derivations.pool import momentum_energy_residuals, printed_eq37
    # the residuals are decided as they stand (identical: an exact zero test, else a certified
    # counterexample point); simplifying them first would only cost time
    res_p = momentum_energy_residuals(printed_eq37(), (sc.v[0], sc.v[1]), simplified=False)
    dom = {sp.Symbol("alpha", positive=True): (sp.Rational(1, 5), 3)}
    checks = [identical(res_p[k], 0, domain=dom) for k in ("px", "py", "energy")]
    if any(x.different for x in checks):
        verdict = "refuted"
    elif all(x.equal for x in checks):
        verdict = "exact-match"
    else:
        raise ValueError(f"the printed state's balance is undecided: {[x.method for x in checks]}")
    return Finding(verdict, published="eq. 37 (as printed, first ẏ3⁺ read as ẋ3⁺)",
                   derived={"sum x+": r["px_printed"], "sum y+": r["py_printed"], "repaired: implied ratios": r["implied_ratios"],
                            "repaired: T+/T-": r["energy_ratio"]},
                   note="Momentum is conserved by every impulsive outcome of internal contacts, whatever the geometry: the "
                        f"printed x-sum {r['px_printed']} equals the pre-impact −√3/2 only at α = 0. The only momentum-restoring "
                        "change of one entry creates energy for every α > 0.")


@_cl("at-sec4.2-case3a-consistent", "sec. 4.2", "Case 3.a: consistent for all τ ∈ [−π/3, 0]", "refuted", [IRL])
def case3a():
    rows = []
    bad = []
    for t in (-sp.pi / 3, -sp.pi / 4, -sp.pi / 6, -sp.pi / 12, 0):
        sc = bernoulli(t)  # one scene per tau, shared by the three ratios
        for al in (0, sp.Rational(1, 4), sp.Rational(1, 2)):
            # every state the rows report is checked against the energy line (momentum: _law), the
            # valid ones included: the claim rests on all of them, not only on its counterexample
            where = f"at tau = {t}, alpha = {al}"
            r = _conserves_energy(sc.M, sc.H, sc.v, _law(sc.M, sc.H, sc.v, 1, [al, al], allow_invalid=True),
                                  1, "impulse_ratio_law", where)
            rc = _conserves_energy(sc.M, sc.H, sc.v,
                                   _law(sc.M, sc.H, sc.v, 1, [al, al], allow_invalid=True, coupling=True),
                                   1, "impulse_ratio_law (coupling)", where)
            row = {"tau": t, "alpha12=alpha13": al, "valid": r.valid,
                   "violations": [v.condition for v in r.violations], "valid with sec. 5 coupling": rc.valid,
                   "H v-": [_expanded_number(x) for x in sc.H * sc.v]}
            rows.append(row)
            if not r.valid and r.velocity is not None:
                # a counterexample must be a state of the law (momentum and T⁺ = T⁻ hold exactly) that
                # violates eq. 28 (a contact penetrates or an impulse is negative)
                c = conservation(sc.M, sc.H, sc.v, r.velocity, 1, values=False)  # its decisions only
                if not (c["momentum"] and c["energy"]):
                    raise ValueError(f"impulse_ratio_law's state at tau = {t}, alpha = {al} violates momentum or "
                                     f"energy: {c}; no counterexample can rest on it")
                row["conservation"] = {"momentum": c["momentum"], "energy": c["energy"], "contacts": c["contacts"],
                                       "p >= 0": c["impulses_nonnegative"]}
                if c["contacts"] is False or c["impulses_nonnegative"] is False:
                    bad.append(row)
    return Finding("refuted" if bad else "exact-match",
                   published="The model always yields consistent result for all τ ∈ [−π/3, 0].",
                   derived=rows,
                   note="impactsym.laws.impulse_ratio.impulse_ratio_law on the Bernoulli scene (θ = 2π/3, incidence θ − τ), "
                        "e = 1, α₁₃ = α₁₂ ∈ {0, 1/4, 1/2}: "
                        + (f"counterexample τ = {bad[0]['tau']}, α = {bad[0]['alpha12=alpha13']}: {bad[0]['violations']} "
                           f"(contact 1–3 separates, H q̇⁻ = {bad[0]['H v-']}, yet receives α p₁). " if bad else "")
                        + "Small ratios are valid; the paper names no α. Caveat: eq. 37 is reproduced by no reading of the "
                          "Bernoulli geometry (see at-eq37-*), so this refutes the statement for the θ − τ reading that eqs. "
                          "27, 35, 36 support.")


@_cl("at-sec4.2-case3bc", "sec. 4.2", "Cases 3.b, 3.c: consistent for τ ∈ [0, π/2], [π/2, 2π/3]", "not-checkable")
def case3bc():
    return Finding("not-checkable", published="for all τ ∈ [0, π/2] the provided solution is consistent ... irrespective of α's",
                   note="No solution, α or e is printed for these ranges; 'consistent' is not defined beyond eq. 28. "
                        "impactsym.domains.validity_domain('bernoulli-tau0') gives the τ = 0 domain, which is not all α.")


# =========================================================================== sec. 5
@_cl("at-eq38-dv", "eq. 38", "'Δv ≥ 0' in the general law", "erratum", [IRL])
def eq38_dv():
    M, H, v = _chain_args()
    e_ = sp.Rational(5, 8)
    law = _law(M, H, v, e_, [1], allow_invalid=True)
    if law.velocity is None:
        raise ValueError("impulse_ratio_law(chain, e = 5/8, alpha = 1) has no real root: nothing to test eq. 38 on")
    A, B, C = law.coefficients
    a = sp.Matrix(law.ratios)
    Tm = (v.T * M * v)[0, 0] / 2
    states = []
    for sgn in (1, -1):  # both roots of the law's quadratic in p1
        p1 = sp.radsimp((-B + sgn * sp.sqrt(B**2 - 4 * A * C)) / (2 * A))
        p = a * p1
        vp = v + M.LUsolve(H.T * p)
        dv, w = H * (vp - v), H * vp
        Tp = sp.radsimp((vp.T * M * vp)[0, 0] / 2)
        printed_ok = all(certified_sign(x) >= 0 for x in [*dv, *p]) and Tp == e_ * Tm  # eq. 38 as printed
        corrected_ok = printed_ok and all(certified_sign(x) >= 0 for x in w)  # with v⁺ = Hq̇⁺ ≥ 0 instead
        states.append({"p": p, "v+": vp, "Delta v": dv, "H v+": w, "e = T+/T-": Tp / Tm,
                       "printed conditions hold": printed_ok, "corrected conditions hold": corrected_ok,
                       "is the law's state": list(vp) == list(law.velocity)})
    n_printed = sum(st["printed conditions hold"] for st in states)
    mine = [st for st in states if st["is the law's state"]]
    if len(mine) != 1 or mine[0]["corrected conditions hold"] != law.valid:
        raise ValueError(f"the law's own validity disagrees with the corrected eq. 38 conditions: {states}, "
                         f"valid = {law.valid}")
    spurious = next((st for st in states if st["printed conditions hold"] and not st["corrected conditions hold"]), None)
    if spurious is None:
        return Finding("exact-match", published=r"\Delta v\ge0\qquad p\ge0", derived=states,
                       note=f"Δv ≥ 0 admits {n_printed} root(s) of the law's quadratic, as v⁺ ≥ 0 does.")
    p, vp, dv, w = spurious["p"], spurious["v+"], spurious["Delta v"], spurious["H v+"]
    return Finding("erratum", published=r"\Delta v\ge0\qquad p\ge0",
                   derived={"p": p, "v+": vp, "Delta v": dv, "H v+": w, "e": e_, "alpha": p[1] / p[0], "roots": states},
                   corrected=r"v(t_k^+) = H\dot q^+\ge0,\qquad p\ge0",
                   note=f"Counterexample to the printed condition: on the chain (α = 1, e = 5/8) {n_printed} root(s) of the "
                        f"law's quadratic satisfy Δv ≥ 0, p ≥ 0 and the energy line; p = {list(p)} has "
                        f"Δv = {list(dv)} ≥ 0 yet H v⁺ = {list(w)}: balls 1 and 2 interpenetrate. Eq. 8 (the paper's own "
                        "constraint) requires v⁺ = Hq̇⁺ ≥ 0, which rejects it; impulse_ratio_law's validity flag agrees "
                        "with the corrected conditions.")


@_cl("at-eq38-qdot", "eq. 38", "'q⁺' in the energy line", "erratum")
def eq38_q():
    return Finding("erratum", judgment="a reading of one symbol: the energy line prints q⁺ where the kinetic energy "
                                       "needs the velocity q̇⁺; a quadratic form in a configuration is typography, not "
                                       "something to compute", published=r"\frac12\dot q^{+T}.M.q^+ = e.\frac12\dot q^{-T}.M.\dot q^-",
                   derived={"law energy line": "T⁺ = e T⁻ (derivations.impulse_ratio.general_quadratic)"},
                   corrected=r"\frac12\dot q^{+T}M\dot q^{+} = e\,\frac12\dot q^{-T}M\dot q^{-}",
                   note="The kinetic energy is a quadratic form in the velocity q̇⁺, not in the configuration q⁺ "
                        "(dimensionally inconsistent as printed).")


@_cl("at-eq38-law", "eq. 38", "the impulse-ratio law closes the system", "exact-match", [GQ])
def eq38_law():
    from derivations.impulse_ratio import general_quadratic, physical_root_proof
    r = physical_root_proof()
    d, _, _ = _chain()
    # the derivation's law on the chain at e = 1 picks the non-trivial root −B/A, the other is p = 0
    M, H, v = _chain_args()
    law = general_quadratic(M, H, v, 1, [sp.Symbol("alpha", positive=True)])
    picks = identical(law.p1, -law.B / law.A).equal and identical(law.p1_other, 0).equal
    return Finding("exact-match" if (r["proven"] and picks) else "refuted",
                   published=r"M\Delta\dot q = P,\ v = H\dot q,\ P = H^Tp,\ p\ge0,\ T^+ = eT^-,\ \mathcal F(p_j - \alpha_{ij}p_i, v, \theta_{ij})",
                   derived={"quadratic": "A p1^2 + B p1 + C = 0", "chain A": d["A"], "chain Delta": d["Delta"]},
                   note="derivations.impulse_ratio.general_quadratic: with p = p₁(1, α₁₂, …) the energy line is a quadratic "
                        "in p₁; the physical root is (−B + √D)/(2A) (physical_root_proof: the other root is p = 0 at e = 1). "
                        "𝓕 is left unspecified by the paper (a definition).")


@_cl("at-eq39", "eq. 39", "M-normal n_i", "definition")
def eq39():
    M = sp.diag(sp.Rational(11, 10), 1)
    n = m_normal(M, sp.Matrix([[-1, 1]]))
    unit = simplify((n.T * M * n)[0, 0])
    return Finding("definition", published=r"n_i = \frac{M^{-1}\nabla_q h_i}{\sqrt{\nabla_q h_i^TM^{-1}\nabla_q h_i}}",
                   derived={"n (M = diag(11/10,1), h = [-1,1])": n, "n^T M n": unit},
                   note="impactsym.mechanics.m_normal; unit in the kinetic metric (nᵀMn = 1).")


@_cl("at-eq40", "eq. 40", "cos θ_ij = n_i n_j", "convention-difference", [KCOS])
def eq40():
    M = sp.diag(sp.Rational(11, 10), 1)
    hi, hj = sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]])
    ni, nj = m_normal(M, hi), m_normal(M, hj)
    euclid = sp.radsimp(simplify((ni.T * nj)[0, 0]))
    kinetic = kinetic_angle_cos(M, hi, hj)
    eq_M = identical((ni.T * M * nj)[0, 0], kinetic)
    if not eq_M.equal:
        raise ValueError(f"n_iᵀMn_j ≠ kinetic_angle_cos ({eq_M.method}): the M-normals and the kinetic angle disagree")
    # the same pair for M = I (the pool's metric): both readings agree there
    n_i1, n_j1 = m_normal(sp.eye(2), hi), m_normal(sp.eye(2), hj)
    same_at_identity = identical((n_i1.T * n_j1)[0, 0], kinetic_angle_cos(sp.eye(2), hi, hj)).equal
    euclid_vs = identical(euclid, kinetic)
    differ = euclid_vs.different
    if not same_at_identity:
        raise ValueError("for M = I the Euclidean and kinetic readings of eq. 40 differ: kinetic_angle_cos is wrong")
    return Finding("convention-difference" if differ else euclid_vs.decide("exact-match", "refuted"), published=r"\cos\theta_{ij} = n_in_j",
                   derived={"n_i^T M n_j": kinetic, "Euclidean n_i . n_j": euclid, "equal for M = diag(11/10,1)": not differ},
                   note="'n_i n_j' must be the kinetic-metric product n_iᵀMn_j (impactsym.mechanics.kinetic_angle_cos; the "
                        "paper speaks of the angle 'in the kinetic metric'). For M = I (the pool) the two readings coincide; "
                        f"for M = diag(11/10, 1) they differ ({kinetic} vs {euclid}) — the M-normals of eq. 39 are not "
                        f"Euclidean unit vectors. nᵢᵀMnⱼ equals the kinetic cosine ({eq_M.method}); for M = I both readings agree (proved).")


@_cl("at-eq41", "eq. 41", "tangent cone 𝒯_i and the impact criterion", "erratum", [IRL])
def eq41():
    sc = pool(0, 0)
    h1 = sc.H[0, :]
    qd = sc.v
    printed_member = certified_sign((-h1 * (-qd))[0, 0]) >= 0  # −v ∈ T_printed ⇔ −∇h·(−q̇) ≥ 0
    corrected_member = certified_sign((h1 * (-qd))[0, 0]) >= 0  # −v ∈ T ⇔ ∇h·(−q̇) ≥ 0
    r = _law(sc.M, sc.H, sc.v, 1, [1])
    # does contact 1 receive impulse? decided from the law's state by the impact equations, exactly
    c = conservation(sc.M, sc.H, sc.v, r.velocity, 1)
    if not c["holds"]:
        raise ValueError(f"impulse_ratio_law's head-on pool state violates the impact equations: {c}")
    impact = certified_sign(c["p"][0]) > 0
    if printed_member == impact:
        verdict = "exact-match"  # the printed cone's criterion agrees with the law
    elif corrected_member == impact:
        verdict = "erratum"
    else:
        raise ValueError("neither sign of the tangent cone agrees with the law's impact")
    return Finding(verdict, published=r"-v_i\in\mathcal T_i(q) = \{p\,|\,-\nabla h_i(q)\cdot p\ge0\}",
                   derived={"H_1 q̇⁻ (pool, θ = τ = 0)": (h1 * qd)[0, 0], "impulse p": r.impulses,
                            "printed criterion says impact": printed_member, "corrected criterion says impact": corrected_member},
                   corrected=r"\mathcal T_i(q) = \{p\,|\,\nabla h_i(q)\cdot p\ge0\},\quad -\dot q^-\in\mathcal T_i(q)\ \text{(impact)}",
                   note="With the printed sign, the head-on pool impact (H₁q̇⁻ = −1, the law gives p₁ > 0) fails the "
                        "criterion. The usual tangent cone {∇h·p ≥ 0} makes eq. 41, sec. 5.1 ('τ ≥ π/2 ⇒ v₁ ∈ 𝒯₁: no "
                        "impact') and eq. 44 consistent.")


@_cl("at-eq42", "eq. 42", "n1·n2 = −½ cos θ = cos θ12", "exact-match", [KCOS])
def eq42():
    from .acary_taha_support import pool_kinetic_angle_check
    r = pool_kinetic_angle_check()
    ok = r["distance"][1] and r["squared"][1]
    return Finding("exact-match" if ok else "erratum", corrected=None if ok else {k: v[0] for k, v in r.items()},
                   published=r"n_1n_2 = -\frac12\cos\theta = \cos(\theta_{12})",
                   derived={k: v[0] for k, v in r.items()},
                   note="paper_checks.acary_taha_support.pool_kinetic_angle_check: kinetic cosine of the pool's rows for symbolic θ, "
                        "both constraint forms of eq. 24.")


@_cl("at-eq43", "eq. 43", "coupling criterion n_i·n_j < 0", "definition")
def eq43():
    d = _coupling_at(sp.pi / 4)
    return Finding("definition", published=r"n_i.n_j < 0",
                   derived={"pool theta = pi/4: cos theta12": d.cosines[(0, 1)], "coupled": d.coupled[(0, 1)]},
                   note="impactsym.laws.coupling.coupled_pairs. Consistent with sec. 4.1.1 (α₁₂ = 0 when cos θ ≤ 0).")


@_cl("at-sec5.1-decoupled-alpha0", "sec. 5.1", "enforce α12 = 0 when cos θ ≤ 0", "exact-match", [DEL])
def decoupled():
    w12, k = _coupling_proof()
    # coupled ⇔ W₁₂ = k cos θ < 0; with k < 0 that is cos θ > 0, so cos θ ≤ 0 ⇒ not coupled ⇒ α₁₂ = 0
    ok = certified_sign(k) < 0
    rows = _coupling_samples((sp.pi / 2, 3 * sp.pi / 5, sp.pi / 3), lambda t: certified_sign(k * sp.cos(t)) < 0)
    rows["W_12(theta)"] = w12
    return Finding("exact-match" if ok else "refuted", published="we have ... to enforce α12 = 0 in the section (4.1.1) when cos θ ≤ 0",
                   derived=rows, note=f"Criterion 43 with eq. 42, for symbolic θ: W₁₂ = {w12} (impactsym.laws.delassus), so "
                                      "coupled ⇔ −½cos θ < 0 ⇔ cos θ > 0; coupling_decision agrees at π/2, 3π/5, π/3.")


@_cl("at-sec5.1-bernoulli-cones", "sec. 5.1", "Bernoulli: v1 ∈ −𝒯1 and v1 ∈ −𝒯3", "exact-match", [INC])
def bern_cones():
    sc = bernoulli()
    w = [simplify(x) for x in sc.H * sc.v]
    ok = certified_sign(w[0]) <= 0 and certified_sign(w[2]) <= 0
    return Finding("exact-match" if ok else "refuted", published="In the case of Bernoulli's problem ... v1 ∈ −𝒯1(q) and v1 ∈ −𝒯3(q)",
                   derived={"H q̇⁻ (tau = -pi/6)": w},
                   note="With the corrected cone of eq. 41: H₁q̇⁻ < 0 (approaching), H₃q̇⁻ = 0 (grazing, on the boundary of −𝒯₃).")


_definition("at-eq44", "eq. 44", "impact condition v1 ∈ −𝒯1", r"v_1\in-\mathcal T_1(q)",
            "Consistent with eq. 41 once 𝒯 has the usual sign (see at-eq41).")


@_cl("at-eq45", "eq. 45", "multiple impact of degree k: θ_{i,i+1} > π/2 ⇔ n_i·n_{i+1} < 0", "exact-match", [DEL])
def eq45():
    t = sp.Symbol("t", real=True)
    # on [0, π] (where angles live): cos t < 0 exactly on ]π/2, π] (solveset, a proof)
    equivalence = solveset_remembered(sp.cos(t) < 0, t, sp.Interval(0, sp.pi)) == sp.Interval.Lopen(sp.pi / 2, sp.pi)
    from impactsym.laws.coupling import impact_degree
    sc3 = chain3()
    deg = impact_degree(sc3.M, sc3.H, sc3.v)
    # the package applies it: the chain's kinetic cosine is −1/2 < 0 (θ₁₂ = 2π/3 > π/2), so degree 2
    expected = 2 if certified_sign(kinetic_angle_cos(sc3.M, sc3.H[0, :], sc3.H[1, :])) < 0 else 1
    ok = equivalence and deg == expected
    return Finding("exact-match" if ok else "refuted", published=r"\theta_{i,i+1} > \frac\pi2,\ \text{i.e.}\ n_i\cdot n_{i+1} < 0,\ i = 1\dots k-1",
                   derived={"chain3 impact degree": deg},
                   note="On [0, π], cos θ < 0 ⇔ θ ∈ ]π/2, π] (solveset: proved); "
                        "impactsym.laws.coupling.impact_degree applies it (the 3-ball chain: degree 2, cos θ₁₂ = −1/2).")
