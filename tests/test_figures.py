"""The figure functions of impactsym.figures: each runs, and the source data it drew agree with the
laws (exactly where the data are exact). The README figures' committed source data are current."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import impactsym.figures as F
from impactsym.domains import validity_domain
from impactsym.laws.classical import energetic, han_gilmore, newton_moreau, poisson
from impactsym.laws.impulse_ratio import impulse_ratio_law
from impactsym.laws.reflection import reflect, reflection_map
from impactsym.laws.sequential import resolve_sequential, termination_bound
from impactsym.mechanics import kinetic_energy
from impactsym.models.acary_taha import bernoulli, chain3
from impactsym.models.seghete_murphey import two_balls_wall

R = sp.Rational
ROOT = Path(__file__).resolve().parents[1]


def _m(v):
    return sp.Matrix([sp.sympify(x) for x in v])


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def test_fig1_convex_corner_closest_is_the_nearest_single_impact():
    fig, src = F.sm_fig1_convex_corner()
    M, H, v0 = sp.eye(2), sp.Matrix([[1, 0], [-1, 1]]), sp.Matrix([-1, -2])
    singles = [reflect(M, H[i, :], v0) for i in range(2)]
    assert [_m(s) for s in src["single_impacts"]] == singles
    d = [kinetic_energy(M, s - v0) for s in singles]
    assert [_m(c) for c in src["closest"]] == [s for s, x in zip(singles, d) if x == min(d)]
    # every sampled point of the drawn arc is a valid exit of the convex corner and no nearer to v0
    arc = F._normal_cone_arc(M, H, v0)
    Hf = np.array([[1.0, 0], [-1, 1]])
    assert np.all((arc @ Hf.T >= -1e-12).any(axis=1))
    assert np.min(np.sum((arc - np.array([-1.0, -2])) ** 2, axis=1)) >= 2 * float(min(d)) - 1e-12


def test_fig2_concave_corner_naive_projection_hits_a_wall_and_orderings_fix_it():
    fig, src = F.sm_fig2_concave_corner()
    sc = two_balls_wall(masses=(R(11, 10), 1))
    r = resolve_sequential(sc.M, sc.H, sc.v)
    assert [_m(o) for o in src["outcomes"]] == [o.velocity for o in r.outcomes]
    assert [_m(o) for o in src["selected"]] == list(r.selected)
    assert src["naive_valid"] == [False]
    naive = _m(src["naive_projection"][0])
    assert any(w < 0 for w in sc.H * naive)  # it points into a wall
    assert naive in [reflect(sc.M, sc.H[i, :], sc.v) for i in range(2)]


def test_fig4_v4a_v4b_are_the_resolvers_outcomes_and_the_printed_products():
    fig, src = F.sm_fig4_configuration_space()
    sc = two_balls_wall(masses=(R(11, 10), 1))
    r = resolve_sequential(sc.M, sc.H, sc.v)
    assert [_m(src["v4a"]), _m(src["v4b"])] == [o.velocity for o in r.outcomes]
    Gu, Gv = reflection_map(sc.M, sc.H[0, :]), reflection_map(sc.M, sc.H[1, :])
    assert _m(src["v4a"]) == Gv * Gu * Gv * Gu * sc.v and _m(src["v4b"]) == Gu * Gv * Gu * Gv * sc.v
    for tr in src["trajectories"]:  # each simulated small-gap trajectory ends where its ordering does
        assert [n for _, n in tr["events"]] == [sc.contacts[i] for i in tr["order"]]
        assert _m(tr["exit"]) == (_m(src["v4a"]) if tr["order"][0] == 0 else _m(src["v4b"]))


def test_fig4_claim_sector_is_the_derived_23_19_to_439_40():
    from derivations.two_surface import paper_example_counts

    fig, src = F.sm_fig4_configuration_space()
    e = paper_example_counts()
    t = sp.Symbol("t", real=True)
    lo, hi = (sp.sympify(x) for x in src["claim_sector_t"])
    assert (lo, hi) == (R(23, 19), R(439, 40))
    # the derivation's conditions change truth exactly at these t
    assert e["u_first_four_iff"].subs(t, lo) is sp.false and e["u_first_four_iff"].subs(t, lo + R(1, 10**6)) is sp.true
    assert e["v_first_four_iff"].subs(t, hi) is sp.false and e["v_first_four_iff"].subs(t, hi - R(1, 10**6)) is sp.true


def test_ordering_regions_agree_with_the_iterating_resolver():
    M, H = sp.diag(R(11, 10), 1), sp.Matrix([[1, 0], [-1, 1]])
    regs = F.ordering_regions(M, H)
    assert regs
    for g in regs:
        s = _m(g["from"]) + _m(g["to"])
        it = resolve_sequential(M, H, s, two_surface="iterate", select=False)
        orders = {o[0]: list(o) for o, _ in it.iter_orderings()}
        assert orders == g["orders"]


def test_fig5_cradle_orderings_and_outcome():
    fig, src = F.sm_fig5_cradle_kinetic_plane(v0=(1, 1, 0))
    r = resolve_sequential(sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]), sp.Matrix([1, 1, 0]))
    assert [_m(o) for o in src["outcomes"]] == [o.velocity for o in r.outcomes] == [sp.Matrix([0, 1, 1])]


def test_termination_counts_are_the_laws_and_within_the_bound():
    fig, src = F.sm_sec3c_termination()
    assert src["counts"] == src["iterated_counts"]
    assert src["bound"] == termination_bound(sp.eye(2), sp.Matrix([[1, 0], [-3, 1]]))
    assert all(1 <= m <= src["bound"] for m in src["counts"].values())


def test_three_surface_overgeneration():
    fig, src = F.sm_three_surface_overgeneration()
    assert src["orderings"] == 15 and len(src["outcomes"]) == 5 and sum(src["orderings_per_outcome"]) == 15
    assert src["realized"] == [["1/7", "5/7", "18/7"]]
    assert all(s == ["1/7", "5/7", "18/7"] for s in src["simulated"])


def test_fig3_boundary_points_lie_on_the_domain_edge():
    from derivations.domains import pool_h, printed_eq31_h

    theta = sp.pi / 4
    fig, src = F.at_fig3_domain("pi/4", printed_h=printed_eq31_h(sp.cos(theta)))
    dom = validity_domain("pool", theta)
    for a, e in src["boundary_points"]:
        a, e = sp.sympify(a), sp.sympify(e)
        assert dom.contains(a, e)
        assert not dom.contains(a, e - R(1, 1000))
    x = sp.Symbol("x")

    def same(a, b):
        a, b = (sp.sympify(y) for y in (a, b))
        return sp.simplify(a.subs({s: x for s in a.free_symbols}) - b.subs({s: x for s in b.free_symbols})) == 0

    assert same(src["boundaries"]["h"], pool_h(sp.cos(theta)))
    assert same(src["printed_h"], printed_eq31_h(sp.cos(theta)))
    assert not same(src["printed_h"], src["boundaries"]["h"])  # the erratum is drawn, not hidden
    assert src["alpha"] == ["sqrt(2)/4", "1"] and src["e"] == ["3/7", "1"]


def test_domain_over_theta_panels_match_validity_domain():
    fig, src = F.at_domain_over_theta(["0", "pi/3", "2*pi/3"])
    for row in src["panels"]:
        dom = validity_domain("pool", sp.sympify(row["theta"]))
        assert [sp.sympify(x) for x in row["e"]] == list(dom.region["e"])
    assert src["panels"][-1]["e"][0] == "5/9"


def test_chain3_velocities_valid_range_lies_in_eq19_domain():
    fig, src = F.at_chain3_velocities(("1", "2/3"), np.linspace(0.3, 1.3, 21))
    sc = chain3()
    ex = impulse_ratio_law(sc.M, sc.H, sc.v, 1, [R(19, 20)])
    assert [_m(src["paper_example"]["velocity"])] == [ex.velocity]
    dom = validity_domain("chain3")
    for e, rng in src["valid_alpha"].items():
        assert rng is not None
        for a in rng:  # the sampled valid end points are in the exact domain
            assert dom.contains(sp.nsimplify(a, rational=True), sp.sympify(e))


def test_bernoulli_figure_is_the_law():
    fig, src = F.at_fig4_bernoulli("1/2")
    sc = bernoulli()
    r = impulse_ratio_law(sc.M, sc.H, sc.v, 1, ["1/2", "1/2"], allow_invalid=True)
    assert [sp.simplify(x - y) == 0 for x, y in zip(_m(src["velocity"]), r.velocity)] == [True] * 6
    assert src["valid"] == r.valid


def test_transmission_law_with_hertz_ratios_reproduces_hertz_exit():
    fig, src = F.at_fig5_transmission(5)
    assert src["law_matches_hertz_velocity"]
    h = src["hertz"]
    assert np.allclose(np.array(h["impulses"]) / h["impulses"][0], h["ratios"], rtol=1e-12)
    assert np.allclose(np.array(src["law"]["impulses"]) / src["law"]["impulses"][0], h["ratios"], rtol=1e-9)


def test_outcomes_per_law_is_each_law():
    sc = two_balls_wall(masses=(R(11, 10), 1))
    out = F.outcomes_per_law(sc.M, sc.H, sc.v, 1, ["1"])
    assert set(out) == set(F.LAWS)
    assert out["newton"]["outcomes"] == [newton_moreau(sc.M, sc.H, sc.v, 1).velocity]
    assert out["poisson"]["outcomes"] == [poisson(sc.M, sc.H, sc.v, 1).velocity]
    assert out["energetic"]["outcomes"] == [energetic(sc.M, sc.H, sc.v, 1).velocity]
    assert out["han-gilmore"]["outcomes"] == [o.velocity for o in han_gilmore(sc.M, sc.H, sc.v).outcomes]
    assert out["sequential"]["outcomes"] == [o.velocity for o in resolve_sequential(sc.M, sc.H, sc.v).outcomes]
    assert out["two-surface"]["outcomes"] == out["sequential"]["outcomes"]
    ir = impulse_ratio_law(sc.M, sc.H, sc.v, 1, ["1"], allow_invalid=True)
    assert out["impulse-ratio"]["outcomes"] == [ir.velocity] and out["impulse-ratio"]["valid"] == [ir.valid]
    three = F.outcomes_per_law(sp.eye(3), "-1,1,0;0,-1,1", "1,0,0")
    assert three["two-surface"]["outcomes"] and "expected 1 ratio(s) alpha_12 " in three["impulse-ratio"]["note"]


def test_laws_side_by_side_runs_on_the_three_scenes():
    for scene in ("cradle", "two-balls-wall", "pool"):
        fig, src = F.laws_side_by_side(scene)
        assert src["laws"]["sequential"]["outcomes"]
    with pytest.raises(F.ImpactInputError, match="scene"):
        F.laws_side_by_side("billiards")


def test_speed_against_error_reads_the_committed_bench():
    fig, src = F.speed_against_error(ROOT / "benchmarks/results/bench.json")
    data = json.loads((ROOT / "benchmarks/results/bench.json").read_text())
    assert set(src["backends"]) == {r["backend"] for r in data["results"]}



def test_layout_is_deferred_to_the_drawing_and_gives_the_same_pixels(tmp_path):
    """A figure is laid out (tight) when it is drawn, not when it is built: save and show lay it
    out at its own dpi first, so the pixels are those of ``tight_layout()`` at the end of building."""
    from matplotlib.layout_engine import TightLayoutEngine

    def build():
        return F.two_surface_figure("2,0;0,1", "1,0;-1,1", "-1,-1")[0]

    eager = build()
    assert isinstance(eager.get_layout_engine(), TightLayoutEngine)  # nothing laid out yet
    eager.tight_layout()
    assert not isinstance(eager.get_layout_engine(), TightLayoutEngine)  # laid out once, then no engine runs
    eager.savefig(tmp_path / "eager.png", dpi=100)
    F.save(build(), tmp_path / "deferred.png")
    assert (tmp_path / "eager.png").read_bytes() == (tmp_path / "deferred.png").read_bytes()
    shown = build()
    before = shown.subplotpars.left
    png = F.show(shown).data
    assert shown.subplotpars.left != before and png[:8] == b"\x89PNG\r\n\x1a\n"
    # and no engine is left behind (not even tight_layout's placeholder, which would cost savefig a
    # priming draw): the eager figure above, saved with it, gave the same bytes
    assert shown.get_layout_engine() is None


def test_readme_figures_source_data_are_current(tmp_path):
    """The committed docs/figures/*.json are what the figure functions compute now (regenerate
    with ``python -m impactsym.figures docs/figures``)."""
    new = F.write_readme_figures(tmp_path, pixels=False)
    for name in F.README_FIGURES:
        committed = ROOT / "docs" / "figures" / f"{name}.json"
        assert committed.exists(), f"missing {committed}: run python -m impactsym.figures docs/figures"
        assert (ROOT / "docs" / "figures" / f"{name}.png").exists()
        assert json.loads(committed.read_text()) == json.loads((tmp_path / f"{name}.json").read_text()), (
            f"{name}: committed source data differ; run python -m impactsym.figures docs/figures")
        assert new[name]


def test_save_writes_a_png(tmp_path):
    fig, _ = F.sm_fig1_convex_corner()
    path = F.save(fig, tmp_path / "f.png")
    assert Path(path).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_two_surface_figure_any_dimension_float_input_and_large_counts():
    fig, src = F.two_surface_figure(np.diag([1.1, 1.0]), [[1.0, 0], [-1, 1]], [-1.0, -2])
    assert src["counts"] == src["iterated_counts"] == {"0": 4, "1": 4}
    fig, src = F.two_surface_figure("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,1,0")
    assert src["exits"] == {"1": ["0", "1", "1"]} and src["iterated_counts"] == {"1": 2}
    fig, src = F.two_surface_figure("1,0;0,1", "1,0;-1000000,1", "-1,0")  # 1570797 reflections, not iterated
    assert src["counts"] == {"0": 1570797} and src["iterated_counts"] == {"0": None} and src["bound"] == 3141593
    with pytest.raises(F.ImpactInputError, match="two rows"):
        F.two_surface_figure("1,0;0,1", "1,0", "-1,0")


@pytest.mark.parametrize("args", [("chain3",), ("pool", "pi/4"), ("pool", "2*pi/3"), ("pool", "pi/4", "pi/6"),
                                  ("pool", "pi/4", "pi")])
def test_domain_figure_draws_the_validity_domain(args):
    fig, src = F.domain_figure(*args)
    dom = validity_domain(*args)
    if dom.region["empty"]:
        assert src["empty"]
    else:
        assert [sp.sympify(x) for x in src["e"]] == list(dom.region["e"])


def test_fig2_pool_kinetic_angle_is_eq42_corrected_sign():
    fig, src = F.at_fig2_pool("pi/3")
    assert src["cos_kinetic_angle_12"] == "-1/4"  # -cos(theta)/2 at theta = pi/3
    assert src["v0"][:2] == ["1/2", "sqrt(3)/2"]


def test_planar_chain_degree_and_zero_ratio_follow_the_coupling_criteria():
    from impactsym.laws.coupling import impact_degree
    from impactsym.scenes import balls_in_plane

    fig, src = F.at_fig5_planar_chain()
    pos = [tuple(sp.sympify(c) for c in p) for p in src["positions"]]
    sc = balls_in_plane([1] * 5, [1] * 5, pos, [(1, 0)] + [(0, 0)] * 4)
    assert src["impact_degree"] == impact_degree(sc.M, sc.H, sc.v) == 3
    assert src["coupled_consecutive"] == [True, True, False]
    assert src["ratios_used"][-1] == "0" and src["impulses"][-1] == "0"  # no impulse past the uncoupled contact
    v = _m(src["velocity"])
    assert list(v[8:]) == [0, 0]  # ball 5 stays at rest
    p = _m(src["impulses"])
    assert sc.M * (v - sc.v) == sc.H.T * p  # momentum balance, exactly
    assert kinetic_energy(sc.M, v) == kinetic_energy(sc.M, sc.v)  # e = 1


def test_ordering_regions_with_irrational_gradients():
    M, H = sp.eye(2), sp.Matrix([[1, 0], [-1, sp.sqrt(3)]])  # a wedge of pi/3
    regs = F.ordering_regions(M, H)
    dirs = [tuple(g["from"]) for g in regs]
    assert len(set(dirs)) == len(dirs)  # one ray per direction
    for g in regs:
        s = _m(g["from"]) + _m(g["to"])
        it = resolve_sequential(M, H, s, two_surface="iterate", select=False)
        assert {o[0]: list(o) for o, _ in it.iter_orderings()} == g["orders"]
    assert max(len(o) for g in regs for o in g["orders"].values()) <= termination_bound(M, H) == 3
