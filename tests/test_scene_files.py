"""Scene files (TOML/JSON), the registry of named scenes, and per-contact restitution.

Every shipped file is loaded and checked to reduce to a valid scene; the files of the papers'
scenes are checked against the built-in builders exactly; every key of the format is exercised,
and bad input is refused naming the key at fault.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import sympy as sp

from impactsym.errors import ImpactInputError
from impactsym.numbers import float_to_rational
from impactsym.mechanics import check_gradients, check_mass_matrix, check_velocity
from impactsym.models import acary_taha, seghete_murphey
from impactsym.scenes import (BUILTIN_SCENES, FORMAT, SCENE_PARAMS, SHIPPED_SCENES, Scene, balls_in_plane,
                              build_scene, describe_scene, load_scene, read_scene_file, scene_from_dict,
                              scene_to_dict)
from impactsym.scenes.registry import SCENE_FILES_DIR


def _ball(mass=1, radius=1, position=0, velocity=0, **kw):
    return {"mass": mass, "radius": radius, "position": position, "velocity": velocity, **kw}


def _line(*specs, **top):
    return {"bodies": [_ball(*s) for s in specs], **top}


def _same(a: Scene, b: Scene):
    """Exact equality of M, H, v (structural SymPy equality, no tolerance)."""
    assert a.exact and b.exact
    assert a.M == b.M and a.H == b.H and a.v == b.v


# --------------------------------------------------------------------------- shipped files
def test_the_files_folder_is_what_is_shipped():
    on_disk = sorted(p.stem for p in SCENE_FILES_DIR.iterdir() if p.suffix in (".toml", ".json"))
    assert sorted(SHIPPED_SCENES) == on_disk and len(on_disk) >= 15
    assert not set(SHIPPED_SCENES) & set(BUILTIN_SCENES)  # a name means one scene


@pytest.mark.parametrize("name", sorted(SHIPPED_SCENES))
def test_every_shipped_file_reduces_to_a_valid_scene(name):
    raw = read_scene_file(SHIPPED_SCENES[name])
    assert raw["format"] == FORMAT and raw["description"].strip() and raw["source"].strip()
    sc = load_scene(name)
    exact = sc.exact
    M = check_mass_matrix(sc.M, exact=exact)
    H = check_gradients(sc.H, M.shape[0], exact=exact)
    check_velocity(sc.v, M.shape[0], exact=exact)
    assert len(sc.contacts) == H.shape[0] == len(set(sc.contacts)) and len(sc.coordinates) == M.shape[0]
    # approaching is H v < 0, recomputed here exactly (float files at their binary values)
    Hq = sp.Matrix(H) if exact else sp.Matrix(H.tolist()).applyfunc(lambda x: float_to_rational(float(x)))
    vq = sp.Matrix(sc.v) if exact else sp.Matrix(np.asarray(sc.v).tolist()).applyfunc(lambda x: float_to_rational(float(x)))
    w = Hq * vq
    assert sc.approaching == [bool(sp.simplify(x) < 0) for x in w]
    assert any(sc.approaching), "a shipped scene is an impact: some contact approaches"
    d = describe_scene(sc)
    assert d["approaching"] == sc.approaching and d["k"] == len(sc.contacts)
    assert len(d["kinetic_angles"]) + d["orthogonal_pairs"] == len(sc.contacts) * (len(sc.contacts) - 1) // 2
    if sc.restitution is not None:
        assert len(sc.restitution) == len(sc.contacts)


@pytest.mark.parametrize("name, builtin", [
    ("acary-taha-chain3", lambda: acary_taha.chain3()),
    ("acary-taha-pool-theta-pi-4", lambda: acary_taha.pool(sp.pi / 4)),
    ("acary-taha-pool-theta-pi-3", lambda: acary_taha.pool(sp.pi / 3)),
    ("acary-taha-pool-theta-pi-2", lambda: acary_taha.pool(sp.pi / 2)),
    ("acary-taha-bernoulli", lambda: acary_taha.bernoulli()),
    ("seghete-murphey-two-balls-wall", lambda: seghete_murphey.two_balls_wall(masses=("11/10", 1))),
    ("seghete-murphey-three-ball-cradle", lambda: seghete_murphey.three_ball_cradle()),
    ("newton-cradle-5-strikers-1", lambda: seghete_murphey.cradle(5, 1)),
    ("newton-cradle-5-strikers-2", lambda: seghete_murphey.cradle(5, 2)),
])
def test_paper_files_reduce_exactly_to_the_builders(name, builtin):
    """The files describe bodies; the builders derive H from constraint functions: same M, H, v."""
    sc, ref = load_scene(name), builtin()
    _same(sc, ref)
    assert sc.contacts == ref.contacts


def test_file_contents_that_the_format_promises():
    corner = load_scene("ball-in-corner")  # normal (3, 4) normalized exactly
    assert corner.H == sp.Matrix([[0, 1], [sp.Rational(3, 5), sp.Rational(4, 5)]])
    assert corner.contacts == ["wall1-1", "wall2-1"] and corner.approaching == [True, True]
    rack = load_scene("billiard-break-3-4-5")  # every normal rational
    assert all(x.is_Rational for x in rack.H) and rack.contacts == ["1-2", "2-3", "2-4"]
    assert rack.H[1, 2:6] == sp.Matrix([[-sp.Rational(3, 5), -sp.Rational(4, 5), sp.Rational(3, 5), sp.Rational(4, 5)]])
    rack6 = load_scene("billiard-break-rack-6")
    assert len(rack6.contacts) == 10 and rack6.M == sp.eye(14)
    for i in range(rack6.k):  # each row of a ball-ball contact is a pair of opposite unit normals
        row = list(rack6.H.row(i))
        assert sp.simplify(sum(x ** 2 for x in row) - 2) == 0
    assert load_scene("chain-mass-ratio-1-2-4").restitution == [sp.Rational(9, 10), sp.Rational(1, 2)]
    assert load_scene("chain-mass-ratio-1-1e-3-1").M[1, 1] == sp.Rational(1, 1000)  # "1e-3" is exact
    between = load_scene("ball-between-walls")
    assert between.H == sp.Matrix([[1]]) and between.approaching == [True]  # the open right wall is not modelled
    fl = load_scene("chain3-float")  # float literals: the float path
    assert not fl.exact and isinstance(fl.M, np.ndarray)
    assert np.array_equal(fl.H, np.array([[-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])) and fl.contacts == ["1-2", "2-3"]


# --------------------------------------------------------------------------- the registry
@pytest.mark.parametrize("name", sorted(BUILTIN_SCENES))
def test_every_builtin_builds_with_its_defaults_and_roundtrips_through_a_dict(name):
    params = {"theta": "pi/4"} if name == "pool" else {}
    sc = build_scene(name, params)
    assert sc.meta["scene_json"]["scene"] == name
    back = scene_from_dict(json.loads(json.dumps(scene_to_dict(sc))))
    _same(back, sc)
    assert back.contacts == sc.contacts


def test_registry_parameters_are_the_cli_ones():
    assert SCENE_PARAMS == {
        "chain3": ("masses", "velocities"), "pool": ("theta", "tau"), "bernoulli": ("tau",),
        "two-balls-wall": ("masses", "velocities"), "three-ball-cradle": ("masses", "velocities"),
        "cradle": ("n_balls", "strikers", "masses"), "balls-against-wall": ("n_balls", "masses", "velocities")}
    sc = build_scene("chain3", {"masses": "1,2,4", "velocities": "1,0,-1/2", "theta": None})
    assert sc.M == sp.diag(1, 2, 4) and sc.v == sp.Matrix([1, 0, sp.Rational(-1, 2)])
    assert sc.meta["scene_json"] == {"scene": "chain3", "masses": ["1", "2", "4"], "velocities": ["1", "0", "-1/2"]}
    assert build_scene("pool", {"theta": "pi/3", "tau": "1/10"}).v == acary_taha.pool(sp.pi / 3, sp.Rational(1, 10)).v
    _same(build_scene("balls-against-wall", {"n_balls": "4", "velocities": "0,0,0,-2"}),
          seghete_murphey.balls_against_wall(4, velocities=[0, 0, 0, -2]))
    _same(build_scene("cradle", {"n_balls": "10**1", "strikers": "3"}), seghete_murphey.cradle(10, 3))


@pytest.mark.parametrize("name, params, argument, message", [
    ("nope", {}, "scene", "unknown scene 'nope'; known: chain3, pool"),
    ("pool", {}, "theta", "is required with --scene pool"),
    ("pool", {"theta": "pi"}, "theta", "must lie in [0, 2*pi/3]"),
    ("pool", {"masses": "1,1,1", "theta": "0"}, "masses", "--masses does not apply to --scene pool (it takes: --theta, --tau)"),
    ("chain3", {"masses": "1,1"}, "masses", "chain3 needs three masses, got 2"),
    ("chain3", {"masses": "1,0,1"}, "masses", "must be positive, got 0"),
    ("chain3", {"velocities": "1,nan,0"}, "velocities", "must be a finite real number"),
    ("cradle", {"n_balls": "2.5"}, "n_balls", "must be an integer"),
    ("cradle", {"n_balls": "10001"}, "n_balls", "must be at most 10000"),
    ("cradle", {"n_balls": "3", "strikers": "3"}, "strikers", "must be smaller than n_balls=3"),
    ("cradle", {"velocities": "1,0"}, "velocities", "--velocities does not apply to --scene cradle (it takes: "
                                                    "--n-balls, --strikers, --masses)"),
    ("two-balls-wall", {"masses": "1,1,1"}, "masses/velocities", "two_balls_wall needs exactly two of each"),
    ("chain3", {"color": "red"}, "color", "unknown scene parameter 'color'"),
    ("acary-taha-chain3", {"masses": "1,1,1"}, "masses", "a shipped scene file takes no parameters"),
])
def test_registry_refusals_name_the_parameter(name, params, argument, message):
    with pytest.raises(ImpactInputError) as info:
        build_scene(name, params)
    assert info.value.argument == argument
    assert message in str(info.value)


# --------------------------------------------------------------------------- the format
def test_line_and_wall_reduce_as_the_builders_do():
    d = {"bodies": [_ball(2, 1, 1, -1), _ball(1, 1, 3, -2), _ball(1, 1, 9, 0)],
         "walls": [{"point": 0, "normal": 1}], "contacts": ["wall@0-1", "1-2"]}
    sc = scene_from_dict(d)
    assert sc.contacts == ["wall@0-1", "1-2"] and sc.H == sp.Matrix([[1, 0], [-1, 1]]) and sc.M == sp.diag(2, 1)
    assert sc.meta["uninvolved"] == [3] and sc.restitution is None


def test_plane_walls_normalize_exactly():
    sc = balls_in_plane([1], [1], [(0, 1)], [(0, -1)], walls=[((5, 0), (0, 2))])
    assert sc.H == sp.Matrix([[0, 1]])
    with pytest.raises(ImpactInputError, match="no contact is closed"):  # gap sqrt(2) - 1 > 0
        balls_in_plane([1], [1], [(1, 1)], [(-1, -1)], walls=[((0, 0), (1, 1))])
    s2 = sp.sqrt(2)
    sc = scene_from_dict({"bodies": [_ball(1, 1, ["sqrt(2)/2", "sqrt(2)/2"], [-1, 0])],
                          "walls": [{"point": [0, 0], "normal": [1, 1]}]})
    assert sc.H == sp.Matrix([[s2 / 2, s2 / 2]]) and sc.approaching == [True]


@pytest.mark.parametrize("value, expected", [
    ("1/2", ["1/2", "1/2"]),
    ([1, "0.5"], ["1", "1/2"]),
    ({"default": "9/10", "2-3": 0}, ["9/10", "0"]),
    ({"1-2": "1/3", "2-3": "2/3"}, ["1/3", "2/3"]),
])
def test_restitution_forms(value, expected):
    sc = scene_from_dict(_line((1, 1, 0, 1), (1, 1, 2, 0), (1, 1, 4, 0), restitution=value))
    assert sc.restitution == [sp.Rational(x) for x in expected]
    assert scene_to_dict(sc)["restitution"] == expected


def test_restitution_on_the_scene_itself():
    sc = build_scene("chain3")
    assert Scene(sc.M, sc.H, sc.v, contacts=sc.contacts, restitution=[1, 0.5]).restitution == [1, 0.5]
    with pytest.raises(ImpactInputError, match=r"restitution: entry 2 \(contact 2-3\) must lie in \[0, 1\], got -1/10"):
        Scene(sc.M, sc.H, sc.v, contacts=sc.contacts, restitution=[1, "-0.1"])
    with pytest.raises(ImpactInputError, match="must be a finite real number"):
        Scene(sc.M, sc.H, sc.v, contacts=sc.contacts, restitution=[1, float("nan")])
    with pytest.raises(ImpactInputError, match="has 1 entries, expected 2"):
        Scene(sc.M, sc.H, sc.v, contacts=sc.contacts, restitution=[1])


def test_explicit_form_and_cli_text_form():
    sc = scene_from_dict({"mass_matrix": "2,1;1,2", "gradients": [["-1", 1]], "velocity": "1,0",
                          "contacts": ["a"], "coordinates": ["p", "q"]})
    assert sc.M == sp.Matrix([[2, 1], [1, 2]]) and sc.contacts == ["a"] and sc.coordinates == ["p", "q"]
    assert sc.approaching == [True]
    fl = scene_from_dict({"mass_matrix": [[1.5]], "gradients": [[1]], "velocity": [-1]})
    assert not fl.exact and fl.M.dtype == float and fl.approaching == [True]


def test_both_forms_must_agree():
    d = scene_to_dict(build_scene("two-balls-wall"))
    assert "bodies" in d and "walls" in d
    _same(scene_from_dict(d), build_scene("two-balls-wall"))
    bad = json.loads(json.dumps(d))
    bad["velocity"][1] = "-3"
    with pytest.raises(ImpactInputError, match="velocity: entry 1 is -3 but the bodies reduce to -2"):
        scene_from_dict(bad)


def test_float_input_closes_contacts_within_the_stated_tolerance():
    d = _line((1.0, 0.1, 0.0, 1.0), (1.0, 0.1, 0.2 + 1e-10, 0.0))
    assert scene_from_dict(d).contacts == ["1-2"]  # default: 1e-9 times the length scale 1
    with pytest.raises(ImpactInputError, match="no contact is closed") as info:
        scene_from_dict({**d, "gap_tolerance": 1e-12})
    assert info.value.argument == "bodies"
    with pytest.raises(ImpactInputError, match="bodies\\[1\\].position: balls 1 and 2 overlap"):
        scene_from_dict(_line((1.0, 0.1, 0.0, 1.0), (1.0, 0.1, 0.2 - 1e-6, 0.0)))


def test_json_and_toml_files(tmp_path):
    toml = tmp_path / "s.toml"
    toml.write_text('format = "impactsym-scene/1"\nrestitution = {default = "1/2", "1-2" = 1}\n'
                    '[[bodies]]\nmass = "11/10"\nradius = 1\nposition = 1\nvelocity = -1\n'
                    '[[bodies]]\nmass = 1\nradius = 1\nposition = 3\nvelocity = -2\n'
                    '[[walls]]\npoint = 0\nnormal = 1\n')
    sc = load_scene(toml)
    assert sc.M == sp.diag(sp.Rational(11, 10), 1) and sc.contacts == ["1-2", "wall@0-1"]
    assert sc.restitution == [1, sp.Rational(1, 2)] and sc.meta["name"] == "s"
    js = tmp_path / "s.json"
    js.write_text(json.dumps(scene_to_dict(sc)))
    back = load_scene(str(js))
    _same(back, sc)
    assert back.restitution == sc.restitution


# --------------------------------------------------------------------------- bad input
BAD_DICTS = [
    ({}, "bodies", "is missing"),
    ({"bodies": []}, "bodies", "non-empty array"),
    ({"bodies": [{"mass": 1, "radius": 1, "position": 0}]}, "bodies[0].velocity", "is missing"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(-2, 1, 2, 0)]}, "bodies[1].mass", "must be positive (ball 2), got -2"),
    ({"bodies": [_ball(1, -1, 0, 1), _ball(1, 1, 2, 0)]}, "bodies[0].radius", "must be non-negative"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, "3/2", 0)]}, "bodies[1].position", "balls 1 and 2 overlap"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 5, 0)]}, "bodies", "no contact is closed"),
    ({"bodies": [_ball(float("nan"), 1, 0, 1)]}, "bodies[0].mass", "must be a finite real number"),
    ({"bodies": [_ball(1, 1, 0, "nan")]}, "bodies[0].velocity", "must be a finite real number"),
    ({"bodies": [_ball(True, 1, 0, 1)]}, "bodies[0].mass", "must be a number, got true"),
    ({"bodies": [_ball(1, 1, {"x": 0}, 1)]}, "bodies[0].position", "must be a number"),
    ({"bodies": [_ball(1, 1, "two", 1)]}, "bodies[0].position", "cannot read 'two' as a number"),
    ({"bodies": [_ball(1, 1, [0, 0], 1)]}, "bodies[0].velocity", "must be a pair"),
    ({"bodies": [_ball(1, 1, [0, 0, 0], [1, 0, 0])]}, "bodies[0].position", "must be a pair"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, [2, 0], [0, 0])]}, "bodies[1].position", "every ball of a scene"),
    ({"bodies": [_ball(1, 0, [0, 0], [1, 0])]}, "bodies[0].radius", "must be positive"),
    ({"bodies": [_ball(1, 1, 0, 1, colour="red")]}, "bodies[0].colour", "unknown key"),
    ({"bodies": [_ball(1, 1, 1, -1)], "walls": [{"point": 0}]}, "walls[0].normal", "is missing"),
    ({"bodies": [_ball(1, 1, 1, -1)], "walls": [{"point": 0, "normal": 0}]}, "walls[0].normal", "must be non-zero"),
    ({"bodies": [_ball(1, 1, 1, -1)], "walls": [{"point": 0, "normal": -1}]}, "bodies[0].position", "lies behind wall 1"),
    ({"bodies": [_ball(1, 1, "1/2", -1)], "walls": [{"point": 0, "normal": 1}]}, "bodies[0].position", "overlap"),
    ({"bodies": [_ball(1, 1, [0, "1/2"], [0, -1])], "walls": [{"point": [0, 0], "normal": [0, 1]}]},
     "bodies[0].position", "ball 1 and wall 1 overlap"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "gap_tolerance": 1e-9}, "gap_tolerance", "float input only"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "restitution": "3/2"}, "restitution", "must lie in [0, 1]"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "restitution": {"2-3": 1}}, "restitution.2-3",
     "is not a closed contact"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0), _ball(1, 1, 4, 0)], "restitution": {"1-2": 1}},
     "restitution", "has no value for contact '2-3' and no default"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "restitution": [1, 1]}, "restitution", "has 2 entries, expected 1"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "contacts": ["2-1"]}, "contacts", "'2-1' is not a closed contact"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "format": "impactsym-scene/9"}, "format", "this impactsym reads"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "masses": [1, 1]}, "masses", "unknown key"),
    ({"mass_matrix": [[1, 2], [2, 1]], "gradients": [[1, 0]], "velocity": [1, 0]}, "mass_matrix", "not positive definite"),
    ({"mass_matrix": [[1, 0], [0, 1]], "gradients": [[1, 0, 0]], "velocity": [1, 0]}, "gradients", "has 3 columns"),
    ({"mass_matrix": [[1, 0], [0, 1]], "gradients": [[0, 0]], "velocity": [1, 0]}, "gradients", "zero covector"),
    ({"mass_matrix": [[1, 0], [0, 1]], "gradients": [[1, 0]]}, "velocity", "is missing"),
    ({"mass_matrix": [[1, "x"], [0, 1]], "gradients": [[1, 0]], "velocity": [1, 0]}, "mass_matrix[0][1]", "cannot read"),
    ({"mass_matrix": [[1]], "gradients": [[1]], "velocity": [1], "contacts": ["a", "b"]}, "contacts", "has 2 names"),
    ({"mass_matrix": [[1]], "gradients": [[1]], "velocity": [1], "walls": []}, "walls", "applies only with bodies"),
    ({"mass_matrix": [[1]], "gradients": [[1]], "velocity": [1], "contacts": ["default"]}, "contacts", "is reserved"),
    ({"mass_matrix": [[1]], "gradients": [[1]], "velocity": [1], "coordinates": "q1"}, "coordinates", "array of texts"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "mass_matrix": [[1, 0], [0, 2]], "gradients": [[-1, 1]],
      "velocity": [1, 0]}, "mass_matrix", "entry (1, 1) is 2 but the bodies reduce to 1"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "mass_matrix": [[1.0, 0], [0, 1]], "gradients": [[-1, 1]],
      "velocity": [1, 0]}, "mass_matrix", "disagree on the number path"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "coordinates": ["a", "b"]}, "coordinates",
     "the bodies' coordinates are ['x1', 'x2']"),
    ({"bodies": [_ball(1, 1, 0, 1)], "walls": {"point": 0}}, "walls", "must be an array"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "restitution": {}}, "restitution", "empty table"),
    ({"bodies": [_ball(1, 1, 0, 1), _ball(1, 1, 2, 0)], "description": 3}, "description", "must be text"),
]


@pytest.mark.parametrize("d, argument, message", BAD_DICTS)
def test_bad_scene_dicts_name_the_key(d, argument, message):
    with pytest.raises(ImpactInputError) as info:
        scene_from_dict(d)
    assert info.value.argument == argument, str(info.value)
    assert message in str(info.value)


@pytest.mark.parametrize("text, suffix, argument, message", [
    ('{"bodies": [{"mass": NaN, "radius": 1, "position": 0, "velocity": 1}]}', ".json", "bodies[0].mass", "finite"),
    ('[[bodies]]\nmass = nan\nradius = 1\nposition = 0\nvelocity = 1\n', ".toml", "bodies[0].mass", "finite"),
    ('{"bodies": [], "bodies": []}', ".json", "bodies", "is given twice"),
    ('bodies = [', ".toml", "scene", "is not valid TOML"),
    ('{"bodies": ', ".json", "scene", "is not valid JSON"),
    ('[1, 2]', ".json", "scene", "must hold one table"),
    ('bodies = []', ".yaml", "scene", "must end with .toml or .json"),
])
def test_bad_files_name_the_key(tmp_path, text, suffix, argument, message):
    p = tmp_path / f"bad{suffix}"
    p.write_text(text)
    with pytest.raises(ImpactInputError) as info:
        load_scene(p)
    assert info.value.argument == argument and message in str(info.value)


def test_unknown_names_and_missing_files():
    with pytest.raises(ImpactInputError, match="unknown scene 'cradel': not a built-in scene") as info:
        load_scene("cradel")
    assert info.value.argument == "scene"
    with pytest.raises(ImpactInputError, match="no such scene file"):
        load_scene("/nonexistent/scene.toml")
    with pytest.raises(ImpactInputError, match="--n-balls applies only to a built-in scene") as info:
        load_scene(SHIPPED_SCENES["acary-taha-chain3"], {"n_balls": "3"})
    assert info.value.argument == "n_balls"


def test_scene_to_dict_refuses_symbols():
    with pytest.raises(ImpactInputError, match="free symbols"):
        scene_to_dict(acary_taha.pool(sp.Symbol("theta"), 0))


def test_kinetic_angles_are_exact():
    d = describe_scene(load_scene("billiard-break-rack-3"))
    cos = {tuple(a["contacts"]): sp.sympify(a["cos"]) for a in d["kinetic_angles"]}
    # unit masses, W_ii = 2; rows share one ball: W_ij = ±(normal_i · normal_j), normals (1, 0),
    # (sqrt(3)/2, ±1/2) from the apex and (0, -1) from ball 3 to ball 4
    assert cos[("1-2", "2-3")] == -sp.sqrt(3) / 4 and cos[("1-2", "2-4")] == -sp.sqrt(3) / 4
    assert cos[("2-3", "2-4")] == cos[("2-3", "3-4")] == cos[("2-4", "3-4")] == sp.Rational(1, 4)
    assert d["orthogonal_pairs"] == 1  # 1-2 and 3-4 share no ball
    for a in d["kinetic_angles"]:
        assert math.isclose(math.cos(a["angle_float"]), a["cos_float"], abs_tol=1e-15)
        assert a["coupled"] == (sp.sympify(a["cos"]) < 0)


@pytest.mark.parametrize("name", sorted(n for n in SHIPPED_SCENES if load_scene(n).exact))
def test_kinetic_angles_agree_with_mechanics(name):
    """describe_scene (from W = H M⁻¹ Hᵀ, python-flint or SymPy) against mechanics.kinetic_angle_cos
    (the conventions' formula, one pair at a time): equal exactly, and every unlisted pair is orthogonal."""
    from impactsym.mechanics import kinetic_angle_cos

    sc = load_scene(name)
    listed = {tuple(a["contacts"]): sp.sympify(a["cos"]) for a in describe_scene(sc)["kinetic_angles"]}
    for i in range(sc.k):
        for j in range(i + 1, sc.k):
            ref = kinetic_angle_cos(sc.M, sc.H.row(i), sc.H.row(j))
            got = listed.get((sc.contacts[i], sc.contacts[j]), sp.Integer(0))
            assert sp.simplify(got - ref) == 0, (sc.contacts[i], sc.contacts[j], got, ref)


def test_the_documented_example_loads(tmp_path):
    """The TOML example of the format's prose spec (the fileformat module docstring) is a valid file."""
    import textwrap

    from impactsym.scenes import fileformat

    doc = fileformat.__doc__
    block = doc.split("Example (TOML)::\n", 1)[1].split("\nExamples\n", 1)[0]
    p = tmp_path / "example.toml"
    p.write_text(textwrap.dedent(block))
    sc = load_scene(p)
    _same(sc, Scene(sp.diag(sp.Rational(11, 10), 1), sp.Matrix([[-1, 1], [1, 0]]), sp.Matrix([-1, -2])))
    assert sc.contacts == ["1-2", "wall@0-1"] and sc.restitution == [1, 1]
