"""Sequential resolution with restitution e < 1 per contact, and inelastic collapse.

The reference is an independent exact event loop (below): point masses on a line, optionally a
wall at x = 0, small positive gaps, exact Fractions, Newton restitution per contact. Small gaps
realize one ordering; the resolver must list that ordering and give exactly the event loop's
final velocity. Every comparison is exact (Rational equality or exact inequalities).
"""

from __future__ import annotations

import random
from fractions import Fraction as Q

import numpy as np
import pytest
import sympy as sp
from flint import fmpq

from impactsym.errors import DomainError, ImpactInputError, NonTermination
from impactsym.laws.sequential import InfiniteOrder, critical_restitution, resolve_sequential
from impactsym.laws.sequential.collapse import _never_ends
from impactsym.laws.sequential.common import _Rational
from impactsym.numbers import float_to_rational

EYE3 = "1,0,0;0,1,0;0,0,1"
CHAIN3 = "-1,1,0;0,-1,1"


# ---------------------------------------------------------------------------------------------
# the independent exact event loop
# ---------------------------------------------------------------------------------------------
def _contacts(nballs, wall):
    """Contacts as (i, j): ball j right of ball i; i = -1 is a wall at x = 0 left of ball 0."""
    return ([(-1, 0)] if wall else []) + [(i, i + 1) for i in range(nballs - 1)]


def scene(masses, wall=False):
    """``(M, H)`` as the resolver's strings, rows in the order of :func:`_contacts`."""
    n = len(masses)
    M = ";".join(",".join(str(masses[i]) if i == j else "0" for j in range(n)) for i in range(n))
    rows = []
    for i, j in _contacts(n, wall):
        row = [0] * n
        if i >= 0:
            row[i] = -1
        row[j] = 1
        rows.append(",".join(map(str, row)))
    return M, ";".join(rows)


def _fq(x) -> fmpq:
    """An exact rational (int, str, Fraction) as a flint fmpq: the event loops below run in fmpq,
    whose big-integer gcds are far cheaper than Fraction's over hundreds of collisions."""
    x = Q(x)
    return fmpq(x.numerator, x.denominator)


def _Q(x: fmpq) -> Q:
    return Q(int(x.p), int(x.q))


def event_loop(masses, gaps, v0, e, wall=False, max_events=5000, partial=False):
    """Exact event-driven motion of point masses with the given gaps (one per contact, > 0).

    Returns (order of contacts hit, final velocities as Fractions), or ``None`` after
    ``max_events`` (with ``partial``: the order of the first ``max_events`` events).
    Refuses simultaneous events (the gaps must separate them). Exact rationals throughout (fmpq)."""
    m = [_fq(x) for x in masses]
    v = [_fq(x) for x in v0]
    cs = _contacts(len(m), wall)
    e = [_fq(x) for x in e]
    # the gap of each contact (x_j - x_i, the wall at x = 0): the positions enter only through them
    g = [_fq(gaps[c]) for c in range(len(cs))]
    order = []
    for _ in range(max_events):
        best = None
        rels = []
        for c, (i, j) in enumerate(cs):
            rel = v[j] - (v[i] if i >= 0 else 0)
            rels.append(rel)
            if rel < 0:
                dt = g[c] / -rel
                assert dt >= 0
                if best is not None and dt == best[0]:
                    raise AssertionError("simultaneous events: choose other gaps")
                if best is None or dt < best[0]:
                    best = (dt, c)
        if best is None:
            return tuple(order), [_Q(vi) for vi in v]
        dt, c = best
        g = [gc + rel * dt for gc, rel in zip(g, rels)]  # the bodies move on for dt
        i, j = cs[c]
        rel = v[j] - (v[i] if i >= 0 else 0)
        s = 1 / m[j] + (1 / m[i] if i >= 0 else 0)
        k = (1 + e[c]) * rel / s  # G(e): v <- v - k M^-1 H_c^T
        if i >= 0:
            v[i] += k / m[i]
        v[j] -= k / m[j]
        order.append(c)
    return tuple(order) if partial else None


def _rat(f):
    return sp.Rational(f.numerator, f.denominator)


def _outcome_of(res, order):
    for o, idx in res.iter_orderings():
        if not isinstance(o, InfiniteOrder) and tuple(o) == tuple(order):
            return res.outcomes[idx]
    raise AssertionError(f"ordering {order} not among the resolver's orderings")


def _check_against_event_loop(masses, gaps, v0, e, wall=False):
    M, H = scene(masses, wall)
    res = resolve_sequential(M, H, ",".join(map(str, v0)), restitution=[str(x) for x in e], select=False)
    run = event_loop(masses, gaps, v0, e, wall)
    assert run is not None
    order, vfin = run
    o = _outcome_of(res, order)
    assert list(o.velocity) == [_rat(f) for f in vfin]
    return res, order, o


# ---------------------------------------------------------------------------------------------
# the event loop against the resolver, e < 1
# ---------------------------------------------------------------------------------------------
def test_three_ball_cradle_half_restitution_matches_event_loop():
    res, order, o = _check_against_event_loop([1, 1, 1], [Q(1, 100), Q(1, 50)], [1, 0, 0], [Q(1, 2)] * 2)
    assert order == (0, 1, 0) and list(o.velocity) == [sp.Rational(13, 64), sp.Rational(15, 64), sp.Rational(9, 16)]
    assert list(o.impulse) == [sp.Rational(51, 64), sp.Rational(9, 16)]
    # mutation: ignoring e (elastic) gives (0, 0, 1)
    assert list(resolve_sequential(EYE3, CHAIN3, "1,0,0").outcomes[0].velocity) == [0, 0, 1]
    assert res.restitution == (sp.Rational(1, 2),) * 2 and res.method == "iteration" and not res.collapse


@pytest.mark.parametrize("gaps", [(Q(1, 1000), Q(3, 1000)), (Q(3, 1000), Q(1, 1000))])
def test_both_contacts_approaching_each_gap_order_realizes_its_ordering(gaps):
    masses, v0, e = [1, 2, 3], [2, 0, -1], [Q(1, 2), Q(1, 3)]
    res, order, o = _check_against_event_loop(masses, list(gaps), v0, e)
    assert order[0] == (0 if gaps[0] < gaps[1] else 1)
    assert len(res.outcomes) >= 1 and res.orderings >= 2


@pytest.mark.parametrize("gaps", [(Q(1, 100), Q(1, 70)), (Q(1, 70), Q(1, 100))])
def test_two_balls_and_a_wall_per_contact_restitution(gaps):
    # sec. III-B.1's scene (M = I, a wall and two balls), e = 1/2 at the wall, 3/4 between the balls
    res, order, o = _check_against_event_loop([1, 1], list(gaps), [-1, -2], [Q(1, 2), Q(3, 4)], wall=True)
    assert res.method == "iteration"  # two contacts with e < 1: iterated, not the elastic closed form
    elastic = resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2", two_surface="closed-form")
    assert elastic.method == "two-surface closed form"
    assert all(list(o.velocity) != list(x.velocity) for x in elastic.outcomes)


def _random_chains(seed: int, count: int, p_wall: float):
    """``count`` random chains (2 to 4 balls, a wall with probability ``p_wall``), each as
    ``(masses, wall, e, v0, M, H, gaps)``; the chains where nothing approaches are dropped.
    e >= 1/2 stays above every critical restitution of these masses (cos^2 <= 4/5 -> e_c < 0.39)."""
    rng = random.Random(seed)
    for _ in range(count):
        n = rng.randint(2, 4)
        wall = rng.random() < p_wall
        masses = [rng.randint(1, 4) for _ in range(n)]
        k = n - 1 + wall
        e = [Q(rng.randint(4, 8), 8) for _ in range(k)]
        v0 = [Q(rng.randint(-6, 6), rng.randint(1, 3)) for _ in range(n)]
        M, H = scene(masses, wall)
        Hm = sp.Matrix([[int(t) for t in r.split(",")] for r in H.split(";")])
        if all(x >= 0 for x in Hm * sp.Matrix([_rat(x) for x in v0])):
            continue  # nothing approaches
        gaps = [Q(rng.randint(1, 10**6), 10**9) for _ in range(k)]
        yield masses, wall, e, v0, M, H, gaps


def test_random_chains_match_event_loop():
    checked = 0
    for masses, wall, e, v0, M, H, gaps in _random_chains(20261130, 25, 0.3):
        try:
            _check_against_event_loop(masses, gaps, v0, e, wall)
        except AssertionError as exc:
            if "simultaneous" in str(exc):
                continue
            raise
        checked += 1
    assert checked >= 15


# ---------------------------------------------------------------------------------------------
# per-contact e, e = 0, e = 1 unchanged
# ---------------------------------------------------------------------------------------------
def test_per_contact_restitution_each_entry_matters():
    r = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=["1/2", "0"])
    (o,) = r.outcomes
    assert o.order == (0, 1) and list(o.velocity) == [sp.Rational(1, 4), sp.Rational(3, 8), sp.Rational(3, 8)]
    run = event_loop([1, 1, 1], [Q(1, 10), Q(1, 20)], [1, 0, 0], [Q(1, 2), 0])
    assert run[0] == (0, 1) and [_rat(f) for f in run[1]] == list(o.velocity)
    swapped = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=["0", "1/2"]).outcomes[0]
    same = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution="1/2").outcomes[0]
    assert list(swapped.velocity) != list(o.velocity) and list(same.velocity) != list(o.velocity)


def test_restitution_zero_is_plastic_per_impact():
    # perpendicular contacts (a corner): each impact stops its contact; finite, v+ = 0
    r = resolve_sequential("1,0;0,1", "1,0;0,1", "-1,-2", restitution=0)
    (o,) = r.outcomes  # both orderings end at rest: one outcome
    assert o.order == (0, 1) and o.orderings == 2 and list(o.velocity) == [0, 0] and list(o.impulse) == [1, 2]
    # two balls and a wall, e = 0: the wall and the pair alternate forever; the limit is rest
    r = resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2", restitution=0)
    assert all(o.collapse for o in r.outcomes)
    assert [list(o.velocity) for o in r.outcomes] == [[0, 0]] * len(r.outcomes)
    # p = -Gram^-1 H v0 with Gram = [[1, -1], [-1, 2]], H v0 = (-1, -1): p = (3, 2)
    assert all(list(o.impulse) == [3, 2] for o in r.outcomes)


@pytest.mark.parametrize("restitution", [1, "1", [1, 1], (sp.Integer(1), "1")])
def test_restitution_one_is_the_elastic_law_unchanged(restitution):
    base = resolve_sequential("11/10,0;0,1", "1,0;-1,1", "-1,-2")
    r = resolve_sequential("11/10,0;0,1", "1,0;-1,1", "-1,-2", restitution=restitution)
    assert r.outcomes == base.outcomes and r.selected == base.selected and r.reading == "energy"
    c = resolve_sequential(EYE3, CHAIN3, "1,1,0", restitution=restitution, two_surface="iterate")
    assert c.outcomes == resolve_sequential(EYE3, CHAIN3, "1,1,0", two_surface="iterate").outcomes


# ---------------------------------------------------------------------------------------------
# the critical restitution and inelastic collapse
# ---------------------------------------------------------------------------------------------
def _G(M, u, e):
    w = M.LUsolve(u.T)
    return sp.eye(M.shape[0]) - (1 + e) * w * u / (u * w)[0, 0]


def test_critical_restitution_three_equal_balls_is_7_minus_4_sqrt3():
    e = sp.Symbol("e", positive=True)
    lam = sp.Symbol("lam")
    M = sp.eye(3)
    A, B = sp.Matrix([[-1, 1, 0]]), sp.Matrix([[0, -1, 1]])
    P = _G(M, B, e) * _G(M, A, e)  # one full alternation 1-2, 2-3
    poly = sp.Poly(P.charpoly(lam).as_expr().subs(sp.Symbol("lambda"), lam), lam)
    # (lambda - 1) on the M-orthogonal complement, a quadratic on the plane of the two normals
    quad, rem = sp.div(poly, sp.Poly(lam - 1, lam))
    assert rem.is_zero
    assert quad.degree() == 2
    a2, a1, a0 = quad.all_coeffs()
    assert sp.simplify(a0 / a2 - e**2) == 0  # det = e_A e_B
    disc = sp.factor(a1**2 - 4 * a2 * a0)
    roots = [r for r in sp.solve(disc, e) if r.is_real and 0 < r < 1]
    assert len(roots) == 1
    ec = roots[0]
    assert sp.simplify(ec - (7 - 4 * sp.sqrt(3))) == 0
    assert sp.simplify(critical_restitution(EYE3, CHAIN3) - (7 - 4 * sp.sqrt(3))) == 0
    # below e_c the eigenvalues are real and < 1 (the alternation contracts), above they are complex
    for val, real in ((sp.Rational(717, 10000), True), (sp.Rational(718, 10000), False)):
        d = disc.subs(e, val)
        assert (d >= 0) == real
        if real:
            assert all(0 < sp.re(x) < 1 for x in sp.Poly(quad.as_expr().subs(e, val), lam).nroots(n=50))


def _pure_alternation_count(e, limit):
    """Independent count of the alternation 1-2, 2-3, 1-2, ... of three equal balls, v0 = (1,0,0)
    (exact, fmpq)."""
    e = _fq(e)
    v = [fmpq(1), fmpq(0), fmpq(0)]
    c = 0
    n = 0
    while n < limit:
        i = c
        rel = v[i + 1] - v[i]
        if rel >= 0:
            return n
        k = (1 + e) * rel / 2
        v[i] += k
        v[i + 1] -= k
        n += 1
        c = 1 - c
    return None


def test_just_above_critical_is_finite_just_below_is_collapse():
    above, below = sp.Rational(718, 10000), sp.Rational(717, 10000)
    ec = 7 - 4 * sp.sqrt(3)
    assert sp.sign(above - ec) == 1 and sp.sign(below - ec) == -1  # exact: they bracket e_c
    (o,) = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=above, select=False).outcomes
    assert not o.collapse and o.reflections == _pure_alternation_count(Q(718, 10000), 10**4) == 503
    run = event_loop([1, 1, 1], [Q(1, 10**6), Q(1, 10**6) + Q(1, 10**9)], [1, 0, 0], [Q(718, 10000)] * 2)
    assert run[0] == tuple(o.order) and [_rat(f) for f in run[1]] == list(o.velocity)
    (c,) = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=below, select=False).outcomes
    assert c.collapse and c.reflections is None and c.order == InfiniteOrder((), (0, 1))
    assert list(c.velocity) == [sp.Rational(1, 3)] * 3 and list(c.impulse) == [sp.Rational(2, 3), sp.Rational(1, 3)]
    assert _pure_alternation_count(Q(717, 10000), 600) is None  # consistent: no end within 600 (503 above)
    # algebraic restitutions bracketing e_c exactly; e_c itself: the double eigen-direction attracts
    (a,) = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=ec + sp.Rational(1, 1000), select=False).outcomes
    assert not a.collapse and a.reflections == 28
    for val in (ec - sp.Rational(1, 10**9), ec, sp.Integer(0)):
        (b,) = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=val, select=False).outcomes
        assert b.collapse and list(b.velocity) == [sp.Rational(1, 3)] * 3


def test_critical_restitution_other_pairs():
    assert critical_restitution("1,0;0,3", "1,0;-1,1") == sp.Rational(1, 3)
    assert critical_restitution("1,0;0,1", "1,0;0,1") == 0  # perpendicular: never
    assert sp.simplify(critical_restitution("1,0;0,1", "1,0;-1,1") - (3 - 2 * sp.sqrt(2))) == 0
    # the wall/ball pair of sec. III-B.1 collapses just below 3 - 2 sqrt 2 and not just above
    (o,) = resolve_sequential("1,0;0,1", "1,0;-1,1", "0,-1", restitution="17/100", select=False).outcomes
    assert o.collapse and o.order.prefix == () and list(o.velocity) == [0, 0]
    (o,) = resolve_sequential("1,0;0,1", "1,0;-1,1", "0,-1", restitution="172/1000", select=False).outcomes
    assert not o.collapse
    with pytest.raises(ImpactInputError, match="second"):
        critical_restitution(EYE3, CHAIN3, 1, 1)


def test_collapse_limit_is_the_plastic_projection_symbolically():
    """Sum the geometric series of one pair's alternation in closed form: the total impulse is
    -Gram^-1 (H_A v, H_B v), i.e. the limit is the M-orthogonal projection onto H_A v = H_B v = 0."""
    sA, sB, eA, eB, u, s = sp.symbols("s_A s_B e_A e_B u s", positive=True)
    g = -sp.Symbol("gamma", positive=True)
    kA, kB = -(1 + eA) * g / sA, -(1 + eB) * g / sB
    Qm = sp.Matrix([[kA * kB - eA, -kB], [eB * kA, -eB]])  # (u, s) before A -> after A then B
    total = (sp.eye(2) - Qm).inv() * sp.Matrix([u, s])  # sum_n Q^n z (spectral radius < 1)
    pA = (1 + eA) / sA * total[0]  # an A impact with approach speed u gives (1+e_A) u / s_A
    pB = (1 + eB) / sB * (kA * total[0] - total[1])  # the B approach speed is k_A u - s
    gram = sp.Matrix([[sA, g], [g, sB]])
    plastic = -gram.inv() * sp.Matrix([-u, s])  # (a, b) = (H_A v, H_B v) = (-u, s)
    # rational functions of the symbols: their normal form (cancel) decides the identity exactly
    assert sp.cancel(pA - plastic[0]) == 0 and sp.cancel(pB - plastic[1]) == 0


def test_iterates_converge_to_the_returned_limit():
    e = Q(1, 20)
    (o,) = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=sp.Rational(1, 20), select=False).outcomes
    vinf = [Q(int(x.p), int(x.q)) for x in o.velocity]
    v = [Q(1), Q(0), Q(0)]
    prev = None
    for n in range(80):
        i = n % 2
        rel = v[i + 1] - v[i]
        assert rel < 0  # every impact of the alternation acts on an approached contact
        k = (1 + e) * rel / 2
        v[i] += k
        v[i + 1] -= k
        d = sum((a - b) ** 2 for a, b in zip(v, vinf))
        assert prev is None or d < prev
        prev = d
    assert prev < Q(1, 10**40)


def _lcm(a, b):
    import math

    return math.lcm(int(a), int(b))


def test_pair_decision_agrees_with_brute_force():
    rng = random.Random(7)
    F = _Rational
    never, ended = 0, 0
    for _ in range(800):
        # Gram entries with g^2 < s_A s_B and g < 0: s_A = c p^2, s_B = c q^2, g = -t c p q, 0 < t < 1
        c, p_, q_ = rng.randint(1, 5), rng.randint(1, 3), rng.randint(1, 3)
        sA, sB = F.num(sp.Integer(c * p_ * p_)), F.num(sp.Integer(c * q_ * q_))
        g = F.num(-sp.Rational(rng.randint(1, 99), 100) * c * p_ * q_)
        eA, eB = F.num(sp.Rational(rng.randint(0, 100), 100)), F.num(sp.Rational(rng.randint(0, 100), 100))
        a, b = F.num(sp.Rational(-rng.randint(1, 9), 1)), F.num(sp.Rational(rng.randint(-3, 9), rng.randint(1, 5)))
        decided = _never_ends(F, sA, sB, g, eA, eB, a, b, (1, 2))
        # brute force: alternate A, B exactly in (a, b): A maps (x, y) to (-eA x, y - kA x), B to
        # (x - kB y, -eB y). Only the signs of x and y decide, so the pair is carried as integers
        # (X, Y) = D (x, y) for a positive D, each step multiplying D by its common denominator
        # (no gcd of ever longer fractions)
        kA, kB = (1 + eA) * g / sA, (1 + eB) * g / sB
        dA, dB = _lcm(eA.q, kA.q), _lcm(eB.q, kB.q)
        eAi, kAi, eBi, kBi = (int(t * d) for t, d in ((eA, dA), (kA, dA), (eB, dB), (kB, dB)))
        den = _lcm(a.q, b.q)
        x, y, turn, steps = int(a * den), int(b * den), 0, 0
        while steps < 300:
            if turn == 0:
                if x >= 0:
                    break
                x, y = -eAi * x, int(dA) * y - kAi * x
            else:
                if y >= 0:
                    break
                x, y = int(dB) * x - kBi * y, -eBi * y
            turn, steps = 1 - turn, steps + 1
        finished = steps < 300
        if finished:
            assert not decided, (sA, sB, g, eA, eB, a, b, steps)
            ended += 1
        if decided:
            assert not finished
            never += 1
    assert never >= 30 and ended >= 30


# ---------------------------------------------------------------------------------------------
# more than two contacts
# ---------------------------------------------------------------------------------------------
EYE4 = "1,0,0,0;0,1,0,0;0,0,1,0;0,0,0,1"
CHAIN4 = "-1,1,0,0;0,-1,1,0;0,0,-1,1"


def test_collapse_with_a_certified_third_contact():
    r = resolve_sequential(EYE4, CHAIN4, "1,0,0,5", restitution=["1/20", "1/20", "1/2"])
    (o,) = r.outcomes
    assert o.collapse and o.order.cycle == (0, 1) and r.collapse
    assert list(o.velocity) == [sp.Rational(1, 3)] * 3 + [5]
    assert [x for x in r.iter_orderings()] == [(InfiniteOrder((), (0, 1)), 0)]


@pytest.mark.parametrize("v0,value", [("1,0,0,0", "-1/3"), ("1,0,0,1/10", "-7/30")])
def test_collapse_whose_limit_approaches_another_contact_is_refused(v0, value):
    msg = rf"contacts 1 and 2 collapse.*approaches contact 3 \(H_3 v∞ = {value}\)"
    with pytest.raises(NonTermination, match=msg):
        resolve_sequential(EYE4, CHAIN4, v0, restitution=["1/20", "1/20", "1/2"])


def test_cap_with_restitution_says_why():
    with pytest.raises(NonTermination, match=r"max_reflections=10 with restitution < 1.*contacts \[1, 2\]"):
        resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution="718/10000", max_reflections=10)


# ---------------------------------------------------------------------------------------------
# float path
# ---------------------------------------------------------------------------------------------
def _close(x, exact, tol=Q(1, 10**12)):
    return abs(float_to_rational(float(x)) - exact) <= tol


@pytest.mark.parametrize("e", [0.5, 0.25, [0.75, 0.5]])
def test_float_path_agrees_with_exact(e):
    Ms, Hs = scene([1, 2, 3])
    ex = resolve_sequential(Ms, Hs, "2,0,-1", restitution=e if isinstance(e, list) else e, exact=True, select=False)
    fl = resolve_sequential(np.diag([1.0, 2, 3]), np.array([[-1.0, 1, 0], [0, -1, 1]]), [2.0, 0, -1],
                            restitution=e, select=False)
    assert not fl.exact and fl.backend == "float" and ex.exact
    assert [o.order for o in fl.outcomes] == [o.order for o in ex.outcomes]
    assert fl.orderings == ex.orderings
    for of, oe in zip(fl.outcomes, ex.outcomes):
        assert all(_close(a, b) for a, b in zip(of.velocity, oe.velocity))
        assert all(_close(a, b) for a, b in zip(of.impulse, oe.impulse))


def test_float_path_collapse_is_decided_exactly():
    fl = resolve_sequential(np.eye(3), [[-1.0, 1, 0], [0, -1, 1]], [1.0, 0, 0], restitution=0.0625)
    (o,) = fl.outcomes
    assert o.collapse and o.order == InfiniteOrder((), (0, 1))
    assert all(_close(x, Q(1, 3), Q(1, 10**15)) for x in o.velocity)
    assert list(fl.selected[0]) == [sp.Rational(1, 3)] * 3  # selected from the exact replays
    above = resolve_sequential(np.eye(3), [[-1.0, 1, 0], [0, -1, 1]], [1.0, 0, 0], restitution=0.0718, select=False)
    assert not above.outcomes[0].collapse
    # the float 0.0718 is its binary value, above e_c: same count as the exact path on that value
    exact = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=float_to_rational(0.0718), select=False)
    assert above.outcomes[0].order == exact.outcomes[0].order


# ---------------------------------------------------------------------------------------------
# selection and bad input
# ---------------------------------------------------------------------------------------------
def test_selection_for_restitution_below_one_is_the_cone_reading():
    r = resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2", restitution="1/2")
    assert r.reading == "cone" and len(r.selected) >= 1
    with pytest.raises(DomainError, match="reading: the energy reading .* only elastic impacts keep"):
        resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2", restitution="1/2", reading="energy")
    r = resolve_sequential("1,0;0,1", "1,0;-1,1", "-1,-2", restitution="1/2", reading="energy", select=False)
    assert r.selected == () and len(r.outcomes) >= 1


@pytest.mark.parametrize("bad,match", [
    ("3/2", r"entry 1 must lie in \[0, 1\], got 3/2"),
    (1.5, r"entry 1 must lie in \[0, 1\], got 1.5"),
    (-0.25, r"must lie in \[0, 1\]"),
    ("-1/2", r"must lie in \[0, 1\]"),
    (float("nan"), "must be a finite real number"),
    (float("inf"), "must be a finite real number"),
    ("nan", "finite real number"),
    (sp.I, "finite real number"),
    ("sqrt(-1)", "finite real number"),
    (["1/2", "1/2", "1/2"], r"has 3 entries; give one number per contact \(k=2"),
    ([0.5], r"has 1 entries"),
    (True, "must be a number"),
    (["1/2", None], "entry 2 must be a number"),
])
def test_bad_restitution_is_refused(bad, match):
    with pytest.raises(ImpactInputError, match=match) as info:
        resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution=bad)
    assert info.value.argument == "restitution"


def test_pinched_ball_with_restitution_is_refused_with_reason():
    with pytest.raises(DomainError, match="only v = 0 would be valid"):
        resolve_sequential("1", "1;-1", "1", restitution="1/2")


def test_collapse_after_a_prefix_once_the_third_contact_is_certified():
    # an elastic light ball bounces back from the first of three heavy balls (e = 1 at contact 1),
    # which then collapse (e = 1/20 < 7 - 4 sqrt 3); contact 1 is certified after one more impact
    r = resolve_sequential("1,0,0,0;0,3,0,0;0,0,3,0;0,0,0,3", CHAIN4, "1,0,0,0", restitution=["1", "1/20", "1/20"])
    (o,) = r.outcomes
    assert o.collapse and o.order == InfiniteOrder((0, 1), (2, 1))
    assert [o.order[i] for i in range(8)] == [0, 1, 2, 1, 2, 1, 2, 1]
    assert list(o.velocity) == [-sp.Rational(1, 2)] + [sp.Rational(1, 6)] * 3
    assert list(o.impulse) == [sp.Rational(3, 2), 1, sp.Rational(1, 2)]
    # the finite prefix is the exact event loop's first two impacts
    first = event_loop([1, 3, 3, 3], [Q(1, 10**6), Q(1, 10**6), Q(1, 10**6) + Q(1, 10**8)], [1, 0, 0, 0],
                       [1, Q(1, 20), Q(1, 20)], max_events=8, partial=True)
    assert first == tuple(o.order[i] for i in range(8))


def test_exact_state_size_is_bounded_with_restitution(monkeypatch):
    import impactsym.laws.sequential.resolve as mod

    monkeypatch.setattr(mod, "MAX_STATE_BITS", 2000)
    with pytest.raises(NonTermination, match="MAX_STATE_BITS"):
        resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution="718/10000")


@pytest.mark.parametrize("floats", [False, True])
def test_collapse_of_three_contacts_is_refused_with_the_reason(floats):
    # four equal balls at e = 1/6: no pair can collapse (1/6 > 7 - 4 sqrt 3), but all three contacts
    # keep colliding; the float path gives way to the exact search once its decisions all fall back
    args = ((np.eye(4), [[-1.0, 1, 0, 0], [0, -1, 1, 0], [0, 0, -1, 1]], [1.0, 0, 0, 0], 1 / 6) if floats
            else (EYE4, CHAIN4, "1,0,0,0", "1/6"))
    with pytest.raises(NonTermination, match=r"max_reflections=300 with restitution < 1; its last 64 impacts "
                                             r"involve contacts \[1, 2, 3\].*more than two contacts"):
        resolve_sequential(*args[:3], restitution=args[3], max_reflections=300)


# ---------------------------------------------------------------------------------------------
# against the project's exact simulator (impactsym.simulate, per-contact restitution)
# ---------------------------------------------------------------------------------------------
def _simulate(masses, gaps, v0, e, wall):
    from impactsym.simulate import simulate_line

    n = len(masses)
    off = 1 if wall else 0
    x = [sp.Rational(gaps[0].numerator, gaps[0].denominator) if wall else sp.Integer(0)]
    for i in range(n - 1):
        x.append(x[-1] + _rat(Q(gaps[i + off])))
    names = (["wall@0-1"] if wall else []) + [f"{i + 1}-{i + 2}" for i in range(n - 1)]
    rest = {name: str(val) for name, val in zip(names, e)}
    if wall:  # the simulator also opens a wall contact for every other ball; they never close here
        rest.update({f"wall@0-{b + 1}": "1" for b in range(1, n)})
    r = simulate_line(masses, [0] * n, x, [_rat(Q(t)) for t in v0], walls=[0] if wall else [], restitution=rest)
    return tuple(names.index(name) for _, name in r.events), list(r.velocities)


def test_random_chains_match_the_exact_simulator():
    checked = 0
    for masses, wall, e, v0, M, H, gaps in _random_chains(11, 30, 0.4):
        try:
            order, vel = _simulate(masses, gaps, v0, e, wall)
        except DomainError as exc:
            if "same instant" in str(exc):
                continue
            raise
        res = resolve_sequential(M, H, ",".join(str(_rat(x)) for x in v0), restitution=[str(x) for x in e],
                                 select=False)
        assert list(_outcome_of(res, order).velocity) == vel
        checked += 1
    assert checked >= 15


def test_simulator_diagnoses_the_collapse_the_resolver_sums():
    from impactsym.simulate import simulate_line

    with pytest.raises(DomainError, match="inelastic collapse"):
        simulate_line([1, 1, 1], [0, 0, 0], [0, "1/1000", "3/1000"], [1, 0, 0], restitution="1/20")
    (o,) = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution="1/20", select=False).outcomes
    assert o.collapse and list(o.velocity) == [sp.Rational(1, 3)] * 3
    # just above e_c both finish, with the same 503 impacts
    order, vel = _simulate([1, 1, 1], [Q(1, 10**6), Q(1, 10**6) + Q(1, 10**9)], [1, 0, 0], [Q(718, 10000)] * 2, False)
    (f,) = resolve_sequential(EYE3, CHAIN3, "1,0,0", restitution="718/10000", select=False).outcomes
    assert len(order) == f.reflections == 503 and order == tuple(f.order) and vel == list(f.velocity)


def test_alternation_limit_helper():
    from impactsym.laws.sequential import alternation_limit

    v, p = alternation_limit(EYE3, CHAIN3, "1,0,0", ["1/20", "1/30"])
    assert list(v) == [sp.Rational(1, 3)] * 3 and list(p) == [sp.Rational(2, 3), sp.Rational(1, 3)]
    assert alternation_limit(EYE3, CHAIN3, "1,0,0", "718/10000") is None
    assert alternation_limit(EYE3, CHAIN3, "1,0,0", "717/10000") is not None
    # the wall pair of sec. III-B.1 from the ball's side: only the pair counts
    v, p = alternation_limit("1,0;0,1", "1,0;-1,1", "0,-1", 0, first=1, second=0)
    assert list(v) == [0, 0] and list(p) == [1, 1]  # M(0 - v0) = (0, 1) = H_2^T p_2 + H_1^T p_1
    with pytest.raises(DomainError, match="contact 1 is not approached"):
        alternation_limit(EYE3, CHAIN3, "0,0,1", "1/20")
    with pytest.raises(ImpactInputError, match="second"):
        alternation_limit(EYE3, CHAIN3, "1,0,0", "1/20", first=0, second=5)
