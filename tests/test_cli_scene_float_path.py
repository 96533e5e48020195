"""Float-path requests on the built-in scenes import no SymPy (issue 15): chain3 and the scenes of
balls on a line (two-balls-wall, three-ball-cradle, cradle, balls-against-wall), whose data are
rational for rational parameters, and the pool at θ = 0 and π/2 (θ − τ a multiple of π/2), are
built in Fractions (:func:`impactsym.scenes.registry.build_rational_scene`) and read as a
:class:`~impactsym.resolution.RationalMatrix` system, answering byte for byte as the SymPy build
does. Every other pool and Bernoulli's problem (cos and sin of their angles are irrational) and
non-plain parameters (``sqrt(2)``, ``2*3``) still take the general reader."""

from __future__ import annotations

import contextlib
import io
import json
from fractions import Fraction

import pytest

import impactsym.cli.scene_args as scene_args
from impactsym.cli import main
from impactsym.scenes.registry import RATIONAL_SCENES, build_rational_scene, build_scene
from probe_server import RequestProbes, session_dir

SEQ = ["resolve", "--law", "sequential", "--float"]
#: built-in scenes of rational data, with and without parameters
SCENES = [
    ["--scene", "chain3"],
    ["--scene", "chain3", "--masses", "1.1,1,1e-3", "--velocities", "1,0,-1/2"],
    ["--scene", "two-balls-wall", "--masses", "11/10,1"],
    ["--scene", "three-ball-cradle", "--velocities", "1,0,-1", "--masses", "1,1/2,2"],
    ["--scene", "cradle", "--n-balls", "5", "--strikers", "2"],
    ["--scene", "cradle", "--n-balls", "4", "--masses", "1,2,3,4"],
    ["--scene", "balls-against-wall"],
    ["--scene", "balls-against-wall", "--n-balls", "4", "--masses", "1,2,3,4", "--velocities", "0,0,0,-1"],
    ["--scene", "pool", "--theta", "pi/2"],
    ["--scene", "pool", "--theta", "0", "--tau", "-3*pi/2"],
]
#: (argv, exit status, libraries loaded so far): the sequential law's --float path loads none, the
#: integrators SciPy; a refused request (strikers = n_balls) takes the general reader's words
_CASES = [
    ([*SEQ, *SCENES[0], "--json"], 0, set()),
    ([*SEQ, *SCENES[4], "--json"], 0, set()),
    ([*SEQ, *SCENES[6], "--restitution", "1/2"], 0, set()),
    ([*SEQ, *SCENES[2], "--json"], 0, set()),
    ([*SEQ, *SCENES[8], "--json"], 0, set()),
    (["resolve", "--law", "hertz", *SCENES[1], "--json"], 0, {"scipy"}),
    (["resolve", "--law", "lzb", *SCENES[3], "--restitution", "0.9", "--json"], 0, {"scipy"}),
    (["resolve", "--law", "power", "--exponent", "5/2", *SCENES[5], "--json"], 0, {"scipy"}),
    (["resolve", "--law", "hunt-crossley", "--restitution", "0.8", *SCENES[7]], 0, {"scipy"}),
]
SCENE_PROBE_CAN_FAIL = [
    [*SEQ, "--scene", "pool", "--theta", "pi/3", "--json"],
    ["resolve", "--law", "hertz", "--scene", "chain3", "--masses", "sqrt(2),1,1"],
]
_BATCH_LINES = [{"argv": [*SEQ, "--scene", "cradle", "--n-balls", "4"]},
                {"command": "resolve", "args": {"law": "hertz", "scene": "two-balls-wall", "masses": "11/10,1"}}]


_BATCH_DIR = session_dir()
(_BATCH_DIR / "scene-requests.jsonl").write_text("\n".join(json.dumps(x) for x in _BATCH_LINES) + "\n")
_BATCH = ["batch", "--input", str(_BATCH_DIR / "scene-requests.jsonl"), "--output",
          str(_BATCH_DIR / "scene-answers.jsonl")]
#: the probes of this module in forks of one fresh interpreter (:class:`probe_server.RequestProbes`;
#: the trunk shared with tests/test_cli_float_path.py's when both modules are collected):
#: :data:`_CASES` then a batch of scene requests (SciPy, no SymPy); after the trunk, each request
#: that must load SymPy in a branch of its own
_PROBES = RequestProbes(_CASES + [(_BATCH, 0, {"scipy"})],
                        [[(argv, 0, {"scipy", "sympy", "mpmath"})] for argv in SCENE_PROBE_CAN_FAIL],
                        group="float-path")


@pytest.mark.parametrize("argv,status,loaded", _CASES)
def test_a_float_path_request_on_a_builtin_scene_imports_no_sympy(argv, status, loaded):
    assert _PROBES.loaded(argv, status) == loaded


@pytest.mark.parametrize("argv", SCENE_PROBE_CAN_FAIL)
def test_the_scene_probe_can_fail(argv):
    """The pool's data are irrational (cos, sin of its angles); sqrt(2) is not plain text. Each
    runs in a branch of its own after the trunk (whose float requests load no SymPy)."""
    assert "sympy" not in _PROBES.before(argv) and "sympy" in _PROBES.loaded(argv)


def _run(argv):
    """``main(argv)`` in this process: (exit status, stdout, stderr). Not imported from
    tests/test_cli_float_path.py, whose import would add its probes to this module's group (run
    alone, this module would then pay for them)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


LAWS = {
    "sequential": ["--law", "sequential", "--float"],
    "cone": ["--law", "sequential", "--float", "--reading", "cone"],
    "hertz": ["--law", "hertz"],
    "linear": ["--law", "linear", "--stiffness", "2"],
    "power": ["--law", "power", "--exponent", "5/2"],
    "hunt-crossley": ["--law", "hunt-crossley", "--restitution", "0.8"],
    "lzb": ["--law", "lzb", "--restitution", "0.9"],
    "refused": ["--law", "hertz", "--restitution", "1/2"],
}
REFUSED_SCENE = ["--scene", "cradle", "--n-balls", "3", "--masses", "1,0,1"]
#: every scene with the sequential law's --float path, and each float law on one or two scenes (the
#: integrators cost a second on four balls; tests/test_cli_float_path.py covers the laws' options)
PAIRS = [(law, scene) for scene in SCENES + [REFUSED_SCENE] for law in ["sequential"]] + [
    ("hertz", SCENES[0]), ("refused", SCENES[0]), ("cone", SCENES[1]), ("hunt-crossley", SCENES[1]),
    ("lzb", SCENES[2]), ("linear", SCENES[3]), ("power", SCENES[4]), ("hunt-crossley", SCENES[5]),
    ("hertz", SCENES[6]), ("linear", SCENES[7]), ("hertz", REFUSED_SCENE), ("cone", SCENES[8]), ("lzb", SCENES[9]),
    ("sequential", ["--scene", "pool", "--theta", "pi/2", "--tau", "pi/2"]),
    ("sequential", ["--scene", "pool", "--theta", "pi/2", "--tau", "pi/3"]),  # irrational: the general reader
    ("sequential", ["--scene", "pool", "--theta", "pi"])]  # refused


@pytest.mark.parametrize("law,scene", PAIRS)
def test_the_rational_scene_answers_as_the_sympy_scene(law, scene, monkeypatch):
    """Byte for byte (stdout, stderr, exit status), with the rational build and with SymPy's."""
    argv = ["resolve", *LAWS[law], *scene, "--json"]
    fast = _run(argv)
    monkeypatch.setattr(scene_args, "read_rational_system", lambda args: None)
    assert _run(argv) == fast


def test_text_output_of_a_rational_scene_is_the_sympy_scenes(monkeypatch):
    argvs = [[*SEQ, *SCENES[4]], ["resolve", "--law", "lzb", *SCENES[2]]]
    fast = [_run(a) for a in argvs]
    monkeypatch.setattr(scene_args, "read_rational_system", lambda args: None)
    assert [_run(a) for a in argvs] == fast


PARAMS = [
    ("chain3", {}), ("chain3", {"masses": "1,2,4", "velocities": "1,0,-1/2"}),
    ("two-balls-wall", {}), ("two-balls-wall", {"masses": "1.1,1", "velocities": "-1,-3"}),
    ("three-ball-cradle", {}), ("three-ball-cradle", {"masses": "1,1/2,2", "velocities": "1,0,-1"}),
    ("cradle", {}), ("cradle", {"n_balls": "6", "strikers": "3", "masses": "1,2,3,4,5,1/6"}),
    ("balls-against-wall", {}), ("balls-against-wall", {"n_balls": "4", "velocities": "0,1,0,-1"}),
    ("pool", {"theta": "0"}), ("pool", {"theta": "pi/2"}), ("pool", {"theta": "0.0", "tau": "pi/2"}),
    ("pool", {"theta": "2*pi/4", "tau": "-3*pi/2"}), ("pool", {"theta": "+pi/2", "tau": "0*pi"}),
]


@pytest.mark.parametrize("name,params", PARAMS)
def test_the_rational_build_is_the_sympy_build(name, params):
    """Same entries (Fraction against SymPy Rational, exactly), contacts, coordinates, approach
    decisions and scene description as :func:`build_scene`."""
    fast, general = build_rational_scene(name, params), build_scene(name, params)
    assert fast is not None and fast.exact
    for a, b in ((fast.M, general.M), (fast.H, general.H), (fast.v, general.v)):
        assert a.shape == b.shape
        assert [Fraction(int(x.p), int(x.q)) for x in b] == list(a)
    assert (fast.contacts, fast.coordinates, fast.approaching) == (general.contacts, general.coordinates,
                                                                    general.approaching)
    assert fast.meta["scene_json"] == general.meta["scene_json"]
    assert [Fraction(int(x.p), int(x.q)) for x in general.relative_velocity()] == list(fast.relative_velocity())


def test_the_rational_build_declines_what_it_cannot_read():
    assert set(RATIONAL_SCENES) == {"chain3", "pool", "two-balls-wall", "three-ball-cradle", "cradle",
                                     "balls-against-wall"}
    for name, params in [("pool", {"theta": "pi/3"}), ("pool", {"theta": "pi/4"}), ("pool", {"theta": "2*pi/3"}),
                         ("pool", {"theta": "pi/2", "tau": "pi/4"}), ("pool", {"theta": "1/2"}),
                         ("pool", {"theta": "pi"}), ("pool", {"theta": "pi/0"}), ("pool", {}), ("bernoulli", {}), ("chain3", {"masses": "sqrt(2),1,1"}),
                         ("chain3", {"masses": "1,2"}), ("chain3", {"masses": "1,-1,1"}),
                         ("cradle", {"n_balls": "2*3"}), ("cradle", {"n_balls": "3", "strikers": "3"}),
                         ("cradle", {"n_balls": "10001"}), ("cradle", {"theta": "1"}),
                         ("balls-against-wall", {"n_balls": "3", "velocities": "1,2"}),
                         ("newton-cradle-5-strikers-1", {})]:
        assert build_rational_scene(name, params) is None, (name, params)


def test_a_batch_of_scene_requests_imports_no_sympy():
    assert _PROBES.loaded(_BATCH) == {"scipy"}
    answers = [json.loads(x) for x in (_BATCH_DIR / "scene-answers.jsonl").read_text().splitlines()]
    assert [a["exit_status"] for a in answers] == [0, 0]
    assert answers[1]["result"]["scene"] == {"scene": "two-balls-wall", "masses": ["11/10", "1"]}
