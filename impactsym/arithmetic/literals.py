"""Plain numeric text, read exactly without SymPy: integers, fractions ``p/q``, decimals and
exponent literals (``"1.1"`` is 11/10, ``"1e-3"`` is 1/1000), and matrices and vectors of them
in the command line's form (``"a,b;c,d"``, ``"a,b"``).

This is the one reading of plain text: :func:`impactsym.numbers.parse_number` calls
:func:`plain_rational` first and builds a SymPy ``Rational`` from its value, and the start-up fast
paths of the command line (``impactsym reflect`` on rational input) use it to skip SymPy
altogether. Anything that is not plain (``sqrt(2)``, ``pi/3``, a symbol, an over-long literal)
gives ``None`` here, and the caller takes the general parser, which also words every error.

:func:`json_float` is the float the JSON form of an exact rational carries (``X_float``).

It imports only the standard library (``tests/test_cli_startup.py`` checks it).

>>> plain_rational("-2/6"), plain_rational("2.5e-3"), plain_rational("sqrt(2)") is None
(Fraction(-1, 3), Fraction(1, 400), True)
>>> plain_matrix("1,1/2; 0.5,2")
[[Fraction(1, 1), Fraction(1, 2)], [Fraction(1, 2), Fraction(2, 1)]]
>>> json_float(1, 3)
0.3333333333333333
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

__all__ = ["MAX_DIGITS", "plain_rational", "plain_vector", "plain_matrix", "split_entries", "json_float"]

#: the most decimal digits of any integer or rational the parser builds (numerator or denominator),
#: and of any integer power's estimated result (:mod:`impactsym.numbers`)
MAX_DIGITS = 1000

#: plain numeric text: ``-3``, ``11/10``, ``1.25``, ``1e-3`` (group 1: the exponent, group 2: the divisor)
PLAIN = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE]([+-]?\d+))?(?:/(\d+))?")


def plain_rational(text: str) -> Fraction | None:
    """The exact value of plain numeric text (stripped), or ``None`` when the text is not plain, is
    longer than :data:`MAX_DIGITS` characters or has an exponent beyond ±:data:`MAX_DIGITS`.

    Raises
    ------
    ZeroDivisionError
        ``p/0`` (the caller words the error).

    Examples
    --------
    >>> plain_rational(" 1.5/2 "), plain_rational("+.5"), plain_rational("1e-3/7")
    (Fraction(3, 4), Fraction(1, 2), Fraction(1, 7000))
    >>> plain_rational("1e1001") is None, plain_rational("2^3") is None
    (True, True)
    """
    s = text.strip()
    plain = PLAIN.fullmatch(s)
    if not plain or len(s) > MAX_DIGITS:
        return None
    if plain.group(2) is not None and int(plain.group(2)) == 0:
        raise ZeroDivisionError(s)
    exponent = plain.group(1)
    if exponent is not None and abs(int(exponent)) > MAX_DIGITS:
        return None
    num, _, den = s.partition("/")
    return Fraction(num) / (int(den) if den else 1)


def split_entries(text: str, sep: str) -> list[str]:
    """``text`` split at ``sep``, each part stripped (empty parts kept: they are errors to report).

    >>> split_entries(" 1, ,2 ", ",")
    ['1', '', '2']
    """
    return [p.strip() for p in text.split(sep)]


def _entries(parts: list[str]) -> list[Fraction] | None:
    out = []
    for part in parts:
        try:
            q = plain_rational(part)
        except ZeroDivisionError:
            return None
        if q is None:
            return None
        out.append(q)
    return out


def plain_vector(text: str) -> list[Fraction] | None:
    """``"a,b,..."`` of plain entries as a list of ``Fraction``; ``None`` if the text is not that
    (then :func:`impactsym.numbers.parse_vector` reads it, or words the error).

    >>> plain_vector("1, -1/2"), plain_vector("1;2"), plain_vector("1,sqrt(2)")
    ([Fraction(1, 1), Fraction(-1, 2)], None, None)
    """
    if ";" in text:
        return None
    return _entries(split_entries(text, ","))


def plain_matrix(text: str) -> list[list[Fraction]] | None:
    """``"a,b;c,d"`` of plain entries, rows of equal length, as lists of ``Fraction``; ``None``
    otherwise (then :func:`impactsym.numbers.parse_matrix` reads it, or words the error).

    >>> plain_matrix("1,0;0"), plain_matrix("2")
    (None, [[Fraction(2, 1)]])
    """
    rows = []
    for row in split_entries(text, ";"):
        entries = _entries(split_entries(row, ","))
        if entries is None:
            return None
        rows.append(entries)
    if len({len(r) for r in rows}) != 1:
        return None
    return rows


def _round_nearest_even(man: int, exp: int, bits: int) -> tuple[int, int]:
    """``man·2^exp`` (``man > 0``) rounded to ``bits`` significant bits, ties to even."""
    excess = man.bit_length() - bits
    if excess <= 0:
        return man, exp
    q, r = man >> excess, man & ((1 << excess) - 1)
    half = 1 << (excess - 1)
    if r > half or (r == half and q & 1):
        q += 1
    return q, exp + excess


def json_float(p: int, q: int = 1, digits: int = 17) -> float:
    """The float of the exact rational ``p/q`` (``q > 0``) as SymPy's ``float(N(p/q, digits))``
    gives it, bit for bit: with ``digits = 17``, the JSON ``X_float`` of an exact number
    (:func:`impactsym.numbers.exact_json`).

    SymPy evaluates a rational to ``b + 4`` bits rounding toward zero (``b`` = ``digits``' bits,
    60 for 17 digits, 70 for 20), keeps ``b`` bits rounding to nearest, then 53 bits rounding to
    nearest, so the result is the nearest float of ``p/q`` except, rarely, at a near-tie.
    Overflow gives ``±inf``, as SymPy's does.

    >>> json_float(1, 3), json_float(-7), json_float(0), json_float(10 ** 400)
    (0.3333333333333333, -7.0, 0.0, inf)
    >>> x = 2 * (2 ** 53 + 1) * 2 ** 6 + 1   # x / 2**7 is just above a tie between two floats
    >>> json_float(x, 2 ** 7), json_float(x, 2 ** 7, digits=20)
    (9007199254740992.0, 9007199254740994.0)
    """
    if p == 0:
        return 0.0
    bits = max(1, int(round((int(digits) + 1) * 3.3219280948873626)))  # mpmath's dps_to_prec
    work = bits + 4
    sign, a = (p < 0), abs(p)
    # step 1: |p|/q truncated to `work` significant bits (mpmath's from_rational, round_down)
    shift = work - (a.bit_length() - q.bit_length()) + 1
    man = (a << shift) // q if shift >= 0 else a // (q << -shift)
    exp = -shift
    excess = man.bit_length() - work
    if excess > 0:
        man >>= excess
        exp += excess
    # steps 2 and 3: `bits` bits, then 53 bits, each rounding to nearest (ties to even)
    man, exp = _round_nearest_even(man, exp, bits)
    man, exp = _round_nearest_even(man, exp, 53)
    try:
        x = math.ldexp(man, exp)
    except OverflowError:
        x = math.inf if exp + man.bit_length() > 0 else 0.0
    return -x if sign else x
