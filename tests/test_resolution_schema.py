"""One ``Resolution`` type and one JSON schema for every law, on every built-in scene.

The key tables of ``docs/resolution_schema.md`` are read here and compared with what every law
prints on every built-in scene (``impactsym resolve --law LAW --scene NAME --json``), so the
document and the code cannot drift apart.
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import re
from pathlib import Path

import pytest
import sympy as sp

from impactsym.cli import main
from impactsym.cli.resolve import LAWS
from impactsym.cli.scene_args import SCENE_OPTIONS
from impactsym.lawbook import get_law, resolve_all
from impactsym.resolution import SCHEMA, UNIQUENESS, Resolution, System

DOC = Path(__file__).resolve().parents[1] / "docs" / "resolution_schema.md"

#: (law, scene) -> what the refusal says: every other pair answers
REFUSED = {(law, "chain-mass-ratio-1-2-4"): "per-contact values" for law in ("newton", "energetic", "han-gilmore", "impulse-ratio")}
REFUSED.update({(law, "chain-mass-ratio-1-2-4"): "e = 1" for law in ("hertz", "linear", "power")})
REFUSED.update({("two-surface", "chain-mass-ratio-1-2-4"): "elastic",
                ("poisson", "chain-mass-ratio-1-2-4"): "penetration: contact 2"})

#: scene parameters for scenes that need them
PARAMS = {"pool": ["--theta", "pi/4"]}


def _table(section: str) -> set[str]:
    text = DOC.read_text()
    part = text.split(f"## {section}\n", 1)[1].split("\n## ", 1)[0]
    return set(re.findall(r"^\| `(\w+)` \|", part, flags=re.M))


@functools.lru_cache(maxsize=None)
def _twins(table: frozenset[str]) -> frozenset[str]:
    """Keys documented with ``(+ `_float`)`` get their twin (read from the document once per table)."""
    text = DOC.read_text()
    return frozenset(k + "_float" for k in table if re.search(rf"^\| `{k}` \|.*\(\+ `_float`\)", text, flags=re.M))


TOP = frozenset(_table("Top level"))
OUTCOME = frozenset(_table("Outcome"))
SYSTEM = frozenset(_table("System"))


@functools.lru_cache(maxsize=None)
def _number(text: str) -> sp.Expr:
    """An exact string of the JSON read back by SymPy (the same few strings recur across laws and scenes)."""
    return sp.sympify(text)


def _run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _law_args(law, scene):
    if law == "power":
        return ["--exponent", "3/2"]
    if law == "impulse-ratio":  # ratios for every contact but the first, and any answer reported
        from impactsym.cli.scene_args import read_system
        import argparse

        ns = argparse.Namespace(scene=scene, mass_matrix=None, gradients=None, velocity=None, restitution=None,
                                theta=None, tau=None, masses=None, velocities=None, n_balls=None, strikers=None)
        if scene == "pool":
            ns.theta = "pi/4"
        k = read_system(ns).k
        return (["--ratios", ",".join(["1/2"] * (k - 1))] if k > 1 else []) + ["--allow-invalid"]
    return []


#: shipped scenes too heavy for the default run (the 6-ball rack: 10 contacts with sqrt(3) normals;
#: newton's exact LCP enumeration takes 15 s)
HEAVY = {"billiard-break-rack-6"}
#: (law, scene) pairs that do not finish in minutes, left out (a known limit, not a pass): the exact
#: ordering search and Han-Gilmore's hypotheses on the 6-ball rack ran past 600 s and 120 s
TOO_SLOW = {("sequential", "billiard-break-rack-6"), ("han-gilmore", "billiard-break-rack-6")}
CASES = [pytest.param(law, scene, id=f"{law}:{scene}", marks=[pytest.mark.slow] if scene in HEAVY else [])
         for scene in SCENE_OPTIONS for law in LAWS if (law, scene) not in TOO_SLOW]


@pytest.mark.parametrize("law, scene", CASES)
def test_every_law_on_every_builtin_scene_has_the_one_schema(law, scene):
    code, out, err = _run(["resolve", "--law", law, "--scene", scene, *PARAMS.get(scene, []),
                           *_law_args(law, scene), "--json"])
    d = json.loads(out)
    if code == 2:  # a law that does not apply, or refuses this scene, says why naming the input
        assert (law == "two-surface" and "exactly two contacts" in d["error"]["message"]) or REFUSED.get(
            (law, scene), "?") in d["error"]["message"], d
        return
    assert code == 0, err
    assert set(d) == TOP | _twins(TOP), set(d) ^ (TOP | _twins(TOP))
    assert d["schema"] == SCHEMA and d["law"] == law and d["uniqueness"] in UNIQUENESS
    assert set(d["system"]) == SYSTEM | _twins(SYSTEM)
    assert d["outcomes"], "every law gives at least one outcome"
    for o in d["outcomes"] + d["selected"]:
        assert set(o) == OUTCOME | _twins(OUTCOME)
        for key in ("velocity", "impulses", "momentum_residual"):
            if o[key] is not None:
                assert len(o[key]) == len(o[key + "_float"])
        if o["exactness"] == "exact" and o["momentum_residual"] is not None:
            assert o["momentum_residual"] == ["0"] * len(o["momentum_residual"])
    if d["uniqueness"] == "unique":
        assert d["answer"] is not None and d["velocity"] == d["answer"]["velocity"]
    if d["answer"] is None:
        assert d["velocity"] is None and len(d["outcomes"]) > 1
    if d["exact"] and d["velocity"] is not None:  # T+ is the answer's, recomputed exactly from the strings
        M = sp.Matrix([[_number(x) for x in row] for row in d["system"]["mass_matrix"]])
        v = sp.Matrix([_number(x) for x in d["velocity"]])
        assert sp.simplify((v.T * M * v)[0, 0] / 2 - _number(d["kinetic_energy_after"])) == 0


@functools.lru_cache(maxsize=None)
def _law_all_cradle_json():
    """``resolve --law all`` on the 5-ball cradle with 2 strikers, ``--json``: run once, read by
    the two tests below."""
    return _run(["resolve", "--law", "all", "--scene", "cradle", "--n-balls", "5", "--strikers", "2", "--json"])


def test_law_all_cradle_prints_every_law_in_one_table():
    code, out, err = _run(["resolve", "--law", "all", "--scene", "cradle", "--n-balls", "5", "--strikers", "2"])
    assert code == 0, err
    lines = out.splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("law "))
    named = {line.split()[0] for line in lines[header + 1:] if line and not line.startswith(" ")}
    assert named == set(LAWS)
    assert "sequential     unique            [0, 0, 0, 1, 1]" in out
    assert "two-surface    does not apply: it resolves exactly two contacts; this system has 4" in out
    code, out, _ = _law_all_cradle_json()
    d = json.loads(out)
    assert list(d["laws"]) == list(LAWS) and d["laws"]["newton"]["velocity"] == ["-1/5", "-1/5", "4/5", "4/5", "4/5"]
    assert d["laws"]["two-surface"] == {"refused": "does not apply: it resolves exactly two contacts; this system has 4"}


def test_law_all_passes_each_option_to_the_laws_that_take_it():
    code, out, _ = _run(["resolve", "--law", "all", "--scene", "chain3", "--ratios", "19/20", "--json"])
    d = json.loads(out)
    assert code == 0
    assert d["laws"]["impulse-ratio"]["velocity"] == ["-19/381", "20/381", "380/381"]
    assert d["laws"]["energetic"]["details"]["direction"] == ["1", "19/20"]


def test_every_law_returns_one_resolution_type():
    chain = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
    results = resolve_all(chain, options={"impulse-ratio": {"ratios": ["1/2"]}, "power": {"exponent": 2}})
    assert set(results) == set(LAWS)
    assert all(isinstance(r, Resolution) for r in results.values()), results
    assert {law: r.uniqueness for law, r in results.items()} == {
        "sequential": "unique", "two-surface": "unique", "newton": "unique", "poisson": "unique",
        "energetic": "unique", "han-gilmore": "set-valued", "impulse-ratio": "unique", "hertz": "unique",
        "linear": "unique", "power": "unique", "hunt-crossley": "unique", "lzb": "unique"}
    assert {law: r.exactness for law, r in results.items() if r.exactness != "exact"} == {
        law: "float" for law in ("hertz", "linear", "power", "hunt-crossley", "lzb")}


def test_two_equal_branches_are_unique_and_different_branches_gap_dependent():
    same = get_law("two-surface")(System.from_matrices("1,0;0,1", "1,0;-1,1", "-1,-2"))
    assert len(same.outcomes) == 2 and same.uniqueness == "unique" and list(same.velocity) == [1, 2]
    differ = get_law("two-surface")(System.from_matrices("11/10,0;0,1", "1,0;-1,1", "-1,-2"))
    assert differ.uniqueness == "gap-dependent" and differ.answer is None and differ.velocity is None


def test_a_wrong_momentum_balance_is_refused_before_it_is_returned():
    from impactsym.errors import VerificationError
    from impactsym.resolution import Outcome

    chain = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")
    good = Outcome(sp.Matrix([0, 0, 1]), sp.Matrix([1, 1]))
    Resolution("demo", chain, [good])
    with pytest.raises(VerificationError, match="momentum balance"):
        Resolution("demo", chain, [Outcome(sp.Matrix([0, 0, 1]), sp.Matrix([1, 2]))])


def test_per_contact_restitution_is_refused_by_a_law_with_one_coefficient():
    code, out, err = _run(["resolve", "--law", "newton", "--scene", "chain3", "--restitution", "1/2,1"])
    assert code == 2 and "restitution" in err and "differ" in err
    code, out, err = _run(["resolve", "--law", "poisson", "--scene", "chain3", "--restitution", "1/2,1", "--json"])
    assert code == 0 and json.loads(out)["system"]["restitution"] == ["1/2", "1"]


def test_law_options_are_refused_where_they_do_not_apply():
    code, _, err = _run(["resolve", "--law", "newton", "--scene", "chain3", "--reading", "cone"])
    assert code == 2 and "--reading" in err and "sequential" in err
    assert get_law("sequential").options == ("reading", "max_reflections", "float", "two_surface_path", "gaps")


def test_law_all_from_a_scene_file_is_the_builtin_scenes_table(tmp_path):
    _, builtin, _ = _law_all_cradle_json()
    code, out, _ = _run(["scene", "show", "cradle", "--n-balls", "5", "--strikers", "2", "--json"])
    path = tmp_path / "cradle.json"
    path.write_text(out)
    code, fromfile, err = _run(["resolve", "--law", "all", "--scene-file", str(path), "--json"])
    assert code == 0, err
    a, b = json.loads(builtin), json.loads(fromfile)
    exact = [law for law in LAWS if "refused" not in a["laws"][law] and a["laws"][law]["exact"]]
    assert len(exact) >= 5
    for law in exact:  # the file is the same system: every exact law gives the same outcomes
        assert [o["velocity"] for o in a["laws"][law]["outcomes"]] == \
               [o["velocity"] for o in b["laws"][law]["outcomes"]], law


def test_gaps_give_the_simulated_ordering_verified_by_replay():
    code, out, err = _run(["resolve", "--law", "sequential", "--scene", "cradle", "--n-balls", "4", "--strikers", "2",
                           "--gaps", "0,1/100,0", "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["uniqueness"] == "unique" and d["velocity"] == ["0", "0", "1", "1"]
    assert d["outcomes"][0]["order"] == [1, 0, 2, 1] and d["details"]["gaps"] == ["0", "1/100", "0"]
    # other gaps, another ordering: 1-2 closes first when the striker pair is apart
    code, out, _ = _run(["resolve", "--law", "sequential", "--scene", "cradle", "--n-balls", "4", "--strikers", "2",
                         "--gaps", "1/100,0,0", "--json"])
    d2 = json.loads(out)
    assert code == 0 and d2["outcomes"][0]["order"] != d["outcomes"][0]["order"]
    # e < 1 per contact: the simulated outcome is the ordering replayed with G_u(e)
    code, out, err = _run(["resolve", "--law", "sequential", "--scene", "three-ball-cradle", "--gaps", "0,1/10",
                           "--restitution", "1/2,1", "--json"])
    d3 = json.loads(out)
    assert code == 0, err
    M = sp.eye(3)
    v = sp.Matrix([1, 0, 0])
    from impactsym.laws.reflection import reflect

    H = sp.Matrix([[-1, 1, 0], [0, -1, 1]])
    for i in d3["outcomes"][0]["order"]:
        v = reflect(M, H[i, :], v, [sp.Rational(1, 2), 1][i])
    assert d3["velocity"] == [str(x) for x in v]


@pytest.mark.parametrize("argv, argument, words", [
    (["--scene", "cradle", "--gaps", "0,1,0"], "gaps", ""),
    (["--scene", "cradle", "--gaps", "-1/10,0"], "gaps", ""),
    (["--scene", "cradle", "--gaps", "0,0", "--reading", "cone"], "reading", "takes no option"),
    (["--scene", "pool", "--theta", "pi/4", "--gaps", "0,0"], "gaps", "balls on a line"),
    (["--mass-matrix", "1,0;0,1", "--gradients", "-1,1", "--velocity", "1,0", "--gaps", "0"], "gaps",
     "balls on a line"),
])
def test_bad_gaps_exit_2_naming_the_argument(argv, argument, words):
    code, out, err = _run(["resolve", "--law", "sequential", *argv, "--json"])
    d = json.loads(out)
    assert code == 2 and d["error"]["argument"] == argument and words in d["error"]["message"], d


def test_a_simulated_outcome_that_is_not_its_ordering_replayed_is_refused(monkeypatch):
    import dataclasses

    import impactsym.gaps as gaps_module
    from impactsym.errors import VerificationError
    from impactsym.scenes import load_scene

    real = gaps_module.resolve_with_gaps

    def corrupted(*args, **kw):  # the simulator's velocity with one entry moved
        g = real(*args, **kw)
        return dataclasses.replace(g, velocity=g.velocity + sp.Matrix([sp.Rational(1, 10**6)] + [0] * (len(g.velocity) - 1)))

    monkeypatch.setattr(gaps_module, "resolve_with_gaps", corrupted)
    system = System.from_scene(load_scene("three-ball-cradle"))
    with pytest.raises(VerificationError, match="replayed with G_u"):
        get_law("sequential")(system, gaps=[0, sp.Rational(1, 10)])
