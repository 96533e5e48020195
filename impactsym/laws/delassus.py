"""The Delassus operator ``W = H M⁻¹ Hᵀ``, and the exact arithmetic the multi-contact laws import.

Every multi-contact law (impulse ratio, Newton/Moreau, Poisson, sequential) works with
``W = H M⁻¹ Hᵀ`` (the matrix of eq. 7, ``Δv = W p``) and with ``w = H v`` (relative normal
velocities). Its branch decisions are signs. They are decided

* in exact rational arithmetic (python-flint ``fmpq_mat``) when every entry is rational, which
  includes float input, taken at its exact binary value (``CONVENTIONS.md``: a float sign is
  re-decided exactly, never guessed);
* by :func:`impactsym.exact.certified_sign` when an entry is irrational (``sqrt(3)/2``, ``cos(pi/5)``).

The arithmetic itself (conversions, signs of ``x + y√d``, exact rank and solve) lives in
:mod:`impactsym.arithmetic`; its names are re-exported here, where the laws have always imported
them.

>>> import sympy as sp
>>> R = rational_matrix(sp.Matrix([[1, sp.Rational(1, 2)], [0, 3]]))
>>> R.solve(rational_matrix(sp.Matrix([1, 3])))[0, 0]
1/2
>>> rational_matrix(sp.Matrix([[sp.sqrt(2)]])) is None
True
>>> sign_surd(sp.Rational(3, 2), -1, 2)   # 3/2 - sqrt(2) > 0
1
"""

from __future__ import annotations

import flint
import numpy as np
import sympy as sp

from functools import lru_cache

from ..arithmetic import (ExactLinearAlgebra, exact_data, exact_rank, rational_matrix, sign_of, sign_surd,
                          to_sympy_matrix, to_sympy_rational)
from ..arithmetic import tidy as _tidy_afresh

__all__ = ["ExactLinearAlgebra", "exact_data", "exact_rank", "rational_matrix", "to_sympy_rational", "to_sympy_matrix",
           "sign_of", "sign_surd", "tidy", "delassus"]


@lru_cache(maxsize=4096)
def _tidy_remembered(x):
    return _tidy_afresh(x)


def tidy(x):
    """:func:`impactsym.arithmetic.tidy` (a canonical exact form, value unchanged), remembered.

    ``tidy`` is a pure function of a SymPy expression (immutable and hashable; equal expressions
    have the same canonical arguments, so they tidy alike), and the laws meet the same numbers
    again and again: every ``(α, e)`` of a grid on one scene has the same ``W`` and ``H v``, every
    law on one scene the same Delassus entries. The last 4096 are kept; an unhashable argument is
    tidied afresh.

    >>> tidy(sp.sqrt(8) / 2 - sp.sqrt(2)), tidy(sp.sqrt(2) * (sp.sqrt(2) + 1))
    (0, sqrt(2) + 2)
    """
    try:
        return _tidy_remembered(x)
    except TypeError:
        return _tidy_afresh(x)


def delassus(M, H):
    """``W = H M⁻¹ Hᵀ`` (symmetric, positive semi-definite; eq. 7 reads ``Δv = W p``).

    Exact (SymPy) for SymPy input, ``fmpq_mat`` for ``fmpq_mat`` input, float otherwise.

    >>> delassus(sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]))
    Matrix([
    [ 2, -1],
    [-1,  2]])
    """
    if isinstance(M, flint.fmpq_mat):
        return H * M.solve(H.transpose())
    if isinstance(M, sp.MatrixBase):
        return H * M.LUsolve(H.T)
    H = np.asarray(H, dtype=float)
    return H @ np.linalg.solve(np.asarray(M, dtype=float), H.T)
