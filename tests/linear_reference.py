"""A high-precision reference for compliant impacts with linear elastic contacts (test helper).

Between contact events the linear model ``M q̈ = Hᵀ f``, ``f_i = K_i δ_i`` on the closed contacts
(``δ = −g``), ``Ṗ = f`` is a linear ODE with constant coefficients in ``(g, q̇, P)``: its solution
is ``expm(A s) y``, computed here in mpmath (30 digits by default). The run steps over a grid of
``T / grid`` (``T`` the shortest contact time scale ``√(μ_i / K_i)``); where a closed contact's gap
turns positive or an open one's negative within a cell, the crossing is found by Newton's method
on ``(expm(A s) y)_j`` (to ``dps − 3`` digits), that gap is set to 0 and its law flipped. Free
flight (every contact open, every gap ≥ 0) jumps to the next closing; the run ends when every
contact is open and none approaches, as :func:`impactsym.compliant.compliant_impact` ends.

What it is not: a proof. A crossing there and back inside one grid cell is not seen (the grid is
64 cells per contact time scale); at 40 digits and 128 cells the ringing scene of
``tests/test_compliant.py`` gave the same float64 velocity. It is independent of the code it checks:
no DOP853, no events of SciPy, no float64 arithmetic after reading the inputs' binary values.

>>> v, events = linear_reference([[2.0]], [[-1.0]], [1.0], 8.0)   # closed at t = 0, then one opening
>>> v.tolist(), events
([-1.0], 1)
"""

from __future__ import annotations

import mpmath as mp
import numpy as np


def linear_reference(M, H, v, K, *, dps: int = 30, grid: int = 64, max_events: int = 10_000):
    """The post-impact velocity (float64, rounded from ``dps`` digits) and the number of contact
    events (closings and openings after ``t = 0``) of the linear elastic model, every contact
    touching at ``t = 0`` (closed where it approaches, open otherwise)."""
    with mp.workdps(dps):
        Mm = mp.matrix(np.asarray(M, dtype=float).tolist())
        Hm = mp.matrix(np.atleast_2d(np.asarray(H, dtype=float)).tolist())
        k, n = Hm.rows, Hm.cols
        Kl = [mp.mpf(float(x)) for x in np.broadcast_to(np.asarray(K, dtype=float), (k,))]
        Bm = Mm ** -1 * Hm.T  # accelerations per unit contact force
        N = 2 * k + n
        y = mp.matrix(N, 1)
        for i, x in enumerate(np.asarray(v, dtype=float)):
            y[k + i] = mp.mpf(float(x))

        def speeds(y):
            return [mp.fsum(Hm[j, i] * y[k + i] for i in range(n)) for j in range(k)]

        mu = [1 / mp.fsum(Hm[j, i] * Bm[i, j] for i in range(n)) for j in range(k)]
        dt = min(mp.sqrt(mu[j] / Kl[j]) for j in range(k)) / grid
        closed = [w < 0 for w in speeds(y)]
        pieces = {}

        def piece(closed):
            key = tuple(closed)
            if key not in pieces:
                A = mp.matrix(N, N)
                for j in range(k):
                    for i in range(n):
                        A[j, k + i] = Hm[j, i]  # g' = H q̇
                    if closed[j]:  # f_j = −K_j g_j: q̈ += M⁻¹ H_jᵀ f_j, P_j' = f_j
                        for i in range(n):
                            A[k + i, j] -= Kl[j] * Bm[i, j]
                        A[k + n + j, j] = -Kl[j]
                pieces[key] = (A, mp.expm(A * dt), [])
            return pieces[key]

        events = 0
        while True:
            if not any(closed) and all(y[j] >= 0 for j in range(k)):
                w = speeds(y)
                approaching = [j for j in range(k) if w[j] < 0]
                if not approaching:
                    break
                jc = min(approaching, key=lambda j: y[j] / -w[j])
                tc = y[jc] / -w[jc]
                for j in range(k):
                    y[j] += tc * w[j]
                y[jc], closed[jc] = mp.mpf(0), True
                events += 1
                continue
            A, E, halves = piece(closed)
            y1 = E * y
            crossed = [j for j in range(k) if (y1[j] > 0 if closed[j] else y1[j] < 0)]
            if not crossed:
                y = y1
                continue
            first = None
            for j in crossed:
                s = _crossing(A, y, j, closed[j], dt, dps, halves)
                if first is None or s < first[0]:
                    first = (s, j)
            s, j = first
            y = mp.expm(A * s) * y
            y[j] = mp.mpf(0)
            closed[j] = not closed[j]
            events += 1
            if events > max_events:
                raise RuntimeError(f"more than {max_events} contact events")
        return np.array([float(y[k + i]) for i in range(n)]), events


#: the bisection's halvings of the grid cell before Newton's method takes over
BISECTIONS = 20


def _halves(A, dt, dps):
    """``[expm(A·dt/2), expm(A·dt/4), …, expm(A·dt/2²⁰)]``: the last by ``expm``, each other the
    square of the next, at ``dps + 10`` digits (the 19 squarings lose at most about 6 of them) and
    rounded to ``dps``. One ``expm`` for a piece's every bisection, instead of one per halving."""
    with mp.workdps(dps + 10):
        out = [mp.expm(A * (dt / 2 ** BISECTIONS))]
        for _ in range(BISECTIONS - 1):
            out.append(out[-1] * out[-1])
    return [E * 1 for E in reversed(out)]  # E * 1: each entry rounded to the caller's precision


def _crossing(A, y, j, closed, dt, dps, halves):
    """The time in ``[0, dt]`` where gap ``j`` of ``expm(A s) y`` leaves its law's side (> 0 for a
    closed contact, < 0 for an open one; it is on that side at ``dt``): bisection to a cell of
    ``dt·2⁻²⁰``, then Newton inside it (bisection on where the derivative vanishes or Newton leaves
    the bracket: a gap resting at 0 whose crossing is of higher order).

    The bisection carries the state at the bracket's low end, ``expm(A·lo) y``, and reaches each
    midpoint by one product with ``expm(A·dt/2^i)`` (:func:`_halves`, made once per piece into the
    list ``halves``); Newton's steps evaluate ``expm(A s) y`` directly."""
    def crossed(ys):
        return ys[j] > 0 if closed else ys[j] < 0

    if not halves:
        halves.extend(_halves(A, dt, dps))
    lo, hi = mp.mpf(0), dt
    y_lo = y
    for E_half in halves:
        mid = (lo + hi) / 2
        y_mid = E_half * y_lo
        if crossed(y_mid):
            hi = mid
        else:
            lo, y_lo = mid, y_mid
    tol = dt * mp.mpf(10) ** (3 - dps)
    s = (lo + hi) / 2
    while hi - lo > tol:
        ys = mp.expm(A * s) * y
        if crossed(ys):
            hi = s
        else:
            lo = s
        d = (A * ys)[j]
        nxt = s - ys[j] / d if d != 0 else None
        s = nxt if nxt is not None and lo < nxt < hi else (lo + hi) / 2
        if nxt is not None and abs(ys[j] / d) < tol:
            return min(max(nxt, lo), hi)
    return hi
