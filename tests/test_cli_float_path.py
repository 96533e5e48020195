"""The float-path requests of the command line import no SymPy (issue 15), and answer byte for byte
as the general (SymPy) reader does: a law that computes in floats (the compliant laws, LZB) reads
plain rational matrices as a :class:`~impactsym.resolution.RationalMatrix` system, checked exactly
in python-flint; anything else (``sqrt(2)``, a refused input) falls back to the general reader."""

from __future__ import annotations

import contextlib
import io
import json
from fractions import Fraction
from pathlib import Path
from types import SimpleNamespace

import pytest

import impactsym.cli.scene_args as scene_args
from impactsym.cli import main
from impactsym.errors import ImpactInputError
from impactsym.resolution import RationalMatrix, System
from probe_server import RequestProbes, probe_paths, session_dir

CHAIN = ["--mass-matrix", "1,0,0;0,1,0;0,0,1", "--gradients", "-1,1,0;0,-1,1", "--velocity", "1,0,0"]
SKEW = ["--mass-matrix", "2,1/3;1/3,1", "--gradients", "1,0.1;-1,1/7", "--velocity", "-1,-2"]

FLOAT_REQUESTS = [
    ["resolve", "--law", "hertz", *SKEW, "--json"],
    ["resolve", "--law", "hertz", *SKEW],
    ["resolve", "--law", "linear", *CHAIN, "--stiffness", "1/3,2e-1", "--tolerance", "1e-9", "--json"],
    ["resolve", "--law", "power", *CHAIN, "--exponent", "5/2,1", "--json"],
    ["resolve", "--law", "hunt-crossley", *CHAIN, "--restitution", "1/3,0.8", "--json"],
    ["resolve", "--law", "hunt-crossley", *CHAIN, "--damping", "1", "--json"],
    ["resolve", "--law", "lzb", *CHAIN, "--restitution", "0.9,0.8", "--json"],
    ["resolve", "--law", "lzb", "--mass-matrix", "1", "--gradients", "1;-1", "--velocity", "-1", "--restitution",
     "1/2", "--json"],
]


FLOAT_LAW_PROBED = FLOAT_REQUESTS[::2] + [FLOAT_REQUESTS[-1]]


@pytest.mark.parametrize("argv", FLOAT_LAW_PROBED)
def test_a_float_law_on_plain_rationals_imports_no_sympy(argv):
    assert _PROBES.loaded(argv) == {"scipy"}  # the integrator's SciPy; no SymPy, no mpmath


IRRATIONAL = ["resolve", "--law", "hertz", "--mass-matrix", "1,0;0,sqrt(2)", "--gradients", "1,0;0,1", "--velocity",
              "-1,-1"]
POOL = ["resolve", "--law", "hertz", "--scene", "pool", "--theta", "pi/4"]


@pytest.mark.parametrize("argv", [IRRATIONAL, POOL])
def test_the_probe_can_fail(argv):
    """Irrational entries and scenes (the pool: cos and sin of its angles) take the general (SymPy)
    reader: each is the first request of its branch of the shared probe, after a trunk of float
    requests that loads none, and loads SymPy. The built-in scenes of rational data do not
    (tests/test_cli_scene_float_path.py)."""
    assert "sympy" not in _PROBES.before(argv) and "sympy" in _PROBES.loaded(argv)


def _run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


REFUSED = [
    ["resolve", "--law", "hertz", "--mass-matrix", "1,0;1,1", "--gradients", "1,0;0,1", "--velocity", "-1,-1", "--json"],
    ["resolve", "--law", "hertz", "--mass-matrix", "1,0;0,-1", "--gradients", "1,0;0,1", "--velocity", "-1,-1"],
    ["resolve", "--law", "hertz", "--mass-matrix", "1,0;0,1", "--gradients", "1,0;0,0", "--velocity", "-1,-1"],
    ["resolve", "--law", "hertz", "--mass-matrix", "1,0;0,1", "--gradients", "1,0,0;0,1,0", "--velocity", "-1,-1"],
    ["resolve", "--law", "hertz", "--mass-matrix", "1,0;0,1", "--gradients", "1,0;0,1", "--velocity", "-1"],
    ["resolve", "--law", "hertz", *SKEW, "--restitution", "1/2", "--json"],
    ["resolve", "--law", "lzb", *CHAIN, "--restitution", "1/0", "--json"],
    ["resolve", "--law", "lzb", "--mass-matrix", "1", "--gradients", "1;-1", "--velocity", "-1", "--json"],
    ["resolve", "--law", "linear", "--mass-matrix", "1", "--gradients", "1;-1", "--velocity", "-1", "--json"],
    ["resolve", "--law", "hertz", "--mass-matrix", "1e400,0;0,1", "--gradients", "1,0;0,1", "--velocity", "-1,-1"],
]


@pytest.mark.parametrize("argv", FLOAT_REQUESTS + REFUSED)
def test_the_rational_reader_answers_as_the_general_one(argv, monkeypatch):
    """Byte for byte (stdout, stderr, exit status), with the rational reader and without it."""
    fast = _run(argv)
    monkeypatch.setattr(scene_args, "read_rational_system", lambda args: None)
    assert _run(argv) == fast


def test_the_rational_reader_takes_only_plain_explicit_input():
    import argparse

    base = dict(scene=None, scene_file=None, mass_matrix="2,0;0,1", gradients="-1,1", velocity="1,0",
                restitution=None, **{p: None for p in scene_args.ALL_PARAMS})
    read = scene_args.read_rational_system
    system = read(argparse.Namespace(**base))
    assert system.rational and system.M == RationalMatrix([[2, 0], [0, 1]])
    assert read(argparse.Namespace(**{**base, "restitution": "1/2,1"})).restitution == [Fraction(1, 2), 1]
    for change in ({"mass_matrix": "sqrt(2),0;0,1"}, {"restitution": "1,"}, {"restitution": "1/0"},
                   {"scene": "chain3"}, {"masses": "1,2"}, {"velocity": None}, {"mass_matrix": "1,2;2,1"}):
        assert read(argparse.Namespace(**{**base, **change})) is None, change


def test_from_rationals_checks_exactly_and_prints_as_sympy():
    import sympy as sp

    Q = Fraction
    M, H, v = [[Q(2), Q(1, 3)], [Q(1, 3), Q(1)]], [[Q(1), Q(1, 10)]], [Q(-1), Q(10) ** 400]
    light = System.from_rationals(M, H, v, Q(1, 3))
    general = System.from_matrices(sp.Matrix(M), sp.Matrix(H), sp.Matrix(v), sp.Rational(1, 3))
    assert light.as_json() == general.as_json()  # exact strings, float twins (None beyond the float range)
    with pytest.raises(ImpactInputError, match="not symmetric"):
        System.from_rationals([[Q(1), Q(0)], [Q(1), Q(1)]], H, v[:2])
    with pytest.raises(ImpactInputError, match="leading principal minor 2 is -1/9"):
        System.from_rationals([[Q(1), Q(1, 3)], [Q(1, 3), Q(0)]], H, v)


_BATCH_LINES = [{"argv": ["resolve", "--law", "hertz", *SKEW], "id": 1},
                {"command": "resolve", "args": {"law": "lzb", "mass_matrix": "1,0,0;0,1,0;0,0,1",
                                                "gradients": "-1,1,0;0,-1,1", "velocity": "1,0,0",
                                                "restitution": "0.9"}},
                {"argv": ["scene", "list"]}]


def _batch_files(d: Path) -> SimpleNamespace:
    """The two batches of :func:`test_a_batch_of_float_requests_imports_no_sympy`, written to ``d``."""
    floats, exact = d / "float-path-requests.jsonl", d / "float-path-with-newton.jsonl"
    floats.write_text("\n".join(json.dumps(x) for x in _BATCH_LINES) + "\n")
    exact.write_text(floats.read_text() + json.dumps({"argv": ["resolve", "--law", "newton", *CHAIN]}) + "\n")
    answers, answers2 = d / "float-path-answers.jsonl", d / "float-path-answers2.jsonl"
    return SimpleNamespace(floats=["batch", "--input", str(floats), "--output", str(answers)],
                           exact=["batch", "--input", str(exact), "--output", str(answers2)], answers=answers,
                           answers2=answers2)


def test_a_batch_of_float_requests_imports_no_sympy():
    """``impactsym batch`` answers float-path requests without SymPy (the check machinery of
    :mod:`impactsym.oracle` imports it on first use), and one exact request still takes it: the
    float batch ends the shared probe's trunk (no SymPy in its set), the exact one runs after it in
    a branch of its own (the one that loads SymPy)."""
    batch = _BATCH
    assert _PROBES.loaded(batch.floats) == {"scipy"}
    answers = [json.loads(x) for x in batch.answers.read_text().splitlines()]
    assert [a["exit_status"] for a in answers] == [0, 0, 0]
    assert answers[0]["result"]["system"]["mass_matrix"] == [["2", "1/3"], ["1/3", "1"]]
    assert "sympy" not in _PROBES.before(batch.exact) and "sympy" in _PROBES.loaded(batch.exact)
    assert [json.loads(x)["exit_status"] for x in batch.answers2.read_text().splitlines()] == [0] * 4


# ------------------------------------------------------------------ the sequential law's --float path
SEQ = ["resolve", "--law", "sequential", "--float"]
EYE2 = ["--mass-matrix", "1,0;0,1"]
#: (argv, exit status): ties beta = pi/K for K = 2 (orthogonal contacts), 4, 3, 6, both two-surface
#: paths, the DAG search (three contacts), the cone reading, restitution < 1, refusals
SEQUENTIAL_FLOAT = [
    ([*SEQ, *EYE2, "--gradients", "1,0;0,1", "--velocity", "-1,-1", "--json"], 0),
    ([*SEQ, *EYE2, "--gradients", "1,0;0,1", "--velocity", "-1,-3", "--two-surface-path", "closed-form"], 0),
    ([*SEQ, *EYE2, "--gradients", "1,0;-1,1", "--velocity", "-1,-2", "--two-surface-path", "iterate", "--json"], 0),
    ([*SEQ, "--mass-matrix", "1,0;0,1/3", "--gradients", "1,0;-1,1", "--velocity", "-1,-2", "--json"], 0),
    ([*SEQ, "--mass-matrix", "1,0;0,3", "--gradients", "1,0;-1,1", "--velocity", "-1,-2", "--json"], 0),
    ([*SEQ, "--mass-matrix", "11/10,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,-2", "--reading", "cone",
      "--json"], 0),
    ([*SEQ, "--mass-matrix", "2,1/3;1/3,1", "--gradients", "1,0.1;-1,1/7", "--velocity", "-1,-2"], 0),
    ([*SEQ, *CHAIN, "--json"], 0),
    ([*SEQ, *CHAIN, "--restitution", "1/2,1", "--json"], 0),
    ([*SEQ, "--mass-matrix", "1,0,0;0,3,0;0,0,4", "--gradients", "1,0,0;-1,1,0;0,-1,1", "--velocity", "-1,-3,0",
      "--json"], 0),
    ([*SEQ, *EYE2, "--gradients", "1,0;0,1", "--velocity", "1,1", "--json"], 0),
    ([*SEQ, "--mass-matrix", "1", "--gradients", "1;-1", "--velocity", "1", "--json"], 2),
    ([*SEQ, *CHAIN, "--max-reflections", "1"], 2),
    # a wedge of 267795 reflections: the closed form, its energy selection, the cone reading refused
    ([*SEQ, *EYE2, "--gradients", "1,0;-1,1/100000", "--velocity", "-1,-2", "--json"], 0),
    ([*SEQ, *EYE2, "--gradients", "1,0;-1,1/100000", "--velocity", "-1,-2", "--reading", "cone", "--json"], 2),
]


SEQUENTIAL_PROBED = SEQUENTIAL_FLOAT[::3] + [SEQUENTIAL_FLOAT[4], SEQUENTIAL_FLOAT[-2]]


@pytest.mark.parametrize("argv,status", SEQUENTIAL_PROBED)
def test_sequential_float_imports_no_sympy_or_mpmath(argv, status):
    assert _PROBES.loaded(argv, status) == set()


@pytest.mark.parametrize("argv,status", SEQUENTIAL_FLOAT)
def test_sequential_float_answers_as_the_general_reader(argv, status, monkeypatch):
    """Byte for byte, with the rational reader and with the SymPy one (whose matrices the law
    turns into the same floats)."""
    fast = _run(argv)
    assert fast[0] == status
    monkeypatch.setattr(scene_args, "read_rational_system", lambda args: None)
    assert _run(argv) == fast


def test_float_selection_is_the_exact_selection_rounded():
    """Float mode keeps the selection exact (SymPy vectors made on first read) and reports each
    entry as float(N(x, 17)) of it; the surd case (a selection inside an arc) included."""
    import numpy as np
    import sympy as sp

    from impactsym.laws.sequential import resolve_sequential

    cases = [(np.diag([1.1, 1.0]), [[1.0, 0], [-1, 1]], [-1.0, -2], "cone"),
             (np.diag([1.1, 1.0]), [[1.0, 0], [-1, 1]], [-1.0, -2], "energy"),
             (np.diag([1.0, 3, 4]), [[1.0, 0, 0], [-1, 1, 0], [0, -1, 1]], [-1.0, -3, 0], "energy"),
             (np.diag([1.0, 3, 4]), [[1.0, 0, 0], [-1, 1, 0], [0, -1, 1]], [-1.0, -3, 0], "cone")]
    for M, H, v, reading in cases:
        r = resolve_sequential(M, H, v, reading=reading, two_surface="iterate")
        floats = r.selected_float
        assert floats and len(floats) == len(r.selected)
        for s, f in zip(r.selected, floats):
            assert all(isinstance(x, sp.Expr) for x in s)
            assert f == [float(sp.N(x, 17)) for x in s]


def test_rational_tie_is_the_exact_tie():
    """beta = pi/K for rational data only for K in {2, 3, 4, 6} (Niven): cos^2(pi/K) is irrational
    for every other K (its minimal polynomial has degree > 1), and on data built to tie, or to
    miss a tie by a little, rational_tie agrees with SymPy's certified sign."""
    import sympy as sp

    from impactsym.arithmetic import certified_sign
    from impactsym.laws.two_surface import RATIONAL_COS2, rational_tie

    x = sp.Symbol("x")
    for K in range(2, 25):
        c2 = sp.cos(sp.pi / K) ** 2
        degree = sp.degree(sp.minimal_polynomial(c2, x), x)
        assert (degree == 1) == (K in RATIONAL_COS2), K
        if K in RATIONAL_COS2:
            assert sp.nsimplify(c2) == sp.Rational(int(RATIONAL_COS2[K].p), int(RATIONAL_COS2[K].q))
    from flint import fmpq

    data = [(fmpq(1), fmpq(1), fmpq(0)), (fmpq(1), fmpq(2), fmpq(-1)), (fmpq(1), fmpq(4), fmpq(-1)),
            (fmpq(1), fmpq(4, 3), fmpq(-1)), (fmpq(1), fmpq(2), fmpq(1)), (fmpq(3), fmpq(5), fmpq(-2)),
            (fmpq(1), fmpq(4), fmpq(-1) + fmpq(1, 10**30)), (fmpq(1), fmpq(1), fmpq(1, 10**40))]
    for sa, sb, g in data:
        for K in range(2, 13):
            Q = (lambda q: sp.Rational(int(q.p), int(q.q)))
            exact = certified_sign(-Q(g) / sp.sqrt(Q(sa) * Q(sb)) - sp.cos(sp.pi / K), max_digits=200) == 0
            assert rational_tie(sa, sb, g, K) == exact, (sa, sb, g, K)


def test_arb_mid_float_is_mpmaths_float():
    import random

    import mpmath
    from flint import arb, ctx

    from impactsym.arithmetic import arb_mid_float, arb_to_mpf

    rng = random.Random(15)
    values = [arb(0), arb(1) / 3, -arb(2) / 7, arb(10) ** 400, arb(10) ** -400, arb(2) ** -1074 * 3, arb(2) ** 1024]
    with ctx.workprec(200):
        values += [arb(rng.randrange(-10**60, 10**60)) / rng.randrange(1, 10**60) * arb(2) ** rng.randrange(-1100, 1100)
                   for _ in range(300)]
        for x in values:
            with mpmath.workprec(53):
                assert arb_mid_float(x) == float(arb_to_mpf(x)), x


_SCENE_FILE_CASES = [
    (["resolve", "--law", "sequential", "--float", "--scene-file", "chain3-float", "--json"], set()),
    (["resolve", "--law", "sequential", "--scene-file", "chain3-float"], set()),  # float literals: the float path
    (["resolve", "--law", "hertz", "--scene-file", "chain3-float", "--json"], {"scipy"}),
]


#: every probe of this module that needs no process of its own, in forks of one fresh interpreter
#: (:class:`probe_server.RequestProbes`; its trunk shared with tests/test_cli_scene_float_path.py's when
#: both modules are collected).
#: The trunk, by growing sets: the sequential law's float path and the float scene file's (nothing
#: heavy), the scene file's Hertz request (the first to load SciPy), the float laws and a batch of
#: float requests (SciPy). Then three branches, each after the whole trunk, each loading SymPy:
#: irrational entries (the general reader) followed by a float request again; the pool scene; a
#: batch with one exact request (test_the_probe_can_fail, test_one_interpreter_probes_each_request,
#: test_a_batch_of_float_requests_imports_no_sympy)
_BATCH = _batch_files(session_dir())
_EVERYTHING = {"scipy", "sympy", "mpmath"}
_PROBES = RequestProbes([(a, s, ()) for a, s in SEQUENTIAL_PROBED] + [(a, 0, loaded) for a, loaded in _SCENE_FILE_CASES]
                        + [(a, 0, {"scipy"}) for a in FLOAT_LAW_PROBED] + [(_BATCH.floats, 0, {"scipy"})],
                        [[(IRRATIONAL, 0, _EVERYTHING), (FLOAT_REQUESTS[2], 0, _EVERYTHING)], [(POOL, 0, _EVERYTHING)],
                         [(_BATCH.exact, 0, _EVERYTHING)]], group="float-path")


@pytest.mark.parametrize("argv,loaded", _SCENE_FILE_CASES)
def test_a_float_scene_file_imports_no_sympy(argv, loaded):
    """A scene file of float literals is read, checked (contacts closed within its gap tolerance,
    approach signs on the floats' exact binary values in fmpq) and resolved without SymPy."""
    assert _PROBES.loaded(argv) == loaded


def test_one_interpreter_probes_each_request():
    """The shared probe sees what each request loads: a request that loads SymPy shows it in its
    own set and every later one, not in the earlier ones (the first branch's two requests)."""
    branch = _PROBES.branches[0]
    assert [c[:2] for c in branch] == [(IRRATIONAL, 0), (FLOAT_REQUESTS[2], 0)]
    sets = [_PROBES.loaded(FLOAT_REQUESTS[0])] + _PROBES.sets(1)[-2:]
    assert sets[0] == {"scipy"} and {"sympy", "scipy"} <= sets[1] and sets[2] == sets[1]


def test_the_number_module_loads_sympy_on_first_use():
    """impactsym.numbers keeps its API (SymPy numbers out) but imports SymPy only when a SymPy
    number is made; its float and type checks run without it."""
    code = ("import sys\nimport numpy as np\nfrom impactsym import numbers\n"
            "assert numbers.is_exact([[1, 2]], '1/2') and not numbers.is_exact(np.eye(2))\n"
            "assert numbers.to_float_array([[1.0, 0.5]]).tolist() == [[1.0, 0.5]]\n"
            "assert 'sympy' not in sys.modules and 'mpmath' not in sys.modules\n"
            "x = numbers.parse_number('sqrt(2)/2')\n"
            "print(type(x).__module__.split('.')[0], numbers.exact_str(x), numbers.parse_number('Integer(4)/2'))")
    assert probe_paths([[code]])[0][0].out.split() == ["sympy", "sqrt(2)/2", "2"]


def test_float_twins_of_exact_and_float_matrices():
    """The float path's conversions are the entry-by-entry ones: a SymPy matrix over QQ read
    sparsely (each rational's nearest float, inf beyond the range, as SymPy's float), and a float
    matrix printed with repr and its float twin (None when not finite, -0.0 kept)."""
    import math

    import numpy as np
    import sympy as sp

    from impactsym.lawbook import _float_array
    from impactsym.resolution import _float, _text, matrix_json

    x = 2 * (2 ** 53 + 1) * 2 ** 6 + 1  # x / 2**7 lies just above a tie between two floats
    A = sp.Matrix([[sp.Rational(1, 3), 0, sp.Rational(-7, 10)], [sp.Rational(x, 2 ** 7), sp.Integer(10) ** 400, -1],
                   [0, 0, sp.Rational(-(10 ** 400), 3)]])
    want = np.array([[float(e) for e in row] for row in A.tolist()])
    got = _float_array(A)
    assert got.tolist() == want.tolist() and math.isinf(got[1, 1]) and got[2, 2] == -math.inf
    assert _float_array(RationalMatrix([[Fraction(1, 3), Fraction(10) ** 400]])).tolist() == [[1 / 3, math.inf]]
    F = np.array([[0.1, -0.0, math.inf], [1e300, -math.nan, 2.0]])
    js = matrix_json("M", F)
    assert js["M"] == [[_text(e, None) for e in row] for row in F.tolist()]
    assert js["M_float"] == [[_float(e) for e in row] for row in F.tolist()]
    assert js["M"][0][1] == "-0.0" and js["M_float"][0][2] is None and js["M_float"][1][1] is None
