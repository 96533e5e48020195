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
* :mod:`~impactsym.arithmetic.balls` — Arb enclosures and their exact reads;
* :mod:`~impactsym.arithmetic.literals` — plain numeric text (``"11/10"``, ``"1e-3"``) read exactly
  with the standard library alone, and the float of an exact rational in JSON.

The names below are imported on first use, so that importing one light submodule costs no SymPy.

It depends only on :mod:`impactsym.errors`; the laws, :mod:`impactsym.verify` and
:mod:`impactsym.exact` (the historical name of the sign functions) import from it.

>>> import sympy as sp
>>> from impactsym.arithmetic import certified_sign, exact_rank
>>> certified_sign(sp.sqrt(2) - sp.Rational(141421, 100000)), exact_rank(sp.Matrix([[1, 2], [2, 4]]))
(1, 1)
"""

import importlib

from .._lazy import lazy_attributes

#: every public name and the submodule it lives in, imported on first use (PEP 562): the plain-text
#: reader (:mod:`~impactsym.arithmetic.literals`) serves the command line's start-up without SymPy
_NAMES = {
    **dict.fromkeys(["arb_mid_float", "arb_to_mpf", "arf_fmpq", "ball_ends", "certified_ceil", "certified_ceiling", "enclose", "enclose_narrow",
                     "nearest_int"], "balls"),
    **dict.fromkeys(["certified_compare", "certified_sign", "tidy"], "closed_form"),
    **dict.fromkeys(["AlgebraicField", "RationalField", "compare_surds", "field_of", "sign_of", "sign_surd"],
                    "fields"),
    **dict.fromkeys(["ExactLinearAlgebra", "dot", "exact_rank", "in_row_space", "independent", "kernel_basis",
                     "matvec", "minner", "nullspace", "rank", "rref", "solve_columns"], "linalg"),
    **dict.fromkeys(["all_rational", "as_fmpq", "bits", "exact_data", "float_to_rational", "float_vector",
                     "rational_matrix", "rational_sqrt", "to_fmpq", "to_sympy_matrix", "to_sympy_rational"],
                    "rational"),
}


class LazyModule:
    """A stand-in for the module ``name``, imported on the first attribute read; it then puts the
    module itself in its place (``namespace[alias]``), so that later reads cost nothing.

    The arithmetic modules hold SymPy this way: their rational paths (python-flint ``fmpq``) run
    without importing it, and the first SymPy number handled imports it.

    >>> ns = {}
    >>> ns["m"] = LazyModule("fractions", ns, "m")
    >>> ns["m"].Fraction(1, 2), type(ns["m"]).__name__
    (Fraction(1, 2), 'module')
    """

    def __init__(self, name: str, namespace: dict, alias: str):
        self._name, self._namespace, self._alias = name, namespace, alias

    def __getattr__(self, attr):
        module = importlib.import_module(self._name)
        self._namespace[self._alias] = module
        return getattr(module, attr)


def sympy_instance(x, kind: str = "Basic") -> bool:
    """``isinstance(x, sympy.<kind>)`` without importing SymPy: before SymPy is loaded no object is
    one, so a float or rational path can test its input's type for free.

    >>> sympy_instance(2.0, "MatrixBase")
    False
    """
    import sys

    mod = sys.modules.get("sympy")
    return mod is not None and isinstance(x, getattr(mod, kind))


__getattr__, __dir__ = lazy_attributes(__name__, _NAMES, globals())


__all__ = [
    "certified_sign", "certified_compare", "tidy",
    "float_to_rational", "as_fmpq", "to_fmpq", "bits", "all_rational", "rational_matrix", "to_sympy_rational", "to_sympy_matrix",
    "exact_data", "float_vector", "rational_sqrt",
    "sign_of", "sign_surd", "compare_surds", "RationalField", "AlgebraicField", "field_of",
    "rref", "kernel_basis", "nullspace", "solve_columns", "rank", "independent", "in_row_space", "dot",
    "matvec", "minner", "exact_rank", "ExactLinearAlgebra",
    "enclose", "enclose_narrow", "arf_fmpq", "ball_ends", "certified_ceil", "certified_ceiling", "nearest_int", "arb_to_mpf",
]
