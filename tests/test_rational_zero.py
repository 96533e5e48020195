"""The flint zero test of rational functions (derivations.rational_zero) agrees with SymPy's
``cancel(together(.))`` on identities and on their perturbations, and declines (None) what is not a
rational function instead of guessing."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from derivations.rational_zero import is_zero_rational_function, to_fraction
from derivations.reflection import printed_G, symbolic_covector, symbolic_mass_matrix
from random_expressions import random_rational


def _sympy_zero(expr) -> bool:
    num, _ = sp.fraction(sp.cancel(sp.together(expr)))
    return sp.expand(num) == 0



@pytest.mark.parametrize("seed", range(12))
def test_agrees_with_sympy_on_random_identities_and_perturbations(seed):
    rng = random.Random(seed)
    x, y, z = syms = sp.symbols("x y z")
    f = random_rational(rng, syms)
    g = sp.together(f)  # the same function in another form
    assert is_zero_rational_function(f - g) is True
    perturbed = f - g + sp.Rational(1, 97) * x / (y**2 + 1)
    assert is_zero_rational_function(perturbed) is False
    assert _sympy_zero(perturbed) is False


def test_the_3x3_reflection_identity_and_a_mutant():
    M, u = symbolic_mass_matrix(3), symbolic_covector(3)
    w = M.adjugate() * u.T
    s = (u * w)[0, 0]
    G = sp.eye(3) - 2 * w * u / s
    D = G - printed_G(M, u)
    assert all(is_zero_rational_function(x) is True for x in D)
    D[0, 0] += sp.Rational(1, 97) * M[0, 1] / s
    assert is_zero_rational_function(D[0, 0]) is False


@pytest.mark.parametrize("expr", ["sqrt(x) - x", "sin(x)", "x - 0.5", "I*x", "1/(x - x + 0)"])
def test_declines_what_is_not_a_rational_function(expr):
    with sp.evaluate(True):
        e = sp.sympify(expr) if expr != "1/(x - x + 0)" else sp.Pow(sp.Symbol("x") - sp.Symbol("x"), -1, evaluate=False)
    assert is_zero_rational_function(e) is None


def test_zero_denominator_is_refused():
    x = sp.Symbol("x")
    with pytest.raises(TypeError):
        to_fraction(sp.Mul(x, sp.Pow(sp.Add(x, -x, evaluate=False), -1, evaluate=False), evaluate=False), [x])
