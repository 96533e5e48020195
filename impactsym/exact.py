"""Certified signs and comparisons of exact numbers (the historical import path).

The implementation lives in :mod:`impactsym.arithmetic.closed_form`; this module re-exports it
so that ``from impactsym.exact import certified_sign`` keeps working. Every branch of an impact
law is a sign test: decided exactly for exact input, by interval evaluation at rising precision
for algebraic and transcendental numbers, and by the minimal polynomial when the number may be
zero. A sign that cannot be certified raises :class:`~impactsym.errors.UndecidableSign`.

>>> import sympy as sp
>>> certified_sign(sp.Rational(-1, 3)), certified_sign(sp.sqrt(2) - sp.Rational(141421, 100000))
(-1, 1)
>>> certified_sign(sp.sqrt(3) / 2 - sp.sin(sp.pi / 3))
0
"""

from .arithmetic.closed_form import certified_compare, certified_sign

__all__ = ["certified_sign", "certified_compare"]
