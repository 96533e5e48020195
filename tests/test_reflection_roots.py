"""derivations.reflection.derive_single_impact takes the energy equation's roots from
``sp.solve(..., simplify=False)`` and simplifies each root itself (half the cost): the roots must be
``sp.solve``'s default output, srepr for srepr (they are printed by the sm-II-A claims)."""
import pytest
import sympy as sp

import derivations.reflection as R


@pytest.mark.parametrize("n", [2, 3])
def test_single_impact_roots_are_solves_default_form(n):
    d = R.derive_single_impact(n)
    lam = sp.Symbol("lambda", real=True)
    qp = R.symbolic_vector(n, "qp")
    momentum = d.M * qp - d.M * d.qminus + lam * d.u.T
    qp_of_lam = qp.subs(sp.solve(list(momentum), list(qp), dict=True)[0])
    energy = (qp_of_lam.T * d.M * qp_of_lam)[0, 0] - (d.qminus.T * d.M * d.qminus)[0, 0]
    reference = sp.solve(R.factored_numerator(energy, free_of=[lam]), lam, check=False)
    assert len(reference) == 2
    assert [sp.srepr(r) for r in d.roots] == [sp.srepr(r) for r in reference]
