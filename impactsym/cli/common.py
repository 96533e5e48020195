"""Argument helpers shared by the subcommands: reading matrices and vectors in the CLI's text
form (``"a,b;c,d"``), exact unless ``--float`` asks otherwise (an exponent literal such as
``1e-3`` is read exactly, like any decimal: ``1/1000``); strict JSON; refusing options that do
not apply; and checking output paths before the work starts."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path
from typing import Any, Iterable

from ..errors import ImpactInputError

# NumPy and impactsym.numbers (SymPy) are imported where they are used: `impactsym --help` and
# the subcommands that read no numbers start without them.

__all__ = ["matrix_arg", "vector_arg", "number_arg", "add_json_flag", "strict_json", "dumps_strict",
           "given_options", "refuse_inapplicable", "option_name", "writable_file", "writable_dir"]


def add_json_flag(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print exactly one JSON object on stdout")


def matrix_arg(text: str, argument: str, *, as_float: bool = False):
    """Exact SymPy matrix from ``"a,b;c,d"``; a float array when ``as_float``."""
    import numpy as np

    from ..numbers import parse_matrix

    m = parse_matrix(text, argument)
    return np.array(m.evalf(17).tolist(), dtype=float) if as_float else m


def vector_arg(text: str, argument: str, *, as_float: bool = False):
    import numpy as np

    from ..numbers import parse_vector

    v = parse_vector(text, argument)
    return np.array([float(x.evalf(17)) for x in v]) if as_float else v


def number_arg(text: str, argument: str, *, as_float: bool = False):
    from ..numbers import parse_number

    x = parse_number(text, argument)
    return float(x.evalf(17)) if as_float else x


# --------------------------------------------------------------------------- strict JSON
#: leaf types that strict JSON keeps as they are (``bool`` before ``int``: both are kept)
_KEPT = frozenset({str, int, bool, type(None)})
#: ... and with ``float``, whose non-finite values become ``None``
_KEPT_OR_FLOAT = _KEPT | {float}


def strict_json(obj: Any) -> Any:
    """``obj`` with every float that is not finite replaced by ``None`` (and NumPy scalars made
    Python ones), so that it is strict JSON (``CONVENTIONS.md``: a float that overflows is
    ``null`` beside its exact string).

    A list (or tuple) whose entries are all plain strings, integers, booleans, ``None`` or floats
    (a matrix row, a vector and its float twin: nearly every leaf of a result) is copied in one
    pass over the entries' types instead of one call per entry; its finite floats are kept and the
    others become ``None``, as entry by entry.

    >>> import numpy as np
    >>> strict_json({"v": ["1e400", float("inf")], "n": [float("nan"), 1.5, np.int64(3)]})
    {'v': ['1e400', None], 'n': [None, 1.5, 3]}
    >>> strict_json([[1.5, -0.0, "1/3", None, True], (2, float("-inf"))])
    [[1.5, -0.0, '1/3', None, True], [2, None]]
    """
    t = type(obj)
    if t is list or t is tuple:
        kinds = set(map(type, obj))
        if kinds <= _KEPT_OR_FLOAT:  # only leaves: no call per entry
            if float not in kinds or all(map(math.isfinite, obj if len(kinds) == 1 else
                                                (x for x in obj if type(x) is float))):
                return list(obj)
            return [x if type(x) is not float or math.isfinite(x) else None for x in obj]
        return [strict_json(v) for v in obj]
    if t is str or t is int or t is bool or obj is None:
        return obj
    if t is float:
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {str(k): strict_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [strict_json(v) for v in obj]
    if isinstance(obj, bool):
        return obj
    if isinstance(obj, int):
        return int(obj)
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    np = sys.modules.get("numpy")  # without NumPy loaded there is no NumPy object to convert
    if np is not None:
        if isinstance(obj, np.ndarray):
            return strict_json(obj.tolist())
        if isinstance(obj, np.bool_):
            return bool(obj)
        if isinstance(obj, np.integer):
            return int(obj)
        if isinstance(obj, np.floating):
            x = float(obj)
            return x if math.isfinite(x) else None
    return obj


def dumps_strict(obj: Any, **kw) -> str:
    """``json.dumps`` of :func:`strict_json` ``(obj)`` with ``allow_nan=False``: never ``Infinity``.

    >>> dumps_strict({"x": float("-inf"), "y": "-10**400"})
    '{"x": null, "y": "-10**400"}'
    """
    return json.dumps(strict_json(obj), allow_nan=False, **kw)


# --------------------------------------------------------------------------- options that apply
def option_name(dest: str) -> str:
    """``"max_reflections"`` -> ``"--max-reflections"``."""
    return "--" + dest.replace("_", "-")


def given_options(args: argparse.Namespace, parser: argparse.ArgumentParser) -> list[str]:
    """The destinations of the optional arguments the user gave (value differs from the default)."""
    out = []
    for action in parser._actions:
        if not action.option_strings or action.dest in ("help", "version", "json", "timeout"):
            continue
        if getattr(args, action.dest, action.default) != action.default:
            out.append(action.dest)
    return out


def refuse_inapplicable(args: argparse.Namespace, parser: argparse.ArgumentParser, allowed: Iterable[str],
                        context: str) -> None:
    """Refuse (exit 2) every option given that is not in ``allowed``: one rule for every subcommand
    and law, so that nothing is silently ignored (``CONVENTIONS.md``).

    ``context`` names what the options were checked against (``"--law newton"``).
    """
    allowed = set(allowed)
    extra = [dest for dest in given_options(args, parser) if dest not in allowed]
    if extra:
        takes = ", ".join(sorted(option_name(a) for a in allowed if a != "law")) or "no options"
        names = ", ".join(option_name(d) for d in extra)
        verb = "does" if len(extra) == 1 else "do"
        raise ImpactInputError(extra[0], f"{names} {verb} not apply to {context} (it takes: {takes})")


# --------------------------------------------------------------------------- output paths
def _check_parent(path: Path, argument: str) -> None:
    parent = path.parent if str(path.parent) else Path(".")
    probe = parent
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        raise ImpactInputError(argument, f"cannot write {str(path)!r}: {str(probe)!r} is not a directory")
    if probe != parent:
        raise ImpactInputError(argument, f"cannot write {str(path)!r}: directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ImpactInputError(argument, f"cannot write {str(path)!r}: directory {str(parent)!r} is not writable")


def writable_file(text: str | None, argument: str, *, suffixes: tuple[str, ...] = ()) -> Path | None:
    """Check, before any work, that a file can be written at ``text`` (its directory exists and is
    writable, it is not a directory); ``None`` passes through.

    >>> writable_file("/nonexistent/dir/x.png", "plot")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: plot: cannot write '/nonexistent/dir/x.png': directory '/nonexistent/dir' does not exist
    """
    if text is None:
        return None
    if not text.strip():
        raise ImpactInputError(argument, "is an empty path")
    path = Path(text)
    if path.is_dir():
        raise ImpactInputError(argument, f"{text!r} is a directory, expected a file name")
    if suffixes and path.suffix.lower() not in suffixes:
        raise ImpactInputError(argument, f"{text!r} must end with {' or '.join(suffixes)}")
    if path.exists() and not os.access(path, os.W_OK):
        raise ImpactInputError(argument, f"cannot write {text!r}: the file is not writable")
    _check_parent(path, argument)
    return path


def writable_dir(text: str | None, argument: str) -> Path | None:
    """Check, before any work, that ``text`` is a writable directory or can be created as one
    (its parent exists and is writable); ``None`` passes through."""
    if text is None:
        return None
    if not text.strip():
        raise ImpactInputError(argument, "is an empty path")
    path = Path(text)
    if path.exists():
        if not path.is_dir():
            raise ImpactInputError(argument, f"{text!r} exists and is not a directory (the report is written "
                                             f"into a directory)")
        if not os.access(path, os.W_OK | os.X_OK):
            raise ImpactInputError(argument, f"cannot write into {text!r}: the directory is not writable")
        return path
    probe = path.parent
    while not probe.exists() and probe.parent != probe:  # the report creates missing parents
        probe = probe.parent
    if not probe.is_dir():
        raise ImpactInputError(argument, f"cannot create {text!r}: {str(probe)!r} is not a directory")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise ImpactInputError(argument, f"cannot create {text!r}: directory {str(probe)!r} is not writable")
    return path
