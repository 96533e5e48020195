"""The paper's matrices (Seghete & Murphey sec. III-B), reproduced exactly by impactsym.reflection_map."""

import mpmath
import sympy as sp

from impactsym import reflect, reflection_map

R = sp.Rational


def test_two_equal_balls_and_wall_sec_IIIB1():
    Gu, Gv = reflection_map("1,0;0,1", "1,0"), reflection_map("1,0;0,1", "-1,1")
    assert Gu == sp.Matrix([[-1, 0], [0, 1]])
    assert Gv == sp.Matrix([[0, 1], [1, 0]])
    assert Gv * Gu * Gv * Gu == -sp.eye(2) == Gu * Gv * Gu * Gv


def test_three_ball_cradle_sec_IIIB2_eq4():
    M = sp.eye(3)
    Gu, Gv = reflection_map(M, "-1,1,0"), reflection_map(M, "0,-1,1")
    assert Gu == sp.Matrix([[0, 1, 0], [1, 0, 0], [0, 0, 1]])
    assert Gv == sp.Matrix([[1, 0, 0], [0, 0, 1], [0, 1, 0]])
    anti = sp.Matrix([[0, 0, 1], [0, 1, 0], [1, 0, 0]])
    assert Gu * Gv * Gu == anti == Gv * Gu * Gv  # eq. 4
    assert anti * sp.Matrix([1, 0, 0]) == sp.Matrix([0, 0, 1])
    assert anti * sp.Matrix([1, 1, 0]) == sp.Matrix([0, 1, 1])


def _rounded(x, places=4):
    """Round half away from zero at `places` decimals, at 50 digits (the print's 4-digit rounding)."""
    with mpmath.workdps(50):
        v = mpmath.mpf(sp.N(x, 60)._mpf_) * 10**places
        return int(mpmath.sign(v) * mpmath.floor(abs(v) + mpmath.mpf(1) / 2))


def test_unequal_masses_sec_IIIB3():
    M = "11/10,0;0,1"
    Gu, Gv = reflection_map(M, "1,0"), reflection_map(M, "-1,1")
    # the paper prints G_u = -I; the derivation gives diag(-1, 1) (wall interaction 'unchanged')
    assert Gu == sp.diag(-1, 1) and Gu != -sp.eye(2)
    assert Gv == sp.Matrix([[R(1, 21), R(20, 21)], [R(22, 21), R(-1, 21)]])
    printed_Gv = [[476, 9524], [10476, -476]]  # 0.0476, 0.9524, 1.0476, -0.0476
    assert [[_rounded(x) for x in row] for row in Gv.tolist()] == printed_Gv
    v4a, v4b = Gv * Gu * Gv * Gu, Gu * Gv * Gu * Gv
    assert v4a == sp.Matrix([[R(-439, 441), R(-40, 441)], [R(44, 441), R(-439, 441)]])
    assert v4b == sp.Matrix([[R(-439, 441), R(40, 441)], [R(-44, 441), R(-439, 441)]])
    # printed v4a = [[-0.9955, -0.0907], [0.0998, -0.9955]], v4b with the off-diagonal signs flipped
    assert [[_rounded(x) for x in row] for row in v4a.tolist()] == [[-9955, -907], [998, -9955]]
    assert [[_rounded(x) for x in row] for row in v4b.tolist()] == [[-9955, 907], [-998, -9955]]
    # with the printed G_u = -I the products would be the identity, not the printed matrices
    assert Gv * (-sp.eye(2)) * Gv * (-sp.eye(2)) == sp.eye(2)


def test_exit_velocity_from_velocity_argument():
    assert reflect("11/10,0;0,1", "-1,1", "1,0") == sp.Matrix([R(1, 21), R(22, 21)])
