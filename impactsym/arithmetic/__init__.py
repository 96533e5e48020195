"""The one exact-arithmetic layer of impactsym.

Every law decides its branches by signs and solves small linear systems exactly. This package
holds all of that, once:

* :mod:`~impactsym.arithmetic.closed_form` — certified signs and comparisons of SymPy closed
  forms (:func:`certified_sign`), and :func:`tidy`, a canonical form of a closed-form number;
* :mod:`~impactsym.arithmetic.rational` — python-flint ``fmpq``/``fmpq_mat`` and their
  conversions from and to SymPy (floats at their exact binary value);
* :mod:`~impactsym.arithmetic.fields` — the two exact fields (rational; algebraic with certified
  signs) behind one interface, and exact signs of ``x + y√d``;
* :mod:`~impactsym.arithmetic.linalg` — row reduction, null space, solve, rank on those fields
  (python-flint ``fmpq_mat`` and SymPy ``DomainMatrix``; certified elimination only where no
  number field exists);
* :mod:`~impactsym.arithmetic.balls` — Arb enclosures and their exact reads.

It depends only on :mod:`impactsym.errors`; the laws, :mod:`impactsym.verify` and
:mod:`impactsym.exact` (the historical name of the sign functions) import from it.

>>> import sympy as sp
>>> certified_sign(sp.sqrt(2) - sp.Rational(141421, 100000)), exact_rank(sp.Matrix([[1, 2], [2, 4]]))
(1, 1)
"""

from .balls import arb_to_mpf, arf_fmpq, ball_ends, certified_ceil, certified_ceiling, enclose, nearest_int
from .closed_form import certified_compare, certified_sign, tidy
from .fields import AlgebraicField, RationalField, compare_surds, field_of, sign_of, sign_surd
from .linalg import (ExactLinearAlgebra, dot, exact_rank, in_row_space, independent, kernel_basis, matvec,
                     minner, nullspace, rank, rref, solve_columns)
from .rational import (all_rational, as_fmpq, bits, exact_data, float_to_rational, float_vector, rational_matrix,
                       rational_sqrt, to_fmpq, to_sympy_matrix, to_sympy_rational)

__all__ = [
    "certified_sign", "certified_compare", "tidy",
    "float_to_rational", "as_fmpq", "to_fmpq", "bits", "all_rational", "rational_matrix", "to_sympy_rational", "to_sympy_matrix",
    "exact_data", "float_vector", "rational_sqrt",
    "sign_of", "sign_surd", "compare_surds", "RationalField", "AlgebraicField", "field_of",
    "rref", "kernel_basis", "nullspace", "solve_columns", "rank", "independent", "in_row_space", "dot",
    "matvec", "minner", "exact_rank", "ExactLinearAlgebra",
    "enclose", "arf_fmpq", "ball_ends", "certified_ceil", "certified_ceiling", "nearest_int", "arb_to_mpf",
]
