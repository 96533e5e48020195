"""The compliant and LZB laws behind the one law interface (:class:`~impactsym.lawbook.Law`), and
impulse ratios taken from them (``ratios="from-hertz"``; Acary & Taha sec. 3.4, eqs. 20–23).

=================  ==============================================  ===================  =========
law                model                                           restitution          exactness
=================  ==============================================  ===================  =========
``hertz``          ``M q̈ = Hᵀf``, ``f = K δ^{3/2}`` (eq. 20)         elastic only         float
``linear``         ``f = K δ`` (eq. 23)                            elastic only         float
``power``          ``f = K δ^p``, ``--exponent p ≥ 1``              elastic only         float
``hunt-crossley``  ``f = K δ^p (1 + D δ̇)``, ``p = 3/2`` by default  per contact, e > 0   float
``lzb``            Liu–Zhao–Brogliato, impulse domain              per contact, e > 0   float
=================  ==============================================  ===================  =========

Every one integrates an ODE (:func:`impactsym.compliant.compliant_impact`,
:func:`impactsym.lzb.lzb_impact`; DOP853), so its outcome is a float (``exactness: "float"``) and
its ``details`` state the tolerance (``tolerance.rtol``; ``atol`` is relative to the problem's own
length, speed and impulse scales) and the integration's counts (contact ``events``, ``steps``,
``nfev``; LZB ``segments``). The numbers are exactly those of a direct call of the engine with the
same arguments. Options (keyword arguments of :meth:`Law.resolve`, CLI ``--option-name``):

``stiffness``
    ``K_i > 0``: one number for every contact or one per contact (default 1; for the elastic
    laws only the ratios of the stiffnesses matter, sec. 3.4 claim 2(b)).
``exponent``
    ``p_i ≥ 1`` (``power``: required; ``hunt-crossley``, ``lzb``: default 3/2).
``damping``
    ``hunt-crossley`` only: the coefficients ``D_i ≥ 0`` themselves, instead of a restitution.
``tolerance``
    the integrator's relative tolerance ``rtol`` (default ``1e-11``), in ``[1e-13, 1e-3]``.

Restitution. The elastic laws take ``e = 1`` only. Hunt–Crossley takes one ``e_i ∈ (0, 1]`` per
contact and turns it into ``D_i`` = :func:`~impactsym.compliant.hunt_crossley_damping` ``(e_i,
u_i)``: the damping with which contact ``i`` alone, struck at the speed ``u_i``, restitutes
``e_i`` (``u_i`` its approach speed ``−(Hv⁻)_i`` if it approaches, else the fastest approach
speed of the system). Hunt–Crossley's restitution depends on the impact speed, so a contact that
closes at another speed restitutes another ``e``; ``details`` report the ``D_i`` used. LZB takes
one energetic coefficient ``e_i ∈ (0, 1]`` per contact (the energy a contact gives back in
expansion is ``e_i²`` times what it stored).

When a law does not apply, :meth:`~impactsym.lawbook.Law.why_not` says why:

* a restitution other than 1 for an elastic law (or ``e = 0`` for Hunt–Crossley and LZB);
* no separating direction (the hypothesis of the termination theorem,
  ``docs/compliant_termination.md``): by Gordan's alternative, no ``u`` has ``H u > 0`` exactly
  when some ``λ ≥ 0``, ``λ ≠ 0`` has ``Hᵀλ = 0`` (a ball between two walls: ``λ = (1, 1)``). The
  contacts in the support of ``λ`` *confine* the bodies: they can never all leave (``H v ≥ 0``
  forces ``λᵀHv = 0``, so ``(Hv)_i = 0`` on the support). The theorem (with a separating
  direction, an elastic compliant impact ends in finite time) then does not apply, and an elastic
  run need not end: a ball between two walls rings for ever (proved in the document). So the
  elastic laws refuse, naming ``λ``; Hunt–Crossley refuses too (a damped run without a separating
  direction ends only at a rest tolerance, which the law does not take; a Hunt–Crossley ball
  between two walls comes to rest only asymptotically, its restitution tending to 1 as the speed
  falls). LZB with ``e_i < 1`` on every confining contact does end (the speed falls by a fixed
  factor per bounce), so LZB refuses only confining contacts with ``e_i = 1``. The certificate
  (``u`` or ``λ``) is :func:`impactsym.termination.separating_direction`'s, verified exactly
  (rational rows in ``fmpq``, algebraic rows such as ``sqrt(3)/2`` with certified signs) before
  it is used (:func:`confinement`).

Every run that ends is checked before it is returned (:func:`impactsym.termination.check_run`):
the momentum balance, the energy (elastic: ``|T⁺/T⁻ − 1| ≤ min(1e5 rtol, 10 √rtol)``) and the
proved impulse bound; ``details.termination`` holds the certificate and the measured residuals.

A system in which no contact approaches has no impact: every law returns ``v⁺ = v⁻`` and ``p = 0``
(``details.events = 0``) instead of integrating.

Ratios from compliance
----------------------
:func:`register` also wraps the impulse-ratio and energetic laws so that their option ``ratios``
may name a model instead of numbers: ``"from-hertz"``, ``"from-linear"`` or ``"from-lzb"``
(:data:`RATIO_SOURCES`). The elastic model (unit stiffness on every contact, the system's own
``M``, ``H``, ``v⁻``; LZB with every ``e_i = 1``) is integrated, its impulses give the ratios
``α_1j = P_j / P_1`` (floats), and eq. 38 is then solved with those float ratios (the law's float
path: the outcome is ``"float"``; the system's global ``e`` is used there). ``details.ratio_source``
holds the model's ratios, velocity and impulses, and how far the law's ``v⁺`` is from the
model's: the kinetic-metric distance ``‖v⁺_law − v⁺_model‖_M = √(Δvᵀ M Δv)``, absolute and
relative to ``‖v⁻‖_M``. With ``e = 1`` the two agree to the integration's tolerance (the model
conserves energy and its impulse has exactly those ratios); with ``e < 1`` the distance is how far
eq. 38's energy loss moves the outcome from the elastic model's.

Examples
--------
>>> from impactsym.lawbook import resolve
>>> from impactsym.resolution import System
>>> chain = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
>>> r = resolve("hertz", chain)
>>> r.exactness, r.velocity.round(5).tolist(), r.details["events"]
('float', [-0.07095, 0.0764, 0.99455], 4)
>>> r = resolve("impulse-ratio", chain, ratios="from-hertz")
>>> src = r.details["ratio_source"]
>>> [round(a, 5) for a in src["ratios"]], src["kinetic_distance_relative"] < 1e-8
([1.0, 0.92866], True)
>>> resolve("linear", System.from_matrices("1", "1;-1", "-1")).velocity
Traceback (most recent call last):
...
impactsym.errors.ImpactInputError: gradients: --law linear does not apply: contacts 1, 2 confine the bodies: lambda = (1, 1) >= 0 has H^T lambda = 0 (checked exactly), so by Gordan's alternative no u has H u > 0. They can never all leave (H v >= 0 forces (H v)_i = 0 on them), so an elastic impact need not end (a ball between two walls rings for ever, proved); the termination theorem needs some u with H u > 0 (docs/compliant_termination.md)
"""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import numpy as np

from .errors import ImpactInputError
from .lawbook import LAWS, Energetic, ImpulseRatio, Law, _is_one
from .resolution import Outcome, RationalMatrix, Resolution, System, is_sympy

__all__ = ["Hertz", "Linear", "Power", "HuntCrossley", "LZB", "COMPLIANT_LAWS", "RATIO_SOURCES", "ratio_source",
           "confining_contacts", "confinement", "ratios_from_model", "register", "DEFAULT_RTOL"]

#: the integrators' default relative tolerance (the engines' own default)
DEFAULT_RTOL = 1e-11
#: the range a tolerance option must lie in (below 1e-13 DOP853 cannot deliver it)
RTOL_RANGE = (1e-13, 1e-3)
#: ``ratios="from-…"`` -> the law whose impulses give the ratios
RATIO_SOURCES = {"from-hertz": "hertz", "from-linear": "linear", "from-lzb": "lzb"}


# ------------------------------------------------------------------------------ option values
def _floats(value, k: int, argument: str) -> np.ndarray:
    """One number, or one per contact (numbers, SymPy, text ``"a,b"``), as ``k`` finite floats."""
    if isinstance(value, str):
        from .numbers import parse_number

        parts = [x.strip() for x in value.split(",")]
        value = [parse_number(x, argument) for x in parts] if len(parts) > 1 else parse_number(parts[0], argument)
    if is_sympy(value, "MatrixBase"):
        value = list(value)
    items = list(value) if isinstance(value, (list, tuple, np.ndarray)) else [value] * k
    if len(items) != k:
        raise ImpactInputError(argument, f"expected one value or one per contact ({k}), got {len(items)}")
    out = []
    for x in items:
        try:
            f = _sympy_float(x) if is_sympy(x) else _fraction_float(x) if isinstance(x, Fraction) else float(x)
        except (TypeError, ValueError):
            raise ImpactInputError(argument, f"must be real numbers, got {x!r}") from None
        if not np.isfinite(f):
            raise ImpactInputError(argument, f"must be finite, got {x}")
        out.append(f)
    return np.array(out, dtype=float)


def _sympy_float(x) -> float:
    import sympy as sp

    return float(sp.N(x, 17))


def _fraction_float(x: Fraction) -> float:
    """``float(N(x, 17))`` of a rational, without SymPy (the float a SymPy ``Rational`` gives here)."""
    from .arithmetic.literals import json_float

    return json_float(x.numerator, x.denominator)


def _stiffness(value, k):
    K = _floats(1 if value is None else value, k, "stiffness")
    if np.any(K <= 0):
        raise ImpactInputError("stiffness", f"must be > 0 on every contact, got {K.tolist()}")
    return K


def _exponent(value, k, default):
    p = _floats(default if value is None else value, k, "exponent")
    if np.any(p < 1):
        raise ImpactInputError("exponent", f"must be >= 1 on every contact (the force K delta^p must be continuous "
                               f"and vanish at first contact), got {p.tolist()}")
    return p


def _tolerance(value) -> float:
    if value is None:
        return DEFAULT_RTOL
    rtol = float(_floats(value, 1, "tolerance")[0])
    lo, hi = RTOL_RANGE
    if not (lo <= rtol <= hi):
        raise ImpactInputError("tolerance", f"must lie in [{lo:g}, {hi:g}] (the integrator's relative tolerance), "
                               f"got {rtol:g}")
    return rtol


def _restitution(system: System, law: str) -> np.ndarray:
    e = _floats(system.restitution_vector(default=1), system.k, "restitution")
    if np.any((e <= 0) | (e > 1)):
        raise ImpactInputError("restitution", f"--law {law} takes 0 < e <= 1 on every contact, got {e.tolist()}")
    return e


def _float_matrices(system: System):
    from .compliant import float_system
    from .numbers import _float_of

    def arr(A):
        if isinstance(A, RationalMatrix):  # the floats SymPy's evalf(17) gives the same rationals
            return np.array(A.json_floats(), dtype=float)
        if is_sympy(A, "MatrixBase"):
            # each entry's float(N(x, 17)), as A.evalf(17) gives it; a rational without evalf (json_float)
            return np.array([[_float_of(x) for x in row] for row in A.tolist()], dtype=float)
        return np.asarray(A, float)

    return float_system(arr(system.M), arr(system.H), arr(system.v).reshape(-1))


# ------------------------------------------------------------------------------- confinement
def confining_contacts(M, H) -> list[int]:
    """The contacts (0-based rows of ``H``) in the support of the certificate ``λ ≥ 0``, ``λ ≠ 0``,
    ``Hᵀλ = 0`` of :func:`impactsym.termination.separating_direction` (empty when some ``u`` has
    ``H u > 0``): contacts that can never all leave (``H v ≥ 0`` forces ``(Hv)_i = 0`` there).

    The certificate is exact (verified before it is returned); its ``λ`` comes from the linear
    program of largest support, so these are all the confining contacts. ``M`` is not needed
    (``Hᵀλ = 0`` does not involve it); it is taken for symmetry with the laws.

    Examples
    --------
    A ball between two walls, and three balls on a line against one wall:

    >>> confining_contacts([[1]], [[1], [-1]]), confining_contacts(np.eye(3), [[-1, 1, 0], [0, -1, 1], [0, 0, -1]])
    ([0, 1], [])
    """
    from .termination import separating_direction

    return list(separating_direction(H).support)


def confinement(system: System):
    """The exact certificate of Gordan's alternative for ``system``'s rows
    (:func:`impactsym.termination.separating_direction` on the exact ``H``: rational rows in
    ``fmpq``, algebraic rows in SymPy with certified signs; float rows at their binary values).

    >>> c = confinement(System.from_matrices("1", "1;-1", "-1"))
    >>> c.separating, c.support, c.vector
    (False, (0, 1), (1, 1))
    """
    from .termination import separating_direction

    return separating_direction(system.H)


def _names(system, idx):
    return ", ".join(system.contacts[i] for i in idx)


# ------------------------------------------------------------------------------------- laws
def _separation(system, H, v, vplus) -> dict:
    """``valid`` and ``violations`` of an integrated outcome: every contact leaves or grazes,
    ``(H v⁺)_i ≥ −ε V`` with the engines' own end threshold ``ε`` (``SEPARATION_EPS``, relative to
    the fastest approach speed ``V``); true by construction of both engines' stopping rules, and
    checked here rather than assumed."""
    from .compliant import SEPARATION_EPS

    w0, w = H @ v, H @ vplus
    V = float(np.max(-w0))
    bad = [i for i in range(len(w)) if w[i] < -SEPARATION_EPS * V]
    return {"valid": not bad,
            "violations": [{"condition": "approaching", "contact": i,
                            "message": f"contact {system.contacts[i]} still approaches after the impact: "
                                       f"(H v+)_{i + 1} = {w[i]:.3g} < -{SEPARATION_EPS:g} V"} for i in bad]}


def _termination(r) -> dict:
    """``details.termination``: the separating-direction certificate of the engine's rows (when it
    computed one) and the a-posteriori checks the run passed (``docs/compliant_termination.md``)."""
    cert = getattr(r, "certificate", None)
    return {"certificate": None if cert is None else cert.as_json(), "checks": r.checks,
            "document": "docs/compliant_termination.md"}


class _Compliant(Law):
    """A law that integrates the time-domain compliant model (:func:`impactsym.compliant.compliant_impact`)."""

    restitution = "none"
    options: tuple[str, ...] = ("stiffness", "tolerance")
    #: the contact exponent when the law fixes it (None: the ``exponent`` option)
    fixed_exponent: float | None = None
    default_exponent: float | None = None
    model = ""

    def _exponent(self, system, exponent=None):
        if self.fixed_exponent is not None:
            return np.full(system.k, self.fixed_exponent)
        return _exponent(exponent, system.k, self.default_exponent)

    def _elastic_why_not(self, system):
        e = system.restitution
        vals = e if isinstance(e, (list, tuple)) else [e]
        if any(x is not None and not _is_one(x) for x in vals):
            return "restitution", (f"the {self.name} law is elastic (e = 1); --law hunt-crossley or --law lzb "
                                   "take a restitution e < 1 per contact")
        return None

    def _confined_why_not(self, system, what=None):
        cert = confinement(system)
        if cert.separating:
            return None
        what = what or ("an elastic impact need not end (a ball between two walls rings for ever, proved); the "
                        "termination theorem needs some u with H u > 0")
        return "gradients", (f"contacts {_names(system, cert.support)} confine the bodies: {cert.statement()}. "
                             "They can never all leave (H v >= 0 forces (H v)_i = 0 on them), so " + what
                             + " (docs/compliant_termination.md)")

    def why_not(self, system, stiffness=None, tolerance=None, exponent=None, **_):
        if self.fixed_exponent is None and self.default_exponent is None and exponent is None:
            return "exponent", f"--law {self.name} needs the contact exponent (--exponent P, P >= 1)"
        _stiffness(stiffness, system.k)
        _tolerance(tolerance)
        self._exponent(system, exponent)
        return self._elastic_why_not(system) or self._confined_why_not(system)

    def _engine_kwargs(self, system, stiffness=None, tolerance=None, exponent=None, **_) -> dict:
        return {"stiffness": _stiffness(stiffness, system.k), "exponent": self._exponent(system, exponent),
                "rtol": _tolerance(tolerance)}

    def _run(self, M, H, v, kw):
        from .compliant import compliant_impact

        return compliant_impact(M, H, v, kw["stiffness"], kw["exponent"], hunt_crossley=kw.get("hunt_crossley"),
                                rtol=kw["rtol"])

    def _details(self, r, kw) -> dict:
        from .compliant import SEPARATION_EPS

        return {"model": self.model, "exponent": kw["exponent"].tolist(), "stiffness": kw["stiffness"].tolist(),
                "tolerance": {"rtol": kw["rtol"], "atol": 1e-14, "separation_eps": SEPARATION_EPS,
                              "note": "DOP853; atol relative to the problem's length, speed and impulse scales; "
                                      "a relative approach speed below separation_eps counts as zero at the end"},
                "events": int(r.events), "steps": int(r.steps), "nfev": int(r.nfev), "duration": float(r.duration),
                "end": r.outcome, "energy_ratio": float(r.energy_ratio), "ratios": [float(x) for x in r.ratios],
                "termination": _termination(r)}

    def resolve(self, system, **options):
        M, H, v = _float_matrices(system)
        kw = self._engine_kwargs(system, **options)
        if not np.any(H @ v < 0):
            details = {"model": self.model, "events": 0, "steps": 0, "nfev": 0,
                       "tolerance": {"rtol": kw["rtol"]}, "end": "no impact"}
            out = Outcome(v.copy(), np.zeros(system.k), details={})
            return Resolution(self.name, system, [out], notes=["no contact approaches: no impact, v+ = v-"],
                              details=details)
        r = self._run(M, H, v, kw)
        out = Outcome(r.velocity, r.impulses, **_separation(system, H, v, r.velocity))
        return Resolution(self.name, system, [out], details=self._details(r, kw), raw=r,
                          notes=[f"the {self.model} model integrated by DOP853: a float result at rtol {kw['rtol']:g}"])


class Hertz(_Compliant):
    name, model = "hertz", "hertz"
    title = "compliant Hertz contacts f = K delta^(3/2), integrated in time (Acary & Taha eq. 20)"
    fixed_exponent = 1.5


class Linear(_Compliant):
    name, model = "linear", "linear"
    title = "compliant linear springs f = K delta, integrated in time (Acary & Taha eq. 23)"
    fixed_exponent = 1.0


class Power(_Compliant):
    name, model = "power", "power"
    title = "compliant power law f = K delta^p (--exponent p >= 1), integrated in time (Acary & Taha eq. 20)"
    options = ("exponent", "stiffness", "tolerance")


class HuntCrossley(_Compliant):
    name, model = "hunt-crossley", "hunt-crossley"
    title = "Hunt-Crossley contacts f = K delta^p (1 + D d(delta)/dt), restitution e per contact, integrated in time"
    options = ("exponent", "stiffness", "damping", "tolerance")
    restitution = "per-contact"
    default_exponent = 1.5

    def why_not(self, system, stiffness=None, tolerance=None, exponent=None, damping=None):
        _stiffness(stiffness, system.k)
        _tolerance(tolerance)
        self._exponent(system, exponent)
        if damping is not None:
            if system.restitution is not None:
                return "damping", "give either --damping (the coefficients D) or --restitution, not both"
            D = _floats(damping, system.k, "damping")
            if np.any(D < 0):
                raise ImpactInputError("damping", f"must be >= 0 on every contact, got {D.tolist()}")
        else:
            _restitution(system, self.name)
        return self._confined_why_not(system, "the termination theorem does not apply and a damped run ends only "
                                              "at a rest tolerance, which this law does not take (a Hunt-Crossley "
                                              "ball between two walls comes to rest only asymptotically: its "
                                              "restitution tends to 1 as the speed falls); --law lzb with e < 1 ends")

    def _engine_kwargs(self, system, stiffness=None, tolerance=None, exponent=None, damping=None):
        from .compliant import hunt_crossley_damping

        kw = super()._engine_kwargs(system, stiffness, tolerance, exponent)
        if damping is not None:
            kw["hunt_crossley"] = _floats(damping, system.k, "damping")
            kw["damping_from"] = "given"
            return kw
        e = _restitution(system, self.name)
        M, H, v = _float_matrices(system)
        w = H @ v
        V = float(np.max(-w)) if np.any(w < 0) else 1.0
        u = np.where(w < 0, -w, V)
        kw["hunt_crossley"] = np.array([hunt_crossley_damping(ei, ui) for ei, ui in zip(e, u)])
        kw["damping_from"] = {"restitution": e.tolist(), "calibration_speed": u.tolist()}
        return kw

    def _details(self, r, kw):
        d = super()._details(r, kw)
        d["damping"] = kw["hunt_crossley"].tolist()
        d["damping_from"] = kw["damping_from"]
        return d


class LZB(_Compliant):
    name, model = "lzb", "lzb"
    title = "LZB multiple impacts: impulse domain, primary contact, distributing rule, energetic e per contact"
    options = ("exponent", "stiffness", "tolerance")
    restitution = "per-contact"
    default_exponent = 1.5

    def why_not(self, system, stiffness=None, tolerance=None, exponent=None):
        _stiffness(stiffness, system.k)
        _tolerance(tolerance)
        self._exponent(system, exponent)
        e = _restitution(system, self.name)
        cert = confinement(system)
        elastic = [i for i in cert.support if e[i] == 1]
        if elastic:
            return "restitution", (f"contacts {_names(system, cert.support)} confine the bodies: {cert.statement()}; "
                                   f"{_names(system, elastic)} restitute e = 1: the confined contacts never all "
                                   "leave and lose no energy, so LZB restarts for ever; give e < 1 on the "
                                   "confining contacts")
        return None

    def _engine_kwargs(self, system, stiffness=None, tolerance=None, exponent=None):
        kw = super()._engine_kwargs(system, stiffness, tolerance, exponent)
        kw["restitution"] = _restitution(system, self.name)
        return kw

    def _run(self, M, H, v, kw):
        from .lzb import lzb_impact

        return lzb_impact(M, H, v, kw["stiffness"], kw["exponent"], kw["restitution"], rtol=kw["rtol"])

    def _details(self, r, kw):
        from .lzb import ENERGY_EPS, SEPARATION_EPS

        return {"model": "lzb", "exponent": kw["exponent"].tolist(), "stiffness": kw["stiffness"].tolist(),
                "restitution": kw["restitution"].tolist(),
                "tolerance": {"rtol": kw["rtol"], "atol": 1e-14, "energy_eps": ENERGY_EPS,
                              "separation_eps": SEPARATION_EPS,
                              "note": "DOP853 in the primary contact's impulse; atol relative to the problem's "
                                      "scales; a primary energy below energy_eps times its approach energy ends a "
                                      "segment"},
                "segments": int(r.segments), "steps": int(r.steps), "nfev": int(r.nfev),
                "energy_ratio": float(r.energy_ratio), "ratios": [float(x) for x in r.ratios],
                "termination": _termination(r)}


#: the laws of this module, in the order of tables
COMPLIANT_LAWS = (Hertz, Linear, Power, HuntCrossley, LZB)


# ------------------------------------------------------------------------- ratios from a model
def ratio_source(text: str) -> str:
    """``text`` if it names a ratio source (:data:`RATIO_SOURCES`), else an error naming ``ratios``.

    >>> ratio_source("from-lzb")
    'from-lzb'
    >>> ratio_source("from-newton")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: ratios: unknown ratio source 'from-newton'; known: from-hertz, from-linear, from-lzb
    """
    if text not in RATIO_SOURCES:
        raise ImpactInputError("ratios", f"unknown ratio source {text!r}; known: {', '.join(RATIO_SOURCES)}")
    return text


def _is_source(ratios) -> bool:
    return isinstance(ratios, str) and ratios.strip().startswith("from-")


def ratios_from_model(system: System, source: str) -> tuple[list, Resolution]:
    """The impulse ratios ``P_j / P_1`` (floats) of the elastic model ``source`` (``"from-hertz"``,
    ``"from-linear"``, ``"from-lzb"``) on ``system`` (unit stiffness, every ``e_i = 1``), and the
    model's resolution.

    Examples
    --------
    >>> chain = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
    >>> [round(a, 5) for a in ratios_from_model(chain, "from-linear")[0]]
    [0.86708]
    """
    from .lawbook import get_law

    law = get_law(RATIO_SOURCES[ratio_source(source)])
    elastic = dataclasses.replace(system, restitution=None)
    why = law.why_not(elastic)
    if why is not None:
        raise ImpactInputError("ratios", f"--ratios {source}: the {law.name} model does not apply ({why[1]})")
    res = law.resolve(elastic)
    P = np.asarray(res.impulses, dtype=float)
    if not P[0] > 0:
        raise ImpactInputError("ratios", f"--ratios {source}: the primary contact {system.contacts[0]} (row 1 of H) "
                               f"receives no impulse in the {law.name} model, so P_j / P_1 is undefined")
    return [float(x) for x in P[1:] / P[0]], res


def _float_of(x) -> float:
    """``float(sympify(x))``."""
    import sympy as sp

    return float(sp.sympify(x))


def _kinetic_norm(M, x) -> float:
    return float(np.sqrt(max(float(x @ M @ x), 0.0)))


class _RatiosFromModel:
    """Mixin for the laws with a ``ratios`` option: ``ratios="from-hertz"`` etc. (module docstring)."""

    def why_not(self, system, ratios=None, **options):
        if _is_source(ratios):
            ratio_source(ratios.strip())
            return super().why_not(system, ratios=[0.0] * (system.k - 1), **options)
        return super().why_not(system, ratios=ratios, **options)

    def resolve(self, system, ratios=None, **options):
        if not _is_source(ratios):
            return super().resolve(system, ratios=ratios, **options)
        source = ratios.strip()
        alphas, model = ratios_from_model(system, source)
        M, H, v = _float_matrices(system)
        # float ratios: the law's float path (the energetic law would read floats on exact M, H, v
        # at their exact binary values and call the outcome exact)
        e = system.restitution
        ef = None if e is None else ([_float_of(x) for x in e] if isinstance(e, (list, tuple)) else _float_of(e))
        res = super().resolve(dataclasses.replace(system, M=M, H=H, v=v, restitution=ef, exact=False),
                              ratios=alphas, **options)
        res.system = system
        vm = np.asarray(model.velocity, dtype=float)
        src = {"source": source, "model": model.law, "ratios": [1.0] + alphas,
               "model_velocity": vm.tolist(), "model_impulses": np.asarray(model.impulses, float).tolist(),
               "model_events": model.details.get("events", model.details.get("segments")),
               "model_tolerance": model.details["tolerance"]["rtol"],
               "ratios_exactness": "float (the law takes its float path with them)"}
        if res.velocity is not None:
            d = _kinetic_norm(M, np.asarray(res.velocity, dtype=float).reshape(-1) - vm)
            src["kinetic_distance"] = d
            src["kinetic_distance_relative"] = d / _kinetic_norm(M, v)
        else:
            src["kinetic_distance"] = src["kinetic_distance_relative"] = None
        res.details["ratio_source"] = src
        res.notes.append(f"ratios from the elastic {model.law} model (unit stiffness): "
                         f"{', '.join(f'{a:.12g}' for a in alphas)}; eq. 38 solved with these floats")
        return res


class ImpulseRatioFromModel(_RatiosFromModel, ImpulseRatio):
    """The impulse-ratio law (eq. 38), whose ``ratios`` may also be ``"from-hertz"`` etc."""


class EnergeticFromModel(_RatiosFromModel, Energetic):
    """The energetic law (eq. 12), whose ``ratios`` may also be ``"from-hertz"`` etc."""


def register(laws: dict) -> None:
    """Add the compliant and LZB laws to ``laws`` (:data:`impactsym.lawbook.LAWS`) and let the
    impulse-ratio and energetic laws take their ratios from a model."""
    for cls in COMPLIANT_LAWS:
        laws[cls.name] = cls()
    laws["impulse-ratio"] = ImpulseRatioFromModel()
    laws["energetic"] = EnergeticFromModel()


# registered on import (impactsym.lawbook imports this module at its end, whichever is imported first)
register(LAWS)
