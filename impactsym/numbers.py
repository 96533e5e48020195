"""Exact numbers, the float path, and the CLI's text and JSON forms of them.

impactsym keeps one rule (``CONVENTIONS.md``, *Numbers*): exact in, exact out.
Integers, rationals (``"11/10"``), decimal strings (``"1.1"`` means ``11/10``) and SymPy
expressions (``"sqrt(3)/2"``) stay exact; Python floats and NumPy float arrays take the
float path. A float is never re-rounded through decimal text: when an exact value of a float
is needed, its exact binary value is used (:func:`float_to_rational`).

Examples
--------
>>> parse_number("1.1")
11/10
>>> parse_number("sqrt(3)/2")
sqrt(3)/2
>>> parse_matrix("11/10,0;0,1")
Matrix([
[11/10, 0],
[    0, 1]])
>>> is_exact([1, "1/3"]), is_exact([1.0, 2])
(True, False)
>>> exact_json("M", parse_matrix("1,1/2;0,-1"))
{'M': [['1', '1/2'], ['0', '-1']], 'M_float': [[1.0, 0.5], [0.0, -1.0]]}
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from numbers import Integral, Rational as _NumRational
from typing import Any, Iterable

import numpy as np
import sympy as sp

from .errors import ImpactInputError

__all__ = [
    "parse_number",
    "parse_vector",
    "parse_matrix",
    "is_exact",
    "to_exact",
    "to_exact_matrix",
    "to_float_array",
    "float_to_rational",
    "exact_str",
    "exact_json",
    "check_finite_exact",
]

_ALLOWED_NAMES = {
    "sqrt": sp.sqrt, "pi": sp.pi, "E": sp.E, "sin": sp.sin, "cos": sp.cos, "tan": sp.tan,
    "asin": sp.asin, "acos": sp.acos, "atan": sp.atan, "exp": sp.exp, "log": sp.log,
    "Rational": sp.Rational, "Integer": sp.Integer, "root": sp.root, "cbrt": sp.cbrt,
}


_SAFE_TEXT = re.compile(r"[0-9A-Za-z_+\-*/().^ eE]+")
_IDENT = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")


def check_finite_exact(value: sp.Expr, argument: str) -> sp.Expr:
    """Reject exact values that are not finite real numbers (``nan``, ``oo``, ``zoo``, ``I``).

    >>> check_finite_exact(sp.Rational(1, 3), "e")
    1/3
    >>> check_finite_exact(sp.oo, "e")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: e: must be a finite real number, got oo
    """
    if value.has(sp.nan, sp.oo, -sp.oo, sp.zoo) or value.free_symbols or value.is_real is False:
        raise ImpactInputError(argument, f"must be a finite real number, got {value}")
    return value


def parse_number(text: Any, argument: str = "value") -> sp.Expr:
    """Parse one exact number: int, ``Fraction``, SymPy number or text.

    Text may be an integer, a rational ``"p/q"``, a decimal ``"1.1"`` (read as 11/10, exactly),
    or a SymPy expression in ``sqrt``, ``pi``, ``sin``, ``cos``, ... Floats are refused here:
    they belong to the float path (see :func:`float_to_rational` for their exact binary value).

    >>> parse_number("-2/6"), parse_number("0.25"), parse_number(3)
    (-1/3, 1/4, 3)
    >>> parse_number("nan", "restitution")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: restitution: must be a finite real number, got nan
    """
    if isinstance(text, bool):
        raise ImpactInputError(argument, f"must be a number, got {text!r}")
    if isinstance(text, sp.Basic):
        if isinstance(text, sp.Float):
            return float_to_rational(float(text))
        return check_finite_exact(sp.sympify(text), argument)
    if isinstance(text, Integral):
        return sp.Integer(int(text))
    if isinstance(text, _NumRational):
        return sp.Rational(int(text.numerator), int(text.denominator))
    if isinstance(text, (float, np.floating)):
        raise ImpactInputError(argument, "a float was given where an exact number is required")
    if not isinstance(text, str):
        raise ImpactInputError(argument, f"must be a number or numeric text, got {type(text).__name__}")
    s = text.strip()
    if not s:
        raise ImpactInputError(argument, "empty entry")
    low = s.lower()
    if low in {"nan", "+nan", "-nan", "inf", "+inf", "-inf", "infinity", "-infinity", "oo", "-oo", "zoo"}:
        raise ImpactInputError(argument, f"must be a finite real number, got {s}")
    if not _SAFE_TEXT.fullmatch(s) or any(name not in _ALLOWED_NAMES for name in _IDENT.findall(s)):
        raise ImpactInputError(
            argument,
            f"cannot read {s!r} as a number (allowed: digits, + - * / ^ ( ), and {', '.join(sorted(_ALLOWED_NAMES))})",
        )
    try:
        value = sp.sympify(s.replace("^", "**"), locals=_ALLOWED_NAMES, rational=True, evaluate=True)
    except (sp.SympifyError, SyntaxError, TypeError, ValueError, TokenError_) as exc:  # noqa: F821
        raise ImpactInputError(argument, f"cannot read {s!r} as a number ({exc.__class__.__name__})") from None
    if not isinstance(value, sp.Expr):
        raise ImpactInputError(argument, f"cannot read {s!r} as a number")
    return check_finite_exact(value, argument)


try:  # tokenizer errors surface from sympify for malformed text such as "1,,"
    from tokenize import TokenError as TokenError_
except ImportError:  # pragma: no cover
    TokenError_ = SyntaxError  # type: ignore


def _split(text: str, sep: str) -> list[str]:
    return [part for part in (p.strip() for p in text.split(sep))]


def parse_vector(text: str, argument: str = "vector") -> sp.Matrix:
    """Parse ``"a,b,c"`` into an exact column vector.

    >>> parse_vector("1, -1/2, sqrt(2)").T
    Matrix([[1, -1/2, sqrt(2)]])
    """
    if ";" in text:
        raise ImpactInputError(argument, "a vector is written 'a,b,...' (no ';')")
    entries = _split(text, ",")
    return sp.Matrix([parse_number(x, argument) for x in entries])


def parse_matrix(text: str, argument: str = "matrix") -> sp.Matrix:
    """Parse ``"a,b;c,d"`` (rows split by ``;``) into an exact matrix.

    >>> parse_matrix("1,0;0,2").shape
    (2, 2)
    >>> parse_matrix("1,0;0", "mass_matrix")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: mass_matrix: rows have different lengths (2, 1)
    """
    rows = [_split(r, ",") for r in _split(text, ";")]
    lengths = [len(r) for r in rows]
    if len(set(lengths)) != 1:
        raise ImpactInputError(argument, f"rows have different lengths {tuple(lengths)}")
    return sp.Matrix([[parse_number(x, argument) for x in r] for r in rows])


def float_to_rational(x: float) -> sp.Rational:
    """The exact binary value of a float, as a SymPy ``Rational`` (never re-rounded).

    >>> float_to_rational(0.1)
    3602879701896397/36028797018963968
    """
    xf = float(x)
    if not math.isfinite(xf):
        raise ImpactInputError("value", f"must be finite, got {xf}")
    f = Fraction(xf)
    return sp.Rational(f.numerator, f.denominator)


def _leaves(obj: Any) -> Iterable[Any]:
    if isinstance(obj, sp.MatrixBase):
        yield from obj
    elif isinstance(obj, np.ndarray):
        if obj.dtype == object:
            yield from obj.ravel()
        else:
            yield obj.dtype.type(0)  # one representative is enough for a typed array
    elif isinstance(obj, (list, tuple)):
        for item in obj:
            yield from _leaves(item)
    else:
        yield obj


def is_exact(*objs: Any) -> bool:
    """True when every leaf is exact (int, Fraction, SymPy number, numeric text).

    Python floats, NumPy floating scalars and float arrays make the whole call take the float path.

    >>> is_exact(sp.Matrix([1, 2]), "1/2"), is_exact(np.eye(2))
    (True, False)
    """
    for obj in objs:
        for leaf in _leaves(obj):
            if isinstance(leaf, (float, np.floating)) or (isinstance(leaf, sp.Float)):
                return False
            if isinstance(leaf, np.integer):
                continue
    return True


def to_exact(obj: Any, argument: str = "value") -> sp.Expr:
    """One exact scalar from any accepted form; floats become their exact binary value."""
    if isinstance(obj, (float, np.floating)):
        return float_to_rational(obj)
    if isinstance(obj, np.integer):
        return sp.Integer(int(obj))
    return parse_number(obj, argument)


def to_exact_matrix(obj: Any, argument: str = "matrix", *, vector: bool = False) -> sp.Matrix:
    """An exact SymPy matrix (column vector when ``vector``) from text, lists, arrays or matrices.

    Float leaves are converted to their exact binary values; that is how the float path
    re-decides a sign exactly.

    >>> to_exact_matrix([[1, "1/2"], [0.5, 2]])
    Matrix([
    [  1, 1/2],
    [1/2,   2]])
    """
    if isinstance(obj, str):
        return parse_vector(obj, argument) if vector else parse_matrix(obj, argument)
    if isinstance(obj, sp.MatrixBase):
        m = sp.Matrix(obj).applyfunc(lambda x: to_exact(x, argument))
    else:
        arr = np.asarray(obj, dtype=object)
        if arr.ndim == 0:
            raise ImpactInputError(argument, "expected an array, got a scalar")
        if vector:
            if arr.ndim == 2 and 1 in arr.shape:
                arr = arr.reshape(-1)
            if arr.ndim != 1:
                raise ImpactInputError(argument, f"expected a vector, got shape {arr.shape}")
            m = sp.Matrix([to_exact(x, argument) for x in arr])
        else:
            if arr.ndim != 2:
                raise ImpactInputError(argument, f"expected a 2-D matrix, got shape {arr.shape}")
            m = sp.Matrix([[to_exact(x, argument) for x in row] for row in arr])
    if vector and m.cols != 1:
        if m.rows == 1:
            m = m.T
        else:
            raise ImpactInputError(argument, f"expected a vector, got shape {m.shape}")
    return m


def to_float_array(obj: Any, argument: str = "array") -> np.ndarray:
    """A float64 array from any accepted form; NaN and inf are refused.

    >>> to_float_array("1,1/2")
    array([1. , 0.5])
    """
    if isinstance(obj, str):
        obj = parse_matrix(obj, argument) if ";" in obj else parse_vector(obj, argument)
    if isinstance(obj, sp.MatrixBase):
        arr = np.array(obj.evalf(17).tolist(), dtype=float)
        if obj.cols == 1:
            arr = arr.reshape(-1)
    else:
        try:
            arr = np.asarray(obj, dtype=float)
        except (TypeError, ValueError):
            arr = np.asarray([[float(sp.sympify(x)) for x in np.atleast_1d(r)] for r in obj], dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ImpactInputError(argument, "contains NaN or inf")
    return arr


def exact_str(x: Any) -> str:
    """SymPy's ``str`` form, the JSON form of an exact number.

    >>> exact_str(sp.Rational(-1, 3)), exact_str(sp.sqrt(3) / 2)
    ('-1/3', 'sqrt(3)/2')
    """
    return str(sp.nsimplify(x) if isinstance(x, sp.Float) else x)


def _float_of(x: Any) -> float:
    if isinstance(x, sp.Basic):
        return float(sp.N(x, 17))
    return float(x)


def exact_json(name: str, value: Any) -> dict:
    """``{name: exact strings, name + "_float": floats}`` for a scalar, vector or matrix.

    A column vector becomes a flat list; a matrix a list of rows.

    >>> exact_json("p", sp.Matrix([sp.Rational(4, 3), sp.Rational(2, 3)]))["p"]
    ['4/3', '2/3']
    """
    if isinstance(value, sp.MatrixBase):
        if value.cols == 1:
            items = list(value)
            return {name: [exact_str(v) for v in items], name + "_float": [_float_of(v) for v in items]}
        rows = value.tolist()
        return {
            name: [[exact_str(v) for v in r] for r in rows],
            name + "_float": [[_float_of(v) for v in r] for r in rows],
        }
    if isinstance(value, (list, tuple)):
        return {name: [exact_str(v) for v in value], name + "_float": [_float_of(v) for v in value]}
    return {name: exact_str(value), name + "_float": _float_of(value)}
