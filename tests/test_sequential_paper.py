"""Seghete & Murphey sec. III-B, reproduced (or shown wrong) with the sequential resolver.

Printed matrices appear only as *transcriptions* (``PRINTED_*``), compared with what SymPy derives.

Findings pinned here:

* sec. III-B.3 prints ``G_u = −I`` for ``M = diag(1.1, 1)``; the derivation gives ``diag(−1, 1)``
  (the wall–ball map does not depend on ball 2's mass, as the text itself says). With ``−I`` both
  products ``G_v G_u G_v G_u`` and ``G_u G_v G_u G_v`` are ``G_v² = I``; the printed ``v4a``, ``v4b``
  were computed with ``diag(−1, 1)``, and match the exact products rounded (not truncated) to 4
  decimals.
* "these two matrices give the outcome for every incoming v0" holds only on part of the incoming
  directions: the number of reflections depends on ``v0``'s direction (3 or 4 in this example);
  the exact sectors are computed in :func:`claim_sectors`.
* "Invariably … either v4a or v4b": true in the energy reading (both, tied, when both orderings
  have 4 reflections: ``G_b = G_a⁻¹`` and ``G_a`` is a kinetic isometry, so
  ``⟨G_a v0, v0⟩_M = ⟨v0, G_b v0⟩_M``); false in the plain-cone reading, which selects ``0``.
"""

from __future__ import annotations

import math

import pytest
import sympy as sp

from impactsym.laws.reflection import reflection_map
from impactsym.laws.sequential import resolve_sequential, termination_bound
from impactsym.mechanics import kinetic_energy
from impactsym.models.seghete_murphey import cradle, three_ball_cradle, two_balls_wall

R = sp.Rational
D = sp.Rational  # transcription helper: printed decimals read exactly ("0.9955" -> 9955/10000)

# ---- transcriptions of the printed matrices (sec. III-B) ----
PRINTED_GU_EQUAL = sp.Matrix([[-1, 0], [0, 1]])
PRINTED_GV_EQUAL = sp.Matrix([[0, 1], [1, 0]])
PRINTED_CRADLE_GU = sp.Matrix([[0, 1, 0], [1, 0, 0], [0, 0, 1]])
PRINTED_CRADLE_GV = sp.Matrix([[1, 0, 0], [0, 0, 1], [0, 1, 0]])
PRINTED_EQ4 = sp.Matrix([[0, 0, 1], [0, 1, 0], [1, 0, 0]])
PRINTED_GU_11 = -sp.eye(2)
PRINTED_GV_11 = sp.Matrix([[D("0.0476"), D("0.9524")], [D("1.0476"), D("-0.0476")]])
PRINTED_V4A = sp.Matrix([[D("-0.9955"), D("-0.0907")], [D("0.0998"), D("-0.9955")]])
PRINTED_V4B = sp.Matrix([[D("-0.9955"), D("0.0907")], [D("-0.0998"), D("-0.9955")]])

U2, V2 = sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]])
M11 = sp.diag(R(11, 10), 1)


def _round(A, places, mode):
    q = sp.Integer(10) ** places
    f = (lambda x: sp.floor(x * q + R(1, 2)) / q) if mode == "round" else (lambda x: sp.sign(x) * sp.floor(abs(x) * q) / q)
    return A.applyfunc(f)


# ------------------------------------------------------------------ III-B.1
def test_equal_masses_printed_maps_and_minus_identity():
    Gu, Gv = reflection_map(sp.eye(2), U2), reflection_map(sp.eye(2), V2)
    assert Gu == PRINTED_GU_EQUAL and Gv == PRINTED_GV_EQUAL
    assert Gv * Gu * Gv * Gu == Gu * Gv * Gu * Gv == -sp.eye(2)


@pytest.mark.parametrize("v0", [(-1, -2), (-3, -5), (-1, -100), (-100, -101), (0, -1), (-1, -1)])
def test_equal_masses_every_ordering_gives_minus_v0(v0):
    # the paper's premise: u v0 <= 0 and v v0 <= 0
    sc = two_balls_wall(velocities=v0)
    for path in ("closed-form", "iterate"):
        r = resolve_sequential(sc.M, sc.H, sc.v, two_surface=path)
        orders = list(r.iter_orderings())
        assert orders and all(r.outcomes[i].velocity == -sc.v for _, i in orders)
        assert len(r.outcomes) == 1 and r.selected == (-sc.v,)


@pytest.mark.parametrize("v0, out, m", [((-2, -1), (1, 2), 3), ((1, -1), (1, 1), 2)])
def test_equal_masses_outside_the_premise_do_not_give_minus_v0(v0, out, m):
    # only one contact approaches: fewer reflections, the outcome is not -v0 (the premise matters)
    sc = two_balls_wall(velocities=v0)
    r = resolve_sequential(sc.M, sc.H, sc.v)
    assert [list(o.velocity) for o in r.outcomes] == [list(out)] and r.outcomes[0].reflections == m


# ------------------------------------------------------------------ III-B.2
def test_cradle_printed_maps_and_eq4():
    sc = three_ball_cradle()
    Gu, Gv = reflection_map(sc.M, sc.H[0, :]), reflection_map(sc.M, sc.H[1, :])
    assert Gu == PRINTED_CRADLE_GU and Gv == PRINTED_CRADLE_GV
    assert Gu * Gv * Gu == Gv * Gu * Gv == PRINTED_EQ4


@pytest.mark.parametrize("v0, expected", [((1, 0, 0), (0, 0, 1)), ((1, 1, 0), (0, 1, 1)),
                                          ((1, 0, -1), (-1, 0, 1)), ((2, 1, -3), (-3, 1, 2))])
def test_cradle_outcomes(v0, expected):
    sc = three_ball_cradle(velocities=v0)
    for path in ("closed-form", "iterate"):
        r = resolve_sequential(sc.M, sc.H, sc.v, two_surface=path)
        assert [list(o.velocity) for o in r.outcomes] == [list(expected)]
        # when both contacts approach, both orderings (3 reflections each) give eq. 4
        for order, _ in r.iter_orderings():
            assert len(order) <= 3


# ------------------------------------------------------------------ III-B.3
def test_printed_gv_rounds_the_derived_map_and_printed_gu_is_a_misprint():
    Gu, Gv = reflection_map(M11, U2), reflection_map(M11, V2)
    assert Gv == sp.Matrix([[R(1, 21), R(20, 21)], [R(22, 21), R(-1, 21)]])
    assert _round(Gv, 4, "round") == PRINTED_GV_11
    assert Gu == sp.diag(-1, 1) and Gu != PRINTED_GU_11
    # with the printed -I, both four-fold products collapse to G_v^2 = I: not the printed v4a/v4b
    assert Gv * PRINTED_GU_11 * Gv * PRINTED_GU_11 == sp.eye(2)


def test_v4a_v4b_to_the_published_digits():
    Gu, Gv = reflection_map(M11, U2), reflection_map(M11, V2)
    A, B = Gv * Gu * Gv * Gu, Gu * Gv * Gu * Gv
    assert A == sp.Matrix([[R(-439, 441), R(-40, 441)], [R(44, 441), R(-439, 441)]])
    assert B == A.inv()
    assert _round(A, 4, "round") == PRINTED_V4A and _round(B, 4, "round") == PRINTED_V4B
    # the print is rounded, not truncated: truncation gives -0.9954 and 0.0997
    assert _round(A, 4, "truncate") != PRINTED_V4A


def claim_sectors(M, H, depth=6):
    """Exact sectors of incoming directions (2-D), each with its branch lengths and whether every
    outcome is ``G_a v0`` or ``G_b v0`` (the four-fold products of sec. III-B.3).

    Boundaries are the rays where some partial product ``P`` of a branch makes ``H_j P v0 = 0``
    (an iterate grazes a surface): rational rays, so the sectors are exact; a sample strictly
    inside each sector (the sum of its two bounding rays) is resolved exactly.
    """
    Gs = [reflection_map(M, H[i, :]) for i in range(2)]
    rays = []
    for first in (0, 1):
        P = sp.eye(2)
        for k in range(depth):
            for j in (0, 1):
                row = H[j, :] * P
                r = sp.Matrix([-row[1], row[0]])
                rays += [r, -r]
            P = Gs[(first + k) % 2] * P
    uniq = {}
    for r in rays:
        g = sp.gcd(list(r))
        r = r / g
        uniq[(r[0], r[1])] = r
    rays = sorted(uniq.values(), key=lambda r: math.atan2(float(r[1]), float(r[0])))
    A = Gs[1] * Gs[0] * Gs[1] * Gs[0]
    B = Gs[0] * Gs[1] * Gs[0] * Gs[1]
    out = []
    for r1, r2 in zip(rays, rays[1:] + rays[:1]):
        s = r1 + r2
        w = H * s
        if all(x >= 0 for x in w):
            continue  # no impact: v0 already valid
        res = resolve_sequential(M, H, s, two_surface="iterate", select=False)
        lengths = {o[0]: len(o) for o, _ in res.iter_orderings()}
        holds = all(res.outcomes[i].velocity in (A * s, B * s) for _, i in res.iter_orderings())
        out.append({"from": tuple(r1), "to": tuple(r2), "lengths": lengths, "claim_holds": holds,
                    "both_approach": all(x < 0 for x in w)})
    return out


def test_the_fixed_matrix_claim_holds_only_where_both_branches_take_four_reflections():
    H = sp.Matrix([[1, 0], [-1, 1]])
    sectors = claim_sectors(M11, H)
    assert termination_bound(M11, H) == 4
    holds = [s for s in sectors if s["claim_holds"]]
    fails = [s for s in sectors if not s["claim_holds"]]
    assert holds and fails  # the claim is neither always true nor always false
    for s in sectors:
        assert s["claim_holds"] == all(m == 4 for m in s["lengths"].values())
    # inside the corner (both contacts approaching) it still fails somewhere: 3 reflections there
    assert any(s["both_approach"] and not s["claim_holds"] for s in sectors)
    assert any(s["both_approach"] and s["claim_holds"] for s in sectors)
    assert {m for s in sectors for m in s["lengths"].values()} <= {1, 2, 3, 4}


def test_where_exactly_the_fixed_matrix_claim_holds_inside_the_corner():
    """Inside the paper's premise (u v0 <= 0, v v0 <= 0: directions from (-1,-1) to (0,-1)), every
    outcome is v4a or v4b exactly on the closed sector between the rays (-19,-23) and (-40,-439)
    (23/19 <= v2/v1 <= 439/40), and on the premise's edges (one branch, ending grazing); in the two
    open sectors between, one branch stops after 3 reflections with another velocity."""
    H = sp.Matrix([[1, 0], [-1, 1]])
    inside = [s for s in claim_sectors(M11, H) if s["both_approach"]]
    assert [(s["from"], s["to"], s["claim_holds"]) for s in inside] == [
        ((-1, -1), (-19, -23), False), ((-19, -23), (-40, -439), True), ((-40, -439), (0, -1), False)]
    Gu, Gv = reflection_map(M11, U2), reflection_map(M11, V2)
    A, B = Gv * Gu * Gv * Gu, Gu * Gv * Gu * Gv
    for ray in [(-19, -23), (-40, -439), (-1, -1), (0, -1)]:
        v0 = sp.Matrix(ray)
        r = resolve_sequential(M11, H, v0, two_surface="iterate")
        assert all(r.outcomes[i].velocity in (A * v0, B * v0) for _, i in r.iter_orderings())


def test_selection_either_v4a_or_v4b_only_in_the_energy_reading():
    Gu, Gv = reflection_map(M11, U2), reflection_map(M11, V2)
    A, B = Gv * Gu * Gv * Gu, Gu * Gv * Gu * Gv
    for v0 in [(-1, -2), (-1, -3), (-2, -5), (-1, -10)]:  # inside the 4-and-4 sector
        sc = two_balls_wall(masses=(R(11, 10), 1), velocities=v0)
        r = resolve_sequential(sc.M, sc.H, sc.v)
        assert {tuple(o.order) for o in r.outcomes} == {(0, 1, 0, 1), (1, 0, 1, 0)}
        assert set(map(tuple, r.selected)) == {tuple(A * sc.v), tuple(B * sc.v)}  # a tie, every time
        rc = resolve_sequential(sc.M, sc.H, sc.v, reading="cone")
        assert rc.selected == (sp.zeros(2, 1),)
        assert kinetic_energy(sc.M, rc.selected[0]) == 0 != kinetic_energy(sc.M, sc.v)


def test_energy_reading_picks_one_outcome_when_the_lengths_differ():
    # a direction where one branch takes 3 reflections and the other 4: no tie
    H = sp.Matrix([[1, 0], [-1, 1]])
    cand = [s for s in claim_sectors(M11, H) if s["both_approach"] and sorted(s["lengths"].values()) == [3, 4]]
    assert cand
    s = cand[0]
    v0 = sp.Matrix(s["from"]) + sp.Matrix(s["to"])
    r = resolve_sequential(M11, H, v0)
    assert len(r.outcomes) == 2 and len(r.selected) == 1 and r.selected[0] in [o.velocity for o in r.outcomes]


# ------------------------------------------------------------------ counts
@pytest.mark.parametrize("n, k", [(3, 1), (4, 2), (5, 2), (6, 3), (7, 3)])
def test_count_bound_n_times_n_minus_1_power(n, k):
    sc = cradle(n, k)
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate")
    surfaces, N = sc.H.shape[0], r.max_reflections_used
    assert r.orderings <= surfaces * (surfaces - 1) ** (N - 1)


def test_at_most_two_distinct_solutions_for_two_surfaces():
    import numpy as np

    rng = np.random.default_rng(7)
    for _ in range(60):
        n = int(rng.integers(2, 5))
        A = rng.integers(-3, 4, size=(n, n))
        M = sp.Matrix(A.T @ A + 2 * np.eye(n, dtype=int))
        H = sp.Matrix(rng.integers(-3, 4, size=(2, n)))
        if H.rank() < 2:
            continue
        r = resolve_sequential(M, H, sp.Matrix(rng.integers(-3, 4, size=n)), two_surface="iterate", select=False)
        assert len(r.outcomes) <= 2 and r.orderings <= 2
        assert r.max_reflections_used <= termination_bound(M, H)
