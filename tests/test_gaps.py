"""Gap-aware resolution (issue 11): the ordering and outcome that given gaps produce, checked
exactly against the sequential resolver (every realized ordering is one of its orderings, every
outcome one of its outcomes) and against hand computations."""

from __future__ import annotations

import pytest
import sympy as sp

from impactsym.errors import DomainError, ImpactInputError, VerificationError
from impactsym.gaps import GapResolution, resolve_with_gaps
from impactsym.laws.sequential import resolve_sequential
from impactsym.models.seghete_murphey import balls_against_wall, cradle, three_ball_cradle, two_balls_wall
from impactsym.scenes import balls_in_plane, balls_on_line
from impactsym.simulate import realize_ordering

R = sp.Rational

SCENES = {
    "two-balls-wall equal": lambda: two_balls_wall(),
    "two-balls-wall 1.1:1": lambda: two_balls_wall(masses=(R(11, 10), 1)),
    "two-balls-wall 1.1:1 (-20,-21)": lambda: two_balls_wall(masses=(R(11, 10), 1), velocities=(-20, -21)),
    "three-ball cradle [1,0,0]": lambda: three_ball_cradle(),
    "three-ball cradle [1,0,-1]": lambda: three_ball_cradle(velocities=(1, 0, -1)),
    "three-ball cradle masses 1,2,3": lambda: three_ball_cradle(velocities=(2, 0, -1), masses=(1, 2, 3)),
    "cradle 4 balls 2 strikers": lambda: cradle(4, 2),
    "cradle 5 balls 2 strikers": lambda: cradle(5, 2),
    "cradle 4 balls unequal": lambda: cradle(4, 1, masses=[2, 1, 3, 1]),
    "balls against wall 3": lambda: balls_against_wall(3),
}


def _sequential(sc):
    return resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate", select=False)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_realized_gaps_reproduce_each_ordering_and_its_outcome(name):
    """realize_ordering in reverse: the gaps it finds for an ordering make exactly that ordering
    happen, with that ordering's outcome velocity and impulses, exactly."""
    sc = SCENES[name]()
    seq = _sequential(sc)
    checked = 0
    for order, idx in seq.iter_orderings():
        gaps = realize_ordering(sc.M, sc.H, sc.v, order)
        if gaps is None:
            continue
        r = resolve_with_gaps(sc, gaps)
        assert isinstance(r, GapResolution) and r.exact
        assert r.order == tuple(order)
        assert r.order_names == tuple(sc.contacts[i] for i in order)
        assert r.velocity == seq.outcomes[idx].velocity
        assert r.impulses == sp.Matrix(seq.outcomes[idx].impulse)
        assert r.impulses_unique
        assert r.kinetic_energy_after == r.kinetic_energy_before
        assert r.gaps == tuple(gaps) and r.restitution == (1,) * sc.k
        checked += 1
    assert checked >= 1


GAP_DRAWS = [(1, 2), (2, 1), (1, 1000), (1000, 1), (3, 7), (0, 5), (5, 0)]


@pytest.mark.parametrize("name", sorted(SCENES))
def test_any_gaps_give_a_sequential_ordering_and_outcome(name):
    """Gaps chosen without the LP (including zeros: touching contacts at t = 0): the outcome is one
    of the sequential outcomes and the ordering one of its orderings, or the gaps make two contacts
    sharing a ball close at one instant (refused, never guessed)."""
    sc = SCENES[name]()
    seq = _sequential(sc)
    orderings = {tuple(o): idx for o, idx in seq.iter_orderings()}
    outcomes = [o.velocity for o in seq.outcomes]
    resolved = 0
    for draw in GAP_DRAWS:
        gaps = [R(draw[i % 2] * (i + 1), 10**6) for i in range(sc.k)]
        try:
            r = resolve_with_gaps(sc, gaps)
        except DomainError as err:
            assert "same instant" in str(err) and str(err).startswith("gaps: with the gaps")
            continue
        assert r.order in orderings
        assert r.velocity == outcomes[orderings[r.order]]
        assert r.velocity in outcomes
        resolved += 1
    assert resolved >= 3


def test_zero_gaps_touching_and_approaching_at_t0():
    """All gaps zero on a cradle struck by one ball: the impact travels down the row at t = 0."""
    r = resolve_with_gaps(cradle(4, 1), [0, 0, 0])
    assert r.order == (0, 1, 2) and r.times == (0, 0, 0)
    assert list(r.velocity) == [0, 0, 0, 1] and list(r.impulses) == [1, 1, 1]
    # both contacts of two balls against a wall approach at t = 0 and share ball 1: refused
    with pytest.raises(DomainError, match=r"gaps: with the gaps 0, 0: positions: contacts 1-2, wall@0-1 close at "
                                          r"the same instant t = 0 \(touching and approaching at t = 0\) and "
                                          r"share ball 1"):
        resolve_with_gaps(two_balls_wall(), [0, 0])
    # one of them touching: it goes first
    r = resolve_with_gaps(two_balls_wall(), [0, R(1, 10)])
    assert r.order_names[0] == "wall@0-1" and r.times[0] == 0


def test_independent_contacts_closing_at_one_instant():
    sc = balls_on_line([1, 1, 1, 1], [1, 1, 1, 1], [0, 2, 10, 12], [1, 0, 0, -1])
    assert sc.contacts == ["1-2", "3-4"]
    r = resolve_with_gaps(sc, [R(1, 10), R(1, 10)])
    assert r.order == (0, 1) and r.times == (R(1, 10), R(1, 10))
    assert list(r.velocity) == [0, 1, -1, 0]
    seq = _sequential(sc)
    assert r.order in {tuple(o) for o, _ in seq.iter_orderings()}


def test_restitution_per_contact():
    """Three-ball cradle, e = 1/2 at 1-2 only, gaps (0, 1/1000): by hand, 1-2 at t = 0 gives
    (1/4, 3/4, 0); 2-3 (elastic) at t = 1/750 gives (1/4, 0, 3/4); 1-2 again at t = 1/250,
    impulse (3/2)(1/4)(1/2) = 3/16, gives (1/16, 3/16, 3/4)."""
    sc = three_ball_cradle()
    r = resolve_with_gaps(sc, [0, R(1, 1000)], restitution={"1-2": R(1, 2)})
    assert r.order == (0, 1, 0) and r.times == (0, R(1, 750), R(1, 250))
    assert list(r.velocity) == [R(1, 16), R(3, 16), R(3, 4)]
    assert list(r.impulses) == [R(3, 4) + R(3, 16), R(3, 4)]
    assert r.restitution == (R(1, 2), 1)
    assert r.kinetic_energy_before - r.kinetic_energy_after == R(51, 256)
    same = resolve_with_gaps(sc, [0, R(1, 1000)], restitution=[R(1, 2), 1])
    assert same == r
    # all sticking (a scalar e = 0): 1-2 sticks at t = 0, then 2-3 at t = 1/500 starts an endless
    # cascade at that instant (1-2, 2-3, 1-2, ... towards 1/3 each): refused, not capped
    with pytest.raises(DomainError, match=r"gaps: with the gaps 0, 1/1000: max_events: inelastic collapse: 200 "
                                          r"collisions .* the last at t = 1/500\)"):
        resolve_with_gaps(sc, [0, R(1, 1000)], restitution=0, max_events=200)
    # all sticking on two balls: one collision, they move together
    r = resolve_with_gaps(cradle(2, 1, masses=[1, 3]), [R(1, 10)], restitution=0)
    assert list(r.velocity) == [R(1, 4), R(1, 4)] and list(r.impulses) == [R(3, 4)]


def test_inelastic_collapse_is_refused():
    sc = three_ball_cradle(velocities=(1, 0, R(-1, 2)))
    with pytest.raises(DomainError, match=r"gaps: with the gaps 1/10, 1/10: max_events: inelastic collapse"):
        resolve_with_gaps(sc, [R(1, 10), R(1, 10)], restitution=R(1, 20), max_events=300)


def test_uninvolved_balls_and_open_contacts():
    """Ball 3 is not in the impact: unchanged velocity; its open contact is watched, and gaps so
    large that it closes during the impact are refused."""
    sc = balls_on_line([1, 1, 1], [1, 1, 1], [0, 2, "41/10"], [1, 0, -1])
    assert sc.contacts == ["1-2"] and sc.meta["uninvolved"] == [3]
    r = resolve_with_gaps(sc, [R(1, 100)])
    assert r.order == (0,) and list(r.velocity) == [0, 1] and r.all_velocities == [0, 1, -1]
    with pytest.raises(DomainError, match=r"contact 2-3, which is not simulated, closes at t = 1/10, before the next "
                                          r"collision of the simulated contacts \(1-2 at t = 1\)"):
        resolve_with_gaps(sc, [1])


def test_opening_moves_bodies_right_of_each_gap():
    sc = two_balls_wall()  # wall at 0, balls at 1 and 3
    r = resolve_with_gaps(sc, [R(1, 10), R(1, 100)])
    assert r.walls == [0] and r.positions == [R(11, 10), R(311, 100)]
    # a ball touching two walls: the right wall moves with the gaps
    sc = balls_on_line([1], [1], [1], [1], walls=[0, 2])
    assert sc.contacts == ["wall@0-1", "wall@2-1"]
    with pytest.raises(DomainError, match="gaps: with the gaps 1/10, 1/5: max_events: more than 20 collisions"):
        resolve_with_gaps(sc, [R(1, 10), R(1, 5)], max_events=20)


def test_explicit_system_of_balls_on_a_line():
    """(M, H, v) that is a line of balls is rebuilt and gives the scene's answer; rows in any order."""
    sc = two_balls_wall(masses=(R(11, 10), 1))
    gaps = [R(3, 10**6), R(1, 10**6)]
    want = resolve_with_gaps(sc, gaps)
    got = resolve_with_gaps((sc.M, sc.H, sc.v), gaps)
    assert (got.order, got.velocity, got.impulses) == (want.order, want.velocity, want.impulses)
    swapped = resolve_with_gaps((sc.M, sc.H[::-1, :], sc.v), gaps[::-1])
    assert swapped.order == tuple(1 - i for i in want.order) and swapped.velocity == want.velocity
    # two independent chains: a cradle pair and a ball at a wall on its left side
    r = resolve_with_gaps(("1,0,0;0,1,0;0,0,2", "-1,1,0;0,0,-1", "1,0,1"), ["1/10", "1/20"])
    assert r.order == (1, 0) and list(r.velocity) == [0, 1, -1] and r.times == (R(1, 20), R(1, 10))


@pytest.mark.parametrize("M, H, v, match", [
    ("2,1;1,2", "1,0;-1,1", "-1,-2", "mass_matrix: is not diagonal: not balls on a line"),
    ("1,0;0,1", "1,1;-1,1", "-1,-2", r"gradients: row 0 is neither a wall row"),
    ("1,0;0,1", "2,0;-1,1", "-1,-2", r"gradients: row 0 is neither a wall row"),
    ("1,0,0;0,1,0;0,0,1", "1,0,0;-1,1,0", "-1,-2,0", "gradients: coordinate 3 is in no contact"),
    ("1,0;0,1", "-1,1;1,-1", "1,-1", "the pair rows form a cycle"),
    ("1,0,0;0,1,0;0,0,1", "-1,1,0;-1,0,1", "1,0,0", "two contacts on one side"),
])
def test_explicit_system_that_is_not_a_line_is_refused(M, H, v, match):
    with pytest.raises(ImpactInputError, match=match):
        resolve_with_gaps((M, H, v), [R(1, 10), R(1, 10)])


def test_explicit_float_system_is_refused():
    import numpy as np

    with pytest.raises(ImpactInputError, match="mass_matrix/gradients/velocity: contain floats"):
        resolve_with_gaps((np.eye(2), [[1, 0], [-1, 1]], [-1, -2]), [R(1, 10), R(1, 10)])


def test_bad_gaps_and_restitution():
    sc = two_balls_wall()
    with pytest.raises(ImpactInputError, match=r"gaps: has 1 entries, expected 2: one per closed contact "
                                               r"\(wall@0-1, 1-2\)"):
        resolve_with_gaps(sc, [R(1, 10)])
    with pytest.raises(ImpactInputError, match=r"gaps: entry 1 \(1-2\) must be >= 0, got -1/10"):
        resolve_with_gaps(sc, [R(1, 10), R(-1, 10)])
    with pytest.raises(ImpactInputError, match=r"gaps\[0\] \(wall@0-1\): must be exact .* got the float 0.1"):
        resolve_with_gaps(sc, [0.1, R(1, 10)])
    with pytest.raises(ImpactInputError, match=r"gaps\[1\] \(1-2\): must be rational"):
        resolve_with_gaps(sc, [R(1, 10), "sqrt(2)/100"])
    with pytest.raises(ImpactInputError, match=r"gaps\[0\] \(wall@0-1\): must be a finite real number"):
        resolve_with_gaps(sc, ["nan", 1])
    with pytest.raises(ImpactInputError, match=r"gaps\[1\] \(1-2\): must be a finite real number"):
        resolve_with_gaps(sc, [1, "inf"])
    with pytest.raises(ImpactInputError, match=r"gaps: must be a sequence of 2 exact numbers"):
        resolve_with_gaps(sc, 1)
    assert resolve_with_gaps(sc, "1/10,1/100").gaps == (R(1, 10), R(1, 100))
    with pytest.raises(ImpactInputError, match=r"restitution\['wall@0-1'\]: must satisfy 0 <= e <= 1, got 2"):
        resolve_with_gaps(sc, [1, 2], restitution=2)
    with pytest.raises(ImpactInputError, match=r"restitution: names no closed contact: '2-3'"):
        resolve_with_gaps(sc, [1, 2], restitution={"2-3": 0})
    with pytest.raises(ImpactInputError, match=r"restitution: has 3 entries, expected 2"):
        resolve_with_gaps(sc, [1, 2], restitution=[1, 1, 1])
    with pytest.raises(ImpactInputError, match=r"restitution\['1-2'\]: must be exact"):
        resolve_with_gaps(sc, [1, 2], restitution=[1, 0.5])


def test_scenes_without_line_geometry_are_refused():
    plane = balls_in_plane([1, 1], [1, 1], [(0, 0), (2, 0)], [(1, 0), (0, 0)])
    with pytest.raises(ImpactInputError, match=r"scene: gaps need balls on a line .* comes from balls_in_plane"):
        resolve_with_gaps(plane, [R(1, 10)])
    floats = balls_on_line([1.0, 1.0], [1.0, 1.0], [0.0, 2.0], [1.0, 0.0])
    with pytest.raises(ImpactInputError, match="scene: is a float scene"):
        resolve_with_gaps(floats, [R(1, 10)])
    with pytest.raises(ImpactInputError, match="scene: must be a Scene of balls on a line or a tuple"):
        resolve_with_gaps("cradle", [R(1, 10)])


def test_a_wrong_impulse_from_the_simulator_is_caught(monkeypatch):
    """The impulses are solved from M(v+ - v-) = H^T p and must equal the simulator's own."""
    import impactsym.gaps as gp

    real = gp.simulate_line

    def corrupted(*args, **kwargs):
        res = real(*args, **kwargs)
        res.impulses = {k: v + 1 for k, v in res.impulses.items()}
        return res

    monkeypatch.setattr(gp, "simulate_line", corrupted)
    with pytest.raises(VerificationError, match="differ from the simulator's"):
        resolve_with_gaps(cradle(3, 1), [R(1, 10), R(1, 10)])


@pytest.mark.parametrize("name", ["two-balls-wall 1.1:1", "three-ball cradle masses 1,2,3", "cradle 4 balls unequal",
                                  "balls against wall 3"])
@pytest.mark.parametrize("e", [R(1, 2), R(4, 5)])
def test_inelastic_outcome_is_its_ordering_replayed_with_the_restitution_map(name, e):
    """With e < 1 the simulator (Newton's law from first principles) and impactsym's G_u(e)
    (impactsym.laws.reflection.reflect) agree: replaying the realized ordering with G_u(e) gives
    the gap outcome, exactly; the energy lost is positive."""
    from impactsym.laws.reflection import reflect

    sc = SCENES[name]()
    for draw in [(1, 2), (5, 1), (2, 9)]:
        gaps = [R(draw[i % 2] * (i + 1), 10**6) for i in range(sc.k)]
        try:
            r = resolve_with_gaps(sc, gaps, restitution=e)
        except DomainError as err:
            assert "same instant" in str(err) or "inelastic collapse" in str(err)
            continue
        v = sc.v
        for i in r.order:
            v = reflect(sc.M, sc.H[i, :], v, e)
        assert r.velocity == v
        assert sc.M * (r.velocity - sc.v) == sc.H.T * r.impulses
        assert r.kinetic_energy_after < r.kinetic_energy_before


def test_wall_names_follow_the_scene_when_walls_move():
    """Opening moves a wall right of a gap; orderings, restitution and messages use the scene's names."""
    sc = balls_on_line([1, 1], [1, 1], [-6, -4], [1, 1], walls=[-3])
    assert sc.contacts == ["1-2", "wall@-3-2"]
    r = resolve_with_gaps(sc, [R(1, 10), R(1, 5)], restitution={"wall@-3-2": R(1, 2)})
    # by hand: ball 2 meets the moved wall (-27/10) at t = 1/5 and leaves at -1/2; 1-2 (gap 1/10,
    # closing at 3/2) at t = 4/15 exchanges (1, -1/2); ball 2 is 1/30 from the wall: again at t = 3/10
    assert r.walls == [R(-27, 10)] and r.order_names == ("wall@-3-2", "1-2", "wall@-3-2")
    assert r.times == (R(1, 5), R(4, 15), R(3, 10))
    assert list(r.velocity) == [R(-1, 2), R(-1, 2)]
    # the moved wall (at -14/5 in the simulation) is named as in the scene in a refusal
    sc = balls_on_line([1, 1], [1, 1], [-6, -4], [2, 1], walls=[-3])
    with pytest.raises(DomainError, match=r"contacts 1-2, wall@-3-2 close at the same instant t = 1/10 and share "
                                          r"ball 2"):
        resolve_with_gaps(sc, [R(1, 10), R(1, 10)])


from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(masses=st.lists(st.integers(1, 5), min_size=3, max_size=3),
       velocities=st.lists(st.integers(-3, 3), min_size=3, max_size=3),
       gaps=st.lists(st.integers(0, 20), min_size=2, max_size=2),
       wall=st.booleans())
def test_property_gap_outcome_is_a_sequential_outcome(masses, velocities, gaps, wall):
    """Three balls touching in a row (with or without a wall touching the first): whatever the
    masses, velocities and gaps, the gap outcome is a sequential outcome and its ordering a
    sequential ordering, or the gaps make a simultaneous impact (refused)."""
    from hypothesis import assume

    if wall:
        sc = balls_on_line(masses[:2], [1, 1], [1, 3], velocities[:2], walls=[0])
        gaps = gaps[:2]
    else:
        sc = balls_on_line(masses, [1, 1, 1], [0, 2, 4], velocities)
    assume(any(sc.approaching))
    try:
        r = resolve_with_gaps(sc, [R(g, 1000) for g in gaps])
    except DomainError as err:
        assert "same instant" in str(err)
        return
    seq = _sequential(sc)
    orderings = {tuple(o): idx for o, idx in seq.iter_orderings()}
    assert r.order in orderings
    assert r.velocity == seq.outcomes[orderings[r.order]].velocity
    assert r.kinetic_energy_after == r.kinetic_energy_before
