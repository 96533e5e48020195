"""Exact answers from 1,000-digit input have integers beyond Python's 4,300-digit int -> str limit;
the library prints them whole (the cost model's digits axis crashed Poisson's JSON at 1024 digits)."""

from __future__ import annotations

import sys

import sympy as sp
from flint import fmpz

from impactsym.numbers import exact_str


def test_long_rational_and_expression_print_whole_and_leave_the_limit_alone():
    limit = sys.get_int_max_str_digits()
    p, q = 10**5000 + 7, 3 * 10**4999 + 1
    num, den = exact_str(sp.Rational(p, q)).split("/")
    assert (fmpz(num), fmpz(den)) == (fmpz(p), fmpz(q)) and len(num) == 5001
    assert exact_str(sp.Integer(-p)) == "-1" + "0" * 4996 + "0007"
    text = exact_str(sp.Rational(p, q) * sp.sqrt(2))
    assert text.endswith("*sqrt(2)/" + den) and len(text) > 10000
    assert sys.get_int_max_str_digits() == limit
