"""The numbers a user gives and gets: text and JSON forms, and the choice of the exact or float path.

impactsym keeps one rule (``CONVENTIONS.md``, *Numbers*): exact in, exact out.
Integers, rationals (``"11/10"``), decimal strings (``"1.1"`` means ``11/10``) and SymPy
expressions (``"sqrt(3)/2"``) stay exact; Python floats and NumPy float arrays take the
float path. A float is never re-rounded through decimal text: when an exact value of a float
is needed, its exact binary value is used (:func:`float_to_rational`).

This module parses, classifies and formats; the exact arithmetic itself (including
:func:`float_to_rational`, re-exported here) is :mod:`impactsym.arithmetic`.

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
import sys
from numbers import Integral, Rational as _NumRational
from functools import lru_cache
from typing import Any, Iterable

import numpy as np

from .arithmetic import LazyModule
from .arithmetic import sympy_instance as _is_sp
from .arithmetic.literals import MAX_DIGITS, json_float, plain_rational, split_entries
from .arithmetic.rational import float_to_rational
from .errors import ImpactInputError

# SymPy and mpmath are imported on first use: the float path's checks (float arrays, plain
# rationals) and the type tests below run without them (issue 15)
sp = LazyModule("sympy", globals(), "sp")
mpmath = LazyModule("mpmath", globals(), "mpmath")

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
    "MAX_DIGITS",
]

def _rational_call(p, q=1):
    """``Rational(p, q)`` in text: ``p/q``, built unevaluated so that its size is bounded first."""
    return sp.Mul(p, sp.Pow(q, -1, evaluate=False), evaluate=False)


def _integer_call(x):
    """``Integer(x)`` in text: ``x`` itself (checked to be an integer once evaluated)."""
    return _integer_call_class()(x, evaluate=False)


_LAZY: dict = {}


def _integer_call_class():
    """``_IntegerCall``, the marker for ``Integer(x)`` in text (a SymPy ``Function``, defined when the
    parser first needs it); it evaluates to ``x`` when ``x`` is an integer."""
    cls = _LAZY.get("IntegerCall")
    if cls is None:
        class _IntegerCall(sp.Function):
            """Marker for ``Integer(x)`` in text; evaluates to ``x`` when ``x`` is an integer."""

            nargs = 1

            @classmethod
            def eval(cls, x):
                if x.is_Integer:
                    return x
                if x.is_number and x.is_Rational:
                    raise ImpactInputError("value", f"Integer({x}): not an integer")
                return None

        cls = _LAZY["IntegerCall"] = _IntegerCall
    return cls


#: the names text may use (their SymPy objects: :func:`_parse_names`)
_ALLOWED_NAMES = ("sqrt", "pi", "E", "sin", "cos", "tan", "asin", "acos", "atan", "exp", "log", "Rational", "Integer",
                  "root", "cbrt")


def _parse_names() -> dict:
    """What the names of the text become while parsing (SymPy's objects of :data:`_ALLOWED_NAMES`):
    ``Rational(p, q)`` and ``Integer(x)`` are built unevaluated (renamed, because the parser itself
    wraps every literal in ``Integer``/``Rational``)."""
    names = _LAZY.get("names")
    if names is None:
        names = {name: getattr(sp, name) for name in _ALLOWED_NAMES}
        names = _LAZY["names"] = {**names, "_text_Rational_": _rational_call, "_text_Integer_": _integer_call}
    return names
_USER_CALL = re.compile(r"\b(Rational|Integer)\s*\(")

# MAX_DIGITS (from :mod:`impactsym.arithmetic.literals`): the most decimal digits of any integer or
# rational the parser builds (numerator or denominator), and of any integer power's estimated result;
# a larger number (``9^9^9^9``, ``2^(2^30)``) is refused before it is computed, naming this limit
#: the longest text accepted for one entry
MAX_TEXT = 2000

_SAFE_TEXT = re.compile(r"[0-9A-Za-z_+\-*/().^ eE]+")
_IDENT = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")
#: a numeric literal, with an optional decimal exponent (``1e-3``, ``2.5E+4``): read exactly
_LITERAL = re.compile(r"(?<![A-Za-z_0-9.])(?:\d+\.?\d*|\.\d+)(?:[eE]([+-]?\d+))?")


def check_finite_exact(value: sp.Expr, argument: str) -> sp.Expr:
    """Reject exact values that are not finite real numbers (``nan``, ``oo``, ``zoo``, ``I``).

    >>> check_finite_exact(sp.Rational(1, 3), "e")
    1/3
    >>> check_finite_exact(sp.oo, "e")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: e: must be a finite real number, got oo
    """
    if isinstance(value, sp.Rational):  # a finite real number (nan, oo and zoo are not Rationals)
        return value
    if value.has(sp.nan, sp.oo, sp.S.NegativeInfinity, sp.zoo) or value.free_symbols or value.is_real is False:
        raise ImpactInputError(argument, f"must be a finite real number, got {value}")
    return value


def parse_number(text: Any, argument: str = "value") -> sp.Expr:
    """Parse one exact number: int, ``Fraction``, SymPy number or text.

    Text may be an integer, a rational ``"p/q"``, a decimal ``"1.1"`` (read as 11/10, exactly),
    an exponent literal ``"1e-3"`` (read as 1/1000, exactly), or a SymPy expression in ``sqrt``,
    ``pi``, ``sin``, ``cos``, ... Floats are refused here: they belong to the float path (see
    :func:`float_to_rational` for their exact binary value).

    The size of what the text builds is bounded *before* it is built: an integer or rational of
    more than :data:`MAX_DIGITS` digits (``9^9^9^9``, ``2^(2^30)``, ``1e100000``), or an irrational
    value beyond ``10^±MAX_DIGITS`` (``exp(exp(exp(10)))``), is refused, naming the limit.

    >>> parse_number("-2/6"), parse_number("0.25"), parse_number(3), parse_number("2.5e-3")
    (-1/3, 1/4, 3, 1/400)
    >>> parse_number("9^9^9^9", "velocity")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: velocity: 9**387420489 would have about 369693099 digits; numbers are limited to 1000 digits
    >>> parse_number("nan", "restitution")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: restitution: must be a finite real number, got nan
    """
    if isinstance(text, bool):
        raise ImpactInputError(argument, f"must be a number, got {text!r}")
    if _is_sp(text, "Basic"):
        if isinstance(text, sp.Rational):  # finite and real: what sympify and the check return, at once
            return text
        if _is_sp(text, "Float"):
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
    try:  # a plain integer, fraction or decimal: no parser needed (the one reading of plain text)
        plain = plain_rational(s)
    except ZeroDivisionError:
        raise ImpactInputError(argument, f"must be a finite real number, got {s} (division by zero)") from None
    if plain is not None:
        return sp.Rational(plain.numerator, plain.denominator)
    if len(s) > MAX_TEXT:
        raise ImpactInputError(argument, f"entry is {len(s)} characters long; at most {MAX_TEXT} are read")
    if not _SAFE_TEXT.fullmatch(s) or any(name not in _ALLOWED_NAMES for name in _IDENT.findall(_LITERAL.sub(" ", s))):
        raise ImpactInputError(
            argument,
            f"cannot read {s!r} as a number (allowed: digits, decimals and exponent literals such as 1e-3, "
            f"+ - * / ^ ( ), and {', '.join(sorted(_ALLOWED_NAMES))})",
        )
    for m in _LITERAL.finditer(s):
        if m.group(1) is not None and abs(int(m.group(1))) > MAX_DIGITS:
            raise ImpactInputError(argument, f"the exponent of {m.group(0)!r} exceeds {MAX_DIGITS} "
                                             f"(numbers are limited to {MAX_DIGITS} digits)")
    try:
        code = _USER_CALL.sub(lambda m: f"_text_{m.group(1)}_(", s.replace("^", "**"))
        tree = sp.sympify(code, locals=_parse_names(), rational=True, evaluate=False)
    except ImpactInputError as exc:
        raise ImpactInputError(argument, exc.condition) from None
    except (sp.SympifyError, SyntaxError, TypeError, ValueError, TokenError_, AttributeError) as exc:  # noqa: F821
        raise ImpactInputError(argument, f"cannot read {s!r} as a number ({exc.__class__.__name__})") from None
    except (RecursionError, MemoryError):
        raise ImpactInputError(argument, f"cannot read {s!r} as a number (nested too deeply)") from None
    if not isinstance(tree, sp.Expr):
        raise ImpactInputError(argument, f"cannot read {s!r} as a number")
    try:
        value = _bounded_eval(tree, argument)
    except ImpactInputError as exc:
        raise ImpactInputError(argument, exc.condition) from None
    except RecursionError:
        raise ImpactInputError(argument, f"cannot read {s!r} as a number (nested too deeply)") from None
    if value.has(_integer_call_class()):
        raise ImpactInputError(argument, f"cannot read {s!r} as a number (Integer() of a non-integer)")
    value = check_finite_exact(value, argument)
    if not value.is_Rational:
        _check_magnitude(value, s, argument)
    return value


def _check_magnitude(value: sp.Expr, text: str, argument: str) -> None:
    """Refuse an irrational value outside ``10^±MAX_DIGITS`` (``exp(exp(exp(10)))``): the exact
    arithmetic downstream could not evaluate it."""
    if _decimal_magnitude(value) > MAX_DIGITS:
        raise ImpactInputError(argument, f"{text!r} is beyond 10^{MAX_DIGITS} in magnitude (or below "
                                         f"10^-{MAX_DIGITS}); numbers are limited to {MAX_DIGITS} digits")


@lru_cache(maxsize=1024)
def _decimal_magnitude(value: sp.Expr) -> float:
    """``|log10 |value||`` (``inf`` when it cannot be evaluated), once per value: evaluating
    ``exp(exp(exp(10)))`` to find it too large takes tens of milliseconds, and the same text
    recurs (issue 15)."""
    try:
        approx = sp.N(value, 15)
        if approx == 0:
            return 0.0
        if isinstance(approx, sp.Float):
            return abs(float(mpmath.log10(abs(mpmath.mpf(approx._mpf_)))))
        return abs(math.log10(abs(complex(approx))))
    except (OverflowError, ValueError, TypeError, ZeroDivisionError, RecursionError):
        return math.inf


def _digits(x: sp.Rational) -> int:
    """Decimal digits of the larger of numerator and denominator (an upper estimate)."""
    return int(max(abs(int(x.p)), int(x.q)).bit_length() * 0.30103) + 1


def _log10_size(base: sp.Expr) -> float:
    """Decimal digits per unit exponent of a power of ``base``: ``|log10 |base||``, and at least the
    digits of the rationals inside ``base`` (SymPy expands ``sqrt(q)**n`` into ``q**(n/2)``)."""
    if base.is_Rational:
        return max(abs(math.log10(abs(int(base.p)))) if base.p else 0.0, math.log10(int(base.q)))
    inner = max((_digits(a) - 1 for a in base.atoms(sp.Rational)), default=0)
    try:
        mag = abs(math.log10(abs(complex(sp.N(base, 15)))))
    except (OverflowError, ValueError, TypeError, ZeroDivisionError):
        mag = math.inf
    return max(mag, float(inner))


def _bounded_eval(node: sp.Basic, argument: str) -> sp.Basic:
    """Evaluate an unevaluated parse tree bottom-up, refusing any integer power or rational whose
    size would exceed :data:`MAX_DIGITS` digits *before* it is computed.

    >>> _bounded_eval(sp.sympify("2**10", evaluate=False), "x")
    1024
    >>> _bounded_eval(sp.sympify("9**9**9", evaluate=False), "x")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: x: 9**387420489 would have about 369693099 digits; numbers are limited to 1000 digits
    """
    if not node.args:
        if node.is_Rational and _digits(node) > MAX_DIGITS:
            raise ImpactInputError(argument, f"{_digits(node)}-digit number; numbers are limited to {MAX_DIGITS} digits")
        return node
    args = [_bounded_eval(a, argument) for a in node.args]
    if isinstance(node, sp.Pow):
        base, expo = args
        if expo.is_Rational and expo.q < 10 ** 6 and not (base.is_zero or base in (sp.S.One, sp.S.NegativeOne)):
            size = abs(float(expo)) * _log10_size(base) if base.is_number else 0.0
            if size > MAX_DIGITS:
                b, x = str(base), str(expo)
                shown = f"{b if len(b) < 40 else 'a power of a large number'}**{x if len(x) < 40 else '(a large exponent)'}"
                about = f"about {int(size)}" if math.isfinite(size) else f"more than {MAX_DIGITS}"
                raise ImpactInputError(argument, f"{shown} would have {about} digits; numbers are limited "
                                                 f"to {MAX_DIGITS} digits")
        elif expo.is_Rational and expo.q >= 10 ** 6:
            raise ImpactInputError(argument, f"the exponent {expo} has a denominator of {_digits(expo)} digits "
                                             f"(roots of order at most 10^6 are read)")
    value = node.func(*args)
    for atom in value.atoms(sp.Rational):
        if _digits(atom) > MAX_DIGITS:
            raise ImpactInputError(argument, f"a {_digits(atom)}-digit number; numbers are limited to {MAX_DIGITS} digits")
    return value


try:  # tokenizer errors surface from sympify for malformed text such as "1,,"
    from tokenize import TokenError as TokenError_
except ImportError:  # pragma: no cover
    TokenError_ = SyntaxError  # type: ignore


_split = split_entries


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


def _leaves(obj: Any) -> Iterable[Any]:
    if _is_sp(obj, "MatrixBase"):
        for row in obj.tolist():  # tolist: one pass, not one __getitem__ per entry
            yield from row
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


def _rational_domain(A) -> bool:
    """Whether the SymPy matrix ``A`` is stored over ``ZZ`` or ``QQ`` (its ``DomainMatrix``)."""
    dom = getattr(getattr(A, "_rep", None), "domain", None)
    return dom is not None and bool(getattr(dom, "is_ZZ", False) or getattr(dom, "is_QQ", False))


def is_exact(*objs: Any) -> bool:
    """True when every leaf is exact (int, Fraction, SymPy number, numeric text).

    Python floats, NumPy floating scalars and float arrays make the whole call take the float path.

    >>> is_exact(sp.Matrix([1, 2]), "1/2"), is_exact(np.eye(2))
    (True, False)
    """
    for obj in objs:
        if _is_sp(obj, "MatrixBase") and _rational_domain(obj):
            continue  # a SymPy matrix over ZZ or QQ holds no Float (1000 x 1000 scenes: not read entry by entry)
        for leaf in _leaves(obj):
            if isinstance(leaf, (float, np.floating)) or _is_sp(leaf, "Float"):
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
    if _is_sp(obj, "MatrixBase"):
        m = _rational_copy(obj) if _rational_domain(obj) else sp.Matrix(obj).applyfunc(lambda x: to_exact(x, argument))
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


def _rational_copy(A) -> sp.Matrix:
    """A new ``Matrix`` of the SymPy matrix ``A`` over ``ZZ`` or ``QQ``: the matrix
    ``Matrix(A).applyfunc(to_exact)`` builds (every entry a finite rational, which :func:`to_exact`
    returns as it is; stored sparse, over ``ZZ`` when every entry is an integer, as SymPy builds a
    matrix of Integers), from ``A``'s own ``DomainMatrix``, without one :func:`parse_number` per
    entry: the laws re-check their ``M``, ``H`` and ``v`` on every call (issue 15)."""
    rep = A._rep.to_sparse()
    if rep.domain.is_QQ and all(x.denominator == 1 for row in rep.rep.values() for x in row.values()):
        rep = rep.convert_to(sp.ZZ)
    else:
        rep = rep.copy()
    return sp.Matrix._fromrep(rep)


def to_float_array(obj: Any, argument: str = "array") -> np.ndarray:
    """A float64 array from any accepted form; NaN and inf are refused.

    >>> to_float_array("1,1/2")
    array([1. , 0.5])
    """
    if isinstance(obj, str):
        obj = parse_matrix(obj, argument) if ";" in obj else parse_vector(obj, argument)
    if _is_sp(obj, "MatrixBase"):
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
    if _is_sp(x, "Rational"):
        # flint prints integers of any length; Python's int -> str stops at 4,300 digits
        # (sys.get_int_max_str_digits), which exact answers from 1,000-digit input exceed.
        from flint import fmpz
        return str(fmpz(int(x.p))) if x.q == 1 else f"{fmpz(int(x.p))}/{fmpz(int(x.q))}"
    y = sp.nsimplify(x) if _is_sp(x, "Float") else x
    old = sys.get_int_max_str_digits()
    try:
        sys.set_int_max_str_digits(0)  # an exact expression is printed whole, however long
        return str(y)
    finally:
        sys.set_int_max_str_digits(old)


def _float_of(x: Any) -> float:
    if _is_sp(x, "Rational"):  # bit for bit float(N(x, 17)), without evalf (shared with the fast paths)
        return json_float(int(x.p), int(x.q))
    if _is_sp(x, "Basic"):
        return float(sp.N(x, 17))
    return float(x)


def exact_json(name: str, value: Any) -> dict:
    """``{name: exact strings, name + "_float": floats}`` for a scalar, vector or matrix.

    A column vector becomes a flat list; a matrix a list of rows.

    >>> exact_json("p", sp.Matrix([sp.Rational(4, 3), sp.Rational(2, 3)]))["p"]
    ['4/3', '2/3']
    """
    if _is_sp(value, "MatrixBase"):
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
