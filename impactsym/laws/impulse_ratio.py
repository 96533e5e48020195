"""The impulse-ratio law of Acary & Taha (eq. 38) for any Lagrangian system.

Given ``M`` (SPD), the gradient rows ``H`` of the closed contacts (row 1 is the primary
contact), the pre-impact velocity ``v⁻``, the global energetic coefficient ``e`` (``T⁺ = e T⁻``,
eq. 12 read with ½ on both sides, ``CONVENTIONS.md``) and the ratios ``α_1j = p_j / p_1``, the
impulse is ``p = p₁ a`` with ``a = (1, α₁₂, …, α₁k)``, the post-impact velocity
``v⁺ = v⁻ + p₁ M⁻¹Hᵀa``, and the energy balance is the quadratic (derived and proved for every
dimension in :mod:`derivations.impulse_ratio`)

    A p₁² + B p₁ + C = 0,   A = ½ aᵀHM⁻¹Hᵀa,   B = aᵀHv⁻,   C = (1 − e) T⁻,   D = B² − 4AC.

The physical root is ``p₁ = (−B + √D)/(2A)`` (:func:`derivations.impulse_ratio.physical_root_proof`),
evaluated in floats by the generated kernel ``impactsym.kernels.impulse_ratio_root`` (the stable
form of :mod:`derivations.impulse_ratio_root`: ``q/A``, ``q = (−B + √D)/2``, when ``B < 0``, and
``−2C/(B + √D)`` otherwise). The exact and float paths restate ``A``, ``B``, ``C`` in their own
arithmetic (fmpq, SymPy, float); ``tests/test_impulse_ratio_formula.py`` evaluates them against
:func:`derivations.impulse_ratio.general_quadratic` at random rationals.

**Δ.** :attr:`ImpulseRatioResult.delta` is ``D`` itself, in the units of ``B²``. The paper's Δ
(eqs. 18, 27) is ``D`` normalized by ``B²`` (``delta_normalized``): its scenes have ``B = −1``
(unit approach speed along ``a``; e.g. the unit-speed chain3 has ``B = −1``, ``A = 1 − α + α²``),
so there the two coincide and ``p₁ = (1 + √Δ)/(2A)`` as printed.

**Validity.** The result is valid when all of these hold, each decided exactly (rational
arithmetic, also for float input at its binary value; certified signs for irrational input):

* ``D ≥ 0`` (else there is no real solution: condition ``negative-discriminant``);
* ``B < 0``, the contacts approach along ``a`` (``no-approach``);
* ``p_j ≥ 0`` for every contact (``negative-impulse``);
* ``H_j v⁺ ≥ 0`` for every closed contact (``penetration``).

A result outside the domain raises :class:`~impactsym.errors.DomainError` naming every violated
condition, unless ``allow_invalid=True``; then it is returned with ``valid=False`` and the list.

**No impact.** When ``B > 0`` (leaving along ``a``) and ``e = 1``, the ``+`` root is ``p₁ = 0`` and
``v⁺ = v⁻``: this is what the paper's ``ε = sign(cos τ)`` device in eqs. 35–36 encodes (at
``ε = −1`` they reduce to ``v⁺ = v⁻``). It is still reported as ``no-approach`` (there is no
impact to resolve); for ``e < 1`` and ``B > 0`` the root is negative and ``negative-impulse`` is
reported too.

Examples
--------
The 3-ball chain of sec. 3.3 with ``e = 1`` and ``α = 1`` (the solution ``[0, 0, 1]`` the paper
says is encompassed):

>>> r = impulse_ratio_law("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", 1, ["1"])
>>> r.impulses.T, r.velocity.T, r.delta, r.valid
(Matrix([[1, 1]]), Matrix([[0, 0, 1]]), 1, True)

Floats take the float path; the validity is still decided exactly:

>>> r = impulse_ratio_law([[1.0, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1.0, 0, 0], 1.0, [0.95])
>>> [round(float(x), 4) for x in r.velocity]   # the paper prints [-0.05, 0.05, 0.99]
[-0.0499, 0.0525, 0.9974]

Outside the domain: with α = 1/4 ball 3 is pushed too little and ball 2 runs into it:

>>> impulse_ratio_law("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", 1, ["1/4"])
Traceback (most recent call last):
...
impactsym.errors.DomainError: impulse-ratio law outside its domain: penetration: contact 2 has H_2 v+ = -8/13 < 0

References
----------
Acary & Taha, eqs. 7, 8, 12, 17, 18, 26, 27, 38.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, Sequence

import math

import numpy as np
import sympy as sp

from .. import kernels
from .._lazy import Later as _Later
from ..errors import DomainError, ImpactInputError
from ..mechanics import check_gradients, check_mass_matrix, check_velocity
from ..numbers import exact_str, is_exact, to_exact
from .coupling import apply_coupling
from .delassus import exact_data, sign_of, sign_surd, tidy, to_sympy_matrix, to_sympy_rational
from .reflection import check_restitution

__all__ = ["Violation", "ImpulseRatioResult", "impulse_ratio_law", "VIOLATION_CONDITIONS"]

#: the conditions a result can violate, in the order they are checked
VIOLATION_CONDITIONS = ("negative-discriminant", "no-approach", "negative-impulse", "penetration")


class _Resolved:
    """Mixin: an attribute holding a :class:`_Later` (:class:`impactsym._lazy.Later`: a canonical
    exact form, :func:`tidy` of values already decided, that a caller reading only the verdict never
    pays for) is computed and stored on first read, so every reader (attribute, ``repr``, ``==``,
    ``dataclasses.fields``) sees the value."""

    def __getattribute__(self, name):
        value = object.__getattribute__(self, name)
        if type(value) is _Later:
            value = value()
            object.__setattr__(self, name, value)
        return value


@dataclass
class Violation(_Resolved):
    """One violated condition: ``condition`` (one of :data:`VIOLATION_CONDITIONS` or a law's own
    code), a readable ``message``, and the contact it concerns (1-based) when there is one."""

    condition: str
    message: str
    contact: int | None = None

    def as_dict(self) -> dict:
        return {"condition": self.condition, "message": self.message, "contact": self.contact}


@dataclass
class ImpulseRatioResult(_Resolved):
    """The solution of eq. 38 and its validity.

    Attributes
    ----------
    impulses : ``p`` (k), or ``None`` when ``D < 0`` (no real solution)
    velocity : ``v⁺`` (n), or ``None`` when ``D < 0``
    delta : ``D = B² − 4AC`` (see the module docstring for the paper's normalized Δ)
    delta_normalized : ``D / B²`` (the paper's Δ), ``None`` when ``B = 0``
    coefficients : ``(A, B, C)``
    ratios : ``a = (1, α₁₂, …)`` as used (after the coupling criteria, if applied)
    exact : whether the numbers are exact (SymPy) or floats
    valid : no condition violated
    violations : every violated condition
    coupling : the notes of :func:`impactsym.laws.coupling.apply_coupling` (ratios it set to 0)
    """

    impulses: Any
    velocity: Any
    delta: Any
    delta_normalized: Any
    coefficients: tuple
    ratios: list
    exact: bool
    valid: bool
    violations: list = field(default_factory=list)
    coupling: list = field(default_factory=list)

    @property
    def real_solution(self) -> bool:
        """Whether the quadratic has a real root (``D ≥ 0``)."""
        return self.impulses is not None


def _ratio_vector(ratios, k: int, exact: bool):
    if ratios is None:
        ratios = []
    if isinstance(ratios, str):
        ratios = [x for x in ratios.split(",") if x.strip()] if ratios.strip() else []
    ratios = list(ratios)
    if len(ratios) != k - 1:
        raise ImpactInputError("ratios", f"expected {k - 1} ratio(s) alpha_12, ..., alpha_1{k} for {k} closed contacts, got {len(ratios)}")
    if exact:
        return [sp.Integer(1)] + [to_exact(x, "ratios") for x in ratios]
    out = [1.0]
    for x in ratios:
        xf = float(to_exact(x, "ratios").evalf(17)) if isinstance(x, str) else float(x)
        if not np.isfinite(xf):
            raise ImpactInputError("ratios", f"must be finite real numbers, got {xf}")
        out.append(xf)
    return out


def impulse_ratio_law(mass_matrix, gradients, velocity, restitution=1, ratios: Sequence | None = None, *,
                      allow_invalid: bool = False, coupling: bool = False) -> ImpulseRatioResult:
    """Solve the impulse-ratio law (eq. 38): ``M Δv = Hᵀp``, ``p = p₁(1, α₁₂, …)``, ``T⁺ = e T⁻``.

    Parameters
    ----------
    mass_matrix : matrix-like (n×n), symmetric positive definite
    gradients : matrix-like (k×n), the gradient rows of the closed contacts; row 1 is primary
    velocity : vector-like (n), the pre-impact velocity ``v⁻``
    restitution : the global energetic coefficient ``e ∈ [0, 1]`` (``T⁺ = e T⁻``)
    ratios : the ``k−1`` ratios ``α_1j = p_j/p_1`` (numbers, numeric text, or floats)
    allow_invalid : return a result outside the law's domain instead of raising
    coupling : apply the sec. 5 criteria first (:func:`impactsym.laws.coupling.apply_coupling`):
        ratios of contacts that cannot receive impulse are set to 0 and reported; those ratios
        need not be given

    Returns
    -------
    ImpulseRatioResult
        Exact (SymPy) for exact input, floats (NumPy) for float input.

    Raises
    ------
    ImpactInputError
        Malformed input (shapes, NaN, non-SPD ``M``, zero gradient row, wrong number of ratios).
    DomainError
        ``e`` outside [0, 1]; ``Hᵀa = 0`` (the ratios give no velocity change; never solvable);
        and, unless ``allow_invalid``, any violated condition (all of them are named).

    Examples
    --------
    Sec. 3.3, e = 1, α = 1/2: the Newton solution ``[-1/3, 2/3, 2/3]`` is the impulse-ratio
    solution with ``α = 1/2`` (it conserves energy):

    >>> r = impulse_ratio_law("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", 1, ["1/2"])
    >>> r.impulses.T, r.velocity.T
    (Matrix([[4/3, 2/3]]), Matrix([[-1/3, 2/3, 2/3]]))

    A negative discriminant, allowed: no real solution.

    >>> r = impulse_ratio_law("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", "1/10", ["1"], allow_invalid=True)
    >>> r.impulses is None, r.delta, [v.condition for v in r.violations]
    (True, -4/5, ['negative-discriminant'])
    """
    exact = is_exact(mass_matrix, gradients, velocity, restitution) and (ratios is None or isinstance(ratios, str) or is_exact(list(ratios)))
    Mx = check_mass_matrix(mass_matrix, exact=exact)
    n = Mx.shape[0]
    Hx = check_gradients(gradients, n, exact=exact)
    vx = check_velocity(velocity, n, exact=exact)
    ex = check_restitution(restitution, exact=exact)
    k = Hx.shape[0]
    notes: list = []
    if coupling:
        given = [x for x in ratios.split(",") if x.strip()] if isinstance(ratios, str) else ratios
        ratios, notes = apply_coupling(Mx, Hx, vx, given) if k > 1 else ([], [])
    a = _ratio_vector(ratios, k, exact)

    return energy_balance_along(Mx, Hx, vx, ex, a, exact=exact, allow_invalid=allow_invalid, notes=notes)


def energy_balance_along(Mx, Hx, vx, ex, a, *, exact: bool, allow_invalid: bool = False, notes=None,
                         law: str = "impulse-ratio law") -> ImpulseRatioResult:
    """Solve ``M Δv = Hᵀp``, ``T⁺ = e T⁻`` for ``p = p₁ a`` along a given direction ``a`` (any
    ``a``, not necessarily ``a₁ = 1``) on *checked* input (``impactsym.mechanics`` checkers).

    This is the computational core of :func:`impulse_ratio_law`, shared by the energetic law of
    :mod:`impactsym.laws.classical`. ``p₁`` is then the multiplier of the direction ``a``.

    >>> r = energy_balance_along(sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]), sp.Matrix([1, 0, 0]), 1,
    ...                          [sp.Integer(2), sp.Integer(1)], exact=True)
    >>> r.impulses.T
    Matrix([[4/3, 2/3]])
    """
    notes = notes or []
    k = Hx.shape[0]
    kind, (Mq, Hq, vq, aq, eM) = exact_data(Mx, Hx, vx, sp.Matrix(a) if exact else np.array(a),
                                            sp.Matrix([[ex]]) if exact else np.array([[ex]]))
    e_q = eM[0, 0]
    if kind == "rational":
        r = Hq.transpose() * aq
        w = Mq.solve(r)
        A = (r.transpose() * w)[0, 0] / 2
        b = Hq * vq
        B = (aq.transpose() * b)[0, 0]
        T = (vq.transpose() * Mq * vq)[0, 0] / 2
        C = (1 - e_q) * T
        c = Hq * w
    else:
        Ms, Hs, vs, as_ = Mq, Hq, vq, aq
        r = Hs.T * as_
        w = Ms.LUsolve(r)
        A = _tidy((r.T * w)[0, 0] / 2)
        b = (Hs * vs).applyfunc(_tidy)
        B = _tidy((as_.T * b)[0, 0])
        T = _simplify((vs.T * Ms * vs)[0, 0] / 2)
        C = _tidy((1 - e_q) * T)
        c = (Hs * w).applyfunc(_tidy)
    if sign_of(A) == 0:
        raise DomainError("ratios: H^T a = 0 (the impulse direction changes no velocity); "
                          "the energy balance cannot fix p_1")
    D = B * B - 4 * A * C
    sD, sB = sign_of(D), sign_of(B)
    violations: list[Violation] = []
    if sD < 0:
        violations.append(Violation("negative-discriminant",
                                    f"negative-discriminant: D = B^2 - 4AC = {_show(D)} < 0, the energy balance "
                                    "T+ = e T- has no real solution along these ratios"))
    if sB >= 0:
        violations.append(Violation("no-approach",
                                    f"no-approach: B = a^T H v- = {_show(B)} >= 0, the contacts do not approach "
                                    "along the ratio direction"))
    if sD >= 0:
        r0, s0 = -B / (2 * A), 1 / (2 * A)  # p1 = r0 + s0 sqrt(D)
        sp1 = sign_surd(r0, s0, D)
        for j in range(k):
            s_pj = sign_of(aq[j, 0]) * sp1
            if s_pj < 0:
                violations.append(Violation("negative-impulse", f"negative-impulse: p_{j + 1} < 0", j + 1))
        for j in range(k):
            x, y = b[j, 0] + c[j, 0] * r0, c[j, 0] * s0
            if sign_surd(x, y, D) < 0:
                violations.append(Violation("penetration", _Later(
                    lambda j=j, x=x, y=y: f"penetration: contact {j + 1} has H_{j + 1} v+ = {_show_surd(x, y, D)} < 0"),
                    j + 1))
    violations.sort(key=lambda v: VIOLATION_CONDITIONS.index(v.condition))
    if violations and not allow_invalid:
        raise DomainError(f"{law} outside its domain: " + "; ".join(v.message for v in violations))

    # verify the exact outcome before it is returned (the law's equations always; the sign
    # conditions when the law labels it valid)
    if exact and sD >= 0:
        _verify(law, kind, Mq, Hq, vq, aq, w, A, B, D, e_q, not violations)

    # values
    if exact:
        to_s = (lambda x: to_sympy_rational(x)) if kind == "rational" else (lambda x: x)
        to_m = (lambda X: to_sympy_matrix(X)) if kind == "rational" else (lambda X: X)
        As, Bs, Cs, Ds = (to_s(x) for x in (A, B, C, D))
        a_s = to_m(aq)
        w_s, v_s = to_m(w), to_m(vq)
        # the values' canonical forms are made when first read (a verdict alone never reads them)
        dnorm = None if sB == 0 else _Later(lambda: _tidy(Ds / Bs**2))
        if sD < 0:
            p = vplus = None
        else:
            root = lru_cache(maxsize=1)(lambda: _tidy((-Bs + sp.sqrt(Ds)) / (2 * As)))  # p1, made once
            p = _Later(lambda: (a_s * root()).applyfunc(_tidy))
            vplus = _Later(lambda: (v_s + root() * w_s).applyfunc(_tidy))
        return ImpulseRatioResult(p, vplus, _Later(lambda: _tidy(Ds)), dnorm, (As, Bs, Cs), list(a_s), True,
                                  not violations, violations, notes)
    Mf, Hf, vf, af = (np.asarray(x, dtype=float) for x in (Mx, Hx, vx, a))
    ef = float(ex)
    ratios_given = list(af)

    def coefficients(af):
        with np.errstate(over="ignore", invalid="ignore"):
            rf = Hf.T @ af
            wf = np.linalg.solve(Mf, rf)
            Af = 0.5 * float(rf @ wf)
            Bf = float(af @ (Hf @ vf))
            Cf = (1.0 - ef) * 0.5 * float(vf @ Mf @ vf)
            return wf, Af, Bf, Cf, Bf * Bf - 4.0 * Af * Cf

    wf, Af, Bf, Cf, Df = coefficients(af)
    amax = float(np.max(np.abs(af))) if af.size else 0.0
    if not all(math.isfinite(x) for x in (Af, Bf, Cf, Df)) and math.isfinite(amax) and amax > 0:
        # Only the direction of a matters (p = p1 a): an exact direction with huge entries (1e168,
        # the elastic impulse of a dense 64x64 M) overflows a^T H M^-1 H^T a. Scale it by a power
        # of two (exact) to a largest entry in [1/2, 1); A, B, C are then the scaled direction's.
        af = np.ldexp(af, -math.frexp(amax)[1])
        wf, Af, Bf, Cf, Df = coefficients(af)
        notes = notes + ["float path: the ratio direction was scaled by a power of two to avoid overflow; "
                         "the coefficients (A, B, C) are those of the scaled direction"]
    if not all(math.isfinite(x) for x in (Af, Bf, Cf, Df)):
        raise DomainError(f"{law}: the float path overflowed (A, B, C or the discriminant of the energy "
                          "balance is not finite in float64 for this M, H, v); give exact input for the exact path")
    dnorm = None if sB == 0 else Df / (Bf * Bf)
    if sD < 0:
        p = vplus = None
    else:
        # D >= 0 was decided exactly. The generated kernel impulse_ratio_root evaluates the stable
        # form (q/A for B < 0, C/q otherwise); at a double root (D = 0 exactly) or when the float D
        # rounds below 0 although D > 0, sqrt(D) is taken as 0 and the root is -B/(2A).
        if sD > 0 and Df > 0:
            p1 = float(kernels.impulse_ratio_root(Af, Bf, Cf)[0])
        else:
            p1 = -Bf / (2.0 * Af) if Bf != 0 else 0.0
        p = p1 * af
        vplus = vf + p1 * wf
        if not (np.all(np.isfinite(p)) and np.all(np.isfinite(vplus))):
            raise DomainError(f"{law}: the float path overflowed (an impulse or velocity is not finite in "
                              "float64 for this M, H, v); give exact input for the exact path")
    return ImpulseRatioResult(p, vplus, Df, dnorm, (Af, Bf, Cf), ratios_given, False, not violations, violations, notes)


def _verify(law, kind, Mq, Hq, vq, aq, w, A, B, D, e_q, valid):
    """Exact verification (:mod:`impactsym.verify`) of ``p = p₁a``, ``v⁺ = v⁻ + p₁M⁻¹Hᵀa`` with
    ``p₁ = (−B + √D)/(2A)``: energy ``T⁺ = e T⁻``, momentum, and (``valid``) ``H v⁺ ≥ 0``,
    ``p ≥ 0``. Rational data in ``Q(√D)`` with fmpq; algebraic data with certified signs."""
    from ..verify import verify_exact, verify_surd

    k, n = Hq.nrows() if kind == "rational" else Hq.rows, vq.nrows() if kind == "rational" else vq.rows
    if kind == "rational":
        r0, s0 = -B / (2 * A), 1 / (2 * A)
        alpha = [vq[i, 0] + r0 * w[i, 0] for i in range(n)]
        beta = [s0 * w[i, 0] for i in range(n)]
        pa = [aq[j, 0] * r0 for j in range(k)]
        pb = [aq[j, 0] * s0 for j in range(k)]
        verify_surd(law, Mq, Hq, [vq[i, 0] for i in range(n)], alpha, beta, pa, pb, D, energy_ratio=e_q,
                    check_signs=valid)
        return
    p1 = (-B + sp.sqrt(D)) / (2 * A)
    verify_exact(law, Mq, Hq, vq, vq + p1 * w, aq * p1, energy_ratio=e_q,
                 closed=None if valid else [], impulse_nonnegative=valid)


def _tidy(x):
    return tidy(x)  # remembered (impactsym.laws.delassus.tidy)


def _simplify(x):
    """``sp.simplify``, remembered (every ``(α, e)`` on one scene has the same ``T⁻``) in the one
    memo of SymPy's simplify (:func:`impactsym.arithmetic.remembered.simplify_remembered`: kept
    across the paper checks' mutation tests, which cleared a memo of this module's own)."""
    from ..arithmetic.remembered import simplify_remembered

    return simplify_remembered(x)


def _show(x) -> str:
    if hasattr(x, "p") and hasattr(x, "q") and not isinstance(x, sp.Basic):
        return exact_str(to_sympy_rational(x))
    return exact_str(sp.sympify(x))


def _show_surd(x, y, d) -> str:
    if not isinstance(x, sp.Basic):
        x, y, d = (to_sympy_rational(t) if not isinstance(t, sp.Basic) else t for t in (x, y, d))
    return exact_str(_tidy(x + y * sp.sqrt(d)))
