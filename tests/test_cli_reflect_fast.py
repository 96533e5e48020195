"""``impactsym reflect`` on rational input takes a path without SymPy (issue 15): the same output,
byte for byte, as the general path; the same errors (the general path words them); a result
verified before it is printed; and the JSON floats of exact rationals as SymPy prints them.

Each case runs ``main(argv)`` twice in-process: as it is, and with the fast path switched off
(``_run_rational`` returning ``None``), and compares stdout, stderr and the exit status.
"""

from __future__ import annotations

import random
import types
from fractions import Fraction

import pytest
import sympy as sp

from impactsym.arithmetic.literals import json_float, plain_matrix, plain_rational, plain_vector
from impactsym.cli import build_parser, main
from impactsym.cli import reflect as cli_reflect
from impactsym.errors import VerificationError
from impactsym.laws import reflection_rational as rr

#: (mass matrix, gradient, velocity or None, restitution or None)
CASES = [
    ("2,0;0,1", "-1,1", "1,0", None),
    ("11/10,0;0,1", "-1,1", None, None),
    ("1.5,0.25;0.25,2", "0.1,-3e-2", "1e-3,2", "0.9"),
    ("1.5,0.25;0.25,2", "0.1,-3e-2", "1e-3,2", "0"),
    (" 2 , 0 ; 0 , 1 ", " -1 , 1 ", " 1 , 0 ", " 1.0 "),
    ("+1,0;0,.5", "5.,-0", "1E3,-2e+2", "1/4"),
    ("3,1,0;1,3,1;0,1,3", "1,-1,0", "-1,2,1/3", "2/3"),
    ("7", "2", "-3", "1/3"),  # 1x1: the matrix is one row on both paths
    ("1e300,0;0,1e-300", "1,1", "1,1", None),
    ("1e-400,0;0,1", "1,1", "1,-1", None),  # floats underflow to 0.0
    ("1e400,0;0,1", "1,1e-200", "1,-1", None),  # and overflow to null
    ("123456789012345678901234567890/7,1;1,3", "1/3,1/7", "2/11,-5/13", "3/10"),
    ("1,0;0,1", "1e-3/7,1.5/2", "1,0", None),
    # not plain: the general path answers
    ("sqrt(2),0;0,1", "-1,1", "1,0", None),
    ("2,0;0,1", "1,1", "1,0", "sqrt(2)/2"),
    ("2,0;0,1", "1,1", "pi,0", None),
    ("1,0;0,1", "1e1001,1", "1,0", None),
    # bad input (exit 2), found by the fast path's checks or by the parser
    ("1,2;2,1", "1,0", "1,0", None),
    ("1,2;3,4", "1,0", "1,0", None),
    ("-1,0;0,1", "1,0", "1,0", None),
    ("2,0;0,1", "0,0", None, None),
    ("1,0;0", "1,0", "1,0", None),
    ("1,0,0;0,1,0", "1,0,0", "1,0,0", None),
    ("1,0;0,1", "1,,0", "1,0", None),
    ("1,0;0,1", "1,0", "1;0", None),
    ("1/0,0;0,1", "1,0", "1,0", None),
    ("nan,0;0,1", "1,0", "1,0", None),
    ("1,0;0,1", "1,0", "1,0", "3/2"),
    ("1,0;0,1", "1,0", "1,0", "-0.1"),
    ("1,0;0,1", "1,0,0", "1,0", None),
    ("1,0;0,1", "1,0", "1,0,0", None),
    ("1,2;2,1", "0,0", "1,0,0", "3/2"),  # several faults: the first one is named, as before
    ("1,0;0,1", "0,0", "x", "3/2"),
    ("1,0;0,1", "1,0", "x", None),
]


def _argv(M, u, v, e, as_json):
    argv = ["reflect", f"--mass-matrix={M}", f"--gradient={u}"]
    if v is not None:
        argv.append(f"--velocity={v}")
    if e is not None:
        argv.append(f"--restitution={e}")
    return argv + (["--json"] if as_json else [])


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _both(capsys, monkeypatch, argv):
    fast = _run(capsys, argv)
    with monkeypatch.context() as m:
        m.setattr(cli_reflect, "_run_rational", lambda args: None)
        general = _run(capsys, argv)
    return fast, general


@pytest.mark.parametrize("as_json", [True, False], ids=["json", "text"])
@pytest.mark.parametrize("case", CASES, ids=[f"case{i}" for i in range(len(CASES))])
def test_fast_path_output_is_the_general_paths(capsys, monkeypatch, case, as_json):
    fast, general = _both(capsys, monkeypatch, _argv(*case, as_json))
    assert fast == general


def _random_case(rng):
    n = rng.randint(1, 4)

    def num():
        q = Fraction(rng.randint(-40, 40), rng.choice([1, 2, 3, 7, 10, 100]))
        return q

    def text(q):
        style = rng.choice(["frac", "dec", "exp"])
        if style == "frac" or q.denominator not in (1, 2, 10, 100):
            return str(q)
        if style == "dec":
            return f"{float(q):.2f}"  # exact for these denominators
        return f"{q * 100}e-2" if q.denominator == 1 else str(q)

    A = [[num() for _ in range(n)] for _ in range(n)]
    M = [[sum((A[i][k] * A[j][k] for k in range(n)), Fraction(0)) + (Fraction(1, 3) if i == j else 0)
          for j in range(n)] for i in range(n)]
    u = [num() for _ in range(n)]
    if all(x == 0 for x in u):
        u[0] = Fraction(1)
    v = [num() for _ in range(n)]
    e = Fraction(rng.randint(0, 20), 20)
    return (";".join(",".join(str(x) for x in row) for row in M), ",".join(text(x) for x in u),
            ",".join(text(x) for x in v), text(e))


@pytest.mark.parametrize("seed", range(12))
def test_fast_path_agrees_with_the_general_path_on_random_rational_systems(capsys, monkeypatch, seed):
    rng = random.Random(seed)
    for _ in range(3):
        case = _random_case(rng)
        args = build_parser().parse_args(_argv(*case, True))
        assert cli_reflect._run_rational(args) is not None, case  # the fast path answers these
        fast, general = _both(capsys, monkeypatch, _argv(*case, True))
        assert fast == general
        assert fast[0] == 0


def test_fast_path_is_taken_only_for_plain_rational_input():
    def answer(*case):
        return cli_reflect._run_rational(build_parser().parse_args(_argv(*case, True)))

    assert answer("2,0;0,1", "-1,1", "1,0", None)["velocity"] == ["1/3", "4/3"]
    assert answer("sqrt(2),0;0,1", "-1,1", "1,0", None) is None
    assert answer("2,0;0,1", "-1,1", "1,0", "1/2^1") is None
    assert answer("1,2;2,1", "1,0", "1,0", None) is None  # refused: the general path words it


def test_the_rational_law_refuses_what_the_general_law_refuses():
    from impactsym.errors import DomainError, ImpactInputError

    with pytest.raises(ImpactInputError, match="not symmetric"):
        rr.rational_reflection([[1, 2], [3, 4]], [1, 0])
    with pytest.raises(ImpactInputError, match="leading principal minor 1 is 0"):
        rr.rational_reflection([[0, 0], [0, 1]], [1, 0])
    with pytest.raises(ImpactInputError, match="non-empty square"):
        rr.rational_reflection([[1, 0]], [1, 0])
    with pytest.raises(ImpactInputError, match="zero covector"):
        rr.rational_reflection([[1, 0], [0, 1]], [0, 0])
    with pytest.raises(ImpactInputError, match="velocity: has length 3"):
        rr.rational_reflection([[1, 0], [0, 1]], [1, 0], 1, [1, 2, 3])
    with pytest.raises(DomainError, match=r"restitution: must lie in \[0, 1\], got 3/2"):
        rr.rational_reflection([[1, 0], [0, 1]], [1, 0], Fraction(3, 2))


def test_the_rational_law_equals_the_sympy_law():
    from impactsym.arithmetic.rational import to_sympy_matrix
    from impactsym.laws.reflection import reflect, reflection_map

    rng = random.Random(7)
    for _ in range(20):
        M, u, v, e = _random_case(rng)
        Mq, uq, vq, eq = plain_matrix(M), plain_vector(u), plain_vector(v), plain_rational(e)
        G, vplus, _ = rr.rational_reflection(Mq, uq, eq, vq)
        assert to_sympy_matrix(G) == reflection_map(M, u, e)
        assert to_sympy_matrix(vplus) == reflect(M, u, v, e)


def _corrupting(**changes):
    """``laws._reflection`` with some functions' results shifted by 1/97 (a wrong law)."""
    ns = types.SimpleNamespace(**{k: getattr(rr._r, k) for k in ("fmpq_parts", "gain", "reflection_matrix",
                                                                   "reflect_along")})
    for name, corrupt in changes.items():
        real = getattr(ns, name)
        setattr(ns, name, lambda *a, _real=real, _corrupt=corrupt: _corrupt(_real(*a)))
    return ns


@pytest.mark.parametrize("changes", [
    {"reflection_matrix": lambda G: G + G.__class__(G.nrows(), G.ncols(), [rr.fmpq(1, 97)] * (G.nrows() * G.ncols()))},
    {"reflect_along": lambda r: (r[0] * rr.fmpq(98, 97), r[1])},  # v+ off the law
    {"reflect_along": lambda r: (r[0], r[1] + 1)},  # the impulse off the momentum balance
], ids=["G", "v+", "p"])
def test_a_wrong_result_is_never_printed(capsys, monkeypatch, changes):
    monkeypatch.setattr(rr, "_r", _corrupting(**changes))
    with pytest.raises(VerificationError, match="reflection"):
        main(_argv("2,0;0,1", "-1,1", "1,0", "1/2", True))
    assert capsys.readouterr().out == ""


def test_verification_catches_an_elastic_map_that_loses_energy():
    # u G = -e u holds, but M(G - I) is not along u^T u: G is not the law's map
    M, u = rr.fmpq_mat([[1, 0], [0, 1]]), rr.fmpq_mat([[1, 0]])
    G = rr.fmpq_mat([[-1, 0], [1, 1]])
    with pytest.raises(VerificationError, match=r"M \(G - I\)"):
        rr.verify_rational_reflection(M, u, rr.fmpq(1), G)


# --------------------------------------------------------------------------- the JSON floats
def _sympy_float(p, q):
    return float(sp.N(sp.Rational(p, q), 17))


def test_json_float_is_sympys_float_bit_for_bit():
    rng = random.Random(15)
    cases = [(0, 1), (1, 1), (-1, 2), (1, 3), (10 ** 400, 1), (-(10 ** 400), 3), (1, 10 ** 400), (1, 2 ** 1074),
             (3, 2 ** 1075), (1, 2 ** 1080), ((2 ** 53 - 1) * 2 ** 971, 1), (2 ** 1024 - 2 ** 970, 1)]
    for _ in range(1500):
        k, j = rng.choice([1, 3, 20, 60, 400]), rng.choice([1, 3, 20, 60, 400])
        cases.append((rng.randrange(-10 ** k, 10 ** k), rng.randrange(1, 10 ** j + 1)))
    for _ in range(1500):  # near ties at the 53rd, 60th and 64th bit, where SymPy's roundings differ
        m = rng.getrandbits(53) | (1 << 52)
        bits = rng.choice([54, 55, 60, 61, 62, 64, 65, 70])
        tail = rng.choice([1 << (bits - 54), (1 << (bits - 54)) - 1, (1 << (bits - 54)) + 1, 0])
        d = rng.choice([1, 3, 7, 1023, 1025])
        p = ((m << (bits - 53)) | tail) * d + rng.choice([-1, 0, 1])
        cases.append((p, d * 2 ** rng.randrange(0, 1100)))
    differs_from_nearest = 0
    for p, q in cases:
        g = sp.igcd(p, q)
        p, q = p // g, q // g
        assert json_float(p, q) == _sympy_float(p, q), (p, q)
        if abs(p) < q * 2 ** 1000:
            differs_from_nearest += json_float(p, q) != float(Fraction(p, q))
    assert differs_from_nearest > 0  # the double rounding is exercised, not only the easy cases


def test_exact_json_floats_of_rationals_are_unchanged():
    from impactsym.numbers import exact_json

    x = sp.Matrix([sp.Rational(1, 3), sp.Rational(-10 ** 30 - 1, 7), sp.Integer(2) ** 2000, sp.sqrt(2)])
    assert exact_json("x", x)["x_float"] == [_sympy_float(1, 3), _sympy_float(-10 ** 30 - 1, 7), float("inf"),
                                             float(sp.N(sp.sqrt(2), 17))]


def test_the_librarys_rational_map_is_verified_too(monkeypatch):
    from impactsym.laws import reflection as rf

    assert rf.reflection_map("2,0;0,1", "-1,1")[0, 0] == sp.Rational(1, 3)
    real = rf._r
    monkeypatch.setattr(rf, "_r", types.SimpleNamespace(
        fmpq_parts=real.fmpq_parts, gain=real.gain, sympy_parts=real.sympy_parts,
        reflection_matrix=lambda I, w, u, g: real.reflection_matrix(I, w, u, g) * rr.fmpq(98, 97)))
    with pytest.raises(VerificationError, match="reflection"):
        rf.reflection_map("2,0;0,1", "-1,1")
