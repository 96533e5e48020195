"""Scene builders: only the closed contacts and the involved bodies enter M and H."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from impactsym.errors import ImpactInputError
from impactsym.models.seghete_murphey import (
    SCENES,
    balls_against_wall,
    cradle,
    three_ball_cradle,
    two_balls_wall,
)
from impactsym.scenes import FLOAT_GAP_RTOL, balls_in_plane, balls_on_line, full_velocity


def test_line_keeps_only_closed_contacts_and_involved_balls():
    sc = balls_on_line([1, 2, 3, 4, 5], [1, 1, 1, 1, 1], [0, 2, 4, 7, 9], [1, 0, 0, 3, -3], walls=[-5])
    assert sc.contacts == ["1-2", "2-3", "4-5"]
    assert sc.coordinates == ["x1", "x2", "x3", "x4", "x5"]
    assert sc.M == sp.diag(1, 2, 3, 4, 5)
    assert sc.approaching == [True, False, True]
    sc2 = balls_on_line([1, 2, 3], [1, 1, 1], [0, 2, 10], [1, 0, 0])
    assert sc2.meta["uninvolved"] == [3] and sc2.M == sp.diag(1, 2)


def test_wall_rows_follow_the_side():
    sc = balls_on_line([1, 1], [1, 1], [1, 5], [-1, 1], walls=[0, 6])
    assert sc.contacts == ["wall@0-1", "wall@6-2"]
    assert sc.H == sp.Matrix([[1, 0], [0, -1]])
    assert sc.approaching == [True, True]


def test_paper_covectors_come_out_of_the_geometry():
    sc = two_balls_wall()
    assert sc.H == sp.Matrix([[1, 0], [-1, 1]])
    assert three_ball_cradle().H == sp.Matrix([[-1, 1, 0], [0, -1, 1]])
    sc = balls_against_wall(3)
    assert sc.contacts == ["1-2", "2-3", "wall@0-1"] and sc.approaching == [False, True, False]


@pytest.mark.parametrize("args, match", [
    (([1, 1], [1, 1], [0, "3/2"], [0, 0]), "overlap"),
    (([1, 1], [1, 1], [0, 3], [0, 0]), "no contact is closed"),
    (([1, 0], [1, 1], [0, 2], [0, 0]), "masses: entry 2 must be positive"),
    (([1, 1], [1, -1], [0, 2], [0, 0]), "radii"),
    (([1, 1], [1, 1], [0, 2], [0]), "velocities: has 1 entries"),
    (([1, 1], [1, 1], [0, 2], [0, "x"]), "velocities"),
])
def test_line_refusals(args, match):
    with pytest.raises(ImpactInputError, match=match):
        balls_on_line(*args)


def test_wall_overlap_and_centred_ball():
    with pytest.raises(ImpactInputError, match="wall"):
        balls_on_line([1], [1], ["1/2"], [0], walls=[0])
    with pytest.raises(ImpactInputError, match="centred on the wall"):
        balls_on_line([1], [1], [0], [0], walls=[0])


def test_float_gap_tolerance_is_relative_to_the_scene():
    tiny = 0.1 * FLOAT_GAP_RTOL
    sc = balls_on_line([1.0, 1.0], [1.0, 1.0], [0.0, 2.0 + tiny], [1.0, 0.0])
    assert sc.contacts == ["1-2"] and isinstance(sc.M, np.ndarray)
    with pytest.raises(ImpactInputError, match="no contact"):
        balls_on_line([1.0, 1.0], [1.0, 1.0], [0.0, 2.0 + 10 * FLOAT_GAP_RTOL], [1.0, 0.0])
    with pytest.raises(ImpactInputError, match="overlap"):
        balls_on_line([1.0, 1.0], [1.0, 1.0], [0.0, 2.0 - 10 * FLOAT_GAP_RTOL], [1.0, 0.0])
    sc = balls_on_line([1.0, 1.0], [1.0, 1.0], [0.0, 2.0 + 1e-6], [1.0, 0.0], gap_tolerance=1e-5)
    assert sc.contacts == ["1-2"]


def test_exact_input_has_no_tolerance():
    with pytest.raises(ImpactInputError, match="no contact"):
        balls_on_line([1, 1], [1, 1], [0, sp.Rational(2) + sp.Rational(1, 10**30)], [1, 0])


def test_plane_normals_are_exact_and_rational():
    # 3-4-5 triangle: centres 5 apart, radii 2 and 3
    sc = balls_in_plane([1, 2], [2, 3], [(0, 0), (3, 4)], [(1, 1), (0, 0)])
    assert sc.H == sp.Matrix([[-sp.Rational(3, 5), -sp.Rational(4, 5), sp.Rational(3, 5), sp.Rational(4, 5)]])
    assert sc.M == sp.diag(1, 1, 2, 2) and sc.approaching == [True]


def test_plane_with_irrational_normals_and_three_contacts():
    h = sp.sqrt(3)
    sc = balls_in_plane([1, 1, 1], [1, 1, 1], [(0, 0), (2, 0), (1, h)], [(0, 0), (0, 0), (0, -1)])
    assert sc.contacts == ["1-2", "1-3", "2-3"]
    assert sc.H[1, :] == sp.Matrix([[-sp.Rational(1, 2), -h / 2, 0, 0, sp.Rational(1, 2), h / 2]])
    assert sc.approaching == [False, True, True]


def test_plane_refusals():
    with pytest.raises(ImpactInputError, match="pair"):
        balls_in_plane([1, 1], [1, 1], [(0, 0), (2,)], [(0, 0), (0, 0)])
    with pytest.raises(ImpactInputError, match="overlap"):
        balls_in_plane([1, 1], [1, 1], [(0, 0), (1, 1)], [(0, 0), (0, 0)])


def test_full_velocity_puts_uninvolved_balls_back():
    sc = balls_on_line([1, 1, 1], [1, 1, 1], [0, 2, 7], [1, 0, 5])
    assert full_velocity(sc, sp.Matrix([0, 1])) == [0, 1, 5]
    sc = balls_in_plane([1, 1, 1], [1, 1, 1], [(0, 0), (2, 0), (9, 9)], [(1, 0), (0, 0), (2, 3)])
    assert full_velocity(sc, sp.Matrix([0, 0, 1, 0])) == [[0, 0], [1, 0], [2, 3]]


def test_cradle_parameters_are_checked():
    assert cradle(6, 3).approaching == [False, False, True, False, False]
    with pytest.raises(ImpactInputError, match="strikers"):
        cradle(3, 3)
    with pytest.raises(ImpactInputError, match="n_balls"):
        cradle(1)
    with pytest.raises(ImpactInputError, match="masses"):
        cradle(3, masses=[1, 1])
    assert set(SCENES) == {"two-balls-wall", "three-ball-cradle", "cradle", "balls-against-wall"}


def test_a_cached_scene_is_handed_out_as_a_deep_copy():
    """copy_scene gives what copy.deepcopy gave (every field equal, matrices over the same domain)
    and a copy whose matrices, lists and meta are its own; the cache is not changed through it."""
    import copy

    from impactsym.scenes import load_scene
    from impactsym.scenes.registry import BUILTIN_SCENES, SHIPPED_SCENES
    from impactsym.scenes.scene import copy_scene

    def form(x):
        if isinstance(x, sp.MatrixBase) and not isinstance(x, sp.Basic):
            return type(x), x._rep.domain, x._rep.rep.fmt, x.tolist()
        if isinstance(x, dict):
            return {k: form(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return type(x), [form(v) for v in x]
        return type(x), repr(x)

    names = [(n, {"theta": "pi/4"} if n == "pool" else None) for n in BUILTIN_SCENES] + \
            [(n, None) for n in SHIPPED_SCENES]
    for name, params in names:
        sc = load_scene(name, params)
        a, b = copy.deepcopy(sc), copy_scene(sc)
        assert form(vars(a)) == form(vars(b)), name
        b.M[0, 0] = 99
        b.contacts.append("x")
        b.meta["scene_json"]["added"] = 1
        again = load_scene(name, params)
        assert form(vars(again)) == form(vars(a)), name
