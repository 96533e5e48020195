"""The pool's validity domain at incidence tau != 0 (Acary & Taha sec. 4.2) against the law itself:
exact membership agrees with the impulse-ratio law's own validity verdict on a rational grid."""

import pytest
import sympy as sp

from impactsym import ImpactInputError
from impactsym.domains import validity_domain
from impactsym.laws.impulse_ratio import impulse_ratio_law
from impactsym.models.acary_taha import pool

R = sp.Rational


@pytest.mark.parametrize("theta, tau", [(sp.pi / 4, sp.pi / 6), (sp.pi / 3, -sp.pi / 5)])
def test_membership_agrees_with_the_law(theta, tau):
    dom = validity_domain("pool", theta, tau)
    sc = pool(theta, tau)
    seen = set()
    for a in [R(0), R(3, 10), R(1, 2), R(1), R(6, 5)]:
        for e in [R(1, 2), R(3, 5), R(4, 5), R(1)]:
            law = impulse_ratio_law(sc.M, sc.H, sc.v, e, [a], allow_invalid=True)
            assert dom.contains(a, e) == law.valid, (a, e, law.violations)
            seen.add(law.valid)
    assert seen == {True, False}  # the grid straddles the boundary


def test_tau_maps_the_tau0_domain():
    d0, d = validity_domain("pool", "pi/4"), validity_domain("pool", "pi/4", "pi/6")
    assert d.region["alpha"] == d0.region["alpha"]
    assert d.region["e"] == (R(1, 4) + R(3, 4) * d0.region["e"][0], 1) == (R(4, 7), 1)


def test_no_approach_gives_empty_domain_and_bad_tau_is_refused():
    d = validity_domain("pool", "pi/4", "2*pi/3")
    assert d.region["empty"] and not d.contains("1/2", "1")
    with pytest.raises(ImpactInputError, match="tau: only the pool"):
        validity_domain("chain3", None, "1/2")
    with pytest.raises(ImpactInputError, match="tau: needs theta"):
        validity_domain("pool", None, "1/2")
    with pytest.raises(ImpactInputError, match="three closed contacts"):
        validity_domain("pool", "2*pi/3", "-pi/6")
