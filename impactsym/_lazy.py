"""Lazy package names (PEP 562): a package lists which module defines each public name, and the
module is imported when the name is first read, so that ``import impactsym`` (and the command line's
start-up) loads no heavy library it does not use.

>>> ns = {}
>>> getattr_, dir_ = lazy_attributes("impactsym", {"ImpactInputError": "errors"}, ns)
>>> getattr_("ImpactInputError").__name__, "ImpactInputError" in ns, dir_()
('ImpactInputError', True, ['ImpactInputError'])
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
