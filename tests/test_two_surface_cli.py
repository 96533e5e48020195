"""``impactsym resolve --law two-surface``: the CLI contract (one JSON object, exit 2 with the
violated condition and no traceback)."""

import json

import pytest

from impactsym.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_json_paper_example(capsys):
    code, out, err = run(capsys, "resolve", "--law", "two-surface", "--mass-matrix", "11/10,0;0,1",
                         "--gradients", "1,0;-1,1", "--velocity", "-1,-2", "--json")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert data["law"] == "two-surface" and data["details"]["bound"] == 4
    assert [o["order"] for o in data["outcomes"]] == [[0, 1, 0, 1], [1, 0, 1, 0]]
    assert data["outcomes"][0]["velocity"] == ["173/147", "278/147"]
    assert data["outcomes"][0]["velocity_float"] == [173 / 147, 278 / 147]
    assert data["details"]["kinetic_angle_cos"] == "-sqrt(210)/21"


def test_json_billion_reflections(capsys):
    code, out, _ = run(capsys, "resolve", "--law", "two-surface", "--mass-matrix", "1,0;0,1",
                       "--gradients", "1,0;-1000000000,1", "--velocity", "-1,0", "--json")
    assert code == 0
    o = json.loads(out)["outcomes"][0]
    assert o["order"] == {"first": 0, "length": o["details"]["reflections"], "alternating": True}
    assert o["details"]["reflections"] > 10**9 and o["exactness"] == "certified" and o["digits"] == 30


def test_text_output_and_scene(capsys):
    code, out, _ = run(capsys, "resolve", "--law", "two-surface", "--scene", "chain3",
                       "--masses", "1,1,1", "--velocities", "1,0,0")
    assert code == 0 and "bound N = ceil(pi/beta) = 3" in out and "v+ = [0, 0, 1]" in out


@pytest.mark.parametrize("argv, words", [
    (["--gradients", "1,0;2,0", "--velocity", "-1,0"], "parallel"),
    (["--gradients", "1,0;0,1;1,1", "--velocity", "-1,0"], "exactly two contacts"),
    (["--gradients", "1,0;-1,1", "--velocity", "-1,0", "--restitution", "1/2"], "elastic"),
])
def test_bad_input_exit_2(capsys, argv, words):
    code, out, err = run(capsys, "resolve", "--law", "two-surface", "--mass-matrix", "1,0;0,1", *argv)
    assert code == 2 and out == "" and words in err and "Traceback" not in err
