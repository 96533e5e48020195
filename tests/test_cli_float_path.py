"""The float-path requests of the command line import no SymPy (issue 15), and answer byte for byte
as the general (SymPy) reader does: a law that computes in floats (the compliant laws, LZB) reads
plain rational matrices as a :class:`~impactsym.resolution.RationalMatrix` system, checked exactly
in python-flint; anything else (``sqrt(2)``, a refused input) falls back to the general reader."""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

import impactsym.cli.scene_args as scene_args
from impactsym.cli import main
from impactsym.errors import ImpactInputError
from impactsym.resolution import RationalMatrix, System

ROOT = Path(__file__).resolve().parents[1]
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


def _loaded(argv, status=0) -> set:
    code = ("import contextlib, io, sys\nfrom impactsym.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            f"    assert main({argv!r}) == {status}\n"
            "print(' '.join(m for m in ('sympy', 'mpmath', 'scipy') if m in sys.modules))")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                         env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert res.returncode == 0, res.stderr
    return set(res.stdout.split())


@pytest.mark.parametrize("argv", FLOAT_REQUESTS[::2] + [FLOAT_REQUESTS[-1]])
def test_a_float_law_on_plain_rationals_imports_no_sympy(argv):
    assert _loaded(argv) == {"scipy"}  # the integrator's SciPy; no SymPy, no mpmath


@pytest.mark.parametrize("argv", [
    ["resolve", "--law", "hertz", "--mass-matrix", "1,0;0,sqrt(2)", "--gradients", "1,0;0,1", "--velocity", "-1,-1"],
    ["resolve", "--law", "hertz", "--scene", "chain3"],
])
def test_the_probe_can_fail(argv):
    """Irrational entries and scenes take the general (SymPy) reader."""
    assert "sympy" in _loaded(argv)


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


def test_a_batch_of_float_requests_imports_no_sympy(tmp_path):
    """``impactsym batch`` answers float-path requests without SymPy (the check machinery of
    :mod:`impactsym.oracle` imports it on first use), and one exact request still takes it."""
    import json

    lines = [{"argv": ["resolve", "--law", "hertz", *SKEW], "id": 1},
             {"command": "resolve", "args": {"law": "lzb", "mass_matrix": "1,0,0;0,1,0;0,0,1",
                                             "gradients": "-1,1,0;0,-1,1", "velocity": "1,0,0", "restitution": "0.9"}},
             {"argv": ["scene", "list"]}]
    path = tmp_path / "requests.jsonl"
    path.write_text("\n".join(json.dumps(x) for x in lines) + "\n")
    assert _loaded(["batch", "--input", str(path), "--output", str(tmp_path / "answers.jsonl")]) == {"scipy"}
    answers = [json.loads(x) for x in (tmp_path / "answers.jsonl").read_text().splitlines()]
    assert [a["exit_status"] for a in answers] == [0, 0, 0]
    assert answers[0]["result"]["system"]["mass_matrix"] == [["2", "1/3"], ["1/3", "1"]]
    path.write_text(path.read_text() + json.dumps({"argv": ["resolve", "--law", "newton", *CHAIN]}) + "\n")
    assert "sympy" in _loaded(["batch", "--input", str(path), "--output", str(tmp_path / "answers.jsonl")])
