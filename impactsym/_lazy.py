"""Lazy package names (PEP 562): a package lists which module defines each public name, and the
module is imported when the name is first read, so that ``import impactsym`` (and the command line's
start-up) loads no heavy library it does not use.

>>> ns = {}
>>> getattr_, dir_ = lazy_attributes("impactsym", {"ImpactInputError": "errors"}, ns)
>>> getattr_("ImpactInputError").__name__, "ImpactInputError" in ns, dir_()
('ImpactInputError', True, ['ImpactInputError'])

Lazy values too: :class:`Later` is a value computed on first use, once, for what a result holds
but few callers read (a canonical exact form, a simplified boundary curve), so that a caller
reading only the verdict or the region does not pay for it. Its holders replace it by its value
when it is first read (:class:`impactsym.laws.impulse_ratio.Violation` and its siblings,
:class:`impactsym.domains.Boundary`), so every reader sees the value.

>>> calls = []
>>> later = Later(lambda: calls.append(1) or 42)
>>> later(), later(), len(calls)
(42, 42, 1)
"""

from __future__ import annotations

import importlib


def lazy_attributes(package: str, names: dict, namespace: dict):
    """The ``__getattr__`` and ``__dir__`` of ``package``: a name of ``names`` (name → module,
    relative to the package) is imported from its module on first use and stored in ``namespace``
    (the package's ``globals()``), so that later lookups skip ``__getattr__``; any other name raises
    ``AttributeError``."""

    def __getattr__(name):
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f".{module}", package), name)
        namespace[name] = value  # later lookups skip __getattr__
        return value

    def __dir__():
        return sorted(set(namespace) | set(names))

    return __getattr__, __dir__


class Later:
    """``make()``, computed on the first call and kept (every holder that shares it shares the value)."""

    __slots__ = ("_make", "_value")

    def __init__(self, make):
        self._make, self._value = make, None

    def __call__(self):
        if self._make is not None:
            self._value, self._make = self._make(), None
        return self._value
