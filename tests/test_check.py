"""``impactsym check`` and :mod:`impactsym.oracle`: distances in the kinetic metric (exact), the
momentum residual, contact violations, the impulse-ratio fit, and the exit statuses 0 / 3 / 2."""

from __future__ import annotations

import argparse
import json

import pytest
import sympy as sp

from impactsym.cli import main
from impactsym.cli.scene_args import read_system
from impactsym.errors import ImpactInputError
from impactsym.laws.impulse_ratio import impulse_ratio_law
from impactsym.lawbook import LAWS, resolve_all
from impactsym.oracle import check, fit_impulse_ratios, kinetic_distance, momentum_residual
from impactsym.resolution import System

CHAIN = System.from_matrices("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0")


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def exact(text):
    return sp.sympify(text)


def test_distance_is_exact_and_independent():
    rep = check(CHAIN, "0,0,1")
    # by hand: v_obs - v_newton = (1/3, -2/3, 1/3), ||.||_M^2 = 6/9, ||v-||_M^2 = 1
    assert sp.simplify(exact(rep.laws["newton"]["distance"]) - sp.sqrt(6) / 3) == 0
    assert rep.laws["newton"]["distance_exact"] is True and rep.laws["newton"]["match"] is False
    assert rep.laws["sequential"]["distance"] == "0" and rep.laws["sequential"]["match"] is True
    # Han-Gilmore is set-valued: the distance is to its nearest outcome, [0, 0, 1]
    hg = rep.laws["han-gilmore"]
    assert hg["distance"] == "0" and hg["nearest"]["velocity"] == ["0", "0", "1"] and len(hg["distances"]) == 2
    assert rep.matches == ["sequential", "two-surface", "han-gilmore"] and rep.exit_status == 0


def test_distance_nonunit_mass_metric():
    s = System.from_matrices("2,0;0,3", "-1,1", "1,0")
    d = kinetic_distance(s, sp.Matrix([0, 1]), sp.Matrix([1, 1]))
    assert d["exact"] and d["distance_squared"] == sp.Rational(2, 2)  # (1^2 * 2) / (1^2 * 2)
    d = kinetic_distance(s, sp.Matrix([0, 1]), sp.Matrix([0, 0]))
    assert d["distance_squared"] == sp.Rational(3, 2)


def test_tolerance_decided_exactly_at_the_boundary():
    # distance to newton exactly sqrt(6)/3: a tolerance equal to it matches, one below does not
    at = check(CHAIN, "0,0,1", laws=["newton"], tolerance=sp.sqrt(6) / 3)
    below = check(CHAIN, "0,0,1", laws=["newton"], tolerance=sp.sqrt(6) / 3 - sp.Rational(1, 10**40))
    assert at.matches == ["newton"] and below.matches == [] and below.exit_status == 3


def _system(scene, **params):
    ns = argparse.Namespace(scene=scene, mass_matrix=None, gradients=None, velocity=None, restitution=None,
                            theta=None, tau=None, masses=None, velocities=None, n_balls=None, strikers=None)
    for k, v in params.items():
        setattr(ns, k, v)
    return read_system(ns)


@pytest.mark.parametrize("scene,params", [("chain3", {}), ("pool", {"theta": "pi/4"}), ("bernoulli", {}),
                                          ("two-balls-wall", {}), ("three-ball-cradle", {}), ("cradle", {}),
                                          ("balls-against-wall", {})])
def test_every_builtin_scene_every_law(scene, params):
    """Each law's own answer is at distance exactly 0 from that law, on every built-in scene."""
    system = _system(scene, **params)
    options = {"impulse-ratio": {"coupling": True}} if system.k > 1 else {}
    results = resolve_all(system, options=options)
    answers = {}
    for name, r in results.items():
        if not isinstance(r, str) and isinstance(r.outcomes[0].velocity, sp.MatrixBase):
            answers.setdefault(tuple(r.outcomes[0].velocity), []).append(name)
    assert answers, scene
    for velocity, owners in answers.items():
        rep = check(system, sp.Matrix(velocity), tolerance=0, options=options)
        assert set(rep.laws) == set(LAWS)
        for name in owners:
            assert rep.laws[name]["distance"] == "0" and rep.laws[name]["match"], (scene, name)
        assert set(owners) <= set(rep.matches) and rep.exit_status == 0
        for name, e in rep.laws.items():
            assert ("refused" in e) == isinstance(results[name], str)
            if "refused" not in e and e["match"]:  # a match at tolerance 0 is an exact equality
                assert exact(e["distance"]) == 0


def test_momentum_residual_is_the_m_inverse_orthogonal_part():
    s = System.from_matrices("2,1,0;1,3,0;0,0,5", "-1,1,0;0,-1,1", "1,0,0")
    obs = sp.Matrix([sp.Rational(1, 3), 2, -1])
    m = momentum_residual(s, obs)
    M, H = s.M, s.H
    g = M * (obs - s.v)
    r = m["residual"]
    # r is M^-1-orthogonal to the range of H^T, and g - r is in that range (g - r = H^T p*)
    assert sp.simplify(H * M.inv() * r) == sp.zeros(2, 1)
    assert sp.simplify(g - r - H.T * m["impulses"]) == sp.zeros(3, 1)
    assert sp.simplify(m["norm"] ** 2 - (r.T * M.inv() * r)[0, 0] / (s.v.T * M * s.v)[0, 0]) == 0
    assert m["zero"] is False
    # an observation made by an impulse on the contacts has zero residual and its impulse back
    p = sp.Matrix([sp.Rational(3, 2), sp.Rational(1, 7)])
    made = s.v + M.inv() * H.T * p
    m2 = momentum_residual(s, made)
    assert m2["zero"] and m2["impulses"] == p


def test_contact_violation_decided_exactly():
    tiny = sp.Rational(1, 10**40)
    rep = check(CHAIN, sp.Matrix([-sp.Rational(1, 3), sp.Rational(2, 3), sp.Rational(2, 3) - tiny]))
    assert [v["contact"] for v in rep.violations] == ["2"] and exact(rep.violations[0]["relative_velocity"]) == -tiny
    assert check(CHAIN, "-1/3,2/3,2/3").violations == []  # H v = (1, 0): grazing is no violation


def test_float_observation_read_at_binary_value():
    rep = check(CHAIN, [-1 / 3, 2 / 3, 2 / 3])
    assert rep.observed_exactness.startswith("float")
    d = exact(rep.laws["newton"]["distance"])
    assert d != 0 and d < sp.Rational(1, 10**15) and "newton" in rep.matches


def test_fit_law_root_and_verified_by_the_law():
    f = fit_impulse_ratios(CHAIN, "-1/3,2/3,2/3")
    assert f["status"] == "law-root" and f["ratios"] == ["1/2"] and f["restitution"] == "1"
    law = impulse_ratio_law(CHAIN.M, CHAIN.H, CHAIN.v, 1, [sp.Rational(1, 2)])
    assert [str(x) for x in law.velocity] == f["velocity"] == ["-1/3", "2/3", "2/3"]


def test_fit_other_root():
    # e = 5/8, ratio 0: p1^2 - p1 + 3/16 = 0 has the roots 3/4 (the law's) and 1/4 (observed)
    f = fit_impulse_ratios(CHAIN, "3/4,1/4,0")
    assert f["status"] == "other-root" and f["ratios"] == ["0"] and f["restitution"] == "5/8"
    assert f["velocity"] == ["1/4", "3/4", "0"] and f["impulses"] == ["1/4", "0"]
    assert "other root" in f["reason"]


def test_fit_not_in_family():
    gain = fit_impulse_ratios(CHAIN, "0,1,1")
    assert gain["status"] == "not-in-family" and "gains energy" in gain["reason"]
    off = fit_impulse_ratios(CHAIN, "0,0,1/2")  # M(v - v-) not in the range of H^T
    assert off["status"] == "not-in-family" and "momentum residual is not zero" in off["reason"]
    none = fit_impulse_ratios(CHAIN, "1,0,0")
    assert none["status"] == "not-in-family" and "no impulse" in none["reason"]


def test_bad_input_raises():
    with pytest.raises(ImpactInputError, match="observed: has length 2"):
        check(CHAIN, "0,1")
    with pytest.raises(ImpactInputError, match="observed"):
        check(CHAIN, [0.0, float("nan"), 1.0])
    with pytest.raises(ImpactInputError, match="tolerance"):
        check(CHAIN, "0,0,1", tolerance="-1/10")
    with pytest.raises(ImpactInputError, match="law"):
        check(CHAIN, "0,0,1", laws=["nope"])


def test_cli_exit_statuses(capsys):
    code, out, err = run(capsys, "check", "--scene", "chain3", "--observed", "0,0,1", "--json")
    d = json.loads(out)
    assert code == 0 and err == "" and d["matches"][0] == "sequential" and d["exit_status"] == 0
    assert d["schema"] == "impactsym.check/1" and d["momentum"]["residual_norm"] == "0"
    code, out, err = run(capsys, "check", "--scene", "chain3", "--observed", "1/2,1/2,0", "--json")
    d = json.loads(out)  # a finding: still one JSON object on stdout
    assert code == 3 and d["matches"] == [] and d["exit_status"] == 3
    code, out, err = run(capsys, "check", "--scene", "chain3", "--observed", "1/2,1/2,0")
    assert code == 3 and "matches: none (exit status 3)" in out
    for argv, argument in ((["--observed", "0,1"], "observed"), (["--observed", "0,nan,1"], "observed"),
                           (["--observed", "0,0,1", "--tolerance", "-1e-3"], "tolerance"),
                           (["--observed", "0,0,1", "--laws", "newton", "--ratios", "1/2"], "ratios"),
                           (["--observed", "0,0,1", "--theta", "pi/4"], "theta"),
                           (["--observed", "0,0,1", "--laws", "nope"], "law")):
        code, out, err = run(capsys, "check", "--scene", "chain3", *argv, "--json")
        assert code == 2 and "Traceback" not in err, argv
        assert json.loads(out)["error"]["argument"] == argument, argv


def test_cli_matrices_and_ratios(capsys):
    code, out, _ = run(capsys, "check", "--mass-matrix", "1,0,0;0,1,0;0,0,1", "--gradients", "-1,1,0;0,-1,1",
                       "--velocity", "1,0,0", "--observed", "-1/3,2/3,2/3", "--laws", "impulse-ratio,newton",
                       "--ratios", "1/2", "--json")
    d = json.loads(out)
    assert code == 0 and d["matches"] == ["newton", "impulse-ratio"]
    assert d["impulse_ratio_fit"]["status"] == "law-root"


# ------------------------------------------------------------------------------ scene files, engines
def test_scene_file(capsys, tmp_path):
    code, out, _ = run(capsys, "check", "--scene-file", "newton-cradle-5-strikers-1", "--observed", "0,0,0,0,1",
                       "--laws", "newton,sequential", "--json")
    d = json.loads(out)
    assert code == 0 and d["matches"] == ["sequential"] and d["impulse_ratio_fit"]["status"] == "law-root"
    f = tmp_path / "two.toml"
    f.write_text('[[bodies]]\nmass = 1\nradius = 1\nposition = 0\nvelocity = 1\n\n'
                 '[[bodies]]\nmass = 1\nradius = 1\nposition = 2\nvelocity = 0\n')
    code, out, _ = run(capsys, "check", "--scene-file", str(f), "--observed", "0,1", "--json")
    d = json.loads(out)
    assert code == 0 and "newton" in d["matches"] and d["system"]["gradients"] == [["-1", "1"]]
    code, out, _ = run(capsys, "check", "--scene-file", str(f), "--scene", "chain3", "--observed", "0,1", "--json")
    assert code == 2 and json.loads(out)["error"]["argument"] == "scene"


#: what each engine does on the three-ball cradle at its default settings and e = 1, as measured
#: (MuJoCo 4.0.0, pybullet 3.2.7, pymunk 7.3.1): law it is nearest, and the distance bounds
ENGINE_CRADLE = {"mujoco": ("newton", 0.04, 0.06), "pybullet": ("newton", 0.0, 0.01),
                 "pymunk": ("sequential", 0.0, 1e-9)}


@pytest.mark.parametrize("engine", sorted(ENGINE_CRADLE))
def test_engine_three_ball_cradle(capsys, engine):
    pytest.importorskip(engine, reason=f"{engine} is not installed (pip install 'impactsym[engines]')")
    law, lo, hi = ENGINE_CRADLE[engine]
    code, out, err = run(capsys, "check", "--engine", engine, "--scene", "three-ball-cradle", "--tolerance", "0.1",
                         "--json")
    d = json.loads(out)
    assert code == 0 and law in d["matches"] and d["engine"]["separated"] is True, err
    assert lo <= d["laws"][law]["distance_float"] <= hi
    other = "sequential" if law == "newton" else "newton"
    assert d["laws"][other]["distance_float"] > 0.7 and other not in d["matches"]
    assert d["observed_float"] == d["engine"]["velocity"] and d["engine"]["name"] == engine


def test_engine_refusals(capsys):
    pytest.importorskip("mujoco", reason="mujoco is not installed (pip install 'impactsym[engines]')")
    for argv, argument in ((["--engine", "mujoco", "--mass-matrix", "1,0;0,1", "--gradients", "-1,1",
                             "--velocity", "1,0"], "engine"),
                           (["--scene", "chain3", "--observed", "0,0,1", "--engine-setting", "timestep=0.001"],
                            "engine_setting"),
                           (["--scene", "chain3", "--engine", "mujoco", "--observed", "0,0,1"], "observed"),
                           (["--scene", "chain3", "--engine", "bullet"], "engine"),
                           (["--scene", "chain3", "--engine", "mujoco", "--engine-setting", "timestep"],
                            "engine_setting")):
        code, out, err = run(capsys, "check", *argv, "--json")
        assert code == 2 and json.loads(out)["error"]["argument"] == argument, (argv, out)
        assert "Traceback" not in err


def test_sweep_shows_which_law_the_engine_follows_per_setting(tmp_path):
    """pymunk strikes exactly touching balls one pair at a time (tests/test_engines.py): at every
    iteration count it is the sequential law, exactly; pybullet's contact slop moves it off Newton."""
    import contextlib
    import io

    from impactsym.cli import main

    def run(argv):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(argv)
        return code, out.getvalue(), err.getvalue()

    png = tmp_path / "sweep.png"
    code, out, err = run(["check", "--engine", "pymunk", "--scene", "three-ball-cradle", "--laws",
                          "sequential,newton", "--sweep", "iterations=1,10", "--plot", str(png), "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["schema"] == "impactsym.check-sweep/1" and [r["value"] for r in d["rows"]] == [1, 10]
    assert all(r["nearest"] == "sequential" and r["distance_float"] == 0 and r["matches"] == ["sequential"]
               for r in d["rows"])
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, out, _ = run(["check", "--engine", "pybullet", "--scene", "three-ball-cradle", "--laws", "newton",
                        "--sweep", "contactSlop=0,0.001"])
    assert code == 3 and "none" in out.splitlines()[-1]  # at slop 1e-3 no law within 1e-3
    for argv, argument in ((["--observed", "0,0,1", "--sweep", "iterations=1"], "sweep"),
                           (["--engine", "pymunk", "--sweep", "iterations"], "sweep"),
                           (["--observed", "0,0,1", "--plot", str(png)], "plot")):
        code, out, err = run(["check", "--scene", "three-ball-cradle", *argv, "--json"])
        assert code == 2 and json.loads(out)["error"]["argument"] == argument, (argv, out)


def test_a_rational_surd_is_its_own_canonical_form():
    """oracle._simplify returns q*sqrt(m) (SymPy's form of a rational times the square root of a
    rational) as it is: what radsimp(expand(.)) gives it, structurally, for small and 40-digit
    rationals and either sign; other surds still go through radsimp."""
    import random

    from impactsym.oracle import _rational_surd, _simplify

    rng = random.Random(15)
    for _ in range(40):
        k = rng.choice([10, 10 ** 6, 10 ** 40])
        r, c = sp.Rational(rng.randint(0, k), rng.randint(1, k)), sp.Rational(rng.randint(-k, k), rng.randint(1, k))
        for x in (sp.sqrt(r), c * sp.sqrt(r)):
            assert sp.srepr(_simplify(x)) == sp.srepr(sp.radsimp(sp.expand(x))), x
    assert _rational_surd(2 * sp.sqrt(6) / 3) and _rational_surd(-sp.sqrt(2))
    assert not any(_rational_surd(x) for x in (1 / (1 + sp.sqrt(2)), sp.sqrt(2) + sp.sqrt(3), sp.cbrt(2),
                                                 sp.sqrt(2) * sp.pi, sp.Integer(3), sp.sqrt(sp.sqrt(2))))
    assert _simplify(1 / (1 + sp.sqrt(2))) == sp.sqrt(2) - 1
