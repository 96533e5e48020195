"""Validity domains of the impulse-ratio law: where it has a solution and where that solution is
admissible, as exact inequalities in ``(α, e)`` with their boundary curves (Acary & Taha eqs. 19,
28–32, Fig. 3).

The curves are derived in :mod:`derivations.domains` (SymPy, from the general law) and committed as
exact expressions in the generated ``impactsym/kernels/domain_boundaries.py``; this module reads them
(it never runs a derivation), packages them per scene, decides membership exactly, and draws Fig. 3.

Scenes
------
``"chain3"``  the 3-ball chain, equal masses, ``q̇⁻ = (1, 0, 0)`` (sec. 3.3, eq. 19)
``"pool"``    the pool at ``τ = 0`` (sec. 4.1.1, eqs. 29–32); θ ∈ [0, 2π/3]. At ``θ = 2π/3`` contact
              1–3 is closed and approaching; the domain is that of three contacts with
              ``α₁₃ = α₁₂`` (the paper's choice for that angle, eq. 37).

In every case ``0 ≤ e ≤ 1`` (a dissipative energetic coefficient, eq. 12). The existence condition
``Δ ≥ 0`` (``e ≥ h(α)``) is implied by every active velocity condition ``e ≥ g_j(α)``, since
``g_j − h = R_j²/(4AT⁻) ≥ 0`` (derived in :func:`derivations.domains.admissibility_conditions`).

Examples
--------
>>> d = validity_domain("chain3")
>>> [b.name for b in d.boundaries]
['alpha_min', 'g', 'h', 'e_max']
>>> d.region["alpha"], d.region["e"]
((1/2, 1), (1/3, 1))
>>> d.contains("3/4", "9/10"), d.contains("3/4", "2/5")
(True, False)
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Any

import sympy as sp

from ._lazy import Later as _Later
from .committed import committed_expressions
from .errors import ImpactInputError
from .exact import certified_sign
from .numbers import exact_str, parse_number, to_exact

__all__ = ["Boundary", "ValidityDomain", "validity_domain", "plot_domain", "SCENES", "THETA_SWEEP"]

SCENES = ("chain3", "pool")

#: the angles at which :func:`validity_domain` (pool, θ unspecified) tabulates the domain
THETA_SWEEP = (0, sp.pi / 6, sp.pi / 4, sp.pi / 3, sp.pi / 2, 7 * sp.pi / 12, 2 * sp.pi / 3)

alpha = sp.Symbol("alpha", nonnegative=True)
e = sp.Symbol("e", positive=True)


class _LazyField:
    """A dataclass field that may hold a :class:`~impactsym._lazy.Later` (a value computed on first
    use, once: every copy of a memoized domain shares it; the simplified boundary curves and the
    inequalities that print them, which few callers read): read, it gives the computed value (a list
    is copied for each domain, as :func:`_fresh` copies it). The field has no default."""

    def __set_name__(self, owner, name):
        self._slot = "_lazy_" + name

    def __get__(self, obj, owner=None):
        if obj is None:
            raise AttributeError(self._slot)  # no class-level default: the field stays required
        v = obj.__dict__[self._slot]
        if isinstance(v, _Later):
            v = v()
            v = list(v) if isinstance(v, list) else v
            obj.__dict__[self._slot] = v
        return v

    def __set__(self, obj, value):
        obj.__dict__[self._slot] = value


def _raw(obj, name: str):
    """The field ``name`` of ``obj`` as stored: a :class:`_Later` stays unevaluated."""
    return obj.__dict__["_lazy_" + name]


@dataclass
class Boundary:
    """One boundary curve of a validity domain.

    Attributes
    ----------
    name : short name (``"g"``, ``"h"``, ``"alpha_min"``, ...)
    lhs : ``"e"`` or ``"alpha"``: the curve is ``lhs = expression``
    expression : exact SymPy expression (in α, or a constant)
    condition : the inequality it bounds and why (which contact, which condition of eq. 28)
    """

    name: str
    lhs: str
    expression: Any = _LazyField()
    condition: str

    def as_json(self) -> dict:
        return {"name": self.name, "expression": f"{self.lhs} = {exact_str(self.expression)}",
                "condition": self.condition}


@dataclass
class ValidityDomain:
    """The validity domain of one scene (at one θ for the pool), exactly.

    Attributes
    ----------
    scene, theta : what it is the domain of
    boundaries : the boundary curves (:class:`Boundary`)
    inequalities : the defining inequalities, as text
    region : its extent: ``alpha`` and ``e`` ranges (exact), ``e_min_at`` (the α of the lowest e),
        ``empty`` and a ``description``
    """

    scene: str
    theta: Any
    boundaries: list
    inequalities: list = _LazyField()
    region: dict
    _member: Any = field(repr=False, default=None)
    sweep: list = field(default_factory=list)
    tau: Any = None

    def contains(self, alpha_value, e_value) -> bool:
        """Exact membership of ``(α, e)`` (numbers or numeric text; floats by their exact value).

        >>> validity_domain("pool", "pi/4").contains("sqrt(2)/4", "3/7")
        True
        """
        if self._member is None:
            raise ImpactInputError("theta", "membership needs a specific theta")
        a, ee = to_exact(alpha_value, "alpha"), to_exact(e_value, "e")
        return self._member(a, ee)

    def as_json(self) -> dict:
        """The JSON form (``boundaries`` as ``{"name", "expression", "condition"}``, exact strings and
        ``_float`` twins for the region's extent)."""
        reg = {}
        for k, v in self.region.items():
            if isinstance(v, tuple):
                reg[k] = [exact_str(x) for x in v]
                if not any(sp.sympify(x).free_symbols for x in v):
                    reg[k + "_float"] = [float(sp.N(x, 17)) for x in v]
            elif isinstance(v, sp.Basic):
                reg[k] = exact_str(v)
                if not v.free_symbols:
                    reg[k + "_float"] = float(sp.N(v, 17))
            else:
                reg[k] = v
        out = {"scene": self.scene, "theta": None if self.theta is None else exact_str(self.theta),
               "variables": ["alpha", "e"], "boundaries": [b.as_json() for b in self.boundaries],
               "inequalities": list(self.inequalities), "region": reg}
        if self.theta is not None:
            out["theta_float"] = float(sp.N(self.theta, 17))
        if self.tau is not None:
            out["tau"], out["tau_float"] = exact_str(self.tau), float(sp.N(self.tau, 17))
        if self.sweep:
            out["theta_sweep"] = self.sweep
        return out


def _boundary(name: str):
    """One exact expression of the generated ``impactsym/kernels/domain_boundaries.py`` (written by
    ``derivations/domains.py``).

    >>> _boundary("pool_tau_c2")
    2*alpha - cos(theta)
    """
    return committed_expressions("domain_boundaries")[name]


_c = sp.Symbol("c", real=True)  # cos(theta) in the generated pool curves


def _pool_g(cos_theta):
    return _boundary("pool_g").subs(_c, cos_theta)


def _pool_h(cos_theta):
    return _boundary("pool_h").subs(_c, cos_theta)


_theta = sp.Symbol("theta", real=True)


@lru_cache(maxsize=None)
def _pool_factors():
    """The two-contact pool curves' factors, in ``c = cos θ``, all read from the committed expressions:
    ``c2`` (``w2⁺ = c2 p₁`` at contact 2-3: ``pool_tau_c2`` at τ = 0), ``A`` (``h``'s denominator is
    ``2A``), ``w`` (``g``'s denominator is ``w²``, signed so that ``w = 2`` at α = 0: ``w1⁺ = −1 + w p₁``)
    and the identity ``g − h = α² c2² / (2 A w²)``, checked exactly here (a failure is a bug)."""
    from .errors import VerificationError

    g, h = _boundary("pool_g"), _boundary("pool_h")
    c2 = _boundary("pool_tau_c2").subs(sp.cos(_theta), _c)
    A = sp.expand(sp.fraction(sp.together(h))[1] / 2)
    base = sp.factor(sp.fraction(sp.together(g))[1])
    if not (isinstance(base, sp.Pow) and base.exp == 2):
        raise VerificationError("validity_domain", f"pool_g's denominator {base} is not a square")
    w = base.base if certified_sign(base.base.subs(alpha, 0)) > 0 else sp.expand(-base.base)
    if sp.cancel(g - h - alpha**2 * c2**2 / (2 * A * w**2)) != 0:
        raise VerificationError("validity_domain", "g - h != alpha^2 c2^2 / (2 A w^2) for the committed curves")
    return c2, A, w


#: ``alpha`` without assumptions: the curves are simplified in it (see :func:`_simplify_curve`)
_alpha_free = sp.Symbol("alpha")


def _simplify_curve(x):
    """``simplify(x)`` for a curve in α with numeric coefficients, computed with α free of assumptions
    and then given back the package's ``alpha``.

    The curves are rational functions of α (integer powers only), so the assumption ``α ≥ 0`` has
    nothing to rewrite in them, but SymPy's simplify asks it anyway: every ``is_positive`` of a
    polynomial in a nonnegative symbol runs ``_monotonic_sign``, which solves that polynomial
    (``roots``), and that was most of the cost of a domain. The form returned is the one simplify
    gives with the assumption (same name, hence same term order; checked on every domain of the
    tests and on 41 angles θ), and the value is the same expression (simplify is an identity).

    >>> _simplify_curve((alpha**2 / 2 + 1) / (alpha**2 + 2))
    1/2
    """
    return sp.simplify(x.xreplace({alpha: _alpha_free})).xreplace({_alpha_free: alpha})


def _linear_root(p):
    """The root in α of ``p``, a polynomial of degree 1 in α (read from its two coefficients: what
    ``sp.solve(p, alpha)`` returns for it, without the generic solver)."""
    from .errors import VerificationError

    poly = sp.Poly(p, alpha)
    if poly.degree() != 1:
        raise VerificationError("validity_domain", f"{p} is not linear in alpha")
    return -poly.nth(0) / poly.nth(1)


def _is_zero(x) -> bool:
    """Whether ``x`` (a rational function of α whose coefficients may hold sin(τ), cos(τ) of one
    number τ) is identically zero, proved: ``cancel`` after the identity ``sin² = 1 − cos²`` is a
    proof when it gives 0; otherwise ``simplify(x) == 0`` decides, as before.

    >>> t = sp.Rational(1, 3)
    >>> _is_zero(sp.sin(t)**2 * alpha + sp.cos(t)**2 * alpha - alpha), _is_zero(alpha * sp.sin(t))
    (True, False)
    """
    y = x.xreplace({alpha: _alpha_free}).replace(
        lambda z: z.is_Pow and z.exp == 2 and isinstance(z.base, sp.sin), lambda z: 1 - sp.cos(z.base.args[0]) ** 2)
    if sp.cancel(y) == 0:
        return True
    return sp.simplify(x) == 0


def _words(x, cs, order=None) -> str:
    """``x`` (in ``c = cos θ``) as the domain's text: ``c`` read as ``cos(theta)`` for the pool, products spaced."""
    x = x.subs(_c, sp.cos(_theta) if cs is None else cs)
    return sp.sstr(x, order=order).replace("*", " ")


def _ge(x, y) -> bool:
    return certified_sign(sp.sympify(x) - sp.sympify(y)) >= 0


def _chain_or_pool(cs, scene: str, theta) -> ValidityDomain:
    """The two-contact domain for ``c = cos θ`` (the chain is c = 1)."""
    g, h = _pool_g(cs), _pool_h(cs)
    c2s, _, ws = _pool_factors()
    c2, w = c2s.subs(_c, cs), ws.subs(_c, cs)  # w2+ = c2 p1 (contact 2-3), w1+ = -1 + w p1 (contact 1-2)
    root = _linear_root(c2s)  # c2 = 0
    lo = sp.Max(0, root.subs(_c, cs))
    emin = sp.simplify(g.subs(alpha, lo))
    lo_s = sp.simplify(lo)
    # the simplified curves are read only by the boundaries and the inequalities: computed when read
    g_s, h_s = _Later(lambda: _simplify_curve(g)), _Later(lambda: _simplify_curve(h))
    pool_ = scene == "pool"
    text_c = None if pool_ else sp.Integer(1)  # the text reads c as cos(theta) for the pool
    bnds = [
        Boundary("alpha_min", "alpha", lo,
                 f"alpha >= {exact_str(lo)}: v2+ >= 0 at contact 2-3 (v2+ = ({_words(c2s, text_c)}) p1) and p2 = alpha p1 >= 0"),
        Boundary("g", "e", g_s,
                 f"e >= g(alpha): v1+ >= 0 at contact 1-2 ({'eq. 29' if pool_ else 'eq. 19'}); g <= 1 iff alpha <= 1, "
                 "so alpha <= 1"),
        Boundary("h", "e", h_s,
                 f"e >= h(alpha): Delta >= 0 ({'eq. 31, corrected' if pool_ else 'eq. 18'}); implied by e >= g since g - h = "
                 f"alpha^2 ({_words(c2s, text_c)})^2 / (2 A ({_words(ws, text_c, 'none')})^2) >= 0; touches g at alpha = 0 and "
                 f"alpha = {_words(root, text_c)}"),
        Boundary("e_max", "e", sp.Integer(1), "e <= 1: dissipative energetic coefficient (eq. 12)"),
    ]

    def inequalities():
        ineq = [f"alpha >= {exact_str(lo)}", f"{exact_str(g_s())} <= e <= 1"]
        if scene == "chain3":
            ineq.append("equivalently (eq. 19): 1/3 <= e <= 1 and 1/2 <= alpha <= "
                        f"{exact_str(_boundary('chain3_alpha_max'))}")
        return ineq
    region = {"alpha": (lo_s, sp.Integer(1)), "e": (emin, sp.Integer(1)), "e_min_at": lo_s,
              "empty": False,
              "description": (f"the set above the curve e = g(alpha) for {exact_str(lo_s)} <= alpha <= 1, "
                              f"e up to 1; lowest point (alpha, e) = ({exact_str(lo_s)}, {exact_str(emin)}), "
                              "g(1) = 1 closes it at (1, 1)")}

    def member(a, ee):
        if not (_ge(ee, 0) and _ge(1, ee) and _ge(a, 0) and _ge(c2.subs(alpha, a), 0)):
            return False
        if certified_sign(w.subs(alpha, a)) <= 0:  # w1+ = -1 + w p1 < 0
            return False
        return _ge(ee, g.subs(alpha, a))

    return ValidityDomain(scene, theta, bnds, _Later(inequalities), region, member)


def _bernoulli_tau0(theta) -> ValidityDomain:
    d = {k: _boundary(f"bernoulli_{k}") for k in ("g1", "g3", "R3", "h", "e_min_at", "e_min")}
    d["alpha_range"] = (sp.Integer(0), sp.Integer(1))
    g1, g3, R3, h = d["g1"], d["g3"], d["R3"], d["h"]
    bnds = [
        Boundary("alpha_min", "alpha", sp.Integer(0), "alpha13 = alpha12 = alpha >= 0: p >= 0"),
        Boundary("g1", "e", g1, "e >= g1(alpha): v+ >= 0 at contact 1-2"),
        Boundary("g3", "e", g3, "e >= g3(alpha) where R3 > 0, i.e. alpha < 2/5 or alpha > 1: v+ >= 0 at contact 1-3 "
                 f"(R3 = {exact_str(R3)})"),
        Boundary("h", "e", h, "e >= h(alpha): Delta >= 0; implied by e >= g1 (g1 - h = R1^2/(4 A T) >= 0)"),
        Boundary("e_max", "e", sp.Integer(1), "e <= 1: dissipative energetic coefficient (eq. 12)"),
    ]
    ineq = ["0 <= alpha <= 1 (alpha13 = alpha12 = alpha, three closed contacts)", f"e >= {exact_str(g1)}",
            f"e >= {exact_str(g3)} if alpha < 2/5", "e <= 1"]
    region = {"alpha": d["alpha_range"], "e": (d["e_min"], sp.Integer(1)), "e_min_at": d["e_min_at"], "empty": False,
              "description": ("theta = 2pi/3: contact 1-3 closes and approaches; with alpha13 = alpha12 the set lies "
                              f"above max(g1, g3) (g3 active for alpha < 2/5); lowest point ({exact_str(d['e_min_at'])}, "
                              f"{exact_str(d['e_min'])}) where g1 = g3; alpha = 0 needs e = 1")}

    def member(a, ee):
        if not (_ge(ee, 0) and _ge(1, ee) and _ge(a, 0) and _ge(ee, g1.subs(alpha, a))):
            return False
        if certified_sign(R3.subs(alpha, a)) > 0 and not _ge(ee, g3.subs(alpha, a)):
            return False
        return True

    return ValidityDomain("pool", theta, bnds, ineq, region, member)


def _parse_theta(theta):
    if theta is None:
        return None
    t = to_exact(theta, "theta") if not isinstance(theta, str) else parse_number(theta, "theta")
    if certified_sign(t) < 0 or certified_sign(t - 2 * sp.pi / 3) > 0:
        raise ImpactInputError("theta", f"must lie in [0, 2*pi/3] (balls 1 and 3 would overlap beyond), got {t}")
    return t


def validity_domain(scene: str, theta=None, tau=None) -> ValidityDomain:
    """The validity domain of the impulse-ratio law on a scene, exactly.

    Parameters
    ----------
    scene : ``"chain3"`` or ``"pool"``
    theta : the pool's angle θ ∈ [0, 2π/3] (exact number, numeric text such as ``"pi/4"``, or a
        float, taken at its exact binary value). ``None`` for the pool gives the domain as a
        function of θ with a table over :data:`THETA_SWEEP`. Not accepted for ``"chain3"``.
    tau : the pool's incidence angle τ (needs θ; default 0). For ``cos τ > 0`` the domain is the
        τ = 0 domain mapped by ``e ↦ sin²τ + cos²τ e`` (derived, see :func:`_pool_tau`); for
        ``cos τ ≤ 0`` contact 1–2 does not approach and the domain is empty (no impact, eq. 41).

    Returns
    -------
    ValidityDomain

    Raises
    ------
    ImpactInputError
        unknown scene; θ outside [0, 2π/3]; θ given for the chain.

    Examples
    --------
    >>> d = validity_domain("pool", "pi/4")
    >>> d.region["alpha"], d.region["e"]
    ((sqrt(2)/4, 1), (3/7, 1))
    >>> validity_domain("pool", "3")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: theta: must lie in [0, 2*pi/3] (balls 1 and 3 would overlap beyond), got 3

    References
    ----------
    Acary & Taha, eqs. 19, 28–32, Fig. 3.
    """
    if scene not in SCENES:
        raise ImpactInputError("scene", f"unknown scene {scene!r}; known: {', '.join(SCENES)}")
    if tau is not None:
        if scene != "pool":
            raise ImpactInputError("tau", "only the pool scene takes tau")
        if theta is None:
            raise ImpactInputError("tau", "needs theta (the domain at one (theta, tau))")
        t = to_exact(tau, "tau") if not isinstance(tau, str) else parse_number(tau, "tau")
        if certified_sign(abs(t) - sp.pi) > 0:
            raise ImpactInputError("tau", f"must lie in [-pi, pi], got {t}")
        if certified_sign(t) != 0:
            return _fresh(_pool_tau(_parse_theta(theta), t))
    return _fresh(_validity_domain(scene, _parse_theta(theta) if scene == "pool" else theta))


def _fresh(d: ValidityDomain) -> ValidityDomain:
    """The caller's own copy of a memoized domain: new lists, dicts and boundaries (the SymPy values
    in them are immutable), so a caller that edits its domain cannot change the memo."""
    ineq = _raw(d, "inequalities")
    return replace(d, boundaries=[replace(b, expression=_raw(b, "expression")) for b in d.boundaries],
                   inequalities=ineq if isinstance(ineq, _Later) else list(ineq),
                   region=dict(d.region), sweep=copy.deepcopy(d.sweep))


@lru_cache(maxsize=None)
def _pool_tau(theta, tau) -> ValidityDomain:
    """The pool's domain at incidence τ ≠ 0, derived from the general admissibility conditions.

    The conditions of eq. 28 for ``pool(θ, τ)``, derived for symbolic ``(θ, τ)`` by
    :func:`derivations.domains.pool_tau_conditions` and committed (``domain_boundaries.py``), are
    substituted at this (θ, τ) and checked, symbolically, to equal the τ = 0 curves mapped by
    ``e ↦ sin²τ + cos²τ e``: the tangential energy ``½ sin²τ`` is untouched by impulses along the
    normals, and the normal problem is the τ = 0 problem scaled by ``cos τ``.

    >>> d = validity_domain("pool", "pi/4", "pi/6")
    >>> d.region["e"]
    (4/7, 1)
    >>> d.contains("sqrt(2)/4", "4/7"), d.contains("1/2", "1/2")
    (True, False)
    """
    if certified_sign(theta - 2 * sp.pi / 3) == 0:
        raise ImpactInputError("tau", "tau != 0 at theta = 2*pi/3 (three closed contacts) has no derived domain; "
                               "use impactsym.laws.impulse_ratio for single points")
    ct, st = sp.cos(tau), sp.sin(tau)
    if certified_sign(ct) <= 0:
        desc = "cos(tau) <= 0: contact 1-2 does not approach (no impact, eq. 41); the law has no solution to admit"
        return ValidityDomain("pool", theta, [], [desc], {"empty": True, "description": desc},
                              lambda a, ee: False, tau=tau)
    base = _validity_domain("pool", theta)
    cs = sp.cos(theta)
    s2, c2 = st**2, ct**2
    g_tau, h_tau = s2 + c2 * _pool_g(cs), s2 + c2 * _pool_h(cs)
    at = {sp.Symbol("theta", real=True): theta, sp.Symbol("tau", real=True): tau}
    g1, h1, b2, c2__ = (_boundary(f"pool_tau_{k}").subs(at) for k in ("g1", "h", "b2", "c2"))
    derived_ok = (_is_zero(g1 - g_tau) and _is_zero(h1 - h_tau)
                  and b2 == 0 and _is_zero(c2__ - (2 * alpha - cs)))
    if not derived_ok:  # pragma: no cover - a failed identity is a bug in the derivation
        raise RuntimeError(f"pool domain at tau = {tau}: the derived conditions differ from the mapped tau = 0 curves")
    g_tau_s = _Later(lambda: _simplify_curve(g_tau))  # computed when read, as in _chain_or_pool
    bnds = [
        base.boundaries[0],
        Boundary("g_tau", "e", g_tau_s,
                 "e >= sin^2(tau) + cos^2(tau) g(alpha): v1+ >= 0 at contact 1-2 (derived for this (theta, tau); "
                 "equal to eq. 29's curve mapped by e -> sin^2(tau) + cos^2(tau) e)"),
        Boundary("h_tau", "e", _Later(lambda: _simplify_curve(h_tau)),
                 "e >= sin^2(tau) + cos^2(tau) h(alpha): Delta >= 0 (eq. 31 corrected, mapped); implied by e >= g_tau"),
        Boundary("e_max", "e", sp.Integer(1), "e <= 1: dissipative energetic coefficient (eq. 12)"),
    ]
    lo = base.region["alpha"][0]
    emin = sp.radsimp(sp.simplify(s2 + c2 * base.region["e"][0]))  # exact rewriting only
    region = {"alpha": base.region["alpha"], "e": (emin, sp.Integer(1)), "e_min_at": lo, "empty": False,
              "description": (f"the tau = 0 domain mapped by e -> sin^2(tau) + cos^2(tau) e: alpha in "
                              f"[{exact_str(lo)}, 1], e in [{exact_str(emin)}, 1]; the tangential energy "
                              "sin^2(tau)/2 is never dissipated, so e >= sin^2(tau)")}

    def member(a, ee):
        return _ge(ee, 0) and _ge(1, ee) and base._member(a, (ee - s2) / c2)

    ineq = _Later(lambda: [f"alpha >= {exact_str(lo)}", f"{exact_str(g_tau_s())} <= e <= 1"])
    return ValidityDomain("pool", theta, bnds, ineq, region, member, tau=tau)


@lru_cache(maxsize=None)
def _validity_domain(scene: str, theta) -> ValidityDomain:
    if scene == "chain3":
        if theta is not None:
            raise ImpactInputError("theta", "only the pool scene takes theta")
        return _chain_or_pool(sp.Integer(1), "chain3", None)
    t = theta
    if t is None:
        return _pool_symbolic()
    if certified_sign(t - 2 * sp.pi / 3) == 0:
        return _bernoulli_tau0(t)
    return _chain_or_pool(sp.cos(t), "pool", t)


def _pool_symbolic() -> ValidityDomain:
    c = sp.cos(sp.Symbol("theta", real=True))
    g, h = _pool_g(c), _pool_h(c)
    bnds = [
        Boundary("alpha_min", "alpha", sp.Max(0, c / 2), "alpha >= max(0, cos(theta)/2): v2+ >= 0 and p >= 0"),
        Boundary("g", "e", g, "e >= g(alpha): v1+ >= 0 (eq. 29)"),
        Boundary("h", "e", h, "e >= h(alpha): Delta >= 0 (eq. 31 corrected); implied by e >= g"),
        Boundary("e_max", "e", sp.Integer(1), "e <= 1"),
    ]
    sweep = []
    for t in THETA_SWEEP:
        d = validity_domain("pool", t)
        sweep.append({"theta": exact_str(t), "theta_float": float(sp.N(t, 17)),
                      "alpha": [exact_str(x) for x in d.region["alpha"]],
                      "e": [exact_str(x) for x in d.region["e"]],
                      "e_float": [float(sp.N(x, 17)) for x in d.region["e"]],
                      "empty": d.region["empty"]})
    region = {"alpha": (sp.Max(0, c / 2), sp.Integer(1)), "e": (sp.Piecewise(((2 - c**2) / (4 - c**2), c >= 0), (sp.Rational(1, 2), True)), sp.Integer(1)),
              "empty": False,
              "description": ("theta in [0, 2pi/3): alpha in [max(0, cos(theta)/2), 1], e in [g(alpha), 1]; never empty "
                              "((1, 1) always valid); e_min = (2 - cos^2 theta)/(4 - cos^2 theta) rises from 1/3 (theta = 0, "
                              "the chain) to 1/2 (theta = pi/2) and stays 1/2 (at alpha = 0) on ]pi/2, 2pi/3[; "
                              "theta = 2pi/3: three closed contacts (alpha13 = alpha12): alpha in [0, 1], e_min = 5/9 at alpha = 1/4")}
    return ValidityDomain("pool", None, bnds, ["alpha >= max(0, cos(theta)/2)", "g(alpha) <= e <= 1"], region, None, sweep)


def plot_domain(theta, path, *, alpha_max=None, points: int = 400, ax=None, legend: bool = True) -> dict:
    """Draw the valid domain of ``(α₁₂, e)`` for the pool at θ (Fig. 3 is θ = π/4) into ``path`` (PNG).

    The curves are the generated kernels ``pool_g`` and ``pool_h`` (derived in
    :mod:`derivations.domains`); the domain is shaded between ``g`` and ``e = 1``.

    Parameters
    ----------
    theta : θ ∈ [0, 2π/3) (exact or float)
    path : output file (``None``: draw only, on ``ax``)
    alpha_max : right end of the α axis (default 1.5)
    points : samples per curve
    ax : a matplotlib Axes to draw on (the figure is then neither saved unless ``path`` is given,
        nor closed); default: a new figure, saved to ``path`` and closed
    legend : draw the legend (default); ``False`` for a panel that shows none (the same figure as
        drawing it and then removing it, without the cost of building it)

    Returns
    -------
    dict with the plotted arrays ``alpha``, ``g``, ``h`` (exactly the data of the drawn lines), the
    shaded range and ``path``.

    Examples
    --------
    >>> import tempfile, os
    >>> out = plot_domain("pi/4", os.path.join(tempfile.mkdtemp(), "fig3.png"))
    >>> round(float(out["e_min"]), 6)
    0.428571
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from .kernels import pool_g as g_kernel, pool_h as h_kernel

    t = _parse_theta(theta)
    if certified_sign(t - 2 * sp.pi / 3) == 0:
        raise ImpactInputError("theta", "plot_domain draws the two-contact pool, theta < 2*pi/3")
    dom = validity_domain("pool", t)
    tf = float(sp.N(t, 17))
    a_hi = 1.5 if alpha_max is None else float(alpha_max)
    a = np.linspace(0.0, a_hi, points)
    g, h = g_kernel(tf, a), h_kernel(tf, a)
    lo, hi = (float(sp.N(x, 17)) for x in dom.region["alpha"])
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(6, 4.5))
    else:
        fig = ax.figure
    ax.plot(a, g, color="C0", label="g: v1+ = 0 (eq. 29)")
    ax.plot(a, h, color="C1", linestyle="--", label="h: Delta = 0 (eq. 31, corrected)")
    inside = (a >= lo) & (a <= hi)
    ax.fill_between(a[inside], g[inside], 1.0, color="C2", alpha=0.3, label="valid domain D")
    ax.axvline(lo, color="grey", linewidth=0.8, linestyle=":")
    emin = dom.region["e"][0]
    ax.plot([lo], [float(sp.N(emin, 17))], "ko", markersize=4)
    ax.set_xlim(0, a_hi)
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("alpha_12")
    ax.set_ylabel("e")
    ax.set_title(f"Valid domain of e and alpha_12, theta = {exact_str(t)}")
    if legend:
        ax.legend(loc="lower right", fontsize=8)
    if own:
        from .figures._common import tight_layout_once

        tight_layout_once(fig)
    if path is not None:
        fig.savefig(path, dpi=100)
    lines = {"g": ax.lines[0].get_ydata().copy(), "h": ax.lines[1].get_ydata().copy(), "alpha": ax.lines[0].get_xdata().copy()}
    if own:
        plt.close(fig)
    return {"path": None if path is None else str(path), "alpha": lines["alpha"], "g": lines["g"], "h": lines["h"],
            "alpha_range": (lo, hi), "e_min": emin, "theta": t}

