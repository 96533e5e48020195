"""An independent reference for compliant impacts with any exponent, elastic, Hunt–Crossley or with
eq. 20's damping: SciPy's DOP853 piece by piece, each piece ending exactly where a contact's force
starts or stops (a terminal event), so that no step crosses a point where the force is not smooth.
Within a piece every contact keeps its law: closed, ``K max(δ, 0)^p`` (times ``1 + D δ̇`` for
Hunt–Crossley; ``K δ^p + C δ^(p−1) δ̇`` for eq. 20), or open, 0. Eq. 20's damped force stops
where ``φ = K δ + C δ̇`` falls through 0, before the gap opens, and Hunt–Crossley's where
``ψ = 1 + D δ̇`` does (``D δ̇ < −1``: the contact opening faster than ``1/D``): a closed contact is
pushing (``φ > 0``, ``ψ > 0``) or not, and a piece also ends where ``φ`` or ``ψ`` crosses 0. It
shares no code with :mod:`impactsym.compliant` (no held laws, no driver of its own, plain
``solve_ivp``), and is a sampled reference, not a proof: a crossing there and back inside one step
is not seen.

>>> import numpy as np
>>> v = piecewise_reference(np.eye(2), np.array([[-1.0, 1.0]]), np.array([1.0, 0.0]), [1.0], 1.5)
>>> bool(abs(v[0]) < 1e-12 and abs(v[1] - 1) < 1e-12)  # two equal balls exchange their velocities
True
>>> v = piecewise_reference(np.eye(1), np.array([[-1.0]]), np.array([1.0]), [1.0], 1.5, damping=[0.2])
>>> bool(-1 < v[0] < -0.5)  # a ball against a damped wall comes back slower
True
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

#: a contact's law within a piece: open, closed and pushing, closed without pushing (eq. 20 only)
OPEN, PUSHING, IDLE = 0, 1, 2


def piecewise_reference(M, H, v0, K, p, rtol=1e-13, max_pieces=20_000, hunt_crossley=None, damping=None,
                        ends=None):
    """The post-impact velocity of ``M q̈ = Hᵀ f``, ``f_i = K_i max(−g_i, 0)^p`` (``ġ = H q̇``, every
    gap 0 at the start, the approaching contacts closed), integrated in pieces between crossings;
    with ``hunt_crossley`` (``D_i``), ``f_i = K_i max(−g_i, 0)^p (1 − D_i ġ_i)`` while pushing
    (``1 − D_i ġ_i > 0``), 0 otherwise; with ``damping`` (eq. 20's ``C_i``),
    ``f_i = K_i δ_i^p + C_i δ_i^(p−1) δ̇_i`` while pushing. With ``ends`` (a list), each piece's end
    is appended to it as ``(t, contact, law after it)``."""
    M, H, v0, K = np.asarray(M, float), np.asarray(H, float), np.asarray(v0, float), np.asarray(K, float)
    D = None if hunt_crossley is None else np.asarray(hunt_crossley, float)
    C = None if damping is None else np.asarray(damping, float)
    A = np.linalg.solve(M, H.T)
    k, n = H.shape
    V = float(np.max(-(H @ v0)))
    y, t = np.concatenate([np.zeros(k), v0]), 0.0
    state = np.where((H @ v0) < 0, PUSHING, OPEN)
    for _ in range(max_pieces):
        law = state.copy()

        def rhs(_t, y, law=law):
            d, gd = np.maximum(-y[:k], 0.0), H @ y[k:]
            if C is not None:
                f = K * d**p + C * d ** (p - 1) * -gd
            elif D is not None:
                f = K * d**p * (1.0 - D * gd)
            else:
                f = K * d**p
            return np.concatenate([gd, A @ np.where(law == PUSHING, f, 0.0)])

        events, laws = [], []  # each event, and (its contact, the law after it, whether it is a gap)
        for j in range(k):
            def gap(_t, y, j=j):
                return y[j]
            gap.terminal, gap.direction = True, (1.0 if law[j] else -1.0)
            events.append(gap)
            laws.append((j, OPEN if law[j] else PUSHING, True))
            if C is not None and law[j]:
                def phi(_t, y, j=j):
                    return -K[j] * y[j] - C[j] * (H[j] @ y[k:])
            elif D is not None and law[j]:
                def phi(_t, y, j=j):
                    return 1.0 - D[j] * (H[j] @ y[k:])
            if (C is not None or D is not None) and law[j]:
                phi.terminal, phi.direction = True, (-1.0 if law[j] == PUSHING else 1.0)
                events.append(phi)
                laws.append((j, IDLE if law[j] == PUSHING else PUSHING, False))
        sol = solve_ivp(rhs, (t, t + 1e3), y, method="DOP853", rtol=rtol, atol=1e-16, events=events)
        if sol.status == 1:
            e = next(e for e in range(len(events)) if len(sol.t_events[e]))
            j, after, is_gap = laws[e]
            t, y = float(sol.t_events[e][0]), sol.y_events[e][0].copy()
            if ends is not None:
                ends.append((t, j, after))
            if is_gap:
                y[j] = 0.0
            state[j] = after
            continue
        t, y = float(sol.t[-1]), sol.y[:, -1]
        if not state.any() and np.all(H @ y[k:] >= -1e-12 * V):
            return y[k:]
    raise RuntimeError(f"piecewise_reference: more than {max_pieces} pieces")
