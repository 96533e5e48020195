"""Verified rewriting in a non-commutative algebra: the engine of the general-n proofs.

A general-n identity between matrices built from a mass matrix ``M``, a covector ``u`` and
``w = M⁻¹uᵀ`` cannot be checked entry by entry (``n`` is a symbol). It can be checked in the
associative algebra the matrices generate: symbols that do not commute (``W``, ``U``, ``M``,
their transposes ``Wt``, ``Ut``), commuting scalars (``s = u w``), and rewrite rules that are
the defining relations, each justified once:

=============  ==================================================
``U*W -> s``   definition of the scalar ``s = u M⁻¹ uᵀ``
``M*W -> Ut``  definition of ``w = M⁻¹uᵀ``
``Wt*M -> U``  transpose of the previous rule, with ``Mᵀ = M``
``Wt*Ut -> s`` transpose of ``U*W -> s``
=============  ==================================================

Because the rules are identities of the actual matrices in every dimension, an expression
that rewrites to another under them is equal to it for every ``n``. SymPy does the expansion
and the rewriting; :func:`rewrite` iterates to a fixed point.

>>> import sympy as sp
>>> W, U = sp.symbols("W U", commutative=False)
>>> s = sp.Symbol("s", nonzero=True)
>>> rewrite(sp.expand((1 - 2*W*U/s)**2), {U*W: s})
1
"""

from __future__ import annotations

import sympy as sp

__all__ = ["rewrite", "nc_symbols", "block_determinant_lemma"]


def nc_symbols(names: str):
    """Non-commutative SymPy symbols (matrices of unspecified size)."""
    return sp.symbols(names, commutative=False)


def rewrite(expr, rules: dict, *, max_rounds: int = 50):
    """Expand ``expr`` and apply ``rules`` (contiguous sub-products) until nothing changes.

    Raises
    ------
    RuntimeError
        If no fixed point is reached in ``max_rounds`` rounds (a non-terminating rule set).
    """
    current = sp.expand(expr)
    for _ in range(max_rounds):
        new = sp.expand(current.subs(rules))
        if new == current:
            return new
        current = new
    raise RuntimeError("rewrite rules did not reach a fixed point")


def block_determinant_lemma():
    """Verify the block identity behind the matrix determinant lemma, for every ``n``.

    With ``a`` an n×1 column and ``b`` a 1×n row (``b a`` a scalar),

        [[I, 0], [b, 1]] · [[I + a b, a], [0, 1]] · [[I, 0], [-b, 1]] = [[I, a], [0, 1 + b a]].

    The outer factors are block unit-triangular (determinant 1); the right side is block
    upper-triangular, so ``det(I + a b) = 1 + b a``. Returns the product, as computed, and
    whether it equals the right side.

    >>> product, ok = block_determinant_lemma()
    >>> ok
    True
    """
    a, b = nc_symbols("a b")
    ba = sp.Symbol("beta")  # the scalar b·a
    L = sp.Matrix([[1, 0], [b, 1]])
    Mid = sp.Matrix([[1 + a * b, a], [0, 1]])
    R = sp.Matrix([[1, 0], [-b, 1]])
    product = (L * Mid * R).applyfunc(lambda x: rewrite(x, {b * a: ba}))
    target = sp.Matrix([[1, a], [0, 1 + ba]])
    return product, (product - target).applyfunc(sp.expand) == sp.zeros(2, 2)
