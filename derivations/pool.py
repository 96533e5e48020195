"""Closed forms of the pool (Acary & Taha sec. 4, eqs. 25–37), derived from the general law.

Every closed form is :func:`derivations.impulse_ratio.general_quadratic` (eq. 38) applied to the
scene built by :func:`impactsym.models.acary_taha.pool` (unit masses and radii, ball 2 at the
origin, ball 3 at ``(2, 0)``, ball 1 at ``−2(cos θ, sin θ)``; contacts ``1–2``, ``2–3`` and, at
``θ = 2π/3``, ``1–3``; distance constraints, so the gradient rows are unit normals), recomposed
by :func:`derivations.chain3.closed_form`. The incidence is the reading that eqs. 27, 35 and 36
support, ``q̇₁⁻ = (cos(θ − τ), sin(θ − τ))`` (see the model's docstring); the text's
``q̇⁻ = [−cos(θ+τ), −sin(θ+τ), …]`` moves ball 1 *away* from ball 2 at ``τ = 0``.

Quantity names (stable; the paper-audit helper keys on them)
-------------------------------------------------------------
``"A"``, ``"B"``, ``"C"``, ``"Delta"``   the quadratic ``A p₁² + B p₁ + C`` and ``Δ = B² − 4AC``
``"p1"``, ``"p2"``, ``"p3"``             impulses at contacts 1–2, 2–3, 1–3 (``p3``: Bernoulli only)
``"x1+"``, ``"y1+"``, … ``"y3+"``        post-impact velocity components of balls 1, 2, 3

Results are cached (``functools.lru_cache``): the returned dicts are shared, copy before
modifying.

Findings against the print (each proved by a function below and in the tests)
-----------------------------------------------------------------------------
* eq. 27 (τ = 0, any θ): every entry equals the derived form.
* eq. 33: labelled θ = π/2 but it is the e = 1 solution at **θ = π/3** (the only θ ∈ [0, 2π/3]
  for which its denominators and its ``ẏ₂⁺``, ``ẋ₃⁺`` hold, :func:`eq33_theta`). Two entries are
  misprinted: ``ẏ₁⁺`` numerator ``√3(2α² − α + 2)`` should be ``√3(2α² − α)``, and ``ẋ₂⁺``
  ``(−1 + 2α)`` should be ``(1 − 2α)``. Proof: the printed state fails momentum in x and y.
* eq. 34 (θ = π/2, τ = 0): equals the derived impulses.
* eq. 35 (θ = 0, e = 1, any τ): ``ẋ₂⁺`` printed ``cos τ (1+ε)(α + 1)/…``, derived
  ``cos τ (1+ε)(1 − α)/…`` (x-momentum fails for the print). The rest equals the derived form.
* eq. 36 (θ = π/2, e = 1, any τ): every entry equals the derived form.
* eq. 37 (Bernoulli, θ = 2π/3, τ = −π/6, e = 1, α₁₃ = α₁₂): not reproduced by any reading
  (:func:`eq37_analysis`); the print does not conserve momentum, and its momentum-consistent
  repair (``ẋ₃⁺`` halved, the first of the two ``ẏ₃⁺``) has impulses ``∝ (2, 2α, α)``
  (``α₁₃ = α₁₂/2``) and *gains* energy, ``T⁺/T⁻ = 1 + 12α(α+1)/(4α²+α+4)²``. The derived form
  (:func:`bernoulli_closed_form`) has the denominator ``2(5α² + 2α + 2)``.

Examples
--------
>>> cf = pool_tau0()
>>> cf["Delta"]
2*alpha**2*e - 2*alpha**2 - 2*alpha*e*cos(theta) + 2*alpha*cos(theta) + 2*e - 1
>>> compare(pool_tau0(), printed_eq27())
{'p1': True, 'p2': True, 'x1+': True, 'y1+': True, 'x2+': True, 'y2+': True, 'x3+': True, 'y3+': True, 'Delta': True}
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import sympy as sp

from .memo import simplify
from .rational_zero import is_zero, is_zero_algebraic, nonzero_at_a_point

from impactsym.models.acary_taha import pool

from .chain3 import closed_form, stable_root
from .codegen import ScalarKernel, render_family
from .impulse_ratio import general_quadratic, on_energy_line

from impactsym.arithmetic.remembered import solve_remembered
from impactsym.errors import DerivationError

__all__ = [
    "SYMBOLS",
    "VELOCITY_NAMES",
    "pool_law",
    "pool_tau0",
    "pool_at_theta",
    "pool_any_tau",
    "epsilon_device",
    "bernoulli_closed_form",
    "printed_eq27",
    "printed_eq33",
    "printed_eq34",
    "printed_eq35",
    "printed_eq36",
    "printed_eq37",
    "compare",
    "momentum_energy_residuals",
    "eq33_theta",
    "eq37_analysis",
    "kernels",
    "generate",
]

theta, tau = sp.symbols("theta tau", real=True)
alpha, e = sp.symbols("alpha e", positive=True)
alpha13 = sp.Symbol("alpha13", nonnegative=True)
eps = sp.Symbol("epsilon", real=True)

#: the symbols of the closed forms (``alpha`` = α₁₂, ``alpha13`` = α₁₃, ``epsilon`` = sign(cos τ))
SYMBOLS = {"theta": theta, "tau": tau, "alpha": alpha, "alpha13": alpha13, "e": e, "epsilon": eps}

VELOCITY_NAMES = ("x1+", "y1+", "x2+", "y2+", "x3+", "y3+")


def pool_law(theta_=theta, tau_=0, restitution=e, ratios=(alpha,), *, third_contact=False,
             incidence="theta-minus-tau"):
    """The pool scene and its general quadratic (eq. 38).

    Parameters
    ----------
    theta_, tau_ : the angles θ and τ (numbers or symbols)
    restitution : energetic coefficient e
    ratios : ``(α₁₂,)`` or ``(α₁₂, α₁₃)`` with ``third_contact=True``
    third_contact : include contact 1–3 (θ = 2π/3)
    incidence : pre-impact velocity reading (see :func:`impactsym.models.acary_taha.pool`)

    Returns
    -------
    (Scene, QuadraticLaw)

    Examples
    --------
    >>> sc, law = pool_law()
    >>> sp.factor(law.A), law.B
    (alpha**2 - alpha*cos(theta) + 1, -1)
    """
    sc = pool(theta_, tau_, incidence=incidence, third_contact=third_contact)
    # the law is checked against the energy line of this restitution before any closed form is built
    return sc, on_energy_line(general_quadratic(sc.M, sc.H, sc.v, restitution, list(ratios)), sc.M, sc.v, restitution)


def _factored(v, numeric_angles: bool):
    """The printed form ``sympy.factor(simplify(v))`` of a closed-form entry. With numeric angles θ
    (and, for Bernoulli, τ) the entry is a rational function of the ratios, ``e``, ``ε``, ``cos τ``,
    ``sin τ``, √Δ and surds, and ``factor`` alone gives that form (the same expressions, pinned by
    ``reproduce --json`` and tests/test_closed_forms.py) without ``simplify``'s search; with a
    symbolic θ, ``simplify`` runs first (trigonometric identities in θ can shorten the entry)."""
    return sp.factor(v if numeric_angles else simplify(v))


def _clean(d: dict) -> dict:
    return {k: simplify(v) if k not in ("A", "Delta") else v for k, v in d.items()}


@lru_cache(maxsize=None)
def pool_tau0() -> dict:
    """Eq. 27: τ = 0, any θ, ratio α = α₁₂, coefficient e (two closed contacts).

    Returns
    -------
    dict with keys ``A, B, C, Delta, p1, p2, x1+, …, y3+``.

    Examples
    --------
    >>> pool_tau0()["x2+"]
    (-alpha + cos(theta))*(sqrt(2*alpha**2*e - 2*alpha**2 - 2*alpha*e*cos(theta) + 2*alpha*cos(theta) + 2*e - 1) + 1)/(2*alpha**2 - 2*alpha*cos(theta) + 2)

    References
    ----------
    Acary & Taha, eqs. 25–27.
    """
    sc, law = pool_law()
    return closed_form(sc, law, VELOCITY_NAMES)


@lru_cache(maxsize=None)
def pool_at_theta(theta_value, restitution=e) -> dict:
    """The τ = 0 pool at one angle (eqs. 33–34): e.g. θ = π/2 (eq. 34) or θ = π/3 (what eq. 33 is).

    Examples
    --------
    >>> pool_at_theta(sp.pi / 3, 1)["x2+"]
    -(2*alpha - 1)/(2*alpha**2 - alpha + 2)
    >>> pool_at_theta(sp.pi / 2)["p1"]
    (sqrt(2*alpha**2*e - 2*alpha**2 + 2*e - 1) + 1)/(2*(alpha**2 + 1))

    References
    ----------
    Acary & Taha, eqs. 33, 34.
    """
    theta_value = sp.sympify(theta_value)
    sc, law = pool_law(theta_value, 0, restitution)
    cf = closed_form(sc, law, VELOCITY_NAMES)
    numeric = not theta_value.free_symbols
    return {k: (v if k in ("A", "Delta") else _factored(v, numeric)) for k, v in cf.items()}


@lru_cache(maxsize=None)
def pool_any_tau(theta_value=theta, restitution=1) -> dict:
    """Eqs. 35–36: any τ, written with ``ε = sign(cos τ)`` (default e = 1; θ a number or symbol).

    At ``e = 1`` the discriminant is ``Δ = cos²τ`` and ``√Δ = |cos τ| = ε cos τ``; the derived forms
    are returned with that substitution (see :func:`epsilon_device`).

    Examples
    --------
    >>> d = pool_any_tau(0)
    >>> d["p1"]
    (epsilon + 1)*cos(tau)/(2*(alpha**2 - alpha + 1))
    >>> d["x2+"]
    -(alpha - 1)*(epsilon + 1)*cos(tau)/(2*(alpha**2 - alpha + 1))

    References
    ----------
    Acary & Taha, eqs. 35, 36.
    """
    theta_value = sp.sympify(theta_value)
    sc, law = pool_law(theta_value, tau, restitution)
    cf = closed_form(sc, law, VELOCITY_NAMES)
    numeric = not theta_value.free_symbols
    out = {}
    for k, v in cf.items():
        if k in ("A", "B", "C", "Delta"):
            out[k] = v
            continue
        v = v.subs(sp.Abs(sp.cos(tau)), eps * sp.cos(tau)).subs(sp.sqrt(sp.cos(tau) ** 2), eps * sp.cos(tau))
        out[k] = _factored(v, numeric)
    return out


@lru_cache(maxsize=None)
def epsilon_device(theta_value=theta) -> dict:
    """Derive the ``ε = sign(cos τ)`` device of eqs. 35–36 from the law at e = 1.

    At e = 1 the quadratic is ``A p₁² − cos τ · p₁ = 0`` (``B = H₁q̇⁻ = −cos τ`` for every θ):
    its roots are ``0`` and ``cos τ / A``. The physical root ``(−B + √Δ)/(2A)`` with
    ``√Δ = |cos τ| = ε cos τ`` is ``(1 + ε) cos τ / (2A)``: ``(1+ε)/2`` is 1 for ``cos τ > 0``
    (selects ``cos τ/A``, the impact) and 0 for ``cos τ < 0`` (selects ``p = 0``, no impact;
    contact 1–2 then has ``H₁q̇⁻ = −cos τ > 0``, it is separating, criterion (41) fails).

    Returns
    -------
    dict: ``roots`` (the set at e = 1), ``B``, ``physical_root`` (with ε), ``selects_impact`` and
    ``selects_no_impact`` (the root evaluated at τ = π/4 and τ = 3π/4, compared exactly), and
    ``proven``.

    Examples
    --------
    >>> epsilon_device()["proven"]
    True
    """
    sc, law = pool_law(theta_value, tau, 1)
    A = sp.factor(law.A)
    p = sp.Symbol("p_1")
    roots = solve_remembered(sp.expand(law.A * p**2 + law.B * p + law.C), p)
    phys = sp.factor((-law.B + eps * sp.cos(tau)) / (2 * A))
    # the law's own root at the two sides of cos τ = 0, with √(cos²τ) evaluated exactly
    at = {}
    for name, t in (("impact", sp.pi / 4), ("no_impact", 3 * sp.pi / 4)):
        at[name] = simplify(law.p1.subs(tau, t))
    ok = (
        is_zero(law.B + sp.cos(tau))
        and is_zero(law.D - sp.cos(tau) ** 2)
        and set(simplify(r) for r in roots) == {0, simplify(sp.cos(tau) / law.A)}
        and is_zero(at["impact"] - (sp.cos(sp.pi / 4) / law.A))
        and at["no_impact"] == 0
        and is_zero(phys.subs(eps, 1) - sp.cos(tau) / law.A)
        and phys.subs(eps, -1) == 0
    )
    return {"B": law.B, "roots": roots, "physical_root": phys, "selects_impact": at["impact"],
            "selects_no_impact": at["no_impact"], "proven": bool(ok)}


@lru_cache(maxsize=None)
def bernoulli_closed_form(tau_value=-sp.pi / 6, restitution=1, *, independent=False) -> dict:
    """Bernoulli's problem (θ = 2π/3, three closed contacts; eq. 37), derived.

    Parameters
    ----------
    tau_value : incidence τ (default −π/6 as in eq. 37)
    restitution : e (default 1 as in eq. 37)
    independent : ``False``: ``α₁₃ = α₁₂ = α`` (the paper's choice); ``True``: ratios ``alpha`` and
        ``alpha13`` independent.

    Returns
    -------
    dict with keys ``A, B, C, Delta, p1, p2, p3, x1+, …, y3+``.

    Examples
    --------
    >>> bernoulli_closed_form()["y2+"]
    3/(2*(5*alpha**2 + 2*alpha + 2))
    >>> bernoulli_closed_form(independent=True)["A"]
    alpha**2 + alpha*alpha13/2 + alpha/2 + alpha13**2 + alpha13/2 + 1

    References
    ----------
    Acary & Taha, sec. 4.2 case 3.a, eq. 37.
    """
    ratios = (alpha, alpha13) if independent else (alpha, alpha)
    tau_value = sp.sympify(tau_value)
    sc, law = pool_law(2 * sp.pi / 3, tau_value, restitution, ratios, third_contact=True)
    cf = closed_form(sc, law, VELOCITY_NAMES, ["p1", "p2", "p3"])
    out = {}
    for k, v in cf.items():
        if k == "A":
            out[k] = sp.expand(v)
        elif k in ("Delta", "B", "C"):
            out[k] = v
        else:
            out[k] = sp.factor(sp.radsimp(v if not tau_value.free_symbols else simplify(v)))
    return out


# ------------------------------------------------------------------ transcriptions of the print
def printed_eq27() -> dict:
    """TRANSCRIPTION of eq. 27 (τ = 0, any θ), for comparison only.

    >>> printed_eq27()["y3+"]
    0
    """
    c, s = sp.cos(theta), sp.sin(theta)
    den = -2 * alpha * c + 2 * alpha**2 + 2
    Delta = 2 * (e - 1) * (alpha**2 - alpha * c + 1) + 1
    P = (1 + sp.sqrt(Delta)) / den
    return {"p1": P, "p2": P * alpha, "x1+": c * (1 - P), "y1+": s * (1 - P), "x2+": (c - alpha) * P,
            "y2+": s * P, "x3+": alpha * P, "y3+": sp.S.Zero, "Delta": Delta}


def printed_eq33() -> dict:
    """TRANSCRIPTION of eq. 33 (labelled θ = π/2, e = 1), for comparison only.

    >>> printed_eq33()["x2+"]
    (2*alpha - 1)/(2*alpha**2 - alpha + 2)
    """
    den = -alpha + 2 * alpha**2 + 2
    r3 = sp.sqrt(3)
    return {"x1+": sp.Rational(1, 2) * (-alpha + 2 * alpha**2) / den,
            "y1+": sp.Rational(1, 2) * r3 * (-alpha + 2 * alpha**2 + 2) / den,
            "x2+": (-1 + 2 * alpha) / den, "y2+": r3 / den, "x3+": 2 * alpha / den, "y3+": sp.S.Zero}


def printed_eq34() -> dict:
    """TRANSCRIPTION of eq. 34 (θ = π/2), for comparison only. Δ is eq. 27's at θ = π/2."""
    Delta = 2 * (e - 1) * (alpha**2 + 1) + 1
    return {"p1": (1 + sp.sqrt(Delta)) / (2 * alpha**2 + 2),
            "p2": (1 + sp.sqrt(Delta)) * alpha / (2 * alpha**2 + 2)}


def printed_eq35() -> dict:
    """TRANSCRIPTION of eq. 35 (θ = 0, e = 1, any τ; ε = sign(cos τ)), for comparison only."""
    c, s = sp.cos(tau), sp.sin(tau)
    den = 2 * (1 - alpha + alpha**2)
    return {"x1+": -c * (-1 + 2 * alpha - 2 * alpha**2 + eps) / den, "y1+": -s,
            "x2+": c * (1 + eps) * (alpha + 1) / den, "y2+": sp.S.Zero,
            "x3+": alpha * c * (1 + eps) / den, "y3+": sp.S.Zero}


def printed_eq36() -> dict:
    """TRANSCRIPTION of eq. 36 (θ = π/2, e = 1, any τ), for comparison only."""
    c, s = sp.cos(tau), sp.sin(tau)
    den = 2 * (1 + alpha**2)
    return {"x1+": s, "y1+": c * (1 + 2 * alpha**2 - eps) / den, "x2+": -alpha * c * (1 + eps) / den,
            "y2+": c * (1 + eps) / den, "x3+": alpha * c * (1 + eps) / den, "y3+": sp.S.Zero}


def printed_eq37(*, repaired: bool = False) -> dict:
    """TRANSCRIPTION of eq. 37 (θ = 2π/3, τ = −π/6, e = 1, α₁₃ = α₁₂), for comparison only.

    The print lists ``ẏ₃⁺`` twice; the first (``5α√3/(4α²+α+4)``) is read as ``ẋ₃⁺``.
    ``repaired=True`` halves it (``5α√3/(2(4α²+α+4))``), the only change of that entry that
    restores momentum (:func:`eq37_analysis`).
    """
    den = 4 * alpha**2 + alpha + 4
    r3 = sp.sqrt(3)
    x3 = 5 * alpha * r3 / den
    return {"x1+": -r3 * (2 * alpha**2 + alpha + 1) / den, "y1+": (2 * alpha**2 - alpha - 1) / den,
            "x2+": -r3 * (1 + 2 * alpha) / den, "y2+": 3 / den,
            "x3+": x3 / 2 if repaired else x3, "y3+": 3 * alpha / (2 * den)}


# ------------------------------------------------------------------ comparison and proofs
def compare(derived: dict, printed: dict) -> dict:
    """Per quantity of ``printed``: is it identical to ``derived``? (exact rational-function test
    after replacing ``√Δ`` by a fresh symbol; ``Delta`` compared as a polynomial).

    >>> compare(pool_any_tau(0), printed_eq35())
    {'x1+': True, 'y1+': True, 'x2+': False, 'y2+': True, 'x3+': True, 'y3+': True}
    """
    Delta = derived.get("Delta")
    out = {}
    for k, b in printed.items():
        d = _sqrt_delta_to_symbol(sp.sympify(derived[k]) - sp.sympify(b), Delta) if k != "Delta" else \
            sp.sympify(derived[k]) - sp.sympify(b)
        t = sp.expand_trig(d)
        # proved zero in flint, proved non-zero at one point (no simplification closes it), or simplify
        out[k] = bool(is_zero_algebraic(t)) or (not nonzero_at_a_point(t)
                                                and simplify(sp.cancel(sp.together(t))) == 0)
    return out


def _sqrt_delta_to_symbol(expr, Delta):
    """Replace every ``√X`` with ``X − Δ`` identically 0 by one positive symbol, so that two forms
    of the same closed form become rational functions that ``cancel`` can compare exactly."""
    if Delta is None or not sp.sympify(Delta).free_symbols:
        return expr
    s = sp.Symbol("s_", positive=True)
    target = sp.expand(Delta)

    def is_sqrt_delta(x):
        return x.is_Pow and x.exp == sp.S.Half and sp.expand(x.base - target) == 0

    return expr.replace(is_sqrt_delta, lambda x: s)


def _simplified(x):
    """``simplify(x)``, or 0 at once when the exact zero test proves ``x`` zero (what simplify
    would return then, in milliseconds instead of a second)."""
    return sp.Integer(0) if is_zero_algebraic(x) else simplify(x)


def momentum_energy_residuals(velocities: dict, vminus=None, restitution=1, *, energy: bool = True,
                              simplified: bool = True) -> dict:
    """Momentum (x, y) and energy residuals of a pool state (unit masses): ``Σq̇⁺ − Σq̇⁻`` per
    axis and ``T⁺ − e T⁻``; ``vminus`` is ball 1's pre-impact velocity (balls 2, 3 at rest).
    With ``energy=False`` only the momentum residuals are returned (``px``, ``py``); with
    ``simplified=False`` the residuals as they stand, for a caller that only decides whether they
    vanish (an exact zero test or a certified point needs no simplified form). Simplifying what no
    one prints is the cost spared: the energy residual is a sum of squares of rational functions
    in α.

    >>> r = momentum_energy_residuals(printed_eq33(), (sp.Rational(1, 2), sp.sqrt(3) / 2), energy=False)
    >>> sorted(r), sp.factor(r["px"]), sp.factor(r["py"])
    (['px', 'py'], 2*(2*alpha - 1)/(2*alpha**2 - alpha + 2), sqrt(3)/(2*alpha**2 - alpha + 2))
    """
    vx, vy = vminus
    q = [sp.sympify(velocities[k]) for k in VELOCITY_NAMES]
    tidy = _simplified if simplified else (lambda x: x)
    out = {"px": tidy(q[0] + q[2] + q[4] - vx), "py": tidy(q[1] + q[3] + q[5] - vy)}
    if energy:
        out["energy"] = tidy(sum(x**2 for x in q) / 2 - restitution * (vx**2 + vy**2) / 2)
    return out


@lru_cache(maxsize=None)
def eq33_theta() -> dict:
    """Which θ does eq. 33 belong to? Solve the identities in α that its correctly printed entries
    (``ẏ₂⁺``, ``ẋ₃⁺``, ``ẋ₁⁺``) impose on the derived e = 1 solution ``(c, s) = (cos θ, sin θ)``.

    Returns
    -------
    dict: ``solutions`` (the (cos θ, sin θ) pairs with c² + s² = 1), ``theta`` (their angles in
    [0, 2π/3]), ``misprinted`` (entries that differ from the derived solution at that θ),
    ``at_pi_over_2`` (the comparison at the labelled θ = π/2).

    Examples
    --------
    >>> r = eq33_theta()
    >>> r["theta"], r["misprinted"]
    ([pi/3], ['y1+', 'x2+'])
    """
    c, s = sp.symbols("c s", real=True)
    A = alpha**2 - alpha * c + 1
    derived = {"x1+": c * (1 - 1 / A), "y2+": s / A, "x3+": alpha / A}  # pool_tau0 at e = 1, Δ = 1
    # cross-check these three against the general derivation
    at_e1 = pool_tau0()
    for k, v in derived.items():
        gen = at_e1[k].subs(e, 1).subs({sp.cos(theta): c, sp.sin(theta): s})
        if not (is_zero(gen - v)):
            raise DerivationError(k)
    printed = printed_eq33()
    eqs = []
    for k, v in derived.items():
        num = sp.numer(sp.together(v - printed[k]))
        eqs.extend(sp.Poly(sp.expand(num), alpha).coeffs())
    sols = solve_remembered(eqs + [c**2 + s**2 - 1], [c, s], dict=True)
    thetas = []
    for sol in sols:
        t = sp.atan2(sol[s], sol[c])
        if sp.Interval(0, 2 * sp.pi / 3).contains(t) == sp.true:
            thetas.append(t)
    mis = [k for k, ok in compare(pool_at_theta(thetas[0], 1), printed).items() if not ok] if thetas else None
    at_pi2 = compare(pool_at_theta(sp.pi / 2, 1), printed)
    return {"solutions": sols, "theta": thetas, "misprinted": mis, "at_pi_over_2": at_pi2}


def _identical_states(a: dict, b: dict) -> bool:
    """Exact identity in α of two states; decided first at α = 1/3 (a difference there, certified,
    already proves non-identity), then symbolically."""
    from impactsym.exact import certified_sign

    for k in VELOCITY_NAMES:
        if certified_sign(sp.radsimp(sp.sympify(a[k] - b[k]).subs(alpha, sp.Rational(1, 3)))) != 0:
            return False
    return all(is_zero(a[k] - b[k]) for k in VELOCITY_NAMES)


@lru_cache(maxsize=None)
def eq37_analysis() -> dict:
    """Audit eq. 37 against every reading, and prove what is wrong with it.

    1. Readings: incidence (θ−τ, θ+τ, printed), constraint scaling (distance, squared),
       ratio assignments ``α₁₃ = α₁₂`` and ``α₁₃ = α₁₂/2``: the derived e = 1 solution is compared
       with the print and with its momentum-repaired version. None matches (``matches``).
    2. The print as printed violates x-momentum for every pre-impact velocity (its x-sum depends
       on α) — ``px_printed``; the y-sum is the constant 1/2.
    3. Halving the first ``ẏ₃⁺`` (read as ``ẋ₃⁺``) restores momentum for
       ``q̇₁⁻ = (−√3/2, 1/2)`` (the θ−τ reading). Its impulses, solved from balls 2 and 3, are
       ``p = (2√3, 2√3α, √3α)/(4α²+α+4)`` (``implied_ratios`` = ``(α, α/2)``), and
       ``T⁺/T⁻ = 1 + 12α(α+1)/(4α²+α+4)²`` (``energy_ratio``): energy is created for every
       α > 0, so it is no solution of eq. 38 for any e ≤ 1.

    Examples
    --------
    >>> r = eq37_analysis()
    >>> r["matches"], r["implied_ratios"]
    ([], (alpha, alpha/2))
    >>> sp.factor(r["energy_ratio"] - 1)
    12*alpha*(alpha + 1)/(4*alpha**2 + alpha + 4)**2
    """
    printed, repaired = printed_eq37(), printed_eq37(repaired=True)
    readings = []
    for incidence in ("theta-minus-tau", "theta-plus-tau", "printed"):
        for constraint in ("distance", "squared"):
            for label, ratios in (("alpha13=alpha12", (alpha, alpha)), ("alpha13=alpha12/2", (alpha, alpha / 2))):
                sc = pool(2 * sp.pi / 3, -sp.pi / 6, incidence=incidence, constraint=constraint, third_contact=True)
                # only the state's identity with the print is decided (form-free): no simplified A, B, C
                law = on_energy_line(general_quadratic(sc.M, sc.H, sc.v, 1, list(ratios), simplified=False),
                                     sc.M, sc.v, 1)
                v = dict(zip(VELOCITY_NAMES, law.vplus))
                ok_p = _identical_states(v, printed)
                ok_r = _identical_states(v, repaired)
                readings.append({"incidence": incidence, "constraint": constraint, "ratios": label,
                                 "matches_printed": ok_p, "matches_repaired": ok_r})
    matches = [r for r in readings if r["matches_printed"] or r["matches_repaired"]]
    vm = (-sp.sqrt(3) / 2, sp.Rational(1, 2))
    res_p = momentum_energy_residuals(printed, vm, energy=False)
    res_r = momentum_energy_residuals(repaired, vm, energy=False)
    # impulses implied by the repaired state: ball 3 gets p2 (1, 0) + p3 n13, ball 2 gets p1 n12 − p2 (1, 0)
    n12 = sp.Matrix([-1, sp.sqrt(3)]) / 2
    n13 = sp.Matrix([1, sp.sqrt(3)]) / 2
    P1, P2, P3 = sp.symbols("P1 P2 P3")
    sol = solve_remembered(list(sp.Matrix([repaired["x2+"], repaired["y2+"]]) - (P1 * n12 - P2 * sp.Matrix([1, 0])))
                   + list(sp.Matrix([repaired["x3+"], repaired["y3+"]]) - (P2 * sp.Matrix([1, 0]) + P3 * n13)),
                   [P1, P2, P3], dict=True)[0]
    # rational functions of alpha with rational coefficients (sqrt(3) cancels): cancel is their normal
    # form (what simplify returned, in a fraction of its time)
    implied = (sp.cancel(sol[P2] / sol[P1]), sp.cancel(sol[P3] / sol[P1]))
    q = sp.Matrix([repaired[k] for k in VELOCITY_NAMES])
    energy_ratio = sp.factor(sp.cancel(q.dot(q)))  # |v⁻|² = 1
    return {"readings": readings, "matches": matches, "px_printed": sp.factor(res_p["px"] + vm[0]),
            "py_printed": simplify(res_p["py"] + vm[1]), "momentum_repaired": (res_r["px"], res_r["py"]),
            "implied_impulses": (sol[P1], sol[P2], sol[P3]), "implied_ratios": implied,
            "energy_ratio": energy_ratio}


# ------------------------------------------------------------------ generated kernels
MODULE_DOC = """Impulse-ratio law on the pool (Acary & Taha sec. 4): any theta and tau with two closed
contacts (eqs. 27, 35, 36), and Bernoulli's problem (theta = 2pi/3, three closed contacts, eq. 37)
with independent ratios. Physical root in cancellation-free form; no impact (p = 0, w = v-) when
no closed contact approaches (criterion 41; at e = 1 this is the epsilon = sign(cos tau) device)."""


def _velocity_direction(sc, ratios):
    return [sp.factor(simplify(x)) for x in sc.M.LUsolve(sc.H.T * sp.Matrix([1, *ratios]))]


def _trig_zero(expr) -> bool:
    return is_zero(sp.expand_trig(sp.expand(expr)))


def _pool_emitted(th, ta, ee, a12, A, B, C, sc):
    """The forms the pool kernel evaluates (issue 15), each asserted equal to the derived one.

    * ``D = e cos²τ − (1 − e)((α − cos θ)² + α² + sin²θ + sin²τ)`` (Lagrange's identity, as for the
      chain): the expanded ``cos²τ − 2A(1 − e)`` cancels where ``D ≪ 2A``.
    * ``w1 = v1⁻ − p1 (cos θ, sin θ)`` with ``v1⁻ = (cos(θ − τ), sin(θ − τ))``: the angle ``θ − τ``
      rounds (absolute error ``eps·|θ|``), which at ``θ ≈ π/2``, ``τ → 0`` is 1e8 eps of a
      well-conditioned ``w1x ≈ sin θ sin τ``. Emitted with the angle addition expanded and the
      impact branch's ``q = cos τ − p1`` in closed form,
      ``q = (2α(α − cos θ) cos²τ + (1 − e)) / ((1 + 2α(α − cos θ)) cos τ + √D)`` (the denominator is
      positive: ``1 + 2α(α − cos θ) = 2A − 1 ≥ 1/2``): ``w1 = (cos θ q + sin θ sin τ, sin θ q − cos θ sin τ)``.

    Returns ``(p1, w)``; the proofs are asserted here: per branch, by the exact zero test of
    :func:`derivations.rational_zero.is_zero_algebraic`, whose numerator is reduced by
    ``(√D)² = D`` and ``sin² = 1 − cos²`` (the relations have coprime leading terms: a normal form).
    """
    c, s_, ct, st = sp.cos(th), sp.sin(th), sp.cos(ta), sp.sin(ta)
    D = ee * ct**2 - (1 - ee) * ((a12 - c) ** 2 + a12**2 + s_**2 + st**2)
    if not (_trig_zero(D - (B**2 - 4 * A * C))):
        raise DerivationError('derivation check failed: _trig_zero(D - (B**2 - 4 * A * C))')
    Ae = a12 * (a12 - c) + 1
    if not (is_zero(Ae - A)):
        raise DerivationError('derivation check failed: sp.simplify(Ae - A) == 0')
    r = sp.Symbol("r", positive=True)
    root_impact = (ct + r) / (2 * Ae)
    q_impact = (2 * a12 * (a12 - c) * ct**2 + (1 - ee)) / ((1 + 2 * a12 * (a12 - c)) * ct + r)
    direction = _velocity_direction(sc, (a12,))
    naive = [vi + ci * root_impact for vi, ci in zip(sc.v, direction)]
    emitted = [c * q_impact + s_ * st, s_ * q_impact - c * st] + [ci * root_impact for ci in direction[2:]]
    if not (all(vi == 0 for vi in sc.v[2:])):
        raise DerivationError('derivation check failed: all(vi == 0 for vi in sc.v[2:])')
    rD = sp.sqrt(D)
    for a, b in zip(emitted, naive):  # impact branch: equal with r = √D, (√D)² = D (rational_zero)
        if not is_zero_algebraic(sp.expand_trig((a - b).xreplace({r: rD}))):
            raise DerivationError(a)
    for a, b in zip((c * ct + s_ * st, s_ * ct - c * st), sc.v[:2]):  # no impact: q = cos(tau), w1 = v1-
        if not (_trig_zero(a - b)):
            raise DerivationError('derivation check failed: _trig_zero(a - b)')
    p1 = sp.Piecewise((root_impact.subs(r, rD), ct > 0), (0, True))
    q = sp.Piecewise((q_impact.subs(r, rD), ct > 0), (ct, True))
    w = [c * q + s_ * st, s_ * q - c * st] + [ci * p1 for ci in direction[2:]]
    return p1, w


def kernels():
    """The pool family: ``pool_impulse_ratio(theta, tau, e, alpha)`` and
    ``bernoulli_impulse_ratio(tau, e, alpha12, alpha13)``.

    Outputs ``(p1, p2[, p3], w1x, w1y, w2x, w2y, w3x, w3y)``: impulses and post-impact velocities.
    Derived once per process (cached like the rest of this module; a new list of the same kernels
    each call).

    >>> [k.name for k in kernels()]
    ['pool_impulse_ratio', 'bernoulli_impulse_ratio']
    """
    return list(_kernels())


@lru_cache(maxsize=None)
def _kernels():
    th, ta = sp.symbols("theta tau", real=True)
    a12, a13 = sp.symbols("alpha alpha13", real=True)
    ee = sp.Symbol("e", real=True)
    names = ["w1x", "w1y", "w2x", "w2y", "w3x", "w3y"]
    # two contacts, any θ, τ
    sc, law = pool_law(th, ta, ee, (a12,))
    A, B, C = sp.factor(law.A), simplify(law.B), sp.factor(law.C)
    if not (is_zero(B + sp.cos(ta))):
        raise DerivationError('derivation check failed: sp.simplify(B + sp.cos(ta)) == 0')
    # contact 1–2 approaches iff H₁q̇⁻ = −cos τ < 0; contact 2–3 has H₂q̇⁻ = 0 (balls 2, 3 at rest)
    hv = sc.H * sc.v  # decided by the exact zero test (no printed form needed)
    if not (is_zero(hv[0] + sp.cos(ta)) and is_zero(hv[1])):
        raise DerivationError('derivation check failed: H v- is not (-cos(tau), 0)')
    p1, w = _pool_emitted(th, ta, ee, a12, A, B, C, sc)
    pool_k = ScalarKernel(
        "pool_impulse_ratio", [th, ta, ee, a12], [p1, a12 * p1, *w], ["p1", "p2", *names],
        """The impulse-ratio law on the pool with two closed contacts (1-2, 2-3), any theta and tau
(Acary & Taha eqs. 27, 35, 36; incidence qdot1- = (cos(theta - tau), sin(theta - tau))).

p1 = (cos(tau) + sqrt(D))/(2A) for cos(tau) > 0 (A = alpha^2 - alpha cos(theta) + 1,
D = cos(tau)^2 - 2A(1 - e)); p1 = 0 (no impact) for cos(tau) <= 0. Returns
(p1, p2, w1x, w1y, w2x, w2y, w3x, w3y). No admissibility check (see impactsym.domains).
""")
    # Bernoulli: θ = 2π/3, three contacts, independent ratios
    sc3, law3 = pool_law(2 * sp.pi / 3, ta, ee, (a12, a13), third_contact=True)
    A3, B3, C3 = sp.factor(law3.A), simplify(law3.B), sp.factor(law3.C)
    hv = sc3.H * sc3.v
    b1, b3 = simplify(hv[0]), simplify(hv[2])
    root = stable_root(A3, B3, C3)
    p1b = sp.Piecewise((0, sp.And(b1 >= 0, b3 >= 0)), *[(ex, cond) for ex, cond in root.args])
    wb = [vi + ci * p1b for vi, ci in zip(sc3.v, _velocity_direction(sc3, (a12, a13)))]
    bern_k = ScalarKernel(
        "bernoulli_impulse_ratio", [ta, ee, a12, a13], [p1b, a12 * p1b, a13 * p1b, *wb],
        ["p1", "p2", "p3", *names],
        """Bernoulli's problem (Acary & Taha sec. 4.2 case 3, eq. 37): theta = 2pi/3, contacts 1-2, 2-3,
1-3 closed, ratios alpha12 = p2/p1 and alpha13 = p3/p1 independent (eq. 37 takes them equal).

No impact (p = 0) when neither 1-2 nor 1-3 approaches; otherwise the physical root
(-B + sqrt(D))/(2A) in cancellation-free form. Returns (p1, p2, p3, w1x, w1y, w2x, w2y, w3x, w3y).
""")
    return [pool_k, bern_k]


def generate(outdir) -> list[Path]:
    """Write ``pool.py`` into ``outdir``."""
    path = Path(outdir) / "pool.py"
    path.write_text(render_family("pool", "pool", MODULE_DOC, kernels()))
    return [path]
