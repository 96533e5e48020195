"""Random rational expressions for the tests of the exact zero tests (``derivations.rational_zero``):
one generator shared by ``test_rational_zero.py`` and ``test_exact_zero_tests.py``.

>>> import random, sympy as sp
>>> f = random_rational(random.Random(0), sp.symbols("x y"))
>>> f.free_symbols <= set(sp.symbols("x y"))
True
"""

from __future__ import annotations

import sympy as sp


def random_rational(rng, syms, depth=3):
    """A random expression tree of ``depth`` levels over ``syms`` and small rationals, built with
    ``+ − × ÷`` (a division by an expression that simplifies to 0 becomes a product)."""
    if depth == 0:
        return rng.choice(syms) if rng.random() < 0.7 else sp.Rational(rng.randint(-5, 5), rng.randint(1, 4))
    a, b = random_rational(rng, syms, depth - 1), random_rational(rng, syms, depth - 1)
    op = rng.choice(("+", "-", "*", "/"))
    if op == "/" and _is_zero(b, syms):
        op = "*"
    return {"+": a + b, "-": a - b, "*": a * b, "/": a / b if op == "/" else a}[op]


def _is_zero(b, syms) -> bool:
    """Whether ``b`` is identically zero. Built from ``syms`` and rationals by ``+ − × ÷``, ``b`` is a
    rational function of ``syms``, whose normal form (``cancel``) is 0 exactly when it is zero; the
    check keeps ``simplify`` for anything else."""
    if b.is_rational_function(*syms):
        return sp.cancel(b) == 0
    return sp.simplify(b) == 0
