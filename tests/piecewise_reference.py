"""An independent reference for elastic and Hunt–Crossley compliant impacts with any exponent: SciPy's
DOP853 piece by piece, each piece ending exactly at a contact's opening or closing (a terminal
event), so that no step crosses the point where ``K δ^p`` stops being smooth. Within a piece every
contact keeps its law (closed: ``K max(δ, 0)^p``, times ``max(1 + D δ̇, 0)`` for Hunt–Crossley;
open: 0). It shares no code with :mod:`impactsym.compliant` (no held
laws, no driver of its own, plain ``solve_ivp``), and is a sampled reference, not a proof: a crossing
there and back inside one step is not seen.

>>> import numpy as np
>>> v = piecewise_reference(np.eye(2), np.array([[-1.0, 1.0]]), np.array([1.0, 0.0]), [1.0], 1.5)
>>> bool(abs(v[0]) < 1e-12 and abs(v[1] - 1) < 1e-12)  # two equal balls exchange their velocities
True
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


def piecewise_reference(M, H, v0, K, p, rtol=1e-13, max_pieces=10_000, hunt_crossley=None):
    """The post-impact velocity of ``M q̈ = Hᵀ f``, ``f_i = K_i max(−g_i, 0)^p`` (``ġ = H q̇``, every
    gap 0 at the start, the approaching contacts closed), integrated in pieces between crossings;
    with ``hunt_crossley`` (``D_i``), ``f_i = max(K_i max(−g_i, 0)^p (1 − D_i ġ_i), 0)``."""
    M, H, v0, K = np.asarray(M, float), np.asarray(H, float), np.asarray(v0, float), np.asarray(K, float)
    D = None if hunt_crossley is None else np.asarray(hunt_crossley, float)
    A = np.linalg.solve(M, H.T)
    k, n = H.shape
    V = float(np.max(-(H @ v0)))
    y, t = np.concatenate([np.zeros(k), v0]), 0.0
    closed = (H @ v0) < 0
    for _ in range(max_pieces):
        law = closed.copy()

        def rhs(_t, y, law=law):
            d, gd = np.maximum(-y[:k], 0.0), H @ y[k:]
            f = K * d**p if hunt_crossley is None else np.maximum(K * d**p * (1.0 - D * gd), 0.0)
            return np.concatenate([gd, A @ np.where(law, f, 0.0)])

        def crossing(j, law=law):
            def ev(_t, y):
                return y[j]
            ev.terminal, ev.direction = True, (1.0 if law[j] else -1.0)
            return ev

        sol = solve_ivp(rhs, (t, t + 1e3), y, method="DOP853", rtol=rtol, atol=1e-16,
                        events=[crossing(j) for j in range(k)])
        if sol.status == 1:
            j = next(j for j in range(k) if len(sol.t_events[j]))
            t, y = float(sol.t_events[j][0]), sol.y_events[j][0].copy()
            y[j] = 0.0
            closed[j] = not closed[j]
            continue
        t, y = float(sol.t[-1]), sol.y[:, -1]
        if not closed.any() and np.all(H @ y[k:] >= -1e-12 * V):
            return y[k:]
    raise RuntimeError(f"piecewise_reference: more than {max_pieces} pieces")


def damped_piecewise_reference(M, H, v0, K, p, C, rtol=1e-13, max_pieces=20_000):
    """The same for eq. 20's damping, ``f_i = max(K_i δ_i^p + C_i δ_i^(p−1) δ̇_i, 0)`` where ``δ_i > 0``:
    each contact is open, pushing (``φ_i = K_i δ_i + C_i δ̇_i > 0``) or closed without pushing, and a
    piece ends where a gap crosses 0 or a closed contact's ``φ_i`` does (the force stops where
    ``φ_i`` falls through 0, before the gap opens, and starts again where it rises).

    >>> v = damped_piecewise_reference(np.eye(1), np.array([[-1.0]]), np.array([1.0]), [1.0], 1.5, [0.2])
    >>> bool(-1 < v[0] < -0.5)  # a ball against a damped wall comes back slower
    True
    """
    M, H, v0, K, C = (np.asarray(x, float) for x in (M, H, v0, K, C))
    A = np.linalg.solve(M, H.T)
    k, n = H.shape
    V = float(np.max(-(H @ v0)))
    y, t = np.concatenate([np.zeros(k), v0]), 0.0
    state = np.where((H @ v0) < 0, 1, 0)  # 0 open, 1 pushing, 2 closed without pushing
    for _ in range(max_pieces):
        law = state.copy()

        def rhs(_t, y, law=law):
            d, gd = np.maximum(-y[:k], 0.0), H @ y[k:]
            f = np.where(law == 1, K * d**p + C * d ** (p - 1) * -gd, 0.0)
            return np.concatenate([gd, A @ f])

        events, ends = [], []
        for j in range(k):
            def gap(_t, y, j=j):
                return y[j]
            gap.terminal, gap.direction = True, (1.0 if law[j] else -1.0)
            events.append(gap)
            ends.append((j, 0, True))  # (contact, its state after, a gap crossing)
            if law[j]:
                def phi(_t, y, j=j):
                    return -K[j] * y[j] - C[j] * (H[j] @ y[k:])
                phi.terminal, phi.direction = True, (-1.0 if law[j] == 1 else 1.0)
                events.append(phi)
                ends.append((j, 2 if law[j] == 1 else 1, False))
            else:
                ends[-1] = (j, 1, True)
        sol = solve_ivp(rhs, (t, t + 1e3), y, method="DOP853", rtol=rtol, atol=1e-16, events=events)
        if sol.status == 1:
            e = next(e for e in range(len(events)) if len(sol.t_events[e]))
            j, after, is_gap = ends[e]
            t, y = float(sol.t_events[e][0]), sol.y_events[e][0].copy()
            if is_gap:
                y[j] = 0.0
            state[j] = after
            continue
        t, y = float(sol.t[-1]), sol.y[:, -1]
        if not state.any() and np.all(H @ y[k:] >= -1e-12 * V):
            return y[k:]
    raise RuntimeError(f"damped_piecewise_reference: more than {max_pieces} pieces")
