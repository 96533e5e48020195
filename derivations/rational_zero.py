"""Exact zero test of a rational function, in python-flint's multivariate polynomials.

A derivation often ends with "``a − b`` is identically zero" where ``a`` and ``b`` are rational
functions of a dozen symbols (the entries of a symbolic mass matrix, a covector, a velocity).
SymPy's ``cancel(together(a − b))`` decides it by gcds of large expressions: 8–13 s for the
energy-loss identity of the 3×3 Newton-restitution map. The test needs no gcd at all: write the
expression as one fraction ``N / D`` with ``D`` a product of non-zero polynomials, and the
expression is identically zero exactly when the expanded numerator ``N`` is the zero polynomial.
python-flint's ``fmpq_mpoly`` (exact rational coefficients, C arithmetic) expands ``N`` in
milliseconds.

:func:`is_zero_rational_function` returns ``None`` (undecided here) for anything that is not a
rational function of commutative symbols with rational coefficients (a square root, a function,
a float, a zero denominator); the caller then falls back to SymPy. It never guesses: ``True``
means the numerator polynomial is exactly 0 and the denominator polynomial exactly non-zero.

Examples
--------
>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> is_zero_rational_function(1 / (x - y) - 1 / (y - x) - 2 / (x - y))
True
>>> is_zero_rational_function((x**2 - y**2) / (x - y) - x)
False
>>> is_zero_rational_function(sp.sqrt(x) - x) is None  # not a rational function: undecided here
True
"""

from __future__ import annotations

import flint
import sympy as sp

__all__ = ["is_zero_rational_function", "to_fraction"]


class _NotRational(TypeError):
    """The expression is not a rational function with rational coefficients."""


def to_fraction(expr, symbols):
    """``(N, D)``: ``expr = N / D`` with ``N, D`` python-flint ``fmpq_mpoly`` in ``symbols``, built
    without any gcd (sums over a common denominator only where the denominators are equal).

    Raises
    ------
    TypeError
        ``expr`` is not a rational function of ``symbols`` with rational coefficients.

    >>> x = sp.Symbol("x")
    >>> n, d = to_fraction(1 / x + 1, [x])
    >>> str(n), str(d)
    ('x + 1', 'x')
    """
    symbols = list(symbols)
    names = tuple(str(s) for s in symbols)
    if len(set(names)) < len(names):  # two symbols of one name (other assumptions): index them
        names = tuple(f"x{i}" for i in range(len(symbols)))
    ctx = flint.fmpq_mpoly_ctx.get(names or ("x0",), "lex")
    index = {s: i for i, s in enumerate(symbols)}
    one = ctx.from_dict({}) + 1
    gens = ctx.gens()
    memo: dict = {}

    def conv(e):
        hit = memo.get(e)
        if hit is not None:
            return hit
        if e.is_Symbol:
            if e not in index:
                raise _NotRational(f"symbol {e} not among the variables")
            out = (gens[index[e]], one)
        elif e.is_Rational:
            out = (one * flint.fmpq(int(e.p), int(e.q)), one)
        elif e.is_Add:
            n, d = conv(e.args[0])
            for a in e.args[1:]:
                n2, d2 = conv(a)
                if d2 == d:
                    n = n + n2
                else:
                    n, d = n * d2 + n2 * d, d * d2
            out = (n, d)
        elif e.is_Mul:
            n, d = one, one
            for a in e.args:
                n2, d2 = conv(a)
                n, d = n * n2, d * d2
            out = (n, d)
        elif e.is_Pow and e.exp.is_Integer:
            n, d = conv(e.base)
            k = int(e.exp)
            if k < 0 and n == 0:
                raise _NotRational("division by the zero polynomial")
            out = (n ** k, d ** k) if k >= 0 else (d ** (-k), n ** (-k))
        else:
            raise _NotRational(f"not a rational function: {type(e).__name__}")
        memo[e] = out
        return out

    n, d = conv(sp.sympify(expr))
    if d == 0:
        raise _NotRational("the denominator is the zero polynomial")
    return n, d


def is_zero_rational_function(expr) -> bool | None:
    """Whether ``expr`` (a SymPy expression) is identically zero as a rational function.

    Returns
    -------
    True or False, decided exactly (numerator polynomial zero or not, denominator non-zero);
    None when ``expr`` is not a rational function of commutative symbols with rational
    coefficients (the caller decides it another way).
    """
    expr = sp.sympify(expr)
    if not expr.is_commutative:
        return None
    try:
        n, _d = to_fraction(expr, sorted(expr.free_symbols, key=str))
    except _NotRational:
        return None
    return n == 0
