"""An event-driven simulator for balls on a line, in exact rational arithmetic.

This is the paper's own justification of the sequential resolution made executable: "nearby
trajectories that undergo successive single impacts" (Seghete & Murphey, sec. II-B, IV-A). The
balls start with tiny positive gaps; the simulator finds the next contact to close, advances every
ball to that instant, and resolves that one collision with Newton's law of restitution (``e = 1``,
elastic, by default; per contact if asked), until no contact will ever close again. It does not use
``G_u`` or any other impactsym law, so it is an independent check of
:func:`impactsym.laws.sequential.resolve_sequential`. It computes with FLINT's ``fmpq``
internally and returns SymPy rationals.

* Two balls ``a`` (left) and ``b`` (right), ``w = v_b − v_a < 0``: the impulse
  ``P = −(1 + e) w m_a m_b/(m_a + m_b)`` pushes ``b`` right and ``a`` left, so momentum is
  conserved and ``v_b' − v_a' = −e w`` (for ``e = 1``: ``v_a' = ((m_a − m_b) v_a + 2 m_b v_b)/(m_a + m_b)``).
* A ball and a fixed wall: ``v' = −e v``.

Two contacts that share a ball and close at the same instant are a simultaneous impact, which a
single-impact simulator cannot resolve: :class:`~impactsym.errors.DomainError` is raised (choose
other gaps). Contacts closing at the same instant that share no ball are independent and are all
resolved; a contact that touches and approaches at ``t = 0`` is resolved at ``t = 0``. With
``e < 1`` infinitely many collisions can accumulate before a finite time (inelastic collapse):
the run stops at its cap and is refused, saying whether the collision times were converging.

:func:`realize_ordering` chooses gaps that make a given impact ordering happen: with event times
``0 < T_1 < … < T_m`` and the velocities ``v_0, v_1, …`` of the ordering, every gap is piecewise
linear in time, so "contact ``c_s`` closes at ``T_s`` and every other gap stays positive" is a
linear program in the gaps and the intervals ``T_s − T_{s−1}``; it is solved exactly (SymPy's
rational simplex, run step for step in FLINT's ``fmpq``) maximizing the smallest margin, and the
gaps are then scaled down to ``scale`` (the schedule is invariant under scaling gaps and times together).

Examples
--------
>>> r = simulate_line([1, 1, 1], [1, 1, 1], [0, "2001/1000", "4002/1000"], [1, 0, 0])
>>> r.velocities, [name for _, name in r.events]
([0, 0, 1], ['1-2', '2-3'])
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import sympy as sp
from flint import fmpq

from .errors import DomainError, ImpactInputError
from .numbers import to_exact

__all__ = ["simulate_line", "SimulationResult", "realize_ordering", "perturbed_scene_positions",
           "DEFAULT_MAX_EVENTS",
           "DEFAULT_MAX_EVENTS_INELASTIC"]

#: cap on the number of collisions of one simulation when every contact is elastic
DEFAULT_MAX_EVENTS = 100_000
#: cap when some contact has ``e < 1``: every inelastic collision lengthens the exact numbers,
#: and a cascade that reaches this cap is diagnosed (inelastic collapse or not) and refused
DEFAULT_MAX_EVENTS_INELASTIC = 2_000


@dataclass
class SimulationResult:
    """What one simulation found, exact throughout.

    Attributes
    ----------
    velocities : list of sympy.Rational
        Final velocity of every ball.
    positions : list of sympy.Rational
        Ball centres at ``time``.
    events : list of (sympy.Rational, str)
        The collisions in order, as ``(time, contact name)``; independent collisions at one
        instant are listed in the order of the simulator's contacts (pairs left to right, then
        walls in the order given).
    time : sympy.Rational
        Time of the last collision (0 when there is none).
    impulses : dict
        Contact name → total impulse ``p ≥ 0`` of that contact (the multiplier of its gradient
        row as :func:`~impactsym.scenes.balls_on_line` builds it: ``−1`` on the left ball, ``+1``
        on the right one; ``+1`` for a ball right of a wall, ``−1`` left of it); only contacts
        that collided appear.
    energy_loss : sympy.Rational
        Kinetic energy lost, the sum over collisions of ``(1 − e²)/2 · μ w²`` (``μ`` the reduced
        mass of the pair, the ball's mass at a wall; ``w`` the approach speed); checked against
        the final velocities before return.
    """

    velocities: list
    positions: list
    events: list
    time: object
    impulses: dict = field(default_factory=dict)
    energy_loss: object = sp.Integer(0)


def _exact_list(values, argument):
    if isinstance(values, str) or not hasattr(values, "__len__"):
        raise ImpactInputError(argument, f"must be a sequence of exact numbers, got {values!r}")
    return [_exact_rational(x, argument) for x in values]


def _exact_rational(x, argument):
    if isinstance(x, float):
        raise ImpactInputError(argument, "the simulator is exact: give integers, rationals or decimal text")
    val = to_exact(x, argument)
    if not val.is_Rational:
        raise ImpactInputError(argument, f"the simulator works in rational arithmetic, got {val}")
    return val


def _fr(x) -> fmpq:
    """A SymPy Rational as a FLINT ``fmpq``, the simulator's working type: exact, and fast on the
    long numbers that inelastic cascades build (CPython's ``Fraction`` spends quadratic time in gcd)."""
    return fmpq(int(x.p), int(x.q))


def _sp(x: fmpq):
    return sp.Rational(int(x.p), int(x.q))


@dataclass
class _Contact:
    name: str
    kind: str  # "pair" (a left of b) or "wall"
    a: int | None  # pair: left ball; wall: None
    b: int  # pair: right ball; wall: the ball
    wall: fmpq | None = None
    side: int = 0  # wall: +1 ball right of it, -1 left of it
    e: fmpq = fmpq(1)

    @property
    def balls(self):
        return (self.a, self.b) if self.kind == "pair" else (self.b,)

    def gap(self, x, r):
        if self.kind == "pair":
            return x[self.b] - x[self.a] - r[self.a] - r[self.b]
        return (x[self.b] - r[self.b] - self.wall) if self.side > 0 else (self.wall - x[self.b] - r[self.b])

    def closing_rate(self, v):
        """``−H_c v``: positive when the contact approaches."""
        if self.kind == "pair":
            return v[self.a] - v[self.b]
        return -self.side * v[self.b]


def _restitution_of(restitution, contacts):
    """Set ``e`` on every contact from a scalar or a mapping contact name → e (others stay 1)."""
    from collections.abc import Mapping

    def one(value, what):
        e = _exact_rational(value, what)
        if not 0 <= e <= 1:
            raise ImpactInputError(what, f"must satisfy 0 <= e <= 1, got {e}")
        return _fr(e)

    if isinstance(restitution, Mapping):
        by_name = {c.name: c for c in contacts}
        for name, value in restitution.items():
            if name not in by_name:
                raise ImpactInputError("restitution", f"names no contact of this line: {name!r} (contacts: "
                                                      f"{', '.join(by_name) or 'none'})")
            by_name[name].e = one(value, f"restitution[{name!r}]")
    else:
        e = one(restitution, "restitution")
        for c in contacts:
            c.e = e


def simulate_line(masses, radii, positions, velocities, walls=(), *, restitution=1, contacts=None,
                  watch: bool = True, max_events: int | None = None) -> SimulationResult:
    """Simulate balls on a line (and fixed walls) until no contact will close again.

    Each collision obeys Newton's law of restitution, written here from first principles (not
    through impactsym's reflection maps, so the simulator stays an independent check). Balls
    ``a`` (left) and ``b`` (right), approach ``w = v_b − v_a < 0``: the impulse on ``b`` is
    ``P = −(1 + e) w · m_a m_b / (m_a + m_b)``, ``v_b' = v_b + P/m_b``, ``v_a' = v_a − P/m_a``, so
    momentum is conserved and ``v_b' − v_a' = −e w``. A ball at a wall: ``v' = −e v``.

    Collisions at one instant: contacts that close at the same time and share no ball are
    independent and are all resolved (in either order, the result is the same); two that share a
    ball are a simultaneous impact, which this single-impact simulator refuses. A contact that
    touches and approaches at ``t = 0`` closes at ``t = 0``, and is resolved first like any other.

    Parameters
    ----------
    masses, radii, positions, velocities : sequences of rationals, one per ball; balls must not
        overlap (gaps ≥ 0)
    walls : wall positions
    restitution : rational in ``[0, 1]``, or a mapping contact name → such a rational
        Newton's coefficient, for every contact or per contact (contacts not named are elastic).
    contacts : collection of contact names, optional
        Only these contacts collide (default: all). Every other contact is watched: if it closes
        before the last collision of these contacts, the simulation is refused (those contacts
        were meant to stay open while the impact lasts).
    watch : bool
        With ``contacts``: ``False`` ignores the other contacts instead of watching them (for a
        system that has no geometry beyond its contacts; balls may then pass through each other).
    max_events : int, optional
        Cap on the number of collisions; default ``DEFAULT_MAX_EVENTS`` (every contact elastic)
        or ``DEFAULT_MAX_EVENTS_INELASTIC``. Reaching it is refused (``DomainError``), and the
        message says whether the collision times were converging (an inelastic collapse: many
        collisions accumulating before a finite time).

    Returns
    -------
    SimulationResult
        ``events`` name contacts as the scene builders do: ``"i-j"`` (ball numbers, ``i < j``)
        and ``"wall@w-i"``. Verified before return: the kinetic energy equals the initial one
        minus ``energy_loss``, every ball's momentum change is the sum of its contacts'
        impulses, and without walls the total momentum is unchanged.

    Raises
    ------
    DomainError
        Two contacts that share a ball close at the same instant (a simultaneous impact), a
        watched contact closes during the impact, or the cap is reached.
    ImpactInputError
        Float or irrational input, overlaps, a restitution outside ``[0, 1]`` or naming no contact.

    Examples
    --------
    Three equal balls with small gaps, struck from the left, ``e = 1/2``: the first two balls
    meet again after the second collision (momentum 1 is kept, energy is lost):

    >>> r = simulate_line([1, 1, 1], [1, 1, 1], [0, 2, "41/10"], [1, 0, 0], restitution="1/2")
    >>> r.velocities, [name for _, name in r.events], r.energy_loss
    ([13/64, 15/64, 9/16], ['1-2', '2-3', '1-2'], 1203/4096)

    Two independent pairs closing at the same instant, and a contact touching and approaching
    at ``t = 0``:

    >>> r = simulate_line([1, 1, 1, 1], [1, 1, 1, 1], [0, "21/10", 10, "121/10"], [0, -1, 1, 0])
    >>> r.events, r.velocities
    ([(1/10, '1-2'), (1/10, '3-4')], [-1, 0, 0, 1])
    >>> simulate_line([2, 1], [1, 1], [0, 2], [1, 0], walls=[-1]).events
    [(0, '1-2')]
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
    if max_events is not None and (isinstance(max_events, bool) or not isinstance(max_events, int) or max_events < 1):
        raise ImpactInputError("max_events", f"must be a positive integer, got {max_events!r}")
    order = sorted(range(nb), key=lambda b: x[b])
    every: list[_Contact] = []
    for a, b in zip(order, order[1:]):
        if x[b] - x[a] - r[a] - r[b] < 0:
            raise ImpactInputError("positions", f"balls {a + 1} and {b + 1} overlap")
        every.append(_Contact(f"{min(a, b) + 1}-{max(a, b) + 1}", "pair", a, b))
    for wall in w:
        for b in range(nb):
            side = 1 if x[b] > wall else -1 if x[b] < wall else 0
            if side == 0 or (x[b] - r[b] - wall if side > 0 else wall - x[b] - r[b]) < 0:
                raise ImpactInputError("positions", f"ball {b + 1} overlaps the wall at {wall}")
            every.append(_Contact(f"wall@{wall}-{b + 1}", "wall", None, b, _fr(wall), side))
    _restitution_of(restitution, every)
    if contacts is None:
        active, watched = every, []
    else:
        if isinstance(contacts, str) or not hasattr(contacts, "__iter__"):
            raise ImpactInputError("contacts", f"must be a collection of contact names, got {contacts!r}")
        wanted = list(contacts)
        names = {c.name for c in every}
        unknown = [c for c in wanted if c not in names]
        if unknown:
            raise ImpactInputError("contacts", f"names no contact of this line: {unknown[0]!r} (contacts: "
                                               f"{', '.join(sorted(names)) or 'none'})")
        active = [c for c in every if c.name in wanted]
        watched = [c for c in every if c.name not in wanted] if watch else []
    inelastic = any(c.e != 1 for c in active)
    cap = max_events if max_events is not None else (DEFAULT_MAX_EVENTS_INELASTIC if inelastic else DEFAULT_MAX_EVENTS)
    mf, rf, xf, vf = [_fr(t) for t in m], [_fr(t) for t in r], [_fr(t) for t in x], [_fr(t) for t in v]
    v0 = list(vf)
    # The positions enter only through the gaps, so the loop tracks each contact's gap (exactly
    # ``gap(x(t))``: the gaps are linear in time between collisions, like the positions) and one
    # anchor ball's position (summed at the end from its velocities and their durations); the
    # colliding contact's gap is exactly 0 at its collision
    # (``g - rate · g/rate``). The final positions follow exactly from the anchor and the gaps of
    # the pairs, which chain every ball. Rates are recomputed only for the contacts of balls that
    # collided, and the energy losses and impulses are summed once at the end (pairwise). The
    # numbers are the same exact rationals as a per-ball position update would give.
    index = {id(c): i for i, c in enumerate(every)}
    gaps = [c.gap(xf, rf) for c in every]
    rates = [c.closing_rate(vf) for c in every]
    touching: dict = {}
    for i, c in enumerate(every):
        for b in c.balls:
            touching.setdefault(b, []).append(i)
    act = [index[id(c)] for c in active]
    wat = [index[id(c)] for c in watched]
    anchor = order[0]
    anchor_epochs = [(fmpq(0), vf[anchor])]  # (time, the anchor's velocity from then on)
    t = fmpq(0)
    events: list = []
    impulse_terms: dict = {}
    loss_terms: list = []

    def soonest(group):
        best, tied = None, []
        for i in group:
            rate = rates[i]
            if rate > 0:
                dt = gaps[i] / rate
                if best is None or dt < best:
                    best, tied = dt, [i]
                elif dt == best:
                    tied.append(i)
        return best, tied

    while True:
        dt, tied = soonest(act)
        if dt is None:
            break
        group = [every[i] for i in tied]
        wdt, wtied = soonest(wat)
        if wdt is not None and wdt <= dt:
            raise DomainError(
                f"contacts: contact {every[wtied[0]].name}, which is not simulated, closes at t = {_sp(t + wdt)}, "
                f"{'at the same instant as' if wdt == dt else 'before'} the next collision of the simulated "
                f"contacts ({group[0].name} at t = {_sp(t + dt)}): it does not stay open while the impact lasts")
        if len(group) > 1:
            shared = _shared_ball(group)
            if shared is not None:
                names = ", ".join(c.name for c in group)
                at_start = " (touching and approaching at t = 0)" if t + dt == 0 else ""
                raise DomainError(f"positions: contacts {names} close at the same instant t = {_sp(t + dt)}"
                                  f"{at_start} and share ball {shared + 1} (a simultaneous impact; choose other gaps)")
        if len(events) + len(group) > cap:
            raise DomainError(_cap_message(cap, [ev[0] for ev in events], inelastic))
        t_next = t + dt
        closing = set(tied)
        for i in range(len(every)):
            if i in closing:
                gaps[i] = fmpq(0)
            elif rates[i] != 0:
                gaps[i] = gaps[i] - rates[i] * dt
        moved = {b for c in group for b in c.balls}
        t = t_next
        for c in group:  # independent: no ball in common, so the order does not matter
            p, lost = _collide(c, mf, vf, -rates[index[id(c)]])
            if lost is not None:
                loss_terms.append(lost)
            impulse_terms.setdefault(c.name, []).append(p)
            events.append((t, c.name))
        for i in {i for b in moved for i in touching[b]}:
            rates[i] = every[i].closing_rate(vf)
        if anchor in moved:
            anchor_epochs.append((t, vf[anchor]))
    xf = list(xf)  # the anchor moved by the sum of its velocities times their durations
    ends = [tt for tt, _ in anchor_epochs[1:]] + [t]
    xf[anchor] = xf[anchor] + _pairwise_sum(vv * (end - start) for (start, vv), end in zip(anchor_epochs, ends))
    for c, g in zip(every, gaps):  # the pairs, left to right: x_b = x_a + r_a + r_b + gap
        if c.kind == "pair":
            xf[c.b] = xf[c.a] + rf[c.a] + rf[c.b] + g
    loss = _pairwise_sum(k * (w * w) for k, w in loss_terms)
    impulses = {n: _pairwise_sum(ps) for n, ps in impulse_terms.items()}
    _verify_final(m, [_sp(q) for q in v0], [_sp(q) for q in vf], bool(w), _sp(loss),
                  [(c, _sp(impulses[c.name])) for c in every if c.name in impulses])
    return SimulationResult([_sp(q) for q in vf], [_sp(q) for q in xf], [(_sp(tt), n) for tt, n in events], _sp(t),
                            {n: _sp(p) for n, p in impulses.items()}, _sp(loss))


def _pairwise_sum(terms) -> fmpq:
    """The exact sum of ``terms``, added pairwise (a balanced tree): the long partial sums of a
    cascade meet only near the root, instead of once per term."""
    terms = list(terms)
    if not terms:
        return fmpq(0)
    while len(terms) > 1:
        terms = [terms[i] + terms[i + 1] if i + 1 < len(terms) else terms[i] for i in range(0, len(terms), 2)]
    return terms[0]


def _shared_ball(group):
    seen = set()
    for c in group:
        for b in c.balls:
            if b in seen:
                return b
            seen.add(b)
    return None


def _collide(c: _Contact, m, v, w):
    """Newton's law on contact ``c``, in place on ``v``; returns the
    impulse and the kinetic energy lost, ``(1 − e²)/2 · μ w²``, as the pair ``((1 − e²)/2 · μ, w)`` (None
    when ``e = 1``: nothing is lost). ``w = −closing rate`` (``v_b − v_a`` for a pair, ``side · v_b`` at
    a wall) is passed in: the loop has it for the current velocities."""
    e = c.e
    if c.kind == "pair":
        a, b = c.a, c.b  # w = v[b] - v[a] < 0: approaching
        mu = m[a] * m[b] / (m[a] + m[b])
        p = -(1 + e) * mu * w  # impulse on b (rightward), on a leftward
        v[a] = v[a] - p / m[a]
        v[b] = v[b] + p / m[b]
    else:
        b = c.b  # w = side * v[b] < 0: approaching the wall
        mu = m[b]
        p = -(1 + e) * mu * w  # along the wall's normal (side)
        v[b] = v[b] + c.side * p / m[b]
    return p, (None if e == 1 else ((1 - e * e) / 2 * mu, w))


def _cap_message(cap, times, inelastic) -> str:
    """Why the cap was reached: collision times that converge (quarters of the run each at most
    half as long as the one before, or all at one instant) point to an inelastic collapse."""
    q = len(times) // 4
    converging = False
    if q >= 1:
        t0, t1, t2, t3, t4 = times[0], times[q], times[2 * q], times[3 * q], times[-1]
        d1, d2, d3, d4 = t1 - t0, t2 - t1, t3 - t2, t4 - t3
        converging = 2 * d4 <= d3 and 2 * d3 <= d2 and 2 * d2 <= d1 if d1 > 0 else d4 == 0
    if converging:
        last = times[-1]
        where = f"t = {_sp(last)}" if times[-1] == times[3 * q] else f"about t = {float(last):.6g}"
        return (f"max_events: inelastic collapse: {cap} collisions and the collision times converge "
                f"(each quarter of the run at most half as long as the one before; the last at {where}): "
                f"infinitely many collisions accumulate before a finite time, which a collision-by-collision "
                f"simulation cannot finish; no result is returned")
    what = " (some contacts inelastic)" if inelastic else ""
    return (f"max_events: more than {cap} collisions (the configured cap){what}; the collision times "
            f"do not converge; no result is returned")


def _verify_final(m, v0, v, walls: bool, energy_loss=0, impulses=()) -> None:
    """The exact final velocities are checked before they are returned (a failure is a bug): the
    kinetic energy is the initial one minus ``energy_loss`` (0 when every collision is elastic);
    without walls the momentum is unchanged; each ball's momentum change is the sum of its
    contacts' impulses (``impulses``: pairs ``(contact, p)``)."""
    from .errors import VerificationError

    if sum(mi * vi * vi for mi, vi in zip(m, v)) != sum(mi * vi * vi for mi, vi in zip(m, v0)) - 2 * energy_loss:
        raise VerificationError("simulate_line", "the final kinetic energy differs from the initial one minus "
                                                 "the collisions' losses")
    if not walls and sum(mi * vi for mi, vi in zip(m, v)) != sum(mi * vi for mi, vi in zip(m, v0)):
        raise VerificationError("simulate_line", "the final momentum differs from the initial one")
    if impulses:
        change = [sp.Integer(0)] * len(m)
        for c, p in impulses:
            if p < 0:
                raise VerificationError("simulate_line", f"contact {c.name} has a negative impulse {p}")
            if c.kind == "pair":
                change[c.a] -= p
                change[c.b] += p
            else:
                change[c.b] += c.side * p
        if any(mi * (vi - ui) != ch for mi, vi, ui, ch in zip(m, v, v0, change)):
            raise VerificationError("simulate_line", "a ball's momentum change differs from its contacts' impulses")


def _ordering_lp(M, H, v0, order):
    """The LP of :func:`realize_ordering`: maximize the margin ``delta`` over the gaps ``g`` (one per
    contact), the interval lengths ``dt`` and ``delta`` itself, with every gap and interval ``>= delta``,
    the contact hit at event ``s`` closing exactly then, and the gaps summing to at most 1. Returns
    ``(k, c, A_ub, b_ub, A_eq, b_eq)`` as lists of exact entries, variables ``g, dt, delta >= 0``."""
    k = H.shape[0]
    m = len(order)
    Mi, Hi = sp.ImmutableMatrix(M), sp.ImmutableMatrix(H)
    order = tuple(int(c) for c in order)
    w = [_closing_rates(Mi, Hi, sp.ImmutableMatrix(v0), order[:s]) for s in range(m + 1)]
    # w[s][i]: closing rate of contact i during interval s (after event s)
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
    return k, c, A_ub, b_ub, A_eq, b_eq


@lru_cache(maxsize=4096)
def _velocity_after(M, H, v0, prefix):
    """The velocity after the single impacts ``prefix`` (exact, verified by ``reflect``), remembered
    per prefix: the orderings of one scene share their prefixes, so each is reflected once."""
    from .laws.reflection import reflect

    if not prefix:
        return v0
    v = _velocity_after(M, H, v0, prefix[:-1])
    if all(x.is_Rational for x in v) and _rational_contact(M, H, prefix[-1]) is not None:
        return _reflect_rational(M, H, prefix[-1], v)
    return sp.ImmutableMatrix(reflect(M, H[prefix[-1], :], v))


@lru_cache(maxsize=256)
def _rational_contact(M, H, i):
    """``(M, h, w = M⁻¹hᵀ, s = h w)`` in ``fmpq`` for contact ``i`` of a rational scene (None otherwise)."""
    from flint import fmpq_mat

    if not all(x.is_Rational for x in list(M) + list(H[i, :])):
        return None
    n = M.shape[0]
    Mq = fmpq_mat(n, n, [_fr(x) for x in M])
    h = [_fr(x) for x in H[i, :]]
    w = Mq.solve(fmpq_mat(n, 1, h))
    w = [w[j, 0] for j in range(n)]
    return Mq, h, w, sum((a * b for a, b in zip(h, w)), fmpq(0))


def _reflect_rational(M, H, i, v):
    """The elastic reflection of ``v`` on contact ``i``, ``v⁺ = v − 2 (h v)/(h M⁻¹hᵀ) M⁻¹hᵀ``, in
    ``fmpq`` (the same exact values as :func:`impactsym.laws.reflection.reflect`), verified before
    return like ``reflect``: ``M(v⁺ − v) = hᵀp`` and Newton's ``h v⁺ = −h v``."""
    from .errors import VerificationError

    Mq, h, w, s = _rational_contact(M, H, i)
    n = len(h)
    vq = [_fr(x) for x in v]
    hv = sum((a * b for a, b in zip(h, vq)), fmpq(0))
    p = -2 * hv / s
    out = [x + p * y for x, y in zip(vq, w)]
    dv = [a - b for a, b in zip(out, vq)]
    if any(sum((Mq[r, j] * dv[j] for j in range(n)), fmpq(0)) != h[r] * p for r in range(n)) or \
            sum((a * b for a, b in zip(h, out)), fmpq(0)) != -hv:
        raise VerificationError("reflection", "M(v+ - v) != h^T p or h v+ != -h v")
    return sp.ImmutableMatrix([_sp(x) for x in out])


@lru_cache(maxsize=4096)
def _closing_rates(M, H, v0, prefix):
    return H * _velocity_after(M, H, v0, prefix)


def ordering_realizable(M, H, v0, order) -> bool:
    """Whether some positive gaps make the impact ``order`` happen: the LP of
    :func:`realize_ordering` has a positive optimal margin, decided exactly (an exact simplex whose
    optimum is certified by a dual point, :func:`impactsym.arithmetic.exact_lp.maximize`). The same
    verdict as ``realize_ordering(...) is not None``, without building the gaps.

    >>> import sympy as sp
    >>> M, H, v0 = sp.eye(2), sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-1, -2])
    >>> ordering_realizable(M, H, v0, [1, 0, 1, 0]), ordering_realizable(M, H, v0, [1, 1])
    (True, False)
    """
    decided = _margin_positive(*_ordering_lp(M, H, v0, order)[1:])
    return decided if decided is not None else realize_ordering(M, H, v0, order) is not None


def _margin_positive(c, A_ub, b_ub, A_eq, b_eq):
    """True/False: the ordering LP's optimal margin is positive (exact, certified); None when its
    data are not all rational (SymPy's ``linprog`` then decides)."""
    from .arithmetic.exact_lp import maximize
    from .errors import VerificationError

    if not all(getattr(x, "is_Rational", False) for row in A_ub + A_eq for x in row):
        return None
    r = maximize([-x for x in c], A_ub, b_ub, A_eq, b_eq)  # c is linprog's (minimize -delta)
    if r.status != "optimal":  # z = 0 is feasible and delta <= 1: never reached for this LP
        raise VerificationError("ordering_realizable", f"the ordering LP is {r.status}")
    return r.value > 0


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

    The answer is a function of the exact data alone; the last 512 are remembered (a scene's
    orderings are asked for again by the figures and the findings that draw on them). The vertex
    is SymPy's ``linprog``'s: its simplex is run pivot for pivot in ``fmpq`` (SymPy's own
    ``linprog`` when the data are not all rational).
    """
    gaps = _realize_ordering(sp.ImmutableMatrix(M), sp.ImmutableMatrix(H), sp.ImmutableMatrix(v0),
                             tuple(int(c) for c in order), sp.sympify(scale))
    return None if gaps is None else list(gaps)


@lru_cache(maxsize=512)
def _realize_ordering(M, H, v0, order, scale):
    M, H, v0 = sp.Matrix(M), sp.Matrix(H), sp.Matrix(v0)
    k, c, A_ub, b_ub, A_eq, b_eq = _ordering_lp(M, H, v0, order)
    rational = all(getattr(x, "is_Rational", False) for row in [c, b_ub, b_eq] + A_ub + A_eq for x in row)
    solved = _linprog_fmpq(c, A_ub, b_ub, A_eq, b_eq) if rational else _linprog_sympy(c, A_ub, b_ub, A_eq, b_eq)
    if solved is None:
        return None
    val, z = solved
    if -val <= 0:
        return None
    gaps = [z[i] for i in range(k)]
    top = max(gaps)
    return tuple(sp.Rational(g) / top * scale for g in gaps)


def _linprog_sympy(c, A_ub, b_ub, A_eq, b_eq):
    """SymPy's ``linprog`` on the ordering LP: ``(value, point)``, or None when infeasible."""
    from sympy.solvers.simplex import InfeasibleLPError, linprog

    try:
        return linprog(sp.Matrix([c]), sp.Matrix(A_ub), sp.Matrix(b_ub),
                       sp.Matrix(A_eq) if A_eq else None, sp.Matrix(b_eq) if b_eq else None)
    except InfeasibleLPError:
        return None


def _linprog_fmpq(c, A_ub, b_ub, A_eq, b_eq):
    """SymPy's ``linprog`` (SymPy 1.14's ``sympy.solvers.simplex``: the two-phase tableau
    simplex with Bland's rule, equalities as two inequalities, variables ``>= 0``) step for step
    in FLINT's ``fmpq``: the same tableau, the same pivots in the same order, hence the same
    vertex, many times faster on the ordering LPs. Rational data only. Returns
    ``(value, point)`` as SymPy rationals like ``linprog`` (minimum of ``c · z``), or None when
    infeasible. The optimum is certified before return: the point satisfies every constraint
    exactly, the tableau's dual point is dual feasible, and both have the value (a failure raises)."""
    from .errors import VerificationError

    q = lambda x: fmpq(int(x.p), int(x.q))  # noqa: E731
    rows = [[q(x) for x in row] + [q(b)] for row, b in zip(A_ub, b_ub)]
    rows += [[q(x) for x in row] + [q(b)] for row, b in zip(A_eq, b_eq)]
    rows += [[-q(x) for x in row] + [-q(b)] for row, b in zip(A_eq, b_eq)]
    T = [list(row) for row in rows] + [[q(x) for x in c] + [fmpq(0)]]  # [[A, B], [C, D = 0]]
    n, m = len(c), len(rows)
    X = [(False, j) for j in range(n)]  # x variables before y variables in Bland's rule
    Y = [(True, i) for i in range(m)]

    def pivot(r, j):  # sympy.solvers.simplex._pivot, in place; rows with a zero in column j stay
        Mi, Mij = T[r], T[r][j]
        scaled = [x / Mij for x in Mi]
        nz = [jj for jj, x in enumerate(scaled) if x != 0 and jj != j]
        for i, row in enumerate(T):
            if i == r:
                continue
            f = row[j]
            if f != 0:
                for jj in nz:
                    row[jj] = row[jj] - f * scaled[jj]
                row[j] = -f / Mij
        scaled[j] = 1 / Mij
        T[r] = scaled

    def choose_row(cands, col):  # smallest ratio, ties by Bland's rule
        return min(cands, key=lambda i: (T[i][-1] / T[i][col], Y[i]))

    last = None
    while True:  # phase 1: a feasible tableau
        k = next((i for i in range(m) if T[i][-1] < 0), None)
        if k is None:
            break
        cols = [j for j in range(n) if T[k][j] < 0]
        if not cols:
            return None  # the constraint set is empty
        _, col = min((X[j], j) for j in cols)
        cands = [i for i in range(m) if T[i][col] > 0 and T[i][-1] > 0]
        cands.append(k)
        r = choose_row(cands, col)
        if (r, col) == last:  # SymPy's guard against oscillation (the point is checked below)
            last = True
            break
        last = r, col
        pivot(r, col)
        X[col], Y[r] = Y[r], X[col]
    while True:  # phase 2: to the optimum
        cols = [j for j in range(n) if T[-1][j] < 0]
        if not cols:
            break
        _, col = min((X[j], j) for j in cols)
        cands = [i for i in range(m) if T[i][col] > 0]
        if not cands:
            raise VerificationError("realize_ordering", "the ordering LP is unbounded (its margin is at most 1)")
        r = choose_row(cands, col)
        pivot(r, col)
        X[col], Y[r] = Y[r], X[col]
    point = [fmpq(0)] * n
    for i, (isy, j) in enumerate(Y):
        if not isy:
            point[j] = T[i][-1]
    value = -T[-1][-1]
    if last and not (all(x >= 0 for x in point) and all(T[-1][i] >= 0 for i, (isy, _) in enumerate(X) if isy)):
        return None  # SymPy: "Oscillating system led to invalid solution" (its argmax and dual point)
    # the certificate: the point is feasible, the tableau's dual point y >= 0 is dual feasible
    # (A^T y >= -c), and c . z = -b . y, so the value is the exact optimum (weak duality)
    dual = [fmpq(0)] * m
    for i, (isy, j) in enumerate(X):
        if isy:
            dual[j] = T[-1][i]
    feasible = all(x >= 0 for x in point) and all(
        sum((a * z for a, z in zip(row[:-1], point)), fmpq(0)) <= row[-1] for row in rows)
    cq = [q(x) for x in c]
    optimal = all(y >= 0 for y in dual) and all(
        sum((rows[i][j] * dual[i] for i in range(m) if dual[i] != 0), fmpq(0)) >= -cq[j] for j in range(n)) and (
        -sum((rows[i][-1] * dual[i] for i in range(m) if dual[i] != 0), fmpq(0)) == value)
    if not feasible or not optimal or sum((a * z for a, z in zip(cq, point)), fmpq(0)) != value:
        raise VerificationError("realize_ordering", "the simplex point or its dual point violates the ordering "
                                                    "LP, or their values differ")
    basic = {j for isy, j in Y if not isy}
    return _sp(value), [_sp(z) if j in basic else 0 for j, z in enumerate(point)]  # SymPy: int 0 off the basis


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
