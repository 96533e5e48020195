"""The classical laws of Acary & Taha secs. 2.2 and 3.2 on the same scenes: the sec. 3.2
numbers exactly, the LCP (uniqueness, enumeration vs NNLS), Poisson's phases, the energetic
law's documented choice, Han–Gilmore's two outcomes, and energy properties (Hypothesis)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from derivations.impulse_ratio import moreau_energy_proof
from impactsym.errors import DomainError, ImpactInputError
from impactsym.exact import certified_sign
from impactsym.laws import classical
from impactsym.laws.classical import energetic, han_gilmore, newton_moreau, poisson, solve_lcp
from impactsym.laws.impulse_ratio import impulse_ratio_law
from impactsym.models.acary_taha import chain3, pool

R = sp.Rational
CHAIN = ("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
NEWTON_V = [R(-1, 3), R(2, 3), R(2, 3)]


def chain_n(n):
    H = sp.zeros(n - 1, n)
    for i in range(n - 1):
        H[i, i], H[i, i + 1] = -1, 1
    v = sp.zeros(n, 1)
    v[0] = 1
    return sp.eye(n), H, v


# ---------------------------------------------------------------------------- sec. 3.2 numbers

def test_newton_sec32_numbers_exactly():
    r = newton_moreau(*CHAIN, 1)
    assert list(r.velocity) == NEWTON_V and list(r.impulses) == [R(4, 3), R(2, 3)]
    assert r.valid and r.unique_impulse and r.exact


def test_newton_sec32_state_conserves_energy_exactly():
    # the paper calls it "not acceptable" but does not say: T+ = T- exactly
    r = newton_moreau(*CHAIN, 1)
    assert r.energy_before == R(1, 2) and r.energy_after == R(1, 2)


def test_poisson_sec32_numbers_exactly():
    r = poisson(*CHAIN, 1)
    assert list(r.details["compression_velocity"]) == [R(1, 3)] * 3  # q1+ = q2+ = q3+ at the end of compression
    assert list(r.details["compression_impulses"]) == [R(2, 3), R(1, 3)]
    assert list(r.impulses) == [R(4, 3), R(2, 3)] and list(r.velocity) == NEWTON_V
    # per-contact coefficients e_p1, e_p2 as the paper writes them
    r2 = poisson(*CHAIN, ["1", "1"])
    assert list(r2.velocity) == NEWTON_V


def test_han_gilmore_eqs_15_16_exactly():
    r = han_gilmore(*CHAIN, 1)
    assert [list(o.velocity) for o in r.outcomes] == [NEWTON_V, [0, 0, 1]]
    assert r.outcomes[0].sequences == [[(1, 2)]]  # both contacts together (2-3 grazing joins): eq. 15
    assert r.outcomes[1].sequences == [[(1,), (2,)]]  # 1-2, then 2-3: eq. 16
    assert all(o.energy_after == R(1, 2) for o in r.outcomes)  # "conservation of kinetic energy"
    assert not r.unique


def test_han_gilmore_first_outcome_is_newton_moreau():
    # eq. 15 is the Newton/Moreau solution: the LCP's active set is {1, 2}, the simultaneous hypothesis
    nm = newton_moreau(*CHAIN, 1)
    hg = han_gilmore(*CHAIN, 1)
    assert list(hg.outcomes[0].velocity) == list(nm.velocity)
    assert list(hg.outcomes[0].impulses) == list(nm.impulses)


def test_laws_side_by_side_on_the_chain():
    # Newton = Poisson = energetic(e=1) = impulse ratio with alpha = 1/2 (sec. 3.2 vs 3.3)
    ir = impulse_ratio_law(*CHAIN, 1, ["1/2"])
    for r in (newton_moreau(*CHAIN, 1), poisson(*CHAIN, 1), energetic(*CHAIN, 1)):
        assert list(r.velocity) == list(ir.velocity)


# ----------------------------------------------------------------------------- Newton / LCP

def test_lcp_enumeration_and_nonuniqueness():
    assert solve_lcp(sp.Matrix([[2, -1], [-1, 2]]), sp.Matrix([-2, 0])) == [sp.Matrix([R(4, 3), R(2, 3)])]
    sols = solve_lcp(sp.Matrix([[1, 1], [1, 1]]), sp.Matrix([-1, -1]))
    assert sols == [sp.Matrix([1, 0]), sp.Matrix([0, 1])]


def test_newton_reports_nonunique_impulse_unique_velocity():
    r = newton_moreau("1,0;0,1", "1,0;1,0", "-1,0", 1)
    assert not r.unique_impulse and list(r.velocity) == [1, 0]
    assert {tuple(r.impulses)} | {tuple(p) for p in r.other_impulses} == {(2, 0), (0, 2)}


def test_newton_penetration_when_a_contact_leaves_fast():
    # contact 2 leaving (w2 = +1); contact 1 approaching pushes ball 2 into ball 3?  The LCP asks only
    # H v+ >= -e H v-, so H_2 v+ may be negative: reported, refused unless allowed.
    M, H, v = "1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "3,0,1"
    r = newton_moreau(M, H, v, 1, allow_invalid=True)
    for j, x in enumerate(sp.Matrix([[-1, 1, 0], [0, -1, 1]]) * r.velocity):
        assert (certified_sign(x) < 0) == any(vv.condition == "penetration" and vv.contact == j + 1 for vv in r.violations)
    if not r.valid:
        with pytest.raises(DomainError, match="penetration"):
            newton_moreau(M, H, v, 1)


def test_newton_nnls_path_matches_enumeration(monkeypatch):
    M, H, v = chain_n(9)
    exact = newton_moreau(M, H, v, R(1, 2))
    monkeypatch.setattr(classical, "MAX_ENUMERATED_CONTACTS", 3)
    viannls = newton_moreau(M, H, v, R(1, 2))
    assert "non-negative least squares" in viannls.notes[0]
    assert list(viannls.velocity) == list(exact.velocity) and list(viannls.impulses) == list(exact.impulses)


def test_newton_large_chain_exact_via_certified_nnls():
    M, H, v = chain_n(15)  # k = 14 > MAX_ENUMERATED_CONTACTS
    r = newton_moreau(M, H, v, 1)
    assert list(r.velocity) == [R(-13, 15)] + [R(2, 15)] * 14
    assert r.energy_after == r.energy_before


def test_newton_float_input_exact_decisions():
    r = newton_moreau(np.eye(3), np.array([[-1.0, 1, 0], [0, -1, 1]]), np.array([1.0, 0, 0]), 1.0)
    assert not r.exact
    assert np.array_equal(r.velocity, np.array([-1 / 3, 2 / 3, 2 / 3]))


def test_moreau_energy_proof():
    assert moreau_energy_proof()["proven"]


@st.composite
def scenes(draw):
    n = draw(st.integers(2, 4))
    k = draw(st.integers(1, 4))
    small = st.integers(-3, 3)
    L = sp.Matrix(n, n, [draw(small) for _ in range(n * n)])
    M = L * L.T + sp.eye(n)
    rows = []
    for i in range(k):
        row = [draw(small) for _ in range(n)]
        if not any(row):
            row[i % n] = 1
        rows.append(row)
    H = sp.Matrix(rows)
    v = sp.Matrix([draw(small) for _ in range(n)])
    e = R(draw(st.integers(0, 4)), 4)
    return M, H, v, e


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.large_base_example])
@given(scenes())
def test_newton_moreau_lcp_and_energy_identity(scene):
    M, H, v, e = scene
    r = newton_moreau(M, H, v, e, allow_invalid=True)
    p, vp = r.impulses, r.velocity
    assert M * (vp - v) - H.T * p == sp.zeros(M.rows, 1)  # momentum, exactly
    y = H * vp + e * H * v
    assert all(x >= 0 for x in p) and all(x >= 0 for x in y)  # the LCP, exactly
    assert (p.T * y)[0, 0] == 0
    # T+ - T- = (1 - e)/2 p^T H v-  (moreau_energy_proof), and = 0 at e = 1
    assert r.energy_after - r.energy_before == (1 - e) / 2 * (p.T * H * v)[0, 0]


# ---------------------------------------------------------------------------------- Poisson

def test_poisson_glocker_pfeiffer_restores_admissibility():
    # three balls, ball 3 moving away slowly: paper's Poisson may penetrate; G-P's expansion LCP never does
    M, H, v = "1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0"
    for e in ("0", "1/2", "1"):
        r = poisson(M, H, v, e, variant="glocker-pfeiffer")
        assert r.valid
        assert all(certified_sign(x) >= 0 for x in sp.Matrix([[-1, 1, 0], [0, -1, 1]]) * r.velocity)


def test_poisson_per_contact_coefficients():
    r = poisson(*CHAIN, ["1", "0"], allow_invalid=True)
    assert list(r.impulses) == [R(4, 3), R(1, 3)]


def test_poisson_bad_variant_and_count():
    with pytest.raises(ImpactInputError, match="variant"):
        poisson(*CHAIN, 1, variant="nope")
    with pytest.raises(ImpactInputError, match="expected 1 or 2"):
        poisson(*CHAIN, ["1", "1", "1"])
    with pytest.raises(DomainError, match="restitution"):
        poisson(*CHAIN, ["1", "3/2"])


# -------------------------------------------------------------------------------- energetic

def test_energetic_single_contact_is_newton_with_sqrt_e():
    r = energetic("2,0;0,1", "1,0", "-1,0", "1/4")
    n = newton_moreau("2,0;0,1", "1,0", "-1,0", "1/2")
    assert list(r.velocity) == list(n.velocity) and r.energy_after == r.energy_before / 4


def test_energetic_direction_and_energy():
    r = energetic(*CHAIN, "1/2")
    assert list(r.details["direction"]) == [2, 1]
    assert r.energy_after == r.energy_before / 2
    r = energetic(*CHAIN, "1/2", ["3/4"])  # with ratios it is the impulse-ratio law
    ir = impulse_ratio_law(*CHAIN, "1/2", ["3/4"])
    assert list(r.velocity) == list(ir.velocity)


def test_energetic_refuses_undetermined_direction():
    with pytest.raises(DomainError, match="not unique"):
        energetic("1,0;0,1", "1,0;1,0", "-1,0", 1)
    with pytest.raises(DomainError, match="vanishes"):
        energetic(*CHAIN[:2], "-1,0,0", 1)


# ---------------------------------------------------------------------------- Han-Gilmore

def test_han_gilmore_inelastic_has_an_infinite_sequence():
    # e = 0: together, the three balls end at 1/3 each; one at a time (1-2, 2-3, 1-2, ...) never ends
    # (velocities converge geometrically to 1/3): reported as an unterminated branch, not hidden
    r = han_gilmore(*CHAIN, 0, max_stages=30)
    assert [list(o.velocity) for o in r.outcomes] == [[R(1, 3)] * 3]
    assert r.unterminated and len(r.unterminated[0]) == 30
    assert r.unterminated[0][:4] == [(1,), (2,), (1,), (2,)]


def test_han_gilmore_caps():
    from impactsym.errors import NonTermination

    with pytest.raises(NonTermination, match="max_stages"):
        han_gilmore(*CHAIN, 1, max_stages=0)
    with pytest.raises(NonTermination, match="max_outcomes"):
        han_gilmore(*CHAIN, 1, max_outcomes=1)


def test_laws_on_the_pool_scene():
    sc = pool(sp.pi / 4)
    r = newton_moreau(sc.M, sc.H, sc.v, 1)
    assert sp.simplify(r.energy_after - r.energy_before) == 0
    hg = han_gilmore(sc.M, sc.H, sc.v, 1)
    assert len(hg.outcomes) >= 1


def test_poisson_energy_proof():
    from derivations.impulse_ratio import poisson_energy_proof

    assert poisson_energy_proof()["proven"]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.large_base_example])
@given(scenes())
def test_poisson_energy_identity(scene):
    # T+ - T- = -(1 - e^2)/2 p_c^T W p_c (poisson_energy_proof), exactly
    M, H, v, e = scene
    r = poisson(M, H, v, e, allow_invalid=True)
    pc = r.details["compression_impulses"]
    W = H * M.inv() * H.T
    assert r.energy_after - r.energy_before == -(1 - e**2) / 2 * (pc.T * W * pc)[0, 0]
    assert M * (r.velocity - v) == H.T * r.impulses
