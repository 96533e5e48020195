"""The single-impact derivation (Seghete & Murphey eqs. 1a-1b) and every machine-checked property."""

import pytest
import sympy as sp

from derivations.impulse_ratio import physical_root_proof
from derivations.reflection import (
    PROPERTIES,
    derive_general,
    derive_restitution,
    derive_single_impact,
    printed_G,
    run_proof,
    symbolic_covector,
    symbolic_mass_matrix,
)


@pytest.mark.parametrize("n", [2, 3])
def test_single_impact_derivation_matches_print(n):
    d = derive_single_impact(n)
    assert d.matches_printed_G and d.matches_printed_lambda
    # two roots of lambda * (lambda s - 2 u q-) = 0; exactly the trivial one is discarded, with its reason
    assert len(d.roots) == 2
    assert [r for r, _ in d.discarded_roots] == [0]
    assert d.discarded_roots[0][1].startswith("lambda = 0 gives qdot+ = qdot-")


@pytest.mark.parametrize("n", [2, 3])
def test_restitution_derivation(n):
    d = derive_restitution(n)
    assert d.matches_printed_G and d.matches_printed_lambda and d.matches_printed_energy_loss


def test_general_derivation_lambda():
    d = derive_general()
    s, c = sp.symbols("s c", real=True, nonzero=True)
    assert sp.simplify(d.lam - 2 * c / s) == 0
    assert [r for r, _ in d.discarded_roots] == [0]
    de = derive_general(restitution=True)
    e = sp.Symbol("e", real=True, nonzero=True)
    assert sp.simplify(de.lam - (1 + e) * c / s) == 0


def test_derived_G_is_not_the_paper_print_with_a_wrong_sign():
    """The comparison can fail: a deliberately wrong 'print' (factor 1 instead of 2) is refused."""
    M, u = symbolic_mass_matrix(2), symbolic_covector(2)
    wrong = sp.eye(2) - (M.adjugate() * u.T * u) / (u * M.adjugate() * u.T)[0, 0]
    assert not all(sp.cancel(x) == 0 for x in derive_single_impact(2).G - wrong)
    assert all(sp.cancel(x) == 0 for x in derive_single_impact(2).G - printed_G(M, u))


@pytest.mark.parametrize("name", list(PROPERTIES))
@pytest.mark.parametrize("dimension", [2, 3, "n"])
def test_property_proven(name, dimension):
    r = run_proof(name, dimension)
    assert r.proven, r.steps
    assert r.dimension == dimension and r.seconds >= 0 and r.method
    assert ("structural" in r.method) == (dimension == "n")


def test_proof_engine_rejects_a_false_identity():
    """The rewriting engine is not a rubber stamp: G^2 = -I does not rewrite to true."""
    from derivations.algebra import nc_symbols, rewrite

    W, U = nc_symbols("W U")
    s = sp.Symbol("s", nonzero=True)
    G = 1 - 2 * W * U / s
    assert rewrite(G * G, {U * W: s}) == 1
    assert rewrite(G * G + 1, {U * W: s}) != 0
    # a reflection with the wrong factor is not an involution
    assert rewrite((1 - W * U / s) ** 2, {U * W: s}) != 1


def test_physical_root_of_impulse_ratio_quadratic():
    assert physical_root_proof()["proven"]
