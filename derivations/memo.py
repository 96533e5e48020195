"""Memoized SymPy ``simplify``: the paper checks and the derivations simplify the same expressions
again and again (the same scene's quantities in several claims); ``simplify`` is pure, so its
result is kept per expression, in the one memo of SymPy's ``simplify``
(:func:`impactsym.arithmetic.remembered.simplify_remembered`, which the library's own recurring
forms share). The mutation tests keep it (``paper_checks.mutations.clear_caches`` skips a cache
marked ``sympy_only``): it calls SymPy alone, which no mutation replaces, so it can never hold a
value a mutant computed (a mutant's different expression is a different key). Unhashable
arguments (mutable matrices) are simplified directly.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> simplify(sp.sin(x)**2 + sp.cos(x)**2), simplify(sp.Matrix([[x / x]]))
(1, Matrix([[1]]))
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

from impactsym.arithmetic.remembered import simplify_remembered

__all__ = ["simplify"]


def simplify(expr, **kwargs):
    """``sympy.simplify(expr, **kwargs)``, memoized per (expression, options)."""
    if not kwargs and isinstance(expr, sp.Expr) and expr.has(sp.sin, sp.cos):
        try:
            reduced = _trigonometry_reduced(expr)
        except TypeError:  # unhashable
            reduced = None
        if reduced is not None:
            expr = reduced
    return simplify_remembered(expr, **kwargs)


@lru_cache(maxsize=8192)
def _trigonometry_reduced(expr):
    """``expr`` with the addition formulas expanded (``expand_trig``) and ``sin²u = 1 − cos²u``
    applied (a normal form), when that removes every sine and cosine or makes the expression
    smaller (``count_ops``); None otherwise.

    Both rewritings are identities, so the result equals ``expr``; it is what ``simplify`` has to
    find through ``trigsimp`` (0.03-0.12 s each for the energies and coefficients of the pool,
    ``sin²(τ − θ) + cos²(τ − θ)``, ``sin θ sin(τ − θ) − cos θ cos(τ − θ)``), found by polynomial
    division instead, and ``simplify`` of it returns the same expression as ``simplify(expr)``
    (srepr for srepr): checked on each of the 64 such calls of the code generator, the closed-form
    and domain tests and the paper audit (the generated files and ``reproduce --json`` are
    byte-identical). ``simplify`` itself then runs on the smaller expression, in about a third of
    the time.

    >>> t, e = sp.symbols("t e", real=True)
    >>> _trigonometry_reduced((1 - e) * (sp.sin(t - 1)**2 + sp.cos(t - 1)**2) / 2)
    1/2 - e/2
    >>> _trigonometry_reduced(sp.sin(t) * sp.sin(t - e) + sp.cos(t) * sp.cos(t - e))
    cos(e)
    >>> _trigonometry_reduced(sp.sin(t)**2 + sp.cos(t)) is None  # 1 - cos(t)**2 + cos(t): not smaller
    True
    """
    other = (sp.tan, sp.cot, sp.sec, sp.csc)
    if not isinstance(expr, sp.Expr) or not expr.has(sp.sin, sp.cos) or expr.has(*other):
        return None
    expanded = sp.expand(sp.expand_trig(expr))
    angles = sorted({f.args[0] for f in expanded.atoms(sp.sin, sp.cos)}, key=sp.default_sort_key)
    gens = [f(u) for u in angles for f in (sp.sin, sp.cos)]
    if not gens:
        reduced = expanded
    else:
        # the relations have the coprime leading monomials sin(u)² (lex, each sine before its
        # cosine): a Gröbner basis, so the remainder is the normal form, with no sin(u)²
        relations = [sp.sin(u) ** 2 + sp.cos(u) ** 2 - 1 for u in angles]
        try:
            reduced = sp.reduced(expanded, relations, *gens, order="lex")[1]
        except sp.polys.polyerrors.BasePolynomialError:  # a sine or cosine in a denominator or a root
            return None
    if reduced.has(*other):
        return None
    if not reduced.has(sp.sin, sp.cos) or sp.count_ops(reduced) < sp.count_ops(expr):
        return reduced
    return None


