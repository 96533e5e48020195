"""Mass-matrix, gradient and velocity checks; the kinetic metric (M-normals, kinetic angles)."""

import numpy as np
import pytest
import sympy as sp

from impactsym import (
    ImpactInputError,
    check_gradients,
    check_mass_matrix,
    check_velocity,
    kinetic_angle,
    kinetic_angle_cos,
    m_normal,
)
from impactsym.numbers import parse_matrix, parse_number


@pytest.mark.parametrize(
    "M, message",
    [
        ("1,0,0;0,1,0", "square"),
        ("1,1/2;1/3,1", "not symmetric"),
        ("1,2;2,1", "not positive definite"),
        ("0,0;0,1", "not positive definite"),
        ("-1,0;0,-1", "not positive definite"),
        ("sqrt(2),3/2;3/2,sqrt(2)", "not positive definite"),
        ("1,oo;oo,1", "finite"),
    ],
)
def test_mass_matrix_refusals_exact(M, message):
    with pytest.raises(ImpactInputError, match=message) as info:
        check_mass_matrix(M)
    assert info.value.argument == "mass_matrix"


def test_mass_matrix_algebraic_entries_decided_exactly():
    # det = 2 - (sqrt(2) - 1e-30)^2 > 0 by a hair: decided exactly, not in floats
    M = check_mass_matrix([[1, "sqrt(2) - 1/10^30"], ["sqrt(2) - 1/10^30", 2]])
    assert M[0, 1] == sp.sqrt(2) - sp.Rational(1, 10**30)
    with pytest.raises(ImpactInputError, match="not positive definite"):
        check_mass_matrix([[1, "sqrt(2)"], ["sqrt(2)", 2]])  # det exactly 0


def test_mass_matrix_refusals_float():
    with pytest.raises(ImpactInputError, match="NaN or inf"):
        check_mass_matrix(np.array([[1.0, np.nan], [np.nan, 1.0]]))
    with pytest.raises(ImpactInputError, match="not positive definite"):
        check_mass_matrix(np.array([[1.0, 2.0], [2.0, 1.0]]))
    with pytest.raises(ImpactInputError, match="not symmetric"):
        check_mass_matrix(np.array([[1.0, 0.1], [0.2, 1.0]]))


def test_gradient_and_velocity_refusals():
    with pytest.raises(ImpactInputError, match="row 1 is the zero covector"):
        check_gradients("1,0;0,0", 2)
    with pytest.raises(ImpactInputError, match="has 3 columns, expected 2"):
        check_gradients("1,0,0", 2)
    with pytest.raises(ImpactInputError, match="velocity: has length 1"):
        check_velocity("1", 2)


def test_number_parsing_is_exact_and_safe():
    assert parse_number("1.1") == sp.Rational(11, 10)
    assert parse_number("2^-1") == sp.Rational(1, 2)
    for bad in ["__import__('os')", "x", "1/0", "lambda: 1", "1e999999999"]:
        with pytest.raises(ImpactInputError):
            parse_number(bad)
    assert parse_matrix("1, 2 ;3,4")[1, 0] == 3


def test_m_normal_unit_and_kinetic_angle_exact():
    M = sp.diag(sp.Rational(11, 10), 1)
    for h in ([1, 0], [-1, 1]):
        n = m_normal(M, sp.Matrix([h]))
        assert sp.simplify((n.T * M * n)[0, 0]) == 1
    c = kinetic_angle_cos(M, sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]]))
    assert c == -sp.sqrt(210) / 21
    assert kinetic_angle(sp.eye(2), sp.Matrix([[1, 0]]), sp.Matrix([[-1, 1]])) == 3 * sp.pi / 4


def test_rational_kinetic_angle_is_in_simplify_form():
    """On rational data ``kinetic_angle_cos`` returns SymPy's automatic form of ``num/√(aᵢᵢaⱼⱼ)``
    without simplifying it: that form must be the one ``radsimp(simplify(.))`` gives (the general
    path's), srepr for srepr, over dense, diagonal, scaled and perfect-square cases."""
    import random

    rng = random.Random(15)

    def q(k):
        return sp.Rational(rng.randint(-5 * k, 5 * k), rng.randint(1, 5 * k))

    for trial in range(60):
        k = rng.choice([1, 3, 10**6, 10**20])
        a, b, c = abs(q(k)) + 1, q(k), abs(q(k)) + 1
        M = sp.Matrix([[a, 0], [0, c]]) if trial % 3 == 0 else sp.Matrix([[a + b * b / c + 1, b], [b, c]])
        hi, hj = sp.Matrix([[q(k), q(k)]]), sp.Matrix([[q(k), 1]])
        if trial % 5 == 0:
            hj = 2 * hi  # a perfect square under the root: cos = ±1
        if not any(hi):
            continue
        got = kinetic_angle_cos(M, hi, hj)
        Minv = M.inv()
        num, aii, ajj = (hi * Minv * hj.T)[0, 0], (hi * Minv * hi.T)[0, 0], (hj * Minv * hj.T)[0, 0]
        assert sp.srepr(got) == sp.srepr(sp.radsimp(sp.simplify(num / sp.sqrt(aii * ajj)))), (M, hi, hj)


def test_kinetic_angle_float_matches_exact():
    M = [[1.1, 0.0], [0.0, 1.0]]
    c = kinetic_angle_cos(np.array(M), [1.0, 0.0], [-1.0, 1.0])
    assert abs(c - float(-sp.sqrt(210) / 21)) < 1e-15
    n = m_normal(np.array(M), [-1.0, 1.0])
    assert abs(n @ np.array(M) @ n - 1) < 1e-15


def test_pool_kinetic_angle_eq42():
    """Acary & Taha eq. 42: n1 . n2 = -cos(theta)/2 for the pool, from the general function."""
    from impactsym.models.acary_taha import pool

    theta = sp.Symbol("theta", real=True)
    sc = pool(theta)
    c = kinetic_angle_cos(sc.M, sc.H[0, :], sc.H[1, :])
    assert sp.simplify(c + sp.cos(theta) / 2) == 0


def test_to_exact_matrix_of_a_rational_matrix_is_the_entrywise_one():
    """The ZZ/QQ fast path of to_exact_matrix builds the matrix the entry-by-entry reading builds:
    the same entries, domain (ZZ when every entry is an integer, also from a QQ matrix) and sparse
    format, as a new mutable matrix; an ImmutableMatrix and a dense-format one too."""
    from impactsym.numbers import to_exact, to_exact_matrix

    half = sp.Rational(1, 2)
    base = [sp.Matrix([[1, 0], [0, 2]]), sp.Matrix([[1, half], [half, 2]]), (sp.Matrix([[1, 3]]) * half) * 2,
            sp.zeros(2, 3), sp.Matrix([1, -half, 0])]
    mats = []
    for m in base:
        dense = sp.Matrix(m)
        dense._rep = dense._rep.to_dense()
        mats += [m, sp.ImmutableMatrix(m), m.T, dense]
    for m in mats:
        for vector in (False, True):
            if vector and 1 not in m.shape:
                continue
            want = sp.Matrix(m).applyfunc(lambda x: to_exact(x, "m"))
            want = want.T if vector and want.cols != 1 else want
            got = to_exact_matrix(m, "m", vector=vector)
            assert type(got) is type(want) and got == want
            assert (got._rep.domain, got._rep.rep.fmt) == (want._rep.domain, want._rep.rep.fmt)
            assert got._rep.rep is not m._rep.rep
