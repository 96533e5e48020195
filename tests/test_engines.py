"""The engine adapters, run for real (MuJoCo, pybullet, pymunk from PyPI wheels; no mocks).

For each engine, on Newton's 3-ball cradle (equal masses, touching, striker at 1) and on two balls
and a wall (Seghete & Murphey sec. III-B.3: ``M = diag(11/10, 1)``, ``v⁻ = (−1, −2)``), the tests
state which impactsym law the engine reproduces under which settings, and how closely, in the
kinetic metric ``d = ‖v_engine − v_law‖_M / ‖v⁻‖_M`` (the nearest outcome where a law has several).
Every tolerance is a measured distance with a margin; the measured value is in the table.

Laws at e = 1: cradle, sequential {(0, 0, 1)}; Newton = Poisson = energetic = impulse ratio
α = 1/2: (−1/3, 2/3, 2/3); impulse ratio α = 1: (0, 0, 1). Two balls and a wall: sequential
{(173/147, 278/147), (359/441, 922/441)} (gap-dependent), Newton = Poisson = energetic (1, 2).
At e = 1/2 the energetic law leaves Newton and Poisson on two balls and a wall.
"""

import functools
import sys

import numpy as np
import pytest
import sympy as sp

from impactsym.engines import (ENGINES, EngineNotInstalled, engine_scene, run, scene_to_dict, settings_of,
                               sweep)
from impactsym.errors import ImpactInputError
from impactsym.laws.classical import energetic, newton_moreau, poisson
from impactsym.laws.impulse_ratio import impulse_ratio_law
from impactsym.laws.sequential import resolve_sequential
from impactsym.models.acary_taha import chain3, pool
from impactsym.models.seghete_murphey import three_ball_cradle, two_balls_wall
from impactsym.scenes import balls_in_plane, balls_on_line

for _name in ("mujoco", "pybullet", "pymunk"):
    pytest.importorskip(_name, reason=f"{_name} is not installed (pip install 'impactsym[engines]'); "
                                      "it installs from a wheel on cp311")

HALF = sp.Rational(1, 2)
SCENES = {"cradle": three_ball_cradle, "two-balls-wall": lambda: two_balls_wall(masses=("11/10", 1))}


def _sequential_with_restitution(sc, e):
    """Sequential impacts, each one Newton's law on one contact (``G_u(e)``), while exactly one
    contact approaches (the order is then forced; refused otherwise)."""
    v = sc.v
    for _ in range(100):
        w = sc.H * v
        approaching = [i for i in range(sc.k) if w[i] < 0]
        if not approaching:
            return v
        assert len(approaching) == 1, "the order is not forced"
        i = approaching[0]
        v = newton_moreau(sc.M, sc.H[i, :], v, e).velocity
    raise AssertionError("more than 100 impacts")


@functools.lru_cache(maxsize=None)
def laws(name, e):
    """Every law's exact outcome set on scene ``name`` with restitution ``e`` (1, 1/2 or 0)."""
    sc = SCENES[name]()
    out = {"newton": [newton_moreau(sc.M, sc.H, sc.v, e).velocity],
           "poisson": [poisson(sc.M, sc.H, sc.v, e).velocity]}
    en = energetic(sc.M, sc.H, sc.v, e, allow_invalid=True)
    if en.velocity is not None:  # e = 0 on the cradle: no real solution along Newton's direction
        out["energetic"] = [en.velocity]
    if e == 1:
        out["sequential"] = [o.velocity for o in resolve_sequential(sc.M, sc.H, sc.v).outcomes]
    elif name == "cradle" and e > 0:  # e = 0: inelastic collapse, infinitely many impacts
        out["sequential"] = [_sequential_with_restitution(sc, e)]
    if name == "cradle" and e == 1:
        out["impulse-ratio a=1/2"] = [impulse_ratio_law(sc.M, sc.H, sc.v, e, [HALF]).velocity]
        out["impulse-ratio a=1"] = [impulse_ratio_law(sc.M, sc.H, sc.v, e, [1]).velocity]
    return out


def test_law_table_is_what_the_docstring_says():
    c = laws("cradle", 1)
    assert c["sequential"] == [sp.Matrix([0, 0, 1])] and c["impulse-ratio a=1"] == c["sequential"]
    third = sp.Matrix([-1, 2, 2]) / 3
    assert all(c[k] == [third] for k in ("newton", "poisson", "energetic", "impulse-ratio a=1/2"))
    w = laws("two-balls-wall", 1)
    assert w["sequential"] == [sp.Matrix([sp.Rational(173, 147), sp.Rational(278, 147)]),
                               sp.Matrix([sp.Rational(359, 441), sp.Rational(922, 441)])]
    assert laws("cradle", HALF)["sequential"] == [sp.Matrix([sp.Rational(13, 64), sp.Rational(15, 64),
                                                             sp.Rational(9, 16)])]
    assert laws("two-balls-wall", HALF)["energetic"] != laws("two-balls-wall", HALF)["newton"]


def _distance(result, outcomes):
    return min(result.distance(o) for o in outcomes)


def _law_gap(name, e, a, b):
    """Kinetic distance between two laws' outcome sets (how far apart they are on this scene)."""
    es = engine_scene(SCENES[name]())
    L = laws(name, e)
    return min(es.kinetic_distance(np.array([float(x) for x in p], dtype=float),
                                   np.array([float(x) for x in q], dtype=float)) for p in L[a] for q in L[b])


# engine, scene, restitution, settings, law reproduced, tolerance (measured distance in the comment)
CASES = [
    # MuJoCo, elastic (direct solref, zero damping): Newton's law in constraint space
    ("mujoco", "cradle", 1, {}, "newton", 0.06),                         # measured 0.0520
    ("mujoco", "cradle", 1, {"solimp": (0.9999, 0.9999, 0.001, 0.5, 2), "timestep": 0.0005}, "newton", 1e-3),  # 3.0e-4
    ("mujoco", "two-balls-wall", 1, {}, "newton", 5e-3),                 # measured 0.00236
    ("mujoco", "two-balls-wall", 1, {"solimp": (0.9999, 0.9999, 0.001, 0.5, 2), "timestep": 0.0005}, "newton",
     5e-4),                                                              # measured 7e-5
    # pybullet, restitution 1 on every contact: Newton; contactSlop 0 makes it exact to float32
    ("pybullet", "cradle", 1, {}, "newton", 5e-3),                       # measured 0.00296
    ("pybullet", "cradle", 1, {"contactSlop": 0.0}, "newton", 1e-4),      # measured 3e-5
    ("pybullet", "two-balls-wall", 1, {}, "newton", 5e-3),               # measured 0.00247
    ("pybullet", "two-balls-wall", 1, {"contactSlop": 0.0}, "newton", 5e-4),  # measured 8e-5
    # one solver iteration: the sequential (textbook) cradle, approximately
    ("pybullet", "cradle", 1, {"numSolverIterations": 1}, "sequential", 0.06),  # measured 0.0474
    # a contact slop of 1 % of the radius swallows the restitution: the inelastic Newton outcome
    ("pybullet", "cradle", 1, {"contactSlop": 0.01}, "newton e=0", 1e-4),       # measured 4.2e-6
    ("pybullet", "cradle", HALF, {"contactSlop": 0.0}, "newton", 1e-4),          # measured 2e-5
    ("pybullet", "two-balls-wall", HALF, {"contactSlop": 0.0}, "newton", 5e-4),  # measured 6e-5
    # pymunk: touching circles are no contact until they overlap, so the cradle goes pair by pair
    ("pymunk", "cradle", 1, {}, "sequential", 1e-12),                     # measured 0 (exactly (0, 0, 1))
    ("pymunk", "cradle", 1, {"iterations": 1}, "sequential", 1e-12),      # measured 0
    ("pymunk", "cradle", HALF, {}, "sequential", 1e-12),                  # measured 6e-17: (13/64, 15/64, 9/16)
    # ... but two contacts that approach together are solved together: Newton
    ("pymunk", "two-balls-wall", 1, {}, "newton", 3e-3),                  # measured 0.00154
    ("pymunk", "two-balls-wall", 1, {"iterations": 100}, "newton", 1e-12),  # measured 1e-16
    ("pymunk", "two-balls-wall", HALF, {"iterations": 100}, "newton", 1e-12),  # measured 0
]


@pytest.mark.parametrize("engine,name,e,settings,law,tol", CASES,
                         ids=[f"{c[0]}-{c[1]}-e{c[2]}-{'-'.join(f'{k}={v}' for k, v in c[3].items()) or 'defaults'}"
                              for c in CASES])
def test_engine_reproduces_law(engine, name, e, settings, law, tol):
    r = run(engine, SCENES[name](), restitution=float(e), settings=settings)
    assert r.separated, r.note
    law_e = 0 if law.endswith("e=0") else e
    law_name = law.split(" ")[0]
    L = laws(name, law_e)
    d = _distance(r, L[law_name])
    assert d <= tol, f"{engine} on {name}: distance {d:.3g} to {law} exceeds {tol}"
    # far from every law whose outcome differs (by more than 0.05) from the reproduced one
    for other, outcomes in L.items():
        gap = _law_gap(name, law_e, law_name, other)
        if gap > 0.05:
            assert _distance(r, outcomes) > gap / 2, f"{engine} is also near {other}"


def test_engine_defaults_without_restitution():
    """``restitution=None``: the engines' own contact defaults.

    pybullet (restitution 0) and pymunk (elasticity 0) give the inelastic Newton outcome (1/3, 1/3, 1/3)
    on the cradle (measured 3.4e-6 and 7.8e-7) and (0, 0) on two balls and a wall (1.2e-5 and 7.7e-4).
    MuJoCo's default solref (0.02, 1), a critically damped contact, reproduces no law: the cradle ends
    at (0.233, 0.374, 0.394), at 0.124 from the inelastic outcome and farther from every elastic one,
    keeping 34.9 % of the energy.
    """
    third = [1 / 3] * 3
    for engine, tol_c, tol_w in (("pybullet", 1e-5, 1e-4), ("pymunk", 1e-5, 2e-3)):
        assert run(engine, SCENES["cradle"](), restitution=None).distance(third) <= tol_c
        assert run(engine, SCENES["two-balls-wall"](), restitution=None).distance([0, 0]) <= tol_w
    r = run("mujoco", SCENES["cradle"](), restitution=None)
    assert r.settings["solref"] == (0.02, 1.0)
    assert 0.10 < r.distance(third) < 0.15 and abs(r.energy_ratio() - 0.3487) < 1e-3
    for outcomes in laws("cradle", 1).values():
        assert _distance(r, outcomes) > 0.5


def test_pybullet_declared_defaults_are_pybullets_own():
    """Passing every declared default gives pybullet's untouched velocities bit for bit."""
    from impactsym.engines import pybullet as adapter
    from impactsym.engines.driver import settle

    for name in SCENES:
        es = engine_scene(SCENES[name]())
        for e in (1.0, 0.5):
            s = adapter.defaults()
            s["restitution"] = e
            out = []
            for explicit in (True, False):
                sim = adapter.build(es, s, explicit=explicit)
                try:
                    out.append(settle(es, sim, hold_steps=20, max_steps=10_000, rest_tol=1e-9)[0])
                finally:
                    sim.close()
            assert np.array_equal(out[0], out[1]), (name, e)


@pytest.mark.parametrize("engine", list(ENGINES))
def test_planar_head_on_and_oblique(engine):
    """In the plane: an oblique elastic hit of equal balls sends them off at right angles (one
    contact: every law agrees, ``v⁺ = (0, 1, 1, 0)`` for ``v⁻ = (1, 1, 0, 0)``, contact along x).

    The engines find the contact normal after the balls have moved (a step, or the whole compliant
    contact), so it is tilted: measured distances mujoco 0.0221, pymunk 0.0119 (0.0012 with a
    timestep of 1/600), pybullet 0.0012.
    """
    sc = balls_in_plane([1, 1], [1, 1], [(0.0, 0.0), (2.0, 0.0)], [(1.0, 1.0), (0.0, 0.0)])
    res = run(engine, sc)
    assert res.separated and res.scene.dim == 2 and res.scene.names == ("x1", "y1", "x2", "y2")
    tol = {"mujoco": 0.03, "pymunk": 0.015, "pybullet": 0.002}[engine]
    assert res.distance([0, 1, 1, 0]) < tol, res.velocity


ONE_BALL = {"bodies": [{"mass": 1, "radius": 1, "position": 1, "velocity": -1}], "walls": [{"point": 0, "normal": 1}]}


@pytest.mark.parametrize("engine,measured,tol", [
    ("mujoco", (1.00117, 0.56002, 0.26077, 0.14053), 1e-3),    # solref mapping: right at e = 1 only
    ("pybullet", (0.9976, 0.4976, 0.0976, 0.0), 1e-3),         # e − 0.0024: the default contactSlop 1e-5
    ("pymunk", (1.0, 0.5, 0.1, 0.0), 1e-12),                   # exactly e
])
def test_single_contact_restitution(engine, measured, tol):
    """A ball against a wall at speed 1: the rebound speed for ``restitution = 1, 0.5, 0.1, 0``."""
    got = [run(engine, ONE_BALL, restitution=e).velocity[0] for e in (1, 0.5, 0.1, 0)]
    assert np.allclose(got, measured, rtol=0, atol=tol), got


@pytest.mark.parametrize("engine,tol", [("mujoco", 2e-3), ("pybullet", 5e-3), ("pymunk", 1e-9)])
def test_planar_wall_with_oblique_normal(engine, tol):
    """A ball sliding along x into a wall of normal (1, 1)/√2 leaves along y (elastic, every law).
    Measured distances: mujoco 7.4e-4, pybullet 2.4e-3, pymunk 5.6e-12."""
    s = 2 ** -0.5
    scene = {"bodies": [{"mass": 2, "radius": 1, "position": [s, s], "velocity": [-1, 0]}],
             "walls": [{"point": [0, 0], "normal": [1, 1]}]}
    r = run(engine, scene)
    assert r.separated and np.allclose(r.scene.H, [[s, s]])
    assert r.distance([0, 1]) < tol, r.velocity


def test_sweep_moves_pybullet_from_newton_to_inelastic():
    """Sweeping contactSlop: 0 gives Newton, 0.01 the inelastic outcome (Bullet issue #3094)."""
    res = sweep("pybullet", SCENES["cradle"](), "contactSlop", [0.0, 0.001, 0.01])
    assert [r.settings["contactSlop"] for r in res] == [0.0, 0.001, 0.01]
    assert res[0].distance([-1 / 3, 2 / 3, 2 / 3]) < 1e-4
    assert 0.2 < res[1].distance([-1 / 3, 2 / 3, 2 / 3]) < 0.5  # measured 0.339: in between
    assert res[2].distance([1 / 3] * 3) < 1e-4
    res = sweep("mujoco", SCENES["cradle"](), "restitution", [1, 0.5])
    assert [r.restitution for r in res] == [1.0, 0.5] and res[0].energy_ratio() > res[1].energy_ratio()


def test_result_reports_every_ball_and_the_settings():
    sc = balls_on_line([1, 1, 1, 1], [1, 1, 1, 1], [0, 2, 4, 20], [1, 0, 0, 0.5])
    r = run("pymunk", sc)
    assert len(r.velocities) == 4 and r.scene.names == ("x1", "x2", "x3")
    assert r.velocity.tolist() == r.velocities[:3]
    assert set(r.settings) == set(settings_of("pymunk")) and r.settings["elasticity"] == 1.0
    assert r.defaults == settings_of("pymunk") and r.defaults["elasticity"] == 0.0
    js = r.as_json()
    assert js["coordinates"] == ["x1", "x2", "x3"] and js["separated"] is True and js["steps"] == r.steps


def test_cap_is_reported():
    r = run("mujoco", SCENES["cradle"](), max_steps=3)
    assert not r.separated and r.steps == 3 and "max_steps=3" in r.note


def test_engine_scene_forms_agree():
    """A line Scene, its dict form, and scenes rebuilt from M and H give the same M, H, v."""
    sc = SCENES["two-balls-wall"]()
    es = engine_scene(sc)
    again = engine_scene(scene_to_dict(es))
    assert set(map(tuple, again.H.tolist())) == set(map(tuple, es.H.tolist()))
    assert np.array_equal(again.M, es.M) and np.array_equal(again.v, es.v)
    c = engine_scene(chain3())
    assert c.H.tolist() == [[-1, 1, 0], [0, -1, 1]] and [b.position for b in c.balls] == [(0.0,), (2.0,), (4.0,)]
    p = engine_scene(pool(sp.pi / 4))
    assert p.dim == 2 and np.allclose(p.H, np.array(pool(sp.pi / 4).H.evalf(), dtype=float))


def test_errors_name_the_argument():
    sc = SCENES["cradle"]()
    with pytest.raises(ImpactInputError, match="engine: must be one of"):
        run("bullet", sc)
    with pytest.raises(ImpactInputError, match="mujoco has no setting 'contactSlop'"):
        run("mujoco", sc, settings={"contactSlop": 0})
    with pytest.raises(ImpactInputError, match="solref is decided by restitution"):
        run("mujoco", sc, settings={"solref": (0.02, 1)})
    with pytest.raises(ImpactInputError, match=r"restitution: must lie in \[0, 1\]"):
        run("pymunk", sc, restitution=1.5)
    with pytest.raises(ImpactInputError, match="restitution: cannot be given when sweeping"):
        sweep("pymunk", sc, "restitution", [1], restitution=0.5)
    with pytest.raises(ImpactInputError, match="integrator must be one of"):
        run("mujoco", sc, settings={"integrator": "leapfrog"})
    with pytest.raises(ImpactInputError, match="both sides of the wall"):
        engine_scene(balls_on_line([1, 1], [1, 1], [-1, 1], [1, -1], walls=[0]))
    with pytest.raises(ImpactInputError, match="no contact is closed"):
        engine_scene({"bodies": [{"mass": 1, "radius": 1, "position": [0, 0], "velocity": [1, 0]}]})
    with pytest.raises(ImpactInputError, match="restitution: a scene's own restitution is not read"):
        engine_scene(dict(ONE_BALL, restitution=0.5))
    with pytest.raises(ImpactInputError, match="mass_matrix: the engines build bodies"):
        engine_scene({"mass_matrix": "1", "gradients": "1", "velocity": "-1"})
    with pytest.raises(ImpactInputError, match="overlap"):
        engine_scene({"bodies": [{"mass": 1, "radius": 1, "position": 0, "velocity": 1},
                                 {"mass": 1, "radius": 1, "position": 1, "velocity": 0}]})


def test_engine_not_installed_names_the_extra(monkeypatch):
    """An engine whose package cannot be imported (here: ``sys.modules["pymunk"] = None`` makes
    ``import pymunk`` raise ImportError) is refused with the install command."""
    from impactsym.engines import pymunk as adapter

    monkeypatch.setitem(sys.modules, "pymunk", None)
    monkeypatch.setattr(adapter, "_DEFAULTS", None)
    with pytest.raises(EngineNotInstalled, match=r"pip install 'impactsym\[engines\]'"):
        run("pymunk", SCENES["cradle"]())
    assert isinstance(EngineNotInstalled("x", "y", "z"), ImportError)


def test_gaps_open_the_contacts_of_a_line_scene():
    es = engine_scene(SCENES["two-balls-wall"]())
    assert es.contacts == ("wall@0-1", "1-2")
    assert [b.position for b in es.with_gaps([0.5, 0.25]).balls] == [(1.5,), (3.75,)]
    assert np.array_equal(es.with_gaps([0.5, 0.25]).H, es.H)
    with pytest.raises(ImpactInputError, match="gaps: must be non-negative"):
        es.with_gaps([-1, 0])
    with pytest.raises(ImpactInputError, match="one per closed contact"):
        es.with_gaps([0.1])
    with pytest.raises(ImpactInputError, match="on a line only"):
        engine_scene(balls_in_plane([1, 1], [1, 1], [(0, 0), (2, 0)], [(1, 0), (0, 0)])).with_gaps([0.1])


def test_cradle_with_gaps():
    """Small gaps between the cradle's balls: the rigid answer is the sequential (0, 0, 1) for any
    positive gaps (the order is forced). Measured, gaps (g, g):

    * pymunk: (0, 0, 1) exactly, for g = 1e-4 ... 0.1;
    * MuJoCo (elastic): g = 0.1 gives (0, 0, 1) within 7.2e-4; g = 1e-3 gains 9 % energy
      ((−0.366, 0.572, 0.795), T⁺/T⁻ = 1.092): the compliant contacts overlap in time;
    * pybullet: gains energy at every gap tried (T⁺/T⁻ = 1.168, 1.129, 1.105, 1.165 for
      g = 1e-4, 1e-3, 1e-2, 0.1), e.g. (−0.031, −0.031, 1.062) at g = 1e-3.
    """
    es = engine_scene(SCENES["cradle"]())
    seq = [0, 0, 1]
    for g in (1e-4, 1e-2):
        assert run("pymunk", es.with_gaps([g, g])).distance(seq) < 1e-12
    assert run("mujoco", es.with_gaps([0.1, 0.1])).distance(seq) < 2e-3
    assert abs(run("mujoco", es.with_gaps([1e-3, 1e-3])).energy_ratio() - 1.092) < 5e-3
    for g, ratio in ((1e-4, 1.168), (1e-3, 1.129), (1e-2, 1.105)):
        r = run("pybullet", es.with_gaps([g, g]))
        assert r.separated and abs(r.energy_ratio() - ratio) < 5e-3, (g, r.energy_ratio())


def test_pymunk_cradle_flips_to_newton_when_the_contacts_overlap():
    """pymunk makes a contact only where circles overlap: exactly touching balls (gap 0) meet one
    pair at a time (sequential, (0, 0, 1)), but an overlap of 1e-9 (inside the builder's touching
    tolerance) makes both contacts exist at the first step and the solver treats them together:
    Newton's (−1/3, 2/3, 2/3), measured within 1e-5."""
    cradle = {"bodies": [{"mass": 1, "radius": 1, "position": x, "velocity": v}
                         for x, v in ((1.0, 1.0), (3.0 - 1e-9, 0.0), (5.0 - 2e-9, 0.0))]}
    r = run("pymunk", cradle)
    assert r.scene.contacts == ("1-2", "2-3")
    assert r.distance([-1 / 3, 2 / 3, 2 / 3]) < 1e-5 and r.distance([0, 0, 1]) > 0.8


def test_pymunk_pool_follows_the_rounding_of_the_touching_distance():
    """Acary & Taha's planar pool, rebuilt from its gradient rows: at θ = π/6 the float distance of
    balls 2 and 3 is exactly 2 (no overlap) and pymunk gives the sequential outcome (measured 0.0059,
    the normal tilted by the first step); at θ = π/4 it is 2 − 2.2e-16 and pymunk gives Newton's
    outcome (measured 4.0e-9). The law a user gets depends on the last bit of a position."""
    for theta, law, tol, overlap in ((sp.pi / 6, "sequential", 0.01, False), (sp.pi / 4, "newton", 1e-7, True)):
        sc = pool(theta)
        es = engine_scene(sc)
        b2, b3 = es.balls[1], es.balls[2]
        assert (float(np.linalg.norm(np.subtract(b3.position, b2.position))) < 2.0) == overlap
        r = run("pymunk", sc)
        outcomes = ([o.velocity for o in resolve_sequential(sc.M, sc.H, sc.v).outcomes] if law == "sequential"
                    else [newton_moreau(sc.M, sc.H, sc.v, 1).velocity])
        assert _distance(r, outcomes) < tol, (theta, r.velocity)
