"""derivations.rational_zero.factor is SymPy's factor, term for term, for rational functions with
rational coefficients (it replaces sympy.factor in the single-impact derivations)."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from derivations.rational_zero import factor

x, y, z, w = sp.symbols("x y z w")


def _battery(seed: int, count: int):
    rnd = random.Random(seed)
    syms = [w, x, y, z]

    def poly():
        return sum(sp.Rational(rnd.randint(-5, 5), rnd.randint(1, 3))
                   * sp.Mul(*[s**rnd.randint(0, 2) for s in rnd.sample(syms, 2)]) for _ in range(rnd.randint(1, 3)))

    out = []
    while len(out) < count:
        a, b, c = poly(), poly(), poly()
        if b == 0 or c == 0:
            continue
        out.append(a * c / (b * c) + (poly() / c if rnd.random() < 0.3 else 0))
    return out


@pytest.mark.parametrize("expr", _battery(7, 40), ids=lambda e: str(e)[:40])
def test_factor_is_sympys_factor(expr):
    assert factor(expr) == sp.factor(expr)


def test_factor_falls_back_outside_rational_functions():
    e = (sp.sqrt(2) * x**2 - sp.sqrt(2)) / (x - 1)
    assert factor(e) == sp.factor(e)
    assert factor(sp.Rational(6, 4)) == sp.Rational(3, 2)
    assert factor(sp.sin(x) ** 2 - 1) == sp.factor(sp.sin(x) ** 2 - 1)


def test_factor_on_the_single_impact_root():
    from derivations.rational_zero import is_zero
    from derivations.reflection import derive_single_impact

    d = derive_single_impact(2)
    kept = [r for r in d.roots if not is_zero(r)]
    assert len(kept) == 1
    assert factor(kept[0]) == sp.factor(kept[0]) == d.lam
