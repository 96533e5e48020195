"""SymPy's ``simplify`` (and ``solve``, ``solveset``), remembered per expression, for the exact
forms that recur: the derivations' and paper checks' simplifications (:mod:`derivations.memo`
calls it), the pool's gradient entries (:mod:`impactsym.models.acary_taha`) and the kinetic angles
and M-normals of :mod:`impactsym.mechanics` are simplified again whenever their own caches are
cleared (the paper checks' mutation tests clear every cache of impactsym between mutations), and
``simplify`` of the same expression is the same expression.

The memo calls SymPy alone (``paper_checks.mutations.clear_caches`` keeps it, marked
``sympy_only``): no function of impactsym runs inside it, so it never holds a value that a mutated
function computed (a mutant's expression is another key). A dense mutable matrix is remembered as
its immutable copy (``simplify`` would sympify it so); other unhashable arguments are simplified
directly.

>>> import sympy as sp
>>> t = sp.Symbol("t")
>>> simplify_remembered(sp.sin(t)**2 + sp.cos(t)**2), simplify_remembered(sp.Matrix([[t / t]]))
(1, Matrix([[1]]))
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

__all__ = ["simplify_remembered", "solveset_remembered", "solve_remembered"]


def simplify_remembered(expr, **kwargs):
    """``sympy.simplify(expr, **kwargs)``, remembered per (immutable) expression and options. A
    mutable matrix is remembered as its immutable copy: ``simplify`` sympifies its argument, so it
    simplifies that copy and returns an immutable matrix either way (the M-normals of
    :func:`impactsym.mechanics.m_normal`, simplified again on every call otherwise)."""
    if type(expr) is sp.MutableDenseMatrix:
        expr = sp.ImmutableDenseMatrix(expr)
    try:
        return _simplify_cached(expr, **kwargs)
    except TypeError as exc:
        if "unhashable" not in str(exc):
            raise
        return sp.simplify(expr, **kwargs)


@lru_cache(maxsize=8192, typed=True)
def _simplify_cached(expr, **kwargs):
    return sp.simplify(expr, **kwargs)


#: SymPy's simplify and nothing of impactsym: kept across the mutation tests' cache clears
_simplify_cached.sympy_only = True


def solveset_remembered(f, symbol, domain):
    """``sympy.solveset(f, symbol, domain)``, remembered per (immutable) arguments: the paper
    checks' sign proofs on an interval (``cos θ > 0`` on ``[π/2, 2π/3[``, ...) are decided again
    whenever a mutation test re-evaluates their claim (0.02-0.1 s each), and SymPy's answer to the
    same question is the same set. Kept across the mutation tests' cache clears, like
    :func:`simplify_remembered` (SymPy alone: a mutant's different inequality is another key)."""
    return _solveset_cached(f, symbol, domain)


@lru_cache(maxsize=1024, typed=True)
def _solveset_cached(f, symbol, domain):
    return sp.solveset(f, symbol, domain)


#: SymPy's solveset and nothing of impactsym: kept across the mutation tests' cache clears
_solveset_cached.sympy_only = True


def solve_remembered(f, *symbols, **flags):
    """``sympy.solve(f, *symbols, **flags)``, remembered per arguments (a list of equations or
    symbols is remembered as the tuple of its entries, which ``solve`` reads the same way): the
    derivations' and paper checks' systems are solved again whenever a mutation test clears their
    caches and re-evaluates a claim, and SymPy's answer to the same system is the same. Kept
    across those clears, like :func:`simplify_remembered` (SymPy alone; a mutant's different
    system is another key). Each call gets its own list (and dicts) of the remembered solutions.

    >>> x, y = sp.symbols("x y")
    >>> solve_remembered(x**2 - 1, x), solve_remembered([x + y - 1, x - y], [x, y], dict=True)
    ([-1, 1], [{x: 1/2, y: 1/2}])
    """
    f = tuple(f) if isinstance(f, list) else f
    symbols = tuple(tuple(s) if isinstance(s, list) else s for s in symbols)
    try:
        out = _solve_cached(f, *symbols, **flags)
    except TypeError as exc:
        if "unhashable" not in str(exc):
            raise
        return sp.solve(f, *symbols, **flags)
    if isinstance(out, dict):
        return dict(out)
    return [dict(x) if isinstance(x, dict) else x for x in out]


@lru_cache(maxsize=1024, typed=True)
def _solve_cached(f, *symbols, **flags):
    return sp.solve(f, *symbols, **flags)


#: SymPy's solve and nothing of impactsym: kept across the mutation tests' cache clears
_solve_cached.sympy_only = True
