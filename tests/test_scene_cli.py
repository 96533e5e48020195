"""``impactsym scene show|list``: the JSON contract, the round trip (``show --json`` written to a file
loads back to the same M, H, v exactly) for every built-in and shipped scene, and exit status 2
naming the argument for bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

from impactsym.cli import main
from impactsym.scenes import BUILTIN_SCENES, SHIPPED_SCENES, build_scene, load_scene

#: every built-in with its defaults (pool needs theta), and a few parameter sets
BUILTIN_CASES = [
    ("chain3", []), ("chain3", ["--masses", "1,2,4", "--velocities", "1,0,-1/2"]),
    ("pool", ["--theta", "pi/4"]), ("pool", ["--theta", "2*pi/3", "--tau", "-pi/6"]),
    ("pool", ["--theta", "1/2", "--tau", "1/10"]),
    ("bernoulli", []), ("bernoulli", ["--tau", "-pi/12"]),
    ("two-balls-wall", []), ("two-balls-wall", ["--masses", "11/10,1"]),
    ("three-ball-cradle", []), ("three-ball-cradle", ["--velocities", "1,0,-1"]),
    ("cradle", []), ("cradle", ["--n-balls", "5", "--strikers", "2"]),
    ("cradle", ["--n-balls", "4", "--masses", "1,2,3,4"]),
    ("balls-against-wall", []), ("balls-against-wall", ["--n-balls", "3", "--velocities", "0,0,-2"]),
]


def _params(argv):
    return {argv[i].lstrip("-").replace("-", "_"): argv[i + 1] for i in range(0, len(argv), 2)}


def _show(capsys, *argv):
    code = main(["scene", "show", *argv, "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert out.count("\n") == 1  # exactly one JSON object
    return json.loads(out)


def _equal(a, b):
    if a.exact:
        assert b.exact
        assert a.M == b.M and a.H == b.H and a.v == b.v  # exact SymPy equality, entry by entry
    else:
        assert not b.exact
        assert np.array_equal(a.M, b.M) and np.array_equal(a.H, b.H) and np.array_equal(a.v, b.v)
    assert a.contacts == b.contacts and a.coordinates == b.coordinates
    assert a.restitution == b.restitution


def test_every_builtin_is_covered():
    assert {name for name, _ in BUILTIN_CASES} == set(BUILTIN_SCENES)


@pytest.mark.parametrize("name, argv", BUILTIN_CASES)
def test_builtin_round_trip(capsys, tmp_path, name, argv):
    d = _show(capsys, name, *argv)
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(d))
    back = load_scene(str(path))
    _equal(back, build_scene(name, _params(argv)))
    assert d["reduced"]["scene"]["scene"] == name
    again = _show(capsys, str(path))  # the second generation is the same file
    for key in ("mass_matrix", "gradients", "velocity", "contacts", "coordinates"):
        assert again[key] == d[key]


@pytest.mark.parametrize("name", sorted(SHIPPED_SCENES))
def test_shipped_round_trip(capsys, tmp_path, name):
    d = _show(capsys, name)
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(d))
    _equal(load_scene(path), load_scene(name))
    # a shipped file is named by its place in the package (the same on every machine)
    assert d["reduced"]["scene"] == {"scene": name, "file": "impactsym/scenes/files/" + SHIPPED_SCENES[name].name}
    assert d["description"] == load_scene(name).meta["description"]


def test_json_contract_exact_strings_and_float_twins(capsys):
    d = _show(capsys, "seghete-murphey-two-balls-wall")
    assert d["mass_matrix"] == [["11/10", "0"], ["0", "1"]] and d["mass_matrix_float"] == [[1.1, 0.0], [0.0, 1.0]]
    assert d["gradients"] == [["1", "0"], ["-1", "1"]] and d["gradients_float"] == [[1.0, 0.0], [-1.0, 1.0]]
    assert d["velocity"] == ["-1", "-2"] and d["velocity_float"] == [-1.0, -2.0]
    assert d["restitution"] == ["1", "1"] and d["restitution_float"] == [1.0, 1.0]
    red = d["reduced"]
    assert red["relative_velocity"] == ["-1", "-1"] and red["approaching_contacts"] == ["wall@0-1", "1-2"]
    # cos = H_1 M^-1 H_2^T / sqrt(...) = (-10/11) / sqrt(10/11 * 21/11) = -sqrt(210)/21
    (angle,) = red["kinetic_angles"]
    assert sp.simplify(sp.sympify(angle["cos"]) + sp.sqrt(210) / 21) == 0 and angle["coupled"] is True
    assert d["bodies"][0] == {"mass": "11/10", "radius": "1", "position": "1", "velocity": "-1"}
    assert d["walls"] == [{"point": "0", "normal": "1"}]


def test_kinetic_angles_of_the_papers(capsys):
    chain = _show(capsys, "chain3")["reduced"]["kinetic_angles"]
    assert [(a["cos"], a["angle"]) for a in chain] == [("-1/2", "2*pi/3")]
    pool = _show(capsys, "pool", "--theta", "pi/4")["reduced"]
    assert pool["kinetic_angles"][0]["cos"] == "-sqrt(2)/4"  # Acary & Taha eq. 42: -cos(theta)/2
    assert pool["contact_states"] == ["approaching", "grazing"]
    right = _show(capsys, "pool", "--theta", "pi/2")["reduced"]
    assert right["kinetic_angles"] == [] and right["orthogonal_pairs"] == 1


def test_float_scene_stays_float(capsys, tmp_path):
    d = _show(capsys, "chain3-float")
    assert d["reduced"]["exact"] is False and d["mass_matrix"] == [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    assert d["gap_tolerance"] == 1e-12 and d["bodies"][1]["position"] == 0.2


def test_text_output(capsys):
    assert main(["scene", "show", "cradle", "--n-balls", "5", "--strikers", "2"]) == 0
    out = capsys.readouterr().out
    assert "2-3: w = -1 (approaching)" in out and "1-2: w = 0 (grazing)" in out
    assert "1-2 / 2-3: cos = -1/2, theta = 2*pi/3" in out and "3 other pair(s) orthogonal" in out
    assert main(["scene", "show", "chain-mass-ratio-1-2-4"]) == 0
    assert "2-3: w = 0 (grazing), e = 1/2" in capsys.readouterr().out


def test_list(capsys):
    assert main(["scene", "list", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [s["name"] for s in d["builtin"]] == list(BUILTIN_SCENES)
    assert [s["name"] for s in d["shipped"]] == list(SHIPPED_SCENES)
    assert all(s["description"] and s["source"] for s in d["shipped"])
    assert main(["scene", "list"]) == 0
    assert "billiard-break-rack-3" in capsys.readouterr().out


def _bad_file(tmp_path, body, suffix=".json"):
    p = tmp_path / f"bad{suffix}"
    p.write_text(body if isinstance(body, str) else json.dumps(body))
    return str(p)


BAD = [
    (lambda t: ["no-such-scene"], "scene", "unknown scene"),
    (lambda t: ["pool"], "theta", "is required"),
    (lambda t: ["cradle", "--theta", "1"], "theta", "does not apply to --scene cradle"),
    (lambda t: ["cradle", "--n-balls", "-3"], "n_balls", "must be >= 1"),
    (lambda t: ["chain3", "--masses", "1,-1,1"], "masses", "must be positive"),
    (lambda t: ["newton-cradle-5-strikers-1", "--strikers", "2"], "strikers", "takes no parameters"),
    (lambda t: [_bad_file(t, {"bodies": [{"mass": 1, "radius": 1, "position": 0}]})], "bodies[0].velocity", "missing"),
    (lambda t: [_bad_file(t, {"bodies": [{"mass": 1, "radius": 1, "position": 0, "velocity": 1},
                                         {"mass": -1, "radius": 1, "position": 2, "velocity": 0}]})],
     "bodies[1].mass", "must be positive"),
    (lambda t: [_bad_file(t, {"bodies": [{"mass": 1, "radius": 1, "position": 0, "velocity": 1},
                                         {"mass": 1, "radius": 1, "position": 1, "velocity": 0}]})],
     "bodies[1].position", "overlap"),
    (lambda t: [_bad_file(t, '{"bodies": [{"mass": NaN, "radius": 1, "position": 0, "velocity": 1}]}')],
     "bodies[0].mass", "finite"),
    (lambda t: [_bad_file(t, {"bodies": [{"mass": "heavy", "radius": 1, "position": 0, "velocity": 1}]})],
     "bodies[0].mass", "cannot read"),
    (lambda t: [_bad_file(t, {"bodies": [{"mass": 1, "radius": 1, "position": [0], "velocity": 1}]})],
     "bodies[0].position", "must be a pair"),
    (lambda t: [_bad_file(t, {"mass_matrix": [[1]], "gradients": [[1]], "velocity": [1], "restitution": 2})],
     "restitution", "must lie in [0, 1]"),
    (lambda t: [_bad_file(t, "x = 1", ".txt")], "scene", "must end with .toml or .json"),
    (lambda t: [str(t / "missing.toml")], "scene", "no such scene file"),
    (lambda t: [_bad_file(t, {"bodies": [{"mass": 1, "radius": 1, "position": 0, "velocity": 1}],
                              "kind": "x"})], "kind", "unknown key"),
]


@pytest.mark.parametrize("argv, argument, message", BAD)
def test_bad_input_exits_2_naming_the_argument(capsys, tmp_path, argv, argument, message):
    args = argv(tmp_path)
    code = main(["scene", "show", *args, "--json"])
    out, err = capsys.readouterr()
    assert code == 2
    d = json.loads(out)
    assert set(d) == {"error"} and d["error"]["argument"] == argument and message in d["error"]["message"]
    assert "Traceback" not in err and message in err
    code = main(["scene", "show", *args])  # text mode: stderr only
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and message in err and "Traceback" not in err


def test_usage_errors_exit_2(capsys):
    assert main(["scene"]) == 2
    assert main(["scene", "show", "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["error"]["argument"] is not None
    assert main(["scene", "draw", "chain3"]) == 2
