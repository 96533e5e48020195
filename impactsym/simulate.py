"""An event-driven simulator for balls on a line, in exact rational arithmetic.

This is the paper's own justification of the sequential resolution made executable: "nearby
trajectories that undergo successive single impacts" (Seghete & Murphey, sec. II-B, IV-A). The
balls start with tiny positive gaps; the simulator finds the next contact to close, advances every
ball to that instant, and resolves that one collision with the textbook elastic formulas, until no
contact will ever close again. It does not use ``G_u`` or any other impactsym law, so it is an
independent check of :func:`impactsym.laws.sequential.resolve_sequential`.

* Two balls ``i`` (left) and ``j`` (right): ``v_i' = ((m_i − m_j) v_i + 2 m_j v_j)/(m_i + m_j)``,
  ``v_j' = ((m_j − m_i) v_j + 2 m_i v_i)/(m_i + m_j)`` (momentum and energy conserved).
* A ball and a fixed wall: ``v' = −v``.

Two contacts closing at the same instant are a simultaneous impact, which a single-impact
simulator cannot resolve: :class:`~impactsym.errors.DomainError` is raised (choose other gaps).

:func:`realize_ordering` chooses gaps that make a given impact ordering happen: with event times
``0 < T_1 < … < T_m`` and the velocities ``v_0, v_1, …`` of the ordering, every gap is piecewise
linear in time, so "contact ``c_s`` closes at ``T_s`` and every other gap stays positive" is a
linear program in the gaps and the intervals ``T_s − T_{s−1}``; it is solved exactly (SymPy's
rational simplex) maximizing the smallest margin, and the gaps are then scaled down to
``scale`` (the schedule is invariant under scaling gaps and times together).

Examples
--------
>>> r = simulate_line([1, 1, 1], [1, 1, 1], [0, "2001/1000", "4002/1000"], [1, 0, 0])
>>> r.velocities, [name for _, name in r.events]
([0, 0, 1], ['1-2', '2-3'])
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .errors import DomainError, ImpactInputError
from .numbers import to_exact

__all__ = ["simulate_line", "SimulationResult", "realize_ordering", "perturbed_scene_positions",
           "DEFAULT_MAX_EVENTS"]

#: cap on the number of collisions of one simulation
DEFAULT_MAX_EVENTS = 100_000


@dataclass
class SimulationResult:
    """Final velocities (exact) and the collisions, in order, as ``(time, contact name)``."""

    velocities: list
    positions: list
    events: list
    time: object


def _exact_list(values, argument):
    if isinstance(values, str) or not hasattr(values, "__len__"):
        raise ImpactInputError(argument, f"must be a sequence of exact numbers, got {values!r}")
    out = []
    for x in values:
        if isinstance(x, float):
            raise ImpactInputError(argument, "the simulator is exact: give integers, rationals or decimal text")
        val = to_exact(x, argument)
        if not val.is_Rational:
            raise ImpactInputError(argument, f"the simulator works in rational arithmetic, got {val}")
        out.append(val)
    return out


def simulate_line(masses, radii, positions, velocities, walls=(), *, max_events: int = DEFAULT_MAX_EVENTS
                  ) -> SimulationResult:
    """Simulate elastic balls on a line (and fixed walls) until no contact will close again.

    Parameters
    ----------
    masses, radii, positions, velocities : sequences of rationals, one per ball; balls must not
        overlap (gaps ≥ 0) and must not both touch and approach at the start.
    walls : wall positions
    max_events : cap on the number of collisions (``NonTermination``-like refusal as DomainError)

    Returns
    -------
    SimulationResult
        ``events`` name contacts as the scene builders do: ``"i-j"`` (ball numbers, ``i < j``)
        and ``"wall@w-i"``.

    Raises
    ------
    DomainError
        Two contacts close at the same instant (a simultaneous impact), a contact that touches
        and approaches at the start, or more than ``max_events`` collisions.
    """
    m = _exact_list(masses, "masses")
    r = _exact_list(radii, "radii")
    x = _exact_list(positions, "positions")
    v = _exact_list(velocities, "velocities")
    w = _exact_list(list(walls), "walls")
    nb = len(m)
    if not (len(r) == len(x) == len(v) == nb) or nb == 0:
        raise ImpactInputError("masses/radii/positions/velocities", "need the same positive number of entries")
    if any(mi <= 0 for mi in m) or any(ri < 0 for ri in r):
        raise ImpactInputError("masses/radii", "masses must be positive and radii non-negative")
    order = sorted(range(nb), key=lambda b: x[b])
    pairs = []
    for a, b in zip(order, order[1:]):
        if x[b] - x[a] - r[a] - r[b] < 0:
            raise ImpactInputError("positions", f"balls {a + 1} and {b + 1} overlap")
        pairs.append((a, b))
    wall_contacts = []
    for wall in w:
        for b in range(nb):
            side = 1 if x[b] > wall else -1 if x[b] < wall else 0
            if side == 0 or (x[b] - r[b] - wall if side > 0 else wall - x[b] - r[b]) < 0:
                raise ImpactInputError("positions", f"ball {b + 1} overlaps the wall at {wall}")
            wall_contacts.append((wall, b, side))
    t = sp.Integer(0)
    events = []
    v0 = list(v)

    def name_pair(a, b):
        i, j = min(a, b), max(a, b)
        return f"{i + 1}-{j + 1}"

    for _ in range(max_events + 1):
        best = None
        tied = []
        for a, b in pairs:  # a left of b
            gap = x[b] - x[a] - r[a] - r[b]
            rate = v[a] - v[b]
            if rate > 0:
                dt = gap / rate
                cand = (dt, ("pair", a, b))
                if best is None or dt < best[0]:
                    best, tied = cand, []
                elif dt == best[0]:
                    tied.append(cand)
        for wall, b, side in wall_contacts:
            gap = (x[b] - r[b] - wall) if side > 0 else (wall - x[b] - r[b])
            rate = -side * v[b]
            if rate > 0:
                dt = gap / rate
                cand = (dt, ("wall", wall, b, side))
                if best is None or dt < best[0]:
                    best, tied = cand, []
                elif dt == best[0]:
                    tied.append(cand)
        if best is None:
            _verify_final(m, v0, v, bool(w))
            return SimulationResult(v, x, events, t)
        if tied:
            names = [_event_name(c[1], name_pair) for c in [best] + tied]
            raise DomainError(f"positions: contacts {', '.join(names)} close at the same instant "
                              f"t = {t + best[0]} (a simultaneous impact; choose other gaps)")
        dt, ev = best
        if dt == 0 and events and events[-1][0] == t and events[-1][1] == _event_name(ev, name_pair):
            raise DomainError("positions: a contact closes twice at one instant")  # pragma: no cover
        t = t + dt
        x = [xi + vi * dt for xi, vi in zip(x, v)]
        if ev[0] == "pair":
            _, a, b = ev
            ma, mb = m[a], m[b]
            va, vb = v[a], v[b]
            v[a] = ((ma - mb) * va + 2 * mb * vb) / (ma + mb)
            v[b] = ((mb - ma) * vb + 2 * ma * va) / (ma + mb)
        else:
            _, wall, b, side = ev
            v[b] = -v[b]
        events.append((t, _event_name(ev, name_pair)))
    raise DomainError(f"max_events: more than {max_events} collisions (the configured cap)")


def _verify_final(m, v0, v, walls: bool) -> None:
    """The exact final velocities conserve the kinetic energy (every collision is elastic) and,
    without walls, the momentum; checked before they are returned (a failure is a bug)."""
    from .errors import VerificationError

    if sum(mi * vi * vi for mi, vi in zip(m, v)) != sum(mi * vi * vi for mi, vi in zip(m, v0)):
        raise VerificationError("simulate_line", "the final kinetic energy differs from the initial one")
    if not walls and sum(mi * vi for mi, vi in zip(m, v)) != sum(mi * vi for mi, vi in zip(m, v0)):
        raise VerificationError("simulate_line", "the final momentum differs from the initial one")


def _event_name(ev, name_pair):
    if ev[0] == "pair":
        return name_pair(ev[1], ev[2])
    return f"wall@{ev[1]}-{ev[2] + 1}"


def realize_ordering(M, H, v0, order, *, scale=sp.Rational(1, 10**6)):
    """Gaps (one per closed contact, exact, positive) that make the impact ``order`` happen.

    Parameters
    ----------
    M, H, v0 : the reduced scene (exact)
    order : sequence of contact indices (rows of ``H``)
    scale : the largest gap after scaling

    Returns
    -------
    list of sympy.Rational, or None when no gaps realize the ordering (the LP's best margin is 0).

    Examples
    --------
    >>> import sympy as sp
    >>> realize_ordering(sp.eye(2), sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-1, -2]), [1, 0, 1, 0])
    [1/1000000, 1/7000000]
    """
    from sympy.solvers.simplex import InfeasibleLPError, linprog

    from .laws.reflection import reflect

    k = H.shape[0]
    m = len(order)
    vels = [sp.Matrix(v0)]
    for c in order:
        vels.append(reflect(M, H[c, :], vels[-1]))
    w = [H * vel for vel in vels]  # w[s][i]: closing rate of contact i during interval s (after event s)
    # variables: g_0..g_{k-1}, dt_1..dt_m, delta
    nv = k + m + 1
    D = nv - 1

    def gap_row(i, s):  # coefficients of g_i(T_s) = g_i + sum_{r<s} w[r][i] dt_{r+1}
        row = [sp.Integer(0)] * nv
        row[i] = sp.Integer(1)
        for rr in range(s):
            row[k + rr] = w[rr][i]
        return row

    A_ub, b_ub, A_eq, b_eq = [], [], [], []

    def ge_delta(row):  # row · z >= delta  ->  -row · z + delta <= 0
        neg = [-c for c in row]
        neg[D] = sp.Integer(1)
        A_ub.append(neg)
        b_ub.append(sp.Integer(0))

    for i in range(k):
        ge_delta(gap_row(i, 0))
    for s in range(1, m + 1):
        row = [sp.Integer(0)] * nv
        row[k + s - 1] = sp.Integer(1)
        ge_delta(row)  # dt_s >= delta
        for i in range(k):
            if i == order[s - 1]:
                A_eq.append(gap_row(i, s))
                b_eq.append(sp.Integer(0))
            else:
                ge_delta(gap_row(i, s))
    norm = [sp.Integer(0)] * nv
    for i in range(k):
        norm[i] = sp.Integer(1)
    A_ub.append(norm)
    b_ub.append(sp.Integer(1))  # sum of gaps <= 1
    c = [sp.Integer(0)] * nv
    c[D] = sp.Integer(-1)
    try:
        val, z = linprog(sp.Matrix([c]), sp.Matrix(A_ub), sp.Matrix(b_ub),
                         sp.Matrix(A_eq) if A_eq else None, sp.Matrix(b_eq) if b_eq else None)
    except InfeasibleLPError:
        return None
    if -val <= 0:
        return None
    gaps = [z[i] for i in range(k)]
    top = max(gaps)
    return [sp.Rational(g) / top * scale for g in gaps]


def perturbed_scene_positions(scene, gaps):
    """Ball positions of a :func:`~impactsym.scenes.balls_on_line` scene moved so that its closed
    contacts open to ``gaps``: displacements ``d`` of the involved balls with ``H d = gaps``
    (exact; free directions set to zero), uninvolved balls unmoved.

    >>> from impactsym.scenes import balls_on_line
    >>> sc = balls_on_line([1, 1], [1, 1], [1, 3], [-1, -2], walls=[0])
    >>> perturbed_scene_positions(sc, [sp.Rational(1, 10), sp.Rational(1, 5)])
    [6/5, 33/10]
    """
    H = sp.Matrix(scene.H)
    g = sp.Matrix(gaps)
    sol, params = H.gauss_jordan_solve(g)
    d = sol.subs({p: 0 for p in params})
    pos = list(scene.meta["positions"])
    for slot, b in enumerate(scene.meta["bodies"]):
        pos[b - 1] = pos[b - 1] + d[slot]
    return pos
