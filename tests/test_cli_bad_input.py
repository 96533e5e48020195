"""Bad input, as a new user would type it, across every subcommand and law (issue 9, section 4).

Every malformed row must exit with status 2, name the argument at fault, print no traceback, and
with ``--json`` print exactly one object ``{"error": {"argument": ..., "message": ...}}`` on stdout
(the message also on stderr). The rows run ``main(argv)`` in-process; a few run as subprocesses to
check the whole process (no traceback on stderr, the time limit, the JSON error object).
"""

from __future__ import annotations

import json

import pytest

from impactsym.cli import main
from probe_server import run_python

EYE = ["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,0"]
LAWS = ["impulse-ratio", "newton", "poisson", "energetic", "han-gilmore", "two-surface", "sequential"]

#: malformed inputs every law must refuse: (options, the argument the error names)
COMMON_BAD = [
    (["--mass-matrix", "1,0;0", "--gradients", "1,0;-1,1", "--velocity", "-1,0"], "mass_matrix"),
    (["--mass-matrix", "1,2;2,1", "--gradients", "1,0;-1,1", "--velocity", "-1,0"], "mass_matrix"),
    (["--mass-matrix", "1,2;3,1", "--gradients", "1,0;-1,1", "--velocity", "-1,0"], "mass_matrix"),
    (["--mass-matrix", "a,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,0"], "mass_matrix"),
    (["--mass-matrix", "sqrt(-1),0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,0"], "mass_matrix"),
    (["--mass-matrix", "2^(2^30),0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,0"], "mass_matrix"),
    (["--mass-matrix", "exp(exp(exp(10))),0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,0"], "mass_matrix"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "9^9^9^9,0"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "10^10^10,0"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "1e100000,0"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "nan,0"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,,0"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1;0"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "inf,0;-1,1", "--velocity", "-1,0"], "gradients"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0,0;-1,1,0", "--velocity", "-1,0"], "gradients"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1"], "velocity"),
    (["--mass-matrix", "1,0;0,1", "--velocity", "-1,0"], "gradients"),
    ([*EYE, "--tau", "0"], "tau"),
    ([*EYE, "--n-balls", "3"], "n_balls"),
    ([*EYE, "--timeout", "-1"], "timeout"),
    ([*EYE, "--timeout", "soon"], "timeout"),
    (["--scene", "nowhere"], "scene"),
    (["--scene", "chain3", *EYE], "mass_matrix"),
    (["--scene", "chain3", "--masses", "1,1"], "masses"),
    (["--scene", "chain3", "--masses", "1,-1,1"], "masses"),
    (["--scene", "chain3", "--velocities", "9^9^9,0,0"], "velocities"),
    (["--scene", "chain3", "--theta", "pi/4"], "theta"),
    (["--scene", "pool", "--masses", "1,1,1"], "masses"),
    (["--scene", "bernoulli", "--theta", "1"], "theta"),
]

#: options a law does not take, and law-specific bad values
LAW_BAD = [
    # the two-surface law
    ("two-surface", ["--scene", "chain3", "--max-reflections", "1"], "max_reflections"),
    ("two-surface", ["--scene", "chain3", "--restitution", "1/2"], "restitution"),
    ("two-surface", ["--scene", "chain3", "--allow-invalid"], "allow_invalid"),
    ("two-surface", ["--scene", "chain3", "--float"], "float"),
    ("two-surface", ["--scene", "chain3", "--ratios", "1/2"], "ratios"),
    ("two-surface", ["--scene", "chain3", "--coupling"], "coupling"),
    ("two-surface", ["--scene", "chain3", "--reading", "cone"], "reading"),
    ("two-surface", ["--scene", "cradle", "--n-balls", "4"], "scene"),  # ... but 3 here: two-surface does not apply
    ("two-surface", ["--mass-matrix", "1,0;0,1", "--gradients", "1,0;0,1;1,1", "--velocity", "-1,0"], "gradients"),
    ("two-surface", ["--scene", "chain3", "--velocities", "10**400,0,0"], "velocities"),
    ("two-surface", ["--mass-matrix", "1,0;0,1", "--gradients", "1,0;0,1", "--velocity", "-10**308,-2*10**308"],
     "velocity"),
    # the sequential law
    ("sequential", ["--scene", "chain3", "--ratios", "1/2"], "ratios"),
    ("sequential", ["--scene", "chain3", "--coupling"], "coupling"),
    ("sequential", ["--scene", "chain3", "--allow-invalid"], "allow_invalid"),
    ("sequential", ["--scene", "chain3", "--variant", "paper"], "variant"),
    ("sequential", ["--scene", "chain3", "--restitution", "3/2"], "restitution"),
    ("sequential", [*EYE, "--theta", "pi/4"], "theta"),
    ("sequential", ["--scene", "cradle", "--theta", "1"], "theta"),
    ("sequential", ["--scene", "cradle", "--velocities", "1,0,0"], "velocities"),
    ("sequential", ["--scene", "two-balls-wall", "--n-balls", "3"], "n_balls"),
    ("sequential", ["--scene", "balls-against-wall", "--strikers", "1"], "strikers"),
    ("sequential", ["--scene", "chain3", "--reading", "nearest"], "reading"),
    ("sequential", ["--scene", "chain3", "--two-surface-path", "shortcut"], "two_surface_path"),
    ("sequential", ["--scene", "chain3", "--max-reflections", "0"], "max_reflections"),
    ("sequential", ["--scene", "chain3", "--max-reflections", "1.5"], "max_reflections"),
    ("sequential", ["--scene", "chain3", "--max-reflections", "many"], "max_reflections"),
    ("sequential", ["--scene", "chain3", "--max-reflections", "1"], "max_reflections"),
    ("sequential", ["--scene", "cradle", "--n-balls", "1000000000000"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "10**12"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "10001"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "100000"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "0"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "5/2"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "many"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "9^9^9^9"], "n_balls"),
    ("sequential", ["--scene", "cradle", "--n-balls", "3", "--strikers", "5"], "strikers"),
    ("sequential", ["--scene", "cradle", "--n-balls", "3", "--masses", "1,1"], "masses"),
    ("sequential", ["--scene", "nowhere"], "scene"),
    ("sequential", ["--scene", "chain3", "--velocities", "10**400,0,0", "--two-surface-path", "closed-form"],
     "velocities"),
    # the classical laws take none of the sequential law's options
    ("newton", ["--scene", "chain3", "--float"], "float"),
    ("newton", ["--scene", "chain3", "--reading", "cone"], "reading"),
    ("newton", ["--scene", "chain3", "--max-reflections", "1"], "max_reflections"),
    ("newton", ["--scene", "chain3", "--strikers", "7"], "strikers"),
    ("newton", ["--scene", "chain3", "--float", "--reading", "cone", "--max-reflections", "1", "--strikers", "7"],
     "strikers"),  # every inapplicable option is named; the argument is the first in the parser's order
    ("newton", ["--scene", "chain3", "--two-surface-path", "iterate"], "two_surface_path"),
    ("newton", ["--scene", "chain3", "--variant", "paper"], "variant"),
    ("newton", ["--scene", "chain3", "--coupling"], "coupling"),
    ("newton", ["--scene", "chain3", "--ratios", "1/2"], "ratios"),
    ("newton", ["--scene", "cradles"], "scene"),
    ("newton", ["--scene", "chain3", "--restitution", "3/2"], "restitution"),
    ("newton", ["--scene", "chain3", "--restitution", "x"], "restitution"),
    ("poisson", ["--scene", "chain3", "--variant", "nope"], "variant"),
    ("poisson", ["--scene", "chain3", "--coupling"], "coupling"),
    ("poisson", ["--scene", "chain3", "--n-balls", "3"], "n_balls"),
    ("poisson", ["--scene", "chain3", "--restitution", "1/2,a"], "restitution"),
    ("energetic", ["--scene", "chain3", "--ratios", "a"], "ratios"),
    ("energetic", ["--scene", "chain3", "--variant", "paper"], "variant"),
    ("energetic", ["--scene", "chain3", "--float"], "float"),
    ("han-gilmore", ["--scene", "chain3", "--allow-invalid"], "allow_invalid"),
    ("han-gilmore", ["--scene", "chain3", "--ratios", "1/2"], "ratios"),
    ("han-gilmore", ["--scene", "chain3", "--strikers", "2"], "strikers"),
    ("impulse-ratio", ["--scene", "chain3", "--ratios", "x"], "ratios"),
    ("impulse-ratio", ["--scene", "chain3", "--ratios", "1/2,1/2,1/2"], "ratios"),
    ("impulse-ratio", ["--scene", "chain3", "--ratios", "1/2", "--restitution", "-1"], "restitution"),
    ("impulse-ratio", ["--scene", "chain3", "--ratios", "1/2", "--reading", "energy"], "reading"),
    ("impulse-ratio", ["--scene", "chain3", "--ratios", "1/2", "--float"], "float"),
    ("impulse-ratio", ["--scene", "chain3", "--ratios", "1/2", "--max-reflections", "3"], "max_reflections"),
    ("impulse-ratio", ["--scene", "pool"], "theta"),
    ("impulse-ratio", ["--scene", "pool", "--theta", "9^9^9"], "theta"),
]

#: the other subcommands (and argparse's own errors): (argv, the argument the error names)
OTHER_BAD = [
    (["reflect", "--mass-matrix", "1,0,0;0,1,0", "--gradient", "1,0"], "mass_matrix"),
    (["reflect", "--mass-matrix", "1,2;2,1", "--gradient", "1,0"], "mass_matrix"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "0,0"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,0,0"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--velocity", "1"], "velocity"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--restitution", "11/10"], "restitution"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--restitution", "nan"], "restitution"),
    (["reflect", "--mass-matrix", "exp(exp(exp(10))),0;0,1", "--gradient", "1,1"], "mass_matrix"),
    (["reflect", "--mass-matrix", "9^9^9^9,0;0,1", "--gradient", "1,1"], "mass_matrix"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "2^(2^30),1"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1e5000,1"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "Integer(1/2),1"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "(" * 3000 + "1" + ")" * 3000 + ",1"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "__import__('os'),1"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", ""], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1"], "gradient"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--scene", "chain3"], "scene"),
    (["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,0", "--timeout", "0"], "timeout"),
    (["domain", "--scene", "billiards"], "scene"),
    (["domain", "--scene", "pool", "--theta", "3"], "theta"),
    (["domain", "--scene", "pool", "--theta", "9^9^9^9"], "theta"),
    (["domain", "--scene", "pool", "--theta", "inf"], "theta"),
    (["domain", "--scene", "chain3", "--theta", "pi/4"], "theta"),
    (["domain"], "scene"),
    (["prove", "--dimension", "4"], "dimension"),
    (["prove", "--dimension", "0"], "dimension"),
    (["prove", "--dimension", "seven"], "dimension"),
    (["prove", "--property", "G^3=I"], "property"),
    (["codegen", "--list", "--lang", "foo"], "lang"),
    (["codegen", "--list", "--lang", "numpy"], "lang"),
    (["codegen", "reflect-2", "--list"], "name"),
    (["codegen", "no-such-kernel"], "name"),
    (["codegen", "reflect-2", "--lang", "cobol"], "lang"),
    (["bench", "--quick", "--plot", "/nonexistent/dir/x.png"], "plot"),
    (["bench", "--quick", "--plot", "/"], "plot"),
    (["bench", "--quick", "--plot", "plot.txt"], "plot"),
    (["bench", "--quick", "--plot="], "plot"),
    (["bench", "--formula", "no_such_formula"], "formula"),
    (["reproduce", "--report="], "report"),
    (["reproduce", "--report", __file__], "report"),
    (["reproduce", "--paper", "newton-1687"], "paper"),
    (["resolve"], "law"),
    (["resolve", "--law", "no-such-law"], "law"),
    (["resolve", "--law"], "law"),
    (["resolve", "--law", "newton", "--scene", "chain3", "--no-such-option"], "--no-such-option"),
    (["no-such-subcommand"], "command"),
]

ROWS = ([pytest.param(["resolve", "--law", law, *opts], arg, id=f"{law}:{' '.join(opts)[:60]}")
         for law in LAWS for opts, arg in COMMON_BAD]
        + [pytest.param(["resolve", "--law", law, *opts], arg, id=f"{law}:{' '.join(opts)[:60]}")
           for law, opts, arg in LAW_BAD]
        + [pytest.param(argv, arg, id=" ".join(argv)[:70]) for argv, arg in OTHER_BAD])


def run(capsys, argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_the_table_is_large():
    assert len(ROWS) >= 150


@pytest.mark.parametrize("argv, argument", ROWS)
def test_bad_input_exits_2_naming_the_argument(capsys, argv, argument):
    code, out, err = run(capsys, argv)
    assert code == 2, (out, err)
    assert out == "" and "Traceback" not in err
    assert argument.lstrip("-").replace("-", "_") in err.replace("-", "_"), err


@pytest.mark.parametrize("argv, argument", ROWS)
def test_bad_input_with_json_is_one_error_object(capsys, argv, argument):
    code, out, err = run(capsys, [*argv, "--json"])
    assert code == 2, (out, err)
    assert "Traceback" not in err
    error = json.loads(out)["error"]  # exactly one JSON object on stdout
    assert set(error) == {"argument", "message"}
    assert error["message"] in err
    assert error["argument"] == argument.lstrip("-").replace("-", "_"), error


# --------------------------------------------------------------------------- inputs that must work
def test_exponent_literals_are_read_exactly(capsys):
    code, out, _ = run(capsys, ["reflect", "--mass-matrix", "1e0,0;0,2.5E-1", "--gradient", "1e-3,0", "--json"])
    assert code == 0 and json.loads(out)["matrix"] == [["-1", "0"], ["0", "1"]]


def test_overflowing_float_twins_are_null_beside_the_exact_string(capsys):
    code, out, _ = run(capsys, ["reflect", "--mass-matrix", "1,0;0,1", "--gradient", "1,1", "--velocity", "10**400,0",
                                "--json"])
    assert code == 0 and "Infinity" not in out
    d = json.loads(out)
    assert d["velocity"] == ["0", "-1" + "0" * 400] and d["velocity_float"] == [0.0, None]


def test_sequential_iterates_a_huge_velocity_exactly(capsys):
    """The closed form refuses 10**400 (its certified float twins overflow); the default path
    iterates the short cradle exactly and gives a null float twin beside the exact string."""
    code, out, _ = run(capsys, ["resolve", "--law", "sequential", "--scene", "chain3", "--velocities", "10**400,0,0",
                                "--json"])
    assert code == 0 and "Infinity" not in out
    o = json.loads(out)["outcomes"][0]
    assert o["velocity"] == ["0", "0", "1" + "0" * 400] and o["velocity_float"] == [0.0, 0.0, None]


@pytest.mark.parametrize("law", ["newton", "poisson", "energetic", "han-gilmore"])
def test_huge_masses_give_strict_json(capsys, law):
    code, out, _ = run(capsys, ["resolve", "--law", law, "--scene", "chain3", "--masses", "10**400,1,1", "--json"])
    assert code == 0 and "Infinity" not in out and "NaN" not in out
    d = json.loads(out)
    assert d["kinetic_energy_before"] == "5" + "0" * 399 and d["kinetic_energy_before_float"] is None


def test_n_balls_takes_an_integer_expression(capsys):
    code, out, _ = run(capsys, ["resolve", "--law", "sequential", "--scene", "cradle", "--n-balls", "2**2", "--json"])
    assert code == 0 and json.loads(out)["scene"]["n_balls"] == 4


def test_no_approach_is_said_in_words(capsys):
    code, out, _ = run(capsys, ["resolve", "--law", "two-surface", "--mass-matrix", "1,0;0,1", "--gradients",
                                "1,0;0,1", "--velocity", "1,1"])
    assert code == 0 and "no surface is approached" in out and "surface -1" not in out


def test_float_path_selects_floats(capsys):
    code, out, _ = run(capsys, ["resolve", "--law", "sequential", "--scene", "pool", "--theta", "pi/4", "--float",
                                "--json"])
    d = json.loads(out)
    assert code == 0 and d["selected"] and d["exactness"] == "float"
    assert all(s["exactness"] == "float" and all(isinstance(x, float) for x in s["velocity_float"])
               for s in d["selected"])


def test_pool_domain_without_impact_renders_as_text(capsys):
    code, out, _ = run(capsys, ["domain", "--scene", "pool", "--theta", "pi/4", "--tau", "pi/2"])
    assert code == 0 and "empty: True" in out


def test_version_and_scene_help(capsys):
    from impactsym import __version__

    code, out, _ = run(capsys, ["--version"])
    assert code == 0 and out.strip() == f"impactsym {__version__}"
    code, out, _ = run(capsys, ["resolve", "--help"])
    assert code == 0 and "cradle" in out and "balls-against-wall" in out


def test_help_documents_the_json_error_object(capsys):
    code, out, _ = run(capsys, ["--help"])
    assert code == 0 and '{"error": {"argument":' in out and "null" in out


# --------------------------------------------------------------------------- whole processes
def _proc(*argv, timeout=120):
    """``python -m impactsym ARGV`` as a real process (a child of the probe server's warm
    interpreter: its own exit status, stdout and stderr)."""
    return run_python(["-m", "impactsym", *argv], timeout=timeout)


@pytest.mark.parametrize("argv, argument", [
    (["resolve", "--law", "two-surface", "--scene", "chain3", "--velocities", "10**400,0,0"], "velocities"),
    (["resolve", "--law", "sequential", "--scene", "cradle", "--n-balls", "1000000000000"], "n_balls"),
    (["reflect", "--mass-matrix", "exp(exp(exp(10))),0;0,1", "--gradient", "1,1"], "mass_matrix"),
    (["resolve", "--law"], "law"),
])
def test_process_exits_2_with_one_json_error_object(argv, argument):
    r = _proc(*argv, "--json")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 1 and json.loads(lines[0])["error"]["argument"] == argument


def test_sequential_with_irrational_masses_answers_or_stops_at_the_time_limit():
    # a law-level hang (issue 9): the CLI's --timeout bounds it; exit 0 (answered) or 2 (stopped), never 1
    r = _proc("resolve", "--law", "sequential", "--mass-matrix", "pi,0;0,E", "--gradients", "1,0;1,1",
              "--velocity", "-1,-1", "--timeout", "5", "--json", timeout=300)
    assert r.returncode in (0, 2) and "Traceback" not in r.stderr
    d = json.loads(r.stdout)
    if r.returncode == 2:
        assert d["error"]["argument"] == "timeout" and "5 s" in d["error"]["message"]
    else:
        assert d["outcomes"]


@pytest.mark.parametrize("law, velocity", [
    ("newton", ["sqrt(2)/2", "sqrt(2)/2"]), ("poisson", ["sqrt(2)/2", "sqrt(2)/2"]),
    ("han-gilmore", ["sqrt(2)/2", "sqrt(2)/2"]), ("energetic", ["2**(3/4)/2", "2**(3/4)/2"]),
])
def test_irrational_restitution_with_rational_matrices(capsys, law, velocity):
    # was a TypeError (an irrational e in the rational arithmetic of the scene)
    code, out, err = run(capsys, ["resolve", "--law", law, "--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,1",
                                  "--velocity", "-1,-1", "--restitution", "sqrt(2)/2", "--json"])
    assert code == 0, err
    assert json.loads(out)["outcomes"][0]["velocity"] == velocity
