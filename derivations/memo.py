"""Memoized SymPy ``simplify``: the paper checks and the derivations simplify the same expressions
again and again (the same scene's quantities in several claims); ``simplify`` is pure, so its
result is kept per expression (``functools.lru_cache``). It is the one cache of ``derivations``
the mutation tests keep (``paper_checks.mutations.clear_caches`` skips a cache marked
``sympy_only``): it calls SymPy alone, which no mutation replaces, so it can never hold a value a
mutant computed (a mutant's different expression is a different key). Unhashable arguments
(mutable matrices) are simplified directly.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> simplify(sp.sin(x)**2 + sp.cos(x)**2), simplify(sp.Matrix([[x / x]]))
(1, Matrix([[1]]))
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

__all__ = ["simplify"]


def simplify(expr, **kwargs):
    """``sympy.simplify(expr, **kwargs)``, memoized per (expression, options)."""
    try:
        return _simplify_cached(expr, **kwargs)
    except TypeError as exc:
        if "unhashable" not in str(exc):
            raise
        return sp.simplify(expr, **kwargs)


@lru_cache(maxsize=8192, typed=True)
def _simplify_cached(expr, **kwargs):
    return sp.simplify(expr, **kwargs)


#: SymPy's simplify and nothing of ours: kept across mutations (see the module docstring)
_simplify_cached.sympy_only = True
