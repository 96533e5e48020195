"""Sec. 5 of Acary & Taha: eq. 42 from the general kinetic-angle function, the coupling
criterion eq. 43, participation eq. 41 and the degree of an open planar chain eq. 45."""

from __future__ import annotations

import sympy as sp
import pytest

from impactsym.laws.coupling import (
    apply_coupling,
    coupled_pairs,
    coupling_decision,
    impact_degree,
    participating_contacts,
)
from impactsym.mechanics import kinetic_angle_cos
from impactsym.models.acary_taha import bernoulli, chain3, pool
from paper_checks.acary_taha_support import pool_kinetic_angle_check


def test_eq42_symbolic():
    r = pool_kinetic_angle_check()
    assert r["distance"][1] and r["squared"][1]


@pytest.mark.parametrize("theta", [0, sp.pi / 6, sp.pi / 4, sp.pi / 3, 2 * sp.pi / 5, sp.pi / 2, 3 * sp.pi / 5])
def test_eq42_and_eq43_at_angles(theta):
    sc = pool(theta)
    c = kinetic_angle_cos(sc.M, sc.H[0, :], sc.H[1, :])
    assert sp.simplify(c + sp.cos(theta) / 2) == 0
    coupled = coupled_pairs(sc.M, sc.H)[(0, 1)]
    assert coupled == bool(sp.cos(theta) > 0)  # eq. 43: coupled iff theta < pi/2
    ratios, notes = apply_coupling(sc.M, sc.H, sc.v, ["1/2"])
    assert (ratios == [0]) == (not coupled) and (len(notes) == 1) == (not coupled)


def test_eq41_participation():
    assert participating_contacts("-1,1,0;0,-1,1", "1,0,0") == [True, True]  # approaching, grazing
    assert participating_contacts("-1,1,0;0,-1,1", "1,0,2") == [True, False]  # 2-3 leaving
    # tau >= pi/2: the primary contact does not approach: no impact (sec. 5.1)
    sc = pool(sp.pi / 4, sp.pi / 2)
    assert coupling_decision(sc.M, sc.H, sc.v).approaching[0] is False
    assert impact_degree(sc.M, sc.H, sc.v) == 0


def test_leaving_contact_ratio_zeroed_with_reason():
    ratios, notes = apply_coupling("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,2", ["1/2"])
    assert ratios == [0] and notes[0]["equation"] == "41"


def planar_chain(angles):
    """An open chain of balls in the plane, ball i+1 placed at the bend angle angles[i] from the
    previous direction; unit masses, contact i between balls i and i+1 (distance constraints)."""
    n = len(angles) + 2
    pos = [sp.Matrix([0, 0])]
    direction = sp.Integer(0)
    for i in range(n - 1):
        if i > 0:
            direction += angles[i - 1]
        pos.append(pos[-1] + 2 * sp.Matrix([sp.cos(direction), sp.sin(direction)]))
    H = sp.zeros(n - 1, 2 * n)
    for i in range(n - 1):
        u = (pos[i + 1] - pos[i]) / 2
        H[i, 2 * i:2 * i + 2] = -u.T
        H[i, 2 * i + 2:2 * i + 4] = u.T
    v = sp.zeros(2 * n, 1)
    v[0], v[1] = 1, 0
    return sp.eye(2 * n), H, v


@pytest.mark.parametrize(
    "angles, degree",
    [  # angles[i] is the bend between contacts i+1 and i+2; cos theta = -cos(bend)/2 (as eq. 42)
        ((0, 0), 3),  # straight chain of 4 balls: both kinetic angles 2pi/3 > pi/2
        ((sp.pi / 3, 0), 3),
        ((sp.pi / 2, 0), 1),  # right-angle bend at the first ball pair: cos = 0, nothing transmitted
        ((2 * sp.pi / 3, 0), 1),
        ((0, sp.pi / 2), 2),
        ((sp.pi / 4, 3 * sp.pi / 4), 2),
        ((sp.pi / 4, sp.pi / 2), 2),
    ],
)
def test_eq45_degree_in_open_planar_chain(angles, degree):
    M, H, v = planar_chain(angles)
    for i, bend in enumerate(angles):
        assert sp.simplify(kinetic_angle_cos(M, H[i, :], H[i + 1, :]) + sp.cos(bend) / 2) == 0
    assert impact_degree(M, H, v) == degree
    # eq. 45 agrees with the general path criterion (W_{i,i+2} = 0 in an open chain)
    assert sum(coupling_decision(M, H, v).reachable) == degree


def test_bernoulli_eq43_contradicts_eq37_choice():
    # at theta = 2pi/3 all three kinetic angles have cos = +1/4 > 0: eq. 43 couples nothing, so the
    # coupling criteria set alpha_12 = alpha_13 = 0, while eq. 37 uses alpha_13 = alpha_12 != 0
    sc = bernoulli()
    d = coupling_decision(sc.M, sc.H, sc.v)
    assert all(c == sp.Rational(1, 4) for c in d.cosines.values())
    ratios, notes = apply_coupling(sc.M, sc.H, sc.v, ["1/2", "1/2"])
    assert ratios == [0, 0] and {n["contact"] for n in notes} == {2, 3}


def test_chain3_degree_two():
    assert impact_degree(chain3().M, chain3().H, chain3().v) == 2


def test_eq41_printed_cone_sign_is_reversed():
    # printed: T_i = {p | -grad h_i . p >= 0}; "-v in T_i" then means grad h_i . v >= 0 (leaving), which
    # would declare "no impact" for the chain's approaching first contact, whose impact the paper computes.
    sc = chain3()
    w1 = (sc.H[0, :] * sc.v)[0, 0]
    printed_condition = -(sc.H[0, :] * (-sc.v))[0, 0] >= 0
    assert w1 == -1 and not bool(printed_condition)
    assert participating_contacts(sc.H, sc.v)[0] is True  # the corrected cone: H_1 v- <= 0
