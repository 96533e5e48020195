"""The exact rank of the multi-contact laws' linear algebra (``impactsym.laws.delassus``) is exact:
no ``nsimplify`` rounds a tiny determinant to zero."""

import sympy as sp

from impactsym.laws.delassus import ExactLinearAlgebra, exact_rank

TINY = sp.Rational(13, 10**34)
# det = -13*sqrt(2)/10**34 ~ -1.8e-33: non-singular
NEAR_SINGULAR = sp.Matrix([[sp.sqrt(2), 1], [1, sp.sqrt(2) / 2 - TINY]])


def test_near_singular_2x2_has_rank_2():
    assert NEAR_SINGULAR.det().equals(-13 * sp.sqrt(2) / 10**34)
    assert ExactLinearAlgebra("sympy").rank(NEAR_SINGULAR) == 2
    # the rounding this replaces would have called it singular
    assert NEAR_SINGULAR.applyfunc(sp.nsimplify).rank(simplify=True) == 1


def test_singular_and_transcendental_entries():
    la = ExactLinearAlgebra("sympy")
    assert la.rank(sp.Matrix([[sp.sqrt(2), 1], [1, sp.sqrt(2) / 2]])) == 1
    assert la.rank(sp.Matrix([[sp.pi, 1], [1, 1 / sp.pi]])) == 1
    assert la.rank(sp.Matrix([[sp.pi, 1], [1, 1 / sp.pi + TINY]])) == 2
    assert la.rank(sp.zeros(2, 3)) == 0
    assert la.rank(sp.Matrix([[sp.cos(sp.pi / 5), 0, 1], [2 * sp.cos(sp.pi / 5), 0, 2]])) == 1


def test_symbols_are_refused():
    import pytest

    with pytest.raises(ValueError, match="A: exact_rank needs numbers"):
        exact_rank(sp.Matrix([[sp.Symbol("x"), 1]]))


def test_newton_moreau_uniqueness_verdict_uses_the_exact_rank():
    """Two nearly parallel contacts (det H ~ -1.8e-33), both active: the impulse is unique."""
    from impactsym.laws.classical import newton_moreau

    v = -NEAR_SINGULAR.T * sp.Matrix([1, 1]) / 2  # chosen so that p = (1, 1) solves the LCP at e = 1
    r = newton_moreau(sp.eye(2), NEAR_SINGULAR, v, 1)
    assert list(r.impulses) == [1, 1]
    assert r.unique_impulse is True
    assert any("independent" in n for n in r.notes)
