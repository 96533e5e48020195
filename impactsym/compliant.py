"""Compliant (regularized) chains of balls: where the impulse ratios come from (Acary & Taha sec. 3.4).

An n-ball chain on a line, balls touching at ``t = 0`` (contact ``i`` between balls ``i`` and
``i+1``), indentation ``δ_i = x_i − x_{i+1}`` (``> 0`` when compressed), contact force

* Hertz (eq. 20 with exponent 3/2): ``f_i = K_i δ_i^{3/2} + C_i δ_i^{1/2} δ̇_i``;
* linear (eq. 23): ``f_i = K_i δ_i`` (optionally ``+ C_i δ̇_i``),

acting only while ``δ_i > 0`` and never pulling: ``f_i`` is taken as ``max(f_i, 0)`` (a damped
contact would otherwise become adhesive at the end of restitution; this is the usual unilateral
reading of eq. 20, stated here rather than done silently). The equations of motion are
``m_i ẍ_i = f_{i−1} − f_i``; the accumulated impulses ``P_i = ∫ f_i dt`` are integrated with the
state, and the integration stops when every contact is open and no pair approaches. The impulse
ratios are eq. 21, ``α_1j = P_j / P_1``.

Scaling (dimensional analysis; tested in ``tests/test_compliant.py``). With ``x = V T x̃``,
``t = T t̃`` and a speed scale ``V``, the Hertz chain is dimensionless for
``T = (m/(K V^{1/2}))^{2/5}`` and ``C/K`` measured in units of ``T``. Hence, *without damping*,
the ratios depend only on the mass ratios, stiffness ratios and the ratios of pre-impact
velocities (claim 2(b) of sec. 3.4), and not on ``|v⁻|``. *With damping*, they are invariant
under ``K → λK``, ``m → μm`` only if ``C → λ (μ/λ)^{2/5} C`` (and under ``v → s v`` only if
``C → s^{−1/5} C``): with ``C`` held fixed, claim 2(b) does not hold as stated. For the linear
model (claim 3) ``T = (m/K)^{1/2}`` does not involve ``V`` and the equations are linear between
contact events, so the ratios depend on neither the absolute stiffness and mass nor ``|v⁻|``.

Examples
--------
Three equal balls, ball 1 striking at unit speed, elastic Hertz contacts: balls 1 and 2 keep a
small motion (sec. 3.3's point) and the ratio is ``α ≈ 0.9287``:

>>> r = chain_impact([1, 1, 1], [1, 0, 0], [1, 1])
>>> r.ratios.round(5).tolist(), r.velocity.round(5).tolist(), round(r.energy_ratio, 9)
([1.0, 0.92866], [-0.07095, 0.0764, 0.99455], 1.0)
>>> chain_impact([1, 1, 1], [1, 0, 0], [1, 1], model="linear").ratios.round(5).tolist()
[1.0, 0.86708]

References
----------
Acary & Taha, sec. 3.4, eqs. 20–23; claims 2(b) and 3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .errors import ImpactInputError, NonTermination

__all__ = ["CompliantResult", "chain_impact", "MODELS"]

MODELS = ("hertz", "linear")


@dataclass
class CompliantResult:
    """Outcome of a compliant chain impact.

    Attributes
    ----------
    impulses : ``P_i = ∫ f_i dt`` per contact (n−1)
    ratios : ``α_1j = P_j / P_1`` (eq. 21), ``ratios[0] = 1``
    velocity : post-impact velocities (n)
    duration : time at which the last contact opened (the ``t_f`` of eq. 21)
    energy_ratio : ``T⁺ / T⁻`` (the global energetic coefficient ``e`` this run realizes)
    events : number of contact openings/closings met
    """

    impulses: np.ndarray
    ratios: np.ndarray
    velocity: np.ndarray
    duration: float
    energy_ratio: float
    events: int


def _vec(x, n, name):
    arr = np.asarray(x, dtype=float).reshape(-1)
    if arr.shape[0] != n:
        raise ImpactInputError(name, f"expected {n} values, got {arr.shape[0]}")
    if not np.all(np.isfinite(arr)):
        raise ImpactInputError(name, "contains NaN or inf")
    return arr


def chain_impact(masses, velocities, stiffness, damping=None, *, model: str = "hertz", rtol: float = 1e-11,
                 atol: float = 1e-14, max_events: int = 10_000) -> CompliantResult:
    """Integrate a compliant n-ball chain through its impact and return the impulses (eq. 21).

    Parameters
    ----------
    masses : n positive masses
    velocities : n pre-impact velocities (balls touching at ``t = 0``)
    stiffness : n−1 positive stiffnesses ``K_i``
    damping : n−1 non-negative damping coefficients ``C_i`` (default 0)
    model : ``"hertz"`` (eq. 20, exponent 3/2) or ``"linear"`` (eq. 23)
    rtol, atol : tolerances of the integrator (DOP853), restarted at every contact event
    max_events : cap on contact events (``NonTermination`` beyond)

    Returns
    -------
    CompliantResult

    Raises
    ------
    ImpactInputError
        Wrong lengths, NaN, non-positive mass or stiffness, negative damping, unknown model,
        or a pre-impact state in which no contact approaches (nothing to integrate).

    Examples
    --------
    Two balls, linear spring: the elastic exchange of velocities, ``P = m v``, contact time
    ``π/ω = π/√(K/μ) = π/√10`` (reduced mass ``μ = 1/2``):

    >>> r = chain_impact([1, 1], [2, 0], [5], model="linear")
    >>> r.velocity.round(9).tolist(), round(float(r.impulses[0]), 9), round(r.duration, 6)
    ([0.0, 2.0], 2.0, 0.993459)
    """
    if model not in MODELS:
        raise ImpactInputError("model", f"must be one of {MODELS}, got {model!r}")
    m = _vec(masses, len(np.atleast_1d(masses)), "masses")
    n = m.shape[0]
    if n < 2:
        raise ImpactInputError("masses", "a chain needs at least two balls")
    v0 = _vec(velocities, n, "velocities")
    K = _vec(stiffness, n - 1, "stiffness")
    C = np.zeros(n - 1) if damping is None else _vec(damping, n - 1, "damping")
    if np.any(m <= 0):
        raise ImpactInputError("masses", "must be positive")
    if np.any(K <= 0):
        raise ImpactInputError("stiffness", "must be positive")
    if np.any(C < 0):
        raise ImpactInputError("damping", "must be non-negative")
    if not np.any(v0[:-1] > v0[1:]):
        raise ImpactInputError("velocities", "no contact approaches (v_i > v_{i+1} for none): there is no impact")
    hertz = model == "hertz"

    def forces(x, v):
        d = x[:-1] - x[1:]
        dd = v[:-1] - v[1:]
        dp = np.maximum(d, 0.0)
        if hertz:
            f = K * dp**1.5 + C * np.sqrt(dp) * dd
        else:
            f = K * dp + C * dd * (d > 0)
        return np.where(d > 0, np.maximum(f, 0.0), 0.0)

    def rhs(_t, s):
        x, v = s[:n], s[n:2 * n]
        f = forces(x, v)
        acc = np.zeros(n)
        acc[:-1] -= f
        acc[1:] += f
        return np.concatenate([v, acc / m, f])

    def make_event(i):
        def ev(_t, s):
            return s[i] - s[i + 1]
        ev.terminal = True
        ev.direction = 0
        return ev

    events = [make_event(i) for i in range(n - 1)]
    # time scale of one contact
    vrel = float(np.max(np.abs(v0[:-1] - v0[1:])))
    mm = float(np.min(m))
    scale = (mm / (float(np.max(K)) * np.sqrt(vrel))) ** 0.4 if hertz else np.sqrt(mm / float(np.max(K)))
    s = np.concatenate([np.zeros(n), v0, np.zeros(n - 1)])
    t = 0.0
    t_last_open = 0.0
    count = 0
    first = True
    while True:
        x, v = s[:n], s[n:2 * n]
        d = x[:-1] - x[1:]
        closing = v[:-1] - v[1:]
        # done: no contact compressed, none with d == 0 that closes, and no gap that will close
        if not first and np.all(d <= 0) and np.all(closing <= 0):
            break
        first = False
        if count >= max_events:
            raise NonTermination(f"compliant chain: more than max_events = {max_events} contact events")
        # step off the event surface: the events fire on sign changes only
        sol = solve_ivp(rhs, (t, t + 1000 * scale), s, method="DOP853", rtol=rtol, atol=atol,
                        events=events, dense_output=False)
        if sol.status == -1:  # pragma: no cover - integrator failure
            raise NonTermination(f"compliant chain: integrator failed ({sol.message})")
        t_new, s_new = sol.t[-1], sol.y[:, -1]
        if sol.status == 1:
            # nudge past the event so that the next segment does not re-trigger at t
            idx = [i for i, te in enumerate(sol.t_events) if len(te)][0]
            s_new = sol.y_events[idx][-1].copy()
            t_new = sol.t_events[idx][-1]
            count += 1
            dx = s_new[n + idx] - s_new[n + idx + 1]
            if dx < 0:
                t_last_open = t_new
            if t_new <= t:  # a zero-length segment: advance a tiny free-flight step
                h = 1e-12 * scale
                s_new = s_new + h * rhs(t_new, s_new)
                t_new = t_new + h
        t, s = t_new, s_new
    P = s[2 * n:]
    vplus = s[n:2 * n]
    T0 = 0.5 * float(m @ v0**2)
    T1 = 0.5 * float(m @ vplus**2)
    ratios = P / P[0] if P[0] != 0 else np.full(n - 1, np.nan)
    return CompliantResult(P, ratios, vplus, float(t_last_open), T1 / T0, count)
