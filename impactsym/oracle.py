"""impactsym as a test oracle: compare an observed post-impact velocity with every law
(:func:`check`), fit the impulse-ratio family to it (:func:`fit_impulse_ratios`), and answer
many CLI requests in one process (:func:`run_request`, :func:`run_many`).

Definitions (all in the kinetic metric ``⟨a, b⟩_M = aᵀMb``, CONVENTIONS.md)
---------------------------------------------------------------------------
Let ``v⁻`` be the pre-impact velocity, ``v`` the observed post-impact velocity and
``‖x‖_M = √(xᵀMx)``.

**Distance to a law.** For one outcome ``v_L`` of a law, ``d = ‖v − v_L‖_M / ‖v⁻‖_M`` (relative,
dimensionless). A law with several outcomes (gap-dependent, set-valued) or a selected outcome is
at the distance of its nearest one (the outcomes and the selected outcomes are all candidates).
For exact input the squared distance ``d²`` is computed exactly and ``d`` is reported as the
exact ``sqrt(d²)`` (string) and a float; whether ``d ≤ tolerance`` is decided exactly
(``d² ≤ tolerance²``, a certified sign). A law *matches* when its distance is at most the
tolerance.

**Momentum residual.** ``g = M(v − v⁻)`` is the impulse the observation implies. A law's impulse
lies in the range of ``Hᵀ``; the residual is the part of ``g`` outside it, orthogonal in the
``M⁻¹`` metric (the metric in which impulses are measured, ``⟨g, h⟩_{M⁻¹} = gᵀM⁻¹h``):

    p* = argmin_p ‖g − Hᵀp‖_{M⁻¹}  ⇔  (H M⁻¹ Hᵀ) p* = H (v − v⁻),     r = g − Hᵀp*,

and ``momentum_residual_norm = ‖r‖_{M⁻¹} / ‖v⁻‖_M``. Equivalently ``‖r‖_{M⁻¹} = ‖Δv − M⁻¹Hᵀp*‖_M``:
the kinetic distance from the observed velocity change to the velocity changes any impulse on the
closed contacts can make. ``p*`` is unique when ``H`` has full row rank (else a maximal set of
independent rows is used and the fit is not reported); when ``r = 0``, ``p*`` is *the* impulse of
the observation: ``M(v − v⁻) = Hᵀp*``.

**Energy ratio** ``T(v)/T(v⁻)`` and **contact violations**: every contact ``i`` with ``H_i v < 0``
(decided exactly for exact input; a float observation is read at its exact binary value).

**Impulse-ratio fit** (Acary & Taha eq. 38): ratios ``α_1j = p*_j / p*_1`` and ``e = T(v)/T(v⁻)``,
then eq. 38 is solved again with them (:func:`impactsym.laws.impulse_ratio.impulse_ratio_law`) and
its velocity compared with the observation. When ``r = 0`` the observation's ``p*_1`` is always a
root of the law's quadratic ``A p₁² + B p₁ + C = 0`` (checked exactly); the law picks
``p₁ = (−B + √D)/(2A)``: the fit says whether the observation is that root (``"law-root"``), the
other one (``"other-root"``), or not in the family at all (``"not-in-family"``: non-zero momentum
residual, no impulse on the primary contact, ``e > 1``, …). The fit is reported beside the laws and
does not count as a match (with ``k − 1`` ratios and ``e`` free, the family covers almost every
momentum-consistent state).

Exit status of ``impactsym check`` (:data:`EXIT_MATCH`, :data:`EXIT_NO_MATCH`): 0 when the
observation matches at least one law within the tolerance, 3 when it matches none (a finding, not
an error: the report is still printed), 2 for bad input.

Examples
--------
>>> from impactsym.resolution import System
>>> chain = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
>>> rep = check(chain, "0,0,1", laws=["sequential", "newton"])
>>> rep.matches, rep.laws["newton"]["distance"], rep.exit_status
(['sequential'], 'sqrt(6)/3', 0)
>>> check(chain, "-1/3,2/3,2/3", laws=["sequential"]).exit_status
3
"""

from __future__ import annotations

import contextlib
import io
import json
import sys
import traceback
from dataclasses import dataclass, field
from typing import Any, Iterable

import numpy as np

from .arithmetic import LazyModule
from .errors import DomainError, ImpactError, ImpactInputError
from .resolution import System, number_json, vector_json

# SymPy, mpmath and the number parser, imported on first use: `impactsym batch` answers a float-path
# request (a compliant law on plain rational matrices) without them
sp = LazyModule("sympy", globals(), "sp")
mpmath = LazyModule("mpmath", globals(), "mpmath")
_numbers = LazyModule("impactsym.numbers", globals(), "_numbers")

__all__ = ["check", "CheckReport", "kinetic_distance", "momentum_residual", "fit_impulse_ratios",
           "run_request", "run_many", "request_argv", "EXIT_MATCH", "EXIT_NO_MATCH", "DEFAULT_TOLERANCE",
           "CHECK_SCHEMA", "BATCH_SCHEMA"]

#: exit status of ``impactsym check``: the observation matches at least one law
EXIT_MATCH = 0
#: exit status of ``impactsym check``: it matches none (a finding; the report is still printed)
EXIT_NO_MATCH = 3
#: default relative tolerance on the kinetic-metric distance ``‖v − v_L‖_M / ‖v⁻‖_M``
DEFAULT_TOLERANCE = "1e-3"
#: the schema of :meth:`CheckReport.as_json`
CHECK_SCHEMA = "impactsym.check/1"
#: the schema of one answer line of ``impactsym batch``
BATCH_SCHEMA = "impactsym.batch/1"


# ------------------------------------------------------------------------------ arithmetic
def _simplify(x):
    """A canonical form of an exact scalar: rationals stay, algebraic numbers are expanded and
    their denominators rationalized."""
    if isinstance(x, sp.Rational):  # what expand returns for a rational: the number itself
        return x
    x = sp.expand(x)
    if x.is_Rational or _rational_surd(x):
        return x
    return sp.radsimp(x)


def _rational_surd(x) -> bool:
    """Whether ``x`` is ``q·√m`` (``q`` rational, ``m > 1`` an integer), SymPy's own form of a
    rational times the square root of a rational (``sqrt(8/3)`` is ``2*sqrt(6)/3``): its
    denominator is rational, so ``radsimp`` returns it unchanged, after a millisecond's search
    (a distance ``sqrt(d²)`` of every outcome of every law; tests/test_check.py checks the forms)."""
    if not isinstance(x, sp.Expr):
        return False
    coeff, rest = x.as_coeff_Mul()
    return bool(coeff.is_Rational and rest.is_Pow and rest.exp is sp.S.Half and rest.base.is_Integer
                and rest.base.p > 1)


def _is_zero(x) -> bool:
    from .exact import certified_sign

    x = _simplify(x)
    if x.is_Rational:
        return x == 0
    return certified_sign(x) == 0


def _sign(x) -> int:
    from .exact import certified_sign

    return certified_sign(_simplify(x))


def _exact_vector(values, argument: str, n: int) -> sp.Matrix:
    """An exact column from text ``"a,b"``, a sequence (floats at their binary value) or a matrix."""
    if isinstance(values, str):
        v = _numbers.parse_vector(values, argument)
    elif isinstance(values, sp.MatrixBase):
        v = sp.Matrix([_numbers.to_exact(x, argument) for x in values])
    else:
        try:
            items = list(np.asarray(values, dtype=object).reshape(-1))
        except (TypeError, ValueError):
            raise ImpactInputError(argument, f"must be a vector of numbers, got {values!r}") from None
        for x in items:
            if isinstance(x, (float, np.floating)) and not np.isfinite(x):
                raise ImpactInputError(argument, f"entry {x} is not finite (NaN or inf)")
        v = sp.Matrix([_numbers.to_exact(x, argument) for x in items])
    if v.rows != n:
        raise ImpactInputError(argument, f"has length {v.rows}, expected {n} (one per coordinate of the system)")
    return v


def _exact_system(system: System) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """``M``, ``H``, ``v⁻`` exactly (a float system at its binary values)."""
    from .numbers import to_exact_matrix

    if system.exact:
        return sp.Matrix(system.M), sp.Matrix(system.H), sp.Matrix(system.v)
    return (to_exact_matrix(np.asarray(system.M, dtype=float), "mass_matrix"),
            to_exact_matrix(np.asarray(system.H, dtype=float), "gradients"),
            to_exact_matrix(np.asarray(system.v, dtype=float).reshape(-1), "velocity", vector=True))


def _quad(M, x) -> Any:
    return _simplify((x.T * M * x)[0, 0])


def kinetic_distance(system: System, a, b) -> dict:
    """The relative kinetic-metric distance ``‖a − b‖_M / ‖v⁻‖_M`` between two velocities.

    Exact (``exact: true``, ``distance`` the exact ``sqrt(d²)``) when the system and both
    velocities are exact; otherwise evaluated with mpmath at 30 digits from the given values
    (``exact: false``; certified or float outcomes of a law).

    >>> s = System.from_matrices("2,0;0,1", "-1,1", "1,0")
    >>> kinetic_distance(s, sp.Matrix([0, 1]), sp.Matrix([1, 0]))["distance"]
    'sqrt(6)/2'
    """
    M, _, v = _exact_system(system)
    return _kinetic_distance(M, _quad(M, v), a, b)


def _kinetic_distance(M, denom, a, b, scratch: dict | None = None) -> dict:
    """:func:`kinetic_distance` given the exact ``M`` and ``denom = ‖v⁻‖²_M`` (:func:`check` reads
    them once for every outcome of every law, and passes one ``scratch`` dict, which keeps their
    30-digit mpmath values for the next inexact outcome)."""
    if denom == 0:
        raise ImpactInputError("velocity", "is zero: the relative distance ||v - v_law||_M / ||v-||_M is undefined")
    if isinstance(a, sp.MatrixBase) and isinstance(b, sp.MatrixBase):
        d2 = _simplify(_quad(M, sp.Matrix(a) - sp.Matrix(b)) / denom)
        d = _simplify(sp.sqrt(d2))
        return {"exact": True, "distance_squared": d2, **number_json("distance", d)}
    with mpmath.workdps(30):
        def mp(vec):
            if isinstance(vec, sp.MatrixBase):
                return [mpmath.mpf(sp.N(x, 40)) for x in vec]
            if isinstance(vec, mpmath.matrix):
                return [vec[i] for i in range(vec.rows)]
            return [mpmath.mpf(float(x)) for x in np.asarray(vec, dtype=float).reshape(-1)]

        got = scratch.get("mpf") if scratch is not None else None
        if got is None:  # M and denom at 30 digits (from 40), as every inexact outcome reads them
            got = ([[mpmath.mpf(sp.N(M[i, j], 40)) for j in range(M.cols)] for i in range(M.rows)],
                   mpmath.mpf(sp.N(denom, 40)))
            if scratch is not None:
                scratch["mpf"] = got
        Mm, dm = got
        diff = [x - y for x, y in zip(mp(a), mp(b))]
        q = mpmath.fsum(diff[i] * Mm[i][j] * diff[j] for i in range(len(diff)) for j in range(len(diff)))
        d = mpmath.sqrt(q / dm)
        return {"exact": False, "distance_squared": None, "distance": mpmath.nstr(d, 17), "distance_float": float(d)}


def _independent_rows(H: sp.Matrix) -> list[int]:
    _, pivots = H.T.rref(simplify=True)
    return list(pivots)


def momentum_residual(system: System, observed) -> dict:
    """The part of the observed impulse ``g = M(v − v⁻)`` outside the range of ``Hᵀ``, in the
    ``M⁻¹`` metric (module docstring): ``p*``, ``r = g − Hᵀp*``, ``‖r‖_{M⁻¹}/‖v⁻‖_M``.

    Returns a dict with the exact ``impulses`` ``p*`` (None when ``H`` has dependent rows),
    ``residual`` ``r``, ``norm`` (exact), ``zero`` (decided exactly) and ``full_row_rank``.

    >>> s = System.from_matrices("1,0;0,1", "-1,1", "1,0")
    >>> m = momentum_residual(s, sp.Matrix([0, 1]))
    >>> m["impulses"].T, m["zero"]
    (Matrix([[1]]), True)
    >>> momentum_residual(s, sp.Matrix([0, 0]))["norm"]
    sqrt(2)/2
    """
    M, H, v = _exact_system(system)
    vo = _exact_vector(observed, "observed", M.rows)
    rows = _independent_rows(H)
    full = len(rows) == H.rows
    Hr = H.extract(rows, list(range(H.cols)))
    Minv = M.inv()
    W = Hr * Minv * Hr.T
    dv = vo - v
    p_r = W.LUsolve(Hr * dv).applyfunc(_simplify)
    g = M * dv
    r = (g - Hr.T * p_r).applyfunc(_simplify)
    norm2 = _simplify((r.T * Minv * r)[0, 0] / _quad(M, v))
    return {"impulses": p_r if full else None, "residual": r, "norm": _simplify(sp.sqrt(norm2)),
            "zero": all(_is_zero(x) for x in r), "full_row_rank": full}


# ------------------------------------------------------------------------------ the fit
def fit_impulse_ratios(system: System, observed, *, tolerance=None, residual: dict | None = None) -> dict:
    """Fit the impulse-ratio family (Acary & Taha eq. 38) to an observed velocity (module
    docstring): the ratios ``α_1j = p*_j/p*_1``, ``e = T(v)/T(v⁻)``, the law re-solved with them,
    and whether the observation is the law's root, the other root, or not in the family.

    Returns a JSON-ready dict (``status``, ``reason``, ``ratios``, ``restitution``, ``velocity``
    of the re-solved law, ``distance`` to it, ``valid`` and ``violations`` of the re-solved law).

    >>> chain = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
    >>> f = fit_impulse_ratios(chain, "-1/3,2/3,2/3")
    >>> f["status"], f["ratios"], f["restitution"]
    ('law-root', ['1/2'], '1')
    """
    from .laws.impulse_ratio import impulse_ratio_law

    M, H, v = _exact_system(system)
    vo = _exact_vector(observed, "observed", M.rows)
    res = residual or momentum_residual(system, vo)
    out: dict = {"family": "impulse-ratio (Acary & Taha eq. 38)", "status": "not-fitted", "reason": None,
                 "ratios": None, "ratios_float": None, "restitution": None, "restitution_float": None,
                 "velocity": None, "velocity_float": None, "distance": None, "distance_float": None,
                 "within_tolerance": False, "membership": None, "valid": None, "violations": []}
    if not res["full_row_rank"]:
        out["reason"] = "the gradient rows are dependent: the impulses of the observation are not determined"
        return out
    p = res["impulses"]
    out.update(vector_json("impulses", p))
    if _is_zero(p[0]):
        out["status"] = "not-in-family"
        out["reason"] = ("no impulse at all (the observation is v-, up to the momentum residual)"
                         if all(_is_zero(x) for x in p) else
                         "the primary contact (row 1 of H) carries no impulse: the ratios p_j/p_1 are undefined")
        return out
    ratios = [_simplify(p[j] / p[0]) for j in range(1, p.rows)]
    T0 = _quad(M, v) / 2
    e = _simplify(_quad(M, vo) / 2 / T0)
    out.update(vector_json("ratios", sp.Matrix(ratios)) if ratios else {"ratios": [], "ratios_float": []})
    out.update(number_json("restitution", e))
    residual_reason = ("the momentum residual is not zero: M(v - v-) is not in the range of H^T, so no impulse "
                       "on the closed contacts gives the observation; the ratios and e above are the least-squares "
                       "fit (M^-1 metric)")
    near = res["zero"] or (tolerance is not None and _sign(sp.sympify(tolerance) ** 2 - res["norm"] ** 2) >= 0)
    if _sign(e - 1) > 0:
        out["status"] = "not-in-family"
        shown = _numbers.exact_str(e) if len(_numbers.exact_str(e)) <= 24 else f"{float(sp.N(e, 17)):.9g}"
        gain = f"the observation gains energy (e = T+/T- = {shown} > 1); the law takes e in [0, 1]"
        out["reason"] = gain if near else f"{residual_reason}; and {gain}"
        return out
    try:
        law = impulse_ratio_law(M, H, v, e, ratios, allow_invalid=True)
    except (ImpactInputError, DomainError) as exc:
        out["status"] = "not-in-family"
        out["reason"] = (residual_reason + "; " if not res["zero"] else "") + \
            f"eq. 38 with the fitted ratios and e cannot be solved: {exc}"
        return out
    out["valid"] = law.valid
    out["violations"] = [x.as_dict() for x in law.violations]
    if law.velocity is None:
        out["status"] = "not-in-family"
        out["reason"] = (residual_reason + "; " if not res["zero"] else "") + \
            "eq. 38 with the fitted ratios and e has no real solution"
        return out
    out.update(vector_json("velocity", law.velocity))
    dist = kinetic_distance(system, vo, sp.Matrix(law.velocity))
    out["distance"], out["distance_float"] = dist["distance"], dist["distance_float"]
    if tolerance is not None:
        out["within_tolerance"] = _sign(sp.sympify(tolerance) ** 2 - dist["distance_squared"]) >= 0
    A, B, C = law.coefficients
    if not res["zero"]:
        if not near:
            out["status"] = "not-in-family"
            out["reason"] = residual_reason + "; 'distance' is to the law with them"
            return out
        # a float observation (an engine's) is never exactly momentum-consistent: within the tolerance,
        # say which root it is nearest to
        out["membership"] = "within-tolerance"
        plus = law.impulses[0]
        minus = _simplify(C / (A * plus)) if not _is_zero(plus) else sp.Integer(0)  # product of the roots: C/A
        if out["within_tolerance"]:
            out["status"] = "law-root"
            out["reason"] = ("within the tolerance (momentum residual and distance at most the tolerance): the "
                             "observation is the law's solution with these ratios and e")
        elif _sign(abs(p[0] - minus) - abs(p[0] - plus)) < 0:
            out["status"] = "other-root"
            out["reason"] = (f"within the tolerance of momentum, the observation's p_1 = {sp.N(p[0], 6)} is nearer the "
                             f"other root {sp.N(minus, 6)} of eq. 38 than the law's {sp.N(plus, 6)}")
        else:
            out["status"] = "not-in-family"
            out["reason"] = "the law with the fitted ratios and e is farther from the observation than the tolerance"
        return out
    out["membership"] = "exact"
    root = _simplify(A * p[0] ** 2 + B * p[0] + C)
    if not _is_zero(root):  # pragma: no cover - an identity (module docstring); a failure is a bug
        from .errors import VerificationError

        raise VerificationError("impulse-ratio fit", f"p*_1 = {p[0]} is not a root of eq. 38 (residual {root})")
    if all(_is_zero(x) for x in sp.Matrix(law.velocity) - vo):
        out["status"] = "law-root"
        out["reason"] = "the observation is the law's solution with these ratios and e (p_1 = (-B + sqrt(D))/(2A))"
    else:
        out["status"] = "other-root"
        out["reason"] = (f"the observation is the other root p_1 = (-B - sqrt(D))/(2A) = "
                         f"{_numbers.exact_str(p[0])} of eq. 38 with these ratios and e; the law picks p_1 = "
                         f"{_numbers.exact_str(law.impulses[0])}")
    return out


# ------------------------------------------------------------------------------ check
@dataclass
class CheckReport:
    """What :func:`check` finds (JSON form: :meth:`as_json`, schema :data:`CHECK_SCHEMA`).

    Attributes
    ----------
    system : the :class:`~impactsym.resolution.System` checked against
    observed : the observed velocity (exact SymPy column; a float at its binary value)
    tolerance : the relative tolerance (exact)
    laws : law -> JSON-ready dict (distance, nearest outcome, match) or ``{"refused": reason}``
    matches : the laws within the tolerance, in the order of ``impactsym.lawbook.LAWS``
    """

    system: System
    observed: Any
    tolerance: Any
    laws: dict
    matches: list
    momentum: dict
    energy_ratio: Any
    contact_velocity: Any
    violations: list
    fit: dict
    observed_exactness: str = "exact"
    notes: list = field(default_factory=list)

    @property
    def exit_status(self) -> int:
        return EXIT_MATCH if self.matches else EXIT_NO_MATCH

    def as_json(self) -> dict:
        out: dict = {"schema": CHECK_SCHEMA, "scene": self.system.scene, "system": self.system.as_json()}
        out.update(vector_json("observed", self.observed))
        out["observed_exactness"] = self.observed_exactness
        out.update(number_json("tolerance", self.tolerance))
        out["matches"] = list(self.matches)
        out["exit_status"] = self.exit_status
        out["laws"] = self.laws
        m = self.momentum
        out["momentum"] = {**vector_json("residual", m["residual"]), **number_json("residual_norm", m["norm"]),
                           "residual_zero": m["zero"], "full_row_rank": m["full_row_rank"],
                           **vector_json("impulses", m["impulses"]),
                           "definition": "r = M(v - v-) - H^T p*, (H M^-1 H^T) p* = H (v - v-); "
                                         "residual_norm = sqrt(r^T M^-1 r) / ||v-||_M"}
        out.update(number_json("energy_ratio", self.energy_ratio))
        out.update(vector_json("contact_velocity", self.contact_velocity))
        out["contact_violations"] = self.violations
        out["impulse_ratio_fit"] = self.fit
        out["notes"] = list(self.notes)
        return out


def _tolerance(value) -> sp.Expr:
    if isinstance(value, (float, np.floating)):
        if not np.isfinite(value):
            raise ImpactInputError("tolerance", f"must be a finite number, got {value}")
    tol = _numbers.to_exact(value, "tolerance") if not isinstance(value, sp.Basic) else sp.sympify(value)
    if not tol.is_real or _sign(tol) < 0:
        raise ImpactInputError("tolerance", f"must be a non-negative number, got {value}")
    return tol


def _law_entry(M, denom, res, vo, tol, scratch: dict | None = None) -> dict:
    candidates = [("outcome", i, o) for i, o in enumerate(res.outcomes)] + \
                 [("selected", i, o) for i, o in enumerate(res.selected)]
    rows = []
    for kind, i, o in candidates:
        if o.velocity is None:
            continue
        d = _kinetic_distance(M, denom, vo, o.velocity, scratch)
        rows.append((kind, i, o, d))
    entry: dict = {"uniqueness": res.uniqueness, "exactness": res.exactness, "outcomes": len(res.outcomes),
                   "selected": len(res.selected)}
    if not rows:
        entry.update({"distance": None, "distance_float": None, "distance_exact": None, "nearest": None,
                      "distances": [], "match": False})
        return entry
    best = rows[0]
    for row in rows[1:]:
        if row[3]["exact"] and best[3]["exact"]:
            if _sign(row[3]["distance_squared"] - best[3]["distance_squared"]) < 0:
                best = row
        elif row[3]["distance_float"] < best[3]["distance_float"]:
            best = row
    kind, i, o, d = best
    if d["exact"]:
        match = _sign(tol ** 2 - d["distance_squared"]) >= 0
    else:  # certified or float outcome: decided on 30 digits
        match = mpmath.mpf(d["distance"]) <= mpmath.mpf(sp.N(tol, 30))
    entry.update({"distance": d["distance"], "distance_float": d["distance_float"], "distance_exact": d["exact"],
                  "nearest": {"kind": kind, "index": i, "order": o.order, **vector_json("velocity", o.velocity, o.digits)},
                  "distances": [{"kind": k, "index": j, "distance": dd["distance"], "distance_float": dd["distance_float"]}
                                for k, j, _, dd in rows],
                  "match": bool(match)})
    return entry


def check(system: System, observed, *, tolerance=DEFAULT_TOLERANCE, laws: Iterable[str] | None = None,
          options: dict | None = None) -> CheckReport:
    """Check an observed post-impact velocity against every law (module docstring).

    Parameters
    ----------
    system : :class:`~impactsym.resolution.System`
    observed : the observed post-impact velocity: ``"v1,v2,…"`` (exact), a sequence or a SymPy
        column; floats are read at their exact binary value
    tolerance : relative kinetic-metric tolerance (default ``1e-3``, read exactly), ``≥ 0``
    laws : law names (default every law of :data:`impactsym.lawbook.LAWS`)
    options : law name -> that law's options (``{"impulse-ratio": {"ratios": ["1/2"]}}``)

    Returns
    -------
    CheckReport
        ``exit_status`` is 0 when at least one law matches, 3 when none does.

    Raises
    ------
    ImpactInputError
        Observed of the wrong length, NaN or inf; a negative tolerance; an unknown law; ``v⁻ = 0``.
    """
    from .lawbook import get_law, resolve_all

    tol = _tolerance(tolerance)
    names = list(laws) if laws is not None else None
    for name in names or []:
        get_law(name)
    observed_exactness = "exact"
    if not isinstance(observed, (str, sp.MatrixBase)):
        items = list(np.asarray(observed, dtype=object).reshape(-1))
        if any(isinstance(x, (float, np.floating)) for x in items):
            observed_exactness = "float (read at its exact binary value)"
    M, H, v = _exact_system(system)
    vo = _exact_vector(observed, "observed", M.rows)
    denom = _quad(M, v)
    if denom == 0:
        raise ImpactInputError("velocity", "is zero: there is no impact to check against")
    results = resolve_all(system, laws=names, options=options or {})
    entries, matches = {}, []
    scratch: dict = {}  # M and denom in mpmath, read once for every inexact outcome of this check
    for name, res in results.items():
        if isinstance(res, str):
            entries[name] = {"refused": res, "match": False}
            continue
        entries[name] = _law_entry(M, denom, res, vo, tol, scratch)
        if entries[name]["match"]:
            matches.append(name)
    mom = momentum_residual(system, vo)
    energy = _simplify(_quad(M, vo) / denom)
    w = (H * vo).applyfunc(_simplify)
    names_c = list(system.contacts)
    violations = [{"contact": names_c[i], "index": i, "condition": "penetration",
                   **number_json("relative_velocity", w[i]),
                   "message": f"contact {names_c[i]}: H v = {_numbers.exact_str(w[i])} < 0 (the bodies still approach)"}
                  for i in range(w.rows) if _sign(w[i]) < 0]
    fit = fit_impulse_ratios(system, vo, tolerance=tol, residual=mom)
    notes = []
    if not system.exact:
        notes.append("the system is given in floats: its matrices are read at their exact binary values")
    return CheckReport(system, vo, tol, entries, matches, mom, energy, w, violations, fit,
                       observed_exactness=observed_exactness, notes=notes)


# ------------------------------------------------------------------------------ batch
_PARSER = None


def _parser():
    global _PARSER
    if _PARSER is None:
        from .cli import build_parser

        _PARSER = build_parser()
    return _PARSER


def request_argv(request: Any) -> list[str]:
    """The command line of one batch request.

    Two forms (``impactsym batch --help``):

    * ``{"argv": ["resolve", "--law", "newton", "--scene", "chain3"]}``: the subcommand and its
      arguments exactly as on the command line;
    * ``{"command": "resolve", "args": {"law": "newton", "scene": "chain3"}}``: option names with
      ``_`` or ``-``, values as strings or numbers; ``true`` gives a flag, ``false``/``null`` omit
      it; a list of strings is a positional argument list under the key ``"_"``.

    ``--json`` is implied. An optional ``"id"`` is echoed in the answer.

    >>> request_argv({"command": "resolve", "args": {"law": "newton", "scene": "chain3", "allow_invalid": True}})
    ['resolve', '--law=newton', '--scene=chain3', '--allow-invalid', '--json']
    """
    if not isinstance(request, dict):
        raise ImpactInputError("request", f"must be a JSON object, got {type(request).__name__}")
    unknown = sorted(set(request) - {"argv", "command", "args", "id"})
    if unknown:
        raise ImpactInputError("request", f"unknown key(s) {', '.join(unknown)}; a request has argv, or command and "
                               "args, and optionally id")
    if "argv" in request:
        if "command" in request or "args" in request:
            raise ImpactInputError("request", "give either argv, or command and args, not both")
        argv = request["argv"]
        if not isinstance(argv, list) or not argv or not all(isinstance(x, str) for x in argv):
            raise ImpactInputError("argv", "must be a non-empty list of strings (the subcommand first)")
        argv = list(argv)
    elif "command" in request:
        cmd = request["command"]
        if not isinstance(cmd, str):
            raise ImpactInputError("command", "must be a subcommand name (a string)")
        args = request.get("args", {})
        if not isinstance(args, dict):
            raise ImpactInputError("args", "must be a JSON object of option -> value")
        argv = [cmd]
        for key, val in args.items():
            if key == "_":
                if not isinstance(val, list) or not all(isinstance(x, (str, int)) for x in val):
                    raise ImpactInputError("args", "'_' must be a list of positional arguments")
                argv += [str(x) for x in val]
                continue
            opt = "--" + key.replace("_", "-")
            if val is True:
                argv.append(opt)
            elif val is False or val is None:
                continue
            elif isinstance(val, (str, int, float)):
                argv.append(f"{opt}={val}")
            elif isinstance(val, list) and all(isinstance(x, (str, int, float)) for x in val):
                argv.append(f"{opt}={','.join(str(x) for x in val)}")
            else:
                raise ImpactInputError("args", f"value of {key!r} must be a string, number, boolean or list of numbers")
    else:
        raise ImpactInputError("request", "needs argv, or command (with args)")
    if argv[0] == "batch":
        raise ImpactInputError("command", "batch cannot be nested in a batch")
    if "--json" not in argv:
        argv.append("--json")
    return argv


def _answer(request_id, status: int, *, result=None, error=None) -> dict:
    out = {"schema": BATCH_SCHEMA}
    if request_id is not None:
        out["id"] = request_id
    out["exit_status"] = status
    if error is not None:
        out["error"] = error
    else:
        out["result"] = result
    return out


def run_request(request: Any) -> dict:
    """Answer one request in this process, as ``impactsym`` would with ``--json``.

    Returns ``{"schema", "id"?, "exit_status", "result": <the subcommand's JSON object>}``, or
    ``{"schema", "id"?, "exit_status": 2, "error": {"argument", "message"}}`` for a bad request
    (exit status 1 and the traceback's last line for a bug). Never raises for a bad request.

    >>> a = run_request({"argv": ["resolve", "--law", "newton", "--scene", "chain3"], "id": 7})
    >>> a["id"], a["exit_status"], a["result"]["velocity"]
    (7, 0, ['-1/3', '2/3', '2/3'])
    >>> run_request({"argv": ["resolve", "--law", "nope", "--scene", "chain3"]})["error"]["argument"]
    'law'
    """
    from .cli import UsageError, _TimeLimit, _timeout_seconds, error_argument, join_negative_values

    rid = request.get("id") if isinstance(request, dict) else None
    try:
        argv = join_negative_values(request_argv(request))
    except ImpactError as exc:
        return _answer(rid, 2, error={"argument": error_argument(exc), "message": str(exc)})
    parser = _parser()
    sink = io.StringIO()
    try:
        with contextlib.redirect_stderr(sink), contextlib.redirect_stdout(sink):
            args = parser.parse_args(argv)
    except UsageError as exc:
        return _answer(rid, 2, error={"argument": exc.argument, "message": exc.message})
    except SystemExit:  # --help, --version: nothing to answer in JSON
        return _answer(rid, 2, error={"argument": None, "message": "--help and --version have no JSON answer"})
    old_limit = sys.get_int_max_str_digits() if hasattr(sys, "get_int_max_str_digits") else None
    if old_limit is not None:
        sys.set_int_max_str_digits(0)
    try:
        with _TimeLimit(_timeout_seconds(args.timeout)):
            result = args.func(args)
        status = 0
        if isinstance(result, tuple):
            result, status = result
        from .cli.common import strict_json

        return _answer(rid, status, result=strict_json(result))
    except ImpactError as exc:
        return _answer(rid, 2, error={"argument": error_argument(exc), "message": str(exc)})
    except Exception as exc:  # a bug: reported on its line, the batch goes on
        last = traceback.format_exception_only(type(exc), exc)[-1].strip()
        return _answer(rid, 1, error={"argument": None, "message": f"internal error (a bug in impactsym): {last}"})
    finally:
        if old_limit is not None:
            sys.set_int_max_str_digits(old_limit)


def run_many(requests: Iterable[Any]) -> list[dict]:
    """Answer many requests in one process (:func:`run_request` for each, in order).

    >>> answers = run_many([{"argv": ["resolve", "--law", "newton", "--scene", "chain3"]},
    ...                     {"command": "check", "args": {"scene": "chain3", "observed": "0,0,1"}},
    ...                     {"argv": ["resolve"]}])
    >>> [a["exit_status"] for a in answers], answers[1]["result"]["matches"][:2]
    ([0, 0, 2], ['sequential', 'two-surface'])
    """
    return [run_request(r) for r in requests]


def parse_request_line(line: str) -> Any:
    """One JSON Lines request; a malformed line raises :class:`ImpactInputError` naming it."""
    try:
        return json.loads(line)
    except json.JSONDecodeError as exc:
        raise ImpactInputError("input", f"the line is not JSON: {exc.msg} at column {exc.colno}") from None


def iter_answers(lines: Iterable[str]) -> Iterable[dict]:
    """Answers to JSON Lines requests (blank lines skipped), one per request line, in order."""
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            request = parse_request_line(line)
        except ImpactInputError as exc:
            yield {**_answer(None, 2, error={"argument": "input", "message": str(exc)}), "line": number}
            continue
        answer = run_request(request)
        answer["line"] = number
        yield answer

