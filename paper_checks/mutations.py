"""Mutants of the laws and derivations that the claims rest on.

A verdict is only worth printing if a computation chose it: were the package (or the
transcription) wrong, the claim would reach another verdict. This module makes that testable.
Each *mutation* replaces one function of impactsym or of ``derivations`` by a wrong version
(the original, with its output corrupted), everywhere it is bound: in its own module and in every
module that imported the name. Claims declare the mutations they depend on
(``claim(..., mutations=("reflection_map",))``), and ``paper_checks/test_mutations.py`` evaluates
each claim under each of its mutations and requires that the verdict changes or the claim raises.

Caches are the trap: a claim memoized before the mutation would repeat its unmutated verdict.
:func:`applied` clears the claim memo and every ``functools.lru_cache`` in impactsym,
``derivations`` and ``paper_checks`` on entry and on exit, and on exit puts back the claim findings
memoized before the mutation (the original functions computed them; nothing computed under the
mutant is kept).

Examples
--------
>>> import sympy as sp
>>> from impactsym.laws.reflection import reflection_map
>>> with applied("reflection_map"):
...     from impactsym.laws import reflection
...     reflection.reflection_map("1,0;0,1", "1,0") == sp.Matrix([[-1, 0], [0, 1]])
False
>>> reflection_map("1,0;0,1", "1,0") == sp.Matrix([[-1, 0], [0, 1]])
True
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import sys
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Callable

import sympy as sp

__all__ = ["Mutation", "MUTATIONS", "mutation", "applied", "corrupt", "clear_caches"]

#: the perturbation every generic corruption adds: small, exact and never a coincidence
EPS = sp.Rational(1, 97)


@dataclass(frozen=True)
class Mutation:
    """A wrong version of ``target`` (``"module:attribute"``), built from the original by ``make``."""

    name: str
    target: str
    description: str
    make: Callable[[Callable], Callable]


#: every mutation, by name
MUTATIONS: dict[str, Mutation] = {}


def mutation(name: str, target: str, description: str):
    """Register ``make(original) -> replacement`` as the mutation ``name`` of ``target``."""

    def register(make):
        if name in MUTATIONS:
            raise ValueError(f"name: mutation {name!r} registered twice")
        MUTATIONS[name] = Mutation(name, target, description, make)
        return make

    return register


# --------------------------------------------------------------------------- corruption
def corrupt(obj: Any) -> Any:
    """A wrong copy of a result: numbers and matrices shifted by :data:`EPS`, containers and
    dataclasses corrupted in their first corruptible field. Raises ``TypeError`` when nothing in
    ``obj`` can be corrupted (a mutation must never be a silent no-op).

    >>> corrupt(sp.Rational(1, 2))
    99/194
    >>> corrupt(sp.Matrix([[1, 0]]))
    Matrix([[98/97, 0]])
    """
    if isinstance(obj, sp.MatrixBase):
        out = sp.Matrix(obj)
        if out.rows * out.cols == 0:
            raise TypeError("corrupt: empty matrix")
        out[0, 0] = out[0, 0] + EPS
        return out
    if isinstance(obj, sp.Basic) and not isinstance(obj, sp.logic.boolalg.Boolean):
        return obj + EPS
    if isinstance(obj, bool):
        return not obj
    if isinstance(obj, (int, float)):
        return obj + float(EPS) if isinstance(obj, float) else sp.Integer(obj) + EPS
    if isinstance(obj, (list, tuple)) and obj:
        head = corrupt(obj[0])
        rest = list(obj[1:])
        return type(obj)([head, *rest]) if isinstance(obj, list) else tuple([head, *rest])
    if isinstance(obj, dict) and obj:
        for k, v in obj.items():
            try:
                return {**obj, k: corrupt(v)}
            except TypeError:
                continue
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        for f in dataclasses.fields(obj):
            try:
                new = corrupt(getattr(obj, f.name))
            except TypeError:
                continue
            try:
                return dataclasses.replace(obj, **{f.name: new})
            except (TypeError, ValueError):
                clone = __import__("copy").copy(obj)
                object.__setattr__(clone, f.name, new)
                return clone
    try:
        import numpy as np

        if isinstance(obj, np.ndarray) and obj.size:
            out = np.array(obj, dtype=float, copy=True)
            out.flat[0] += float(EPS)
            return out
    except ImportError:  # pragma: no cover
        pass
    raise TypeError(f"corrupt: nothing to corrupt in a {type(obj).__name__}")


def corrupting(original: Callable) -> Callable:
    """The original function with its result passed through :func:`corrupt`."""

    @functools.wraps(original)
    def wrong(*args, **kwargs):
        return corrupt(original(*args, **kwargs))

    wrong.__wrapped_mutant__ = True
    return wrong


# --------------------------------------------------------------------------- the mutations
@mutation("reflection_map", "impactsym.laws.reflection:reflection_map",
          "G_u with its first entry shifted by 1/97 (no longer a reflection)")
def _reflection_map(original):
    return corrupting(original)


# --------------------------------------------------------------------------- applying
_SCOPES = ("impactsym", "derivations", "paper_checks")


def _in_scope(modname: str) -> bool:
    return modname.partition(".")[0] in _SCOPES


def _scoped_modules() -> list:
    """The imported modules of impactsym, derivations and paper_checks (one pass over sys.modules)."""
    return [mod for name, mod in list(sys.modules.items()) if mod is not None and name.partition(".")[0] in _SCOPES]


def clear_caches() -> None:
    """Forget every memoized claim and every ``lru_cache`` in impactsym, derivations and
    paper_checks (so that nothing computed under one mutation leaks into another run), except a
    cache marked ``sympy_only`` (a memo of a SymPy function alone, which no mutation replaces)."""
    from . import framework

    framework._MEMO.clear()
    for mod in _scoped_modules():
        for value in list(vars(mod).values()):
            clear = getattr(value, "cache_clear", None)
            # a cache marked sympy_only memoizes a SymPy function alone (derivations.memo): no
            # mutation can reach inside it, so it cannot hold a mutant's value and is kept
            if callable(clear) and not getattr(value, "sympy_only", False):
                clear()


@contextmanager
def applied(name: str):
    """Install the mutation ``name`` wherever its target is bound, clear caches, and undo both
    on exit."""
    if name not in MUTATIONS:
        raise KeyError(f"name: no mutation {name!r}; known: {sorted(MUTATIONS)}")
    m = MUTATIONS[name]
    modname, attr = m.target.split(":")
    module = importlib.import_module(modname)
    original = getattr(module, attr)
    replacement = m.make(original)
    patched = []
    for mod in _scoped_modules():
        for key, value in list(vars(mod).items()):
            if value is original:
                setattr(mod, key, replacement)
                patched.append((mod, key))
    if not patched:  # pragma: no cover - the target itself is always bound
        raise RuntimeError(f"mutation {name!r}: {m.target} is bound nowhere")
    from . import framework

    # the findings memoized before the mutation were computed by the original functions: they are
    # put back on exit (every lru_cache stays cleared: it may hold values computed under the mutant)
    before = dict(framework._MEMO)
    clear_caches()
    try:
        yield replacement
    finally:
        for mod, key in patched:
            setattr(mod, key, original)
        # a module first imported under the mutation bound the replacement (``from x import f``): undo that too
        for mod in _scoped_modules():
            for key, value in list(vars(mod).items()):
                if value is replacement:
                    setattr(mod, key, original)
        clear_caches()
        framework._MEMO.update(before)


# The mutants that only one paper's claims use live beside that paper's checks (one file each),
# registered on import.
from . import mutants_acary_taha, mutants_seghete_murphey  # noqa: E402,F401
