"""Exact expressions that the derivations committed as generated data (``impactsym/kernels/*.py``
modules with an ``EXPRESSIONS`` table of ``sympy.srepr`` text, written by
``derivations.codegen.render_expressions``).

The package reads what a derivation found through this module, so that it never imports
``derivations`` at run time (the layer rule of the README's Layout section).

Examples
--------
>>> committed_expressions("domain_boundaries")["chain3_alpha_max"]
(2*e - sqrt(6*e - 2) - 2)/(e - 3)
"""

from __future__ import annotations

import importlib
from functools import lru_cache

import sympy as sp
from sympy.functions.elementary.piecewise import ExprCondPair

__all__ = ["committed_expressions"]


@lru_cache(maxsize=None)
def committed_expressions(module: str) -> dict:
    """The expressions of the generated module ``impactsym.kernels.<module>``, parsed once.

    Parameters
    ----------
    module : the generated module's name (``"domain_boundaries"``, ``"chain3_naive"``)

    Returns
    -------
    dict
        name -> SymPy expression (or list of expressions), symbols with their assumptions.

    Raises
    ------
    KeyError
        no such generated data module.
    """
    try:
        mod = importlib.import_module(f"impactsym.kernels.{module}")
    except ModuleNotFoundError:
        raise KeyError(f"no generated data module impactsym/kernels/{module}.py") from None
    ns = {**vars(sp), "ExprCondPair": ExprCondPair}

    def parse(text):
        return eval(text, ns)  # srepr text of a committed generated file, never user input

    return {k: [parse(x) for x in v] if isinstance(v, list) else parse(v) for k, v in mod.EXPRESSIONS.items()}
