"""Shared fixtures. mpmath's precision is global state: reset it after every test (mpmath's own
habit), so one test's workdps can never leak into another's reference."""

import mpmath
import pytest


@pytest.fixture(autouse=True)
def _reset_mpmath_precision():
    saved = mpmath.mp.prec
    yield
    mpmath.mp.prec = saved
