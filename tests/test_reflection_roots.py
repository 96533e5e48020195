"""derivations.reflection.derive_single_impact keeps the energy equation's roots as
``sp.solve(..., simplify=False)`` finds them (simplifying them cost more than the solve, and only
n = 2 is printed); the claims that print them simplify each root. That printed form must be
``sp.solve``'s default output, srepr for srepr, and the kept root's factored form the same."""
import functools

import pytest
import sympy as sp

import derivations.reflection as R
from paper_checks import framework


@functools.lru_cache(maxsize=None)
def _reference_roots(n):
    """SymPy's default roots for dimension n (computed once per module: two tests compare with them)."""
    d = R.derive_single_impact(n)
    lam = sp.Symbol("lambda", real=True)
    qp = R.symbolic_vector(n, "qp")
    momentum = d.M * qp - d.M * d.qminus + lam * d.u.T
    qp_of_lam = qp.subs(sp.solve(list(momentum), list(qp), dict=True)[0])
    energy = (qp_of_lam.T * d.M * qp_of_lam)[0, 0] - (d.qminus.T * d.M * d.qminus)[0, 0]
    return tuple(sp.solve(R.factored_numerator(energy, free_of=[lam]), lam, check=False))


@pytest.mark.parametrize("n", [2, 3])
def test_simplified_roots_are_solves_default_form(n):
    d = R.derive_single_impact(n)
    reference = _reference_roots(n)
    assert len(reference) == len(d.roots) == 2
    assert [sp.srepr(sp.simplify(r)) for r in d.roots] == [sp.srepr(r) for r in reference]
    assert sp.srepr(d.lam) == sp.srepr(sp.factor(reference[1]))


def test_the_claims_print_the_simplified_roots():
    want = [str(r) for r in _reference_roots(2)]
    framework.load_all()
    trivial = framework.evaluate("sm-II-A-trivial-root")
    assert trivial.status == "ok" and [str(r) for r in trivial.derived["roots"]] == want


@pytest.mark.parametrize("derive", [R.derive_single_impact, R.derive_restitution])
@pytest.mark.parametrize("n", [2, 3])
def test_G_is_the_cancelled_jacobian(derive, n):
    """G is taken column by column from the linear q̇⁺ (verified G q̇⁻ = q̇⁺); it must be the
    cancelled Jacobian it replaces, srepr for srepr."""
    from derivations.rational_zero import cancel

    d = derive(n)
    assert sp.srepr(d.G) == sp.srepr(d.qplus.jacobian(d.qminus).applyfunc(cancel))


def test_a_nonlinear_qplus_is_refused():
    from impactsym.errors import DerivationError

    a, b = sp.symbols("a b")
    with pytest.raises(DerivationError, match="not linear"):
        R._jacobian_of_linear(sp.Matrix([a * b, b]), sp.Matrix([a, b]))
