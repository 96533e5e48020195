"""``impactsym resolve --law sequential``: JSON contract, scenes, and exit status 2 for bad input."""

from __future__ import annotations

import json

import pytest

from impactsym.cli import main
from probe_server import run_python


def _run(capsys, *argv):
    code = main(["resolve", "--law", "sequential", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def _json(capsys, *argv):
    code, out, err = _run(capsys, *argv, "--json")
    assert code == 0, err
    return json.loads(out)


def test_matrices_json_contract(capsys):
    d = _json(capsys, "--mass-matrix", "11/10,0;0,1", "--gradients", "1,0;-1,1", "--velocity", "-1,-2")
    assert d["law"] == "sequential" and d["exact"] is True and d["details"]["reading"] == "energy" and d["uniqueness"] == "gap-dependent"
    assert [o["order"] for o in d["outcomes"]] == [[0, 1, 0, 1], [1, 0, 1, 0]]
    assert d["outcomes"][0]["velocity"] == ["173/147", "278/147"]
    assert d["outcomes"][0]["velocity_float"] == [173 / 147, 278 / 147]
    assert d["details"]["two_surface_bound"] == 4
    assert [s["velocity"] for s in d["selected"]] == [["173/147", "278/147"], ["359/441", "922/441"]]
    assert set(d["details"]["counts"]) == {"orderings", "states_visited", "sign_tests", "exact_fallbacks", "max_reflections_used"}


def test_cone_reading_selects_zero(capsys):
    d = _json(capsys, "--scene", "two-balls-wall", "--masses", "11/10,1", "--reading", "cone")
    assert [s["velocity"] for s in d["selected"]] == [["0", "0"]]


def test_scene_cradle_with_strikers(capsys):
    d = _json(capsys, "--scene", "cradle", "--n-balls", "5", "--strikers", "2")
    assert [o["velocity"] for o in d["outcomes"]] == [["0", "0", "0", "1", "1"]]
    assert d["details"]["counts"]["orderings"] == 5 and d["details"]["counts"]["states_visited"] == 10
    assert d["scene"] == {"scene": "cradle", "n_balls": 5, "strikers": 2} and d["uniqueness"] == "unique"


def test_float_mode_reports_exact_fallbacks(capsys):
    d = _json(capsys, "--scene", "three-ball-cradle", "--float", "--two-surface-path", "iterate")
    assert d["exact"] is False and d["details"]["counts"]["exact_fallbacks"] >= 1
    assert d["outcomes"][0]["velocity_float"] == [0.0, 0.0, 1.0]


def test_text_output(capsys):
    code, out, _ = _run(capsys, "--scene", "three-ball-cradle", "--velocities", "1,1,0")
    assert code == 0 and "v+ = [0, 1, 1]" in out and "N = ceil" in out


@pytest.mark.parametrize("argv, message", [
    (["--mass-matrix", "1", "--gradients", "1;-1", "--velocity", "1"], "no non-zero velocity"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0;-1,0;0,1", "--velocity", "1,-1", "--max-reflections", "50"],
     "max_reflections"),
    (["--scene", "two-balls-wall", "--reading", "sphere"], "reading"),
    (["--scene", "two-balls-wall", "--max-reflections", "0"], "max_reflections"),
    (["--scene", "two-balls-wall", "--max-reflections", "x"], "max_reflections"),
    (["--scene", "two-balls-wall", "--n-balls", "3"], "does not apply"),
    (["--scene", "cradle", "--strikers", "5"], "strikers"),
    (["--scene", "cradle", "--n-balls", "4", "--strikers", "4"], "strikers"),
    (["--scene", "cradle", "--velocities", "1,0,0"], "does not apply"),
    (["--scene", "nowhere"], "unknown scene"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0"], "velocity"),
    (["--mass-matrix", "1,2;2,1", "--gradients", "1,0", "--velocity", "-1,0"], "positive definite"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0,0", "--velocity", "-1,0"], "gradients"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "1,0", "--velocity", "-1,0", "--n-balls", "3"], "n_balls"),
    (["--scene", "two-balls-wall", "--masses", "1,0"], "masses"),
    (["--scene", "two-balls-wall", "--restitution", "3/2"], "restitution"),
    (["--scene", "two-balls-wall", "--restitution", "1/2", "--reading", "energy"], "energy reading"),
    (["--scene", "two-balls-wall", "--two-surface-path", "x"], "two_surface_path"),
])
def test_bad_input_exits_2_with_a_message(capsys, argv, message):
    code, out, err = _run(capsys, *argv)
    assert code == 2 and out == "" and message in err and "Traceback" not in err


def test_subprocess_exit_status():
    proc = run_python(["-m", "impactsym", "resolve", "--law", "sequential", "--scene", "cradle", "--n-balls", "1"])
    assert proc.returncode == 2 and "n_balls" in proc.stderr and "Traceback" not in proc.stderr
