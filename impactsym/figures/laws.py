"""Figures across laws: one impact under every law, the two-surface iteration, a scene's valid
domain, a resolved impact (``impactsym plot``), and the benchmark's speed against error.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import sympy as sp

from ..errors import ImpactInputError
from ._common import _f, _fill_wedges, _plt, _s, _tight, _vs, _plane_basis
from .acary_taha import at_domain_over_theta, at_fig3_domain

__all__ = [
    "two_surface_figure", "domain_figure", "LAWS", "outcomes_per_law", "laws_side_by_side", "resolve_figure",
    "speed_against_error", "MAX_DRAWN_REFLECTIONS"
]


# --------------------------------------------------------------------------- two surfaces (sec. III-C)
#: iterates drawn per branch by :func:`two_surface_figure` (the count itself is never capped)
MAX_DRAWN_REFLECTIONS = 200


def _exact_inputs(M, H, v):
    """``M``, ``H``, ``v`` checked and exact: float entries taken at their exact binary value (as the
    laws decide float input)."""
    from ..mechanics import check_gradients, check_mass_matrix, check_velocity
    from ..numbers import float_to_rational

    Mx = check_mass_matrix(M)
    n = Mx.shape[0]
    Hx, vx = check_gradients(H, n), check_velocity(v, n)

    def ex(A):
        A = sp.Matrix(np.asarray(A, dtype=object).tolist()) if not isinstance(A, sp.MatrixBase) else A
        return A.applyfunc(lambda x: float_to_rational(float(x)) if isinstance(x, (float, np.floating))
                           or getattr(x, "is_Float", False) else sp.sympify(x))
    return ex(Mx), ex(Hx), ex(vx).reshape(n, 1)


def two_surface_figure(M, H, v, *, title=None):
    """The two-surface law as a picture, in any dimension: the plane of the two M-normals (sec. III-C).

    In M-orthonormal coordinates of that plane the valid velocities form a wedge of opening ``β``
    (π minus the kinetic angle); each pair of reflections rotates ``v`` by ``2β``, so the branch
    that starts with surface ``i`` ends after ``⌈ψᵢ/β⌉`` reflections, never more than
    ``N = ⌈π/β⌉``. The counts, ``β``, ``N`` and the exits are read from
    :func:`impactsym.laws.two_surface.resolve_two_surfaces`; the drawn iterates are single
    reflections (``G_u w`` with :func:`impactsym.laws.reflection.reflection_map` on rational data,
    :func:`impactsym.laws.reflection.reflect` otherwise), at most :data:`MAX_DRAWN_REFLECTIONS`
    per branch. One panel per branch.

    Returns
    -------
    (Figure, dict) : ``counts`` (the law's, per first surface), ``iterated_counts`` (by explicit
    iteration, ``None`` beyond the drawing cap), ``bound``, ``wedge_angle``, ``exits``.

    Examples
    --------
    The 3-ball cradle, balls 1 and 2 striking ball 3 (3-D; eq. 4):

    >>> fig, src = two_surface_figure("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,1,0")
    >>> src["counts"], src["exits"], src["bound"]
    ({'1': 2}, {'1': ['0', '1', '1']}, 3)
    """
    from matplotlib.collections import LineCollection

    from ..laws.reflection import reflect, reflection_map
    from ..laws.two_surface import resolve_two_surfaces

    plt = _plt()
    Mx, Hx, vx = _exact_inputs(M, H, v)
    if Hx.shape[0] != 2:
        raise ImpactInputError("gradients", f"the two-surface picture needs exactly two rows, got {Hx.shape[0]}")
    res = resolve_two_surfaces(Mx, Hx, vx)
    Mf, e1, e2 = _plane_basis(Mx, Hx)
    Hf = np.array(Hx.evalf(17).tolist(), dtype=float)

    def coords(w):
        wf = _f(w)
        return np.array([wf @ Mf @ e1, wf @ Mf @ e2])

    # rational data: each single reflection is G_u w with G_u = reflection_map(M, u) formed once (the
    # same exact rationals as reflect(M, u, w), which checks its inputs and verifies every call: most
    # of the cost of a figure with MAX_DRAWN_REFLECTIONS iterates); otherwise reflect itself
    rational = all(x.is_Rational for A in (Mx, Hx, vx) for x in A)
    Gs = [reflection_map(Mx, Hx[j, :]) for j in (0, 1)] if rational else None

    def valid(w):  # H w >= 0, exactly
        return all((c >= 0) if rational else (sp.sign(c) >= 0) for c in Hx * w)

    panels = len(res.outcomes)
    fig, axes = plt.subplots(1, panels, figsize=(5.2 * panels, 5.2), squeeze=False)
    counts, iterated = {}, {}
    beta = float(res.wedge_angle)
    t = np.linspace(0, 2 * np.pi, 721)
    dirs = np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2)
    ok = ((dirs @ Hf.T) >= 0).all(axis=1)
    x0 = coords(vx)
    rad = float(np.linalg.norm(x0)) or 1.0
    for ax, o in zip(axes[0], res.outcomes):
        _fill_wedges(ax, t, ok, 1.6, facecolor="C2", edgecolor="C2", alpha=0.25, linewidth=0)
        ax.fill([], [], color="C2", alpha=0.25, label=f"valid wedge, opening beta = {beta:.6g} rad")
        pts = [x0]
        if o.first in (0, 1):
            w, i, m = vx, o.first, 0
            while not valid(w) and m < MAX_DRAWN_REFLECTIONS:
                w = Gs[i] * w if rational else reflect(Mx, Hx[i, :], w)
                i, m = 1 - i, m + 1
                pts.append(coords(w))
            done = valid(w)
            iterated[str(o.first)] = m if done else None
        if not iterated.get(str(o.first)):
            pts.append(np.array([o.velocity_float @ Mf @ e1, o.velocity_float @ Mf @ e2]))
        # the rays to the iterates, as one collection of the same segments in the same order and style
        # as one ax.plot each (up to MAX_DRAWN_REFLECTIONS + 2 lines; the PNG is byte-identical)
        ax.add_collection(LineCollection([[(0, 0), (p[0] / rad, p[1] / rad)] for p in pts], linewidths=1.2,
                                         colors=[plt.cm.viridis(k / max(1, len(pts) - 1)) for k in range(len(pts))],
                                         capstyle=plt.rcParams["lines.solid_capstyle"],
                                         joinstyle=plt.rcParams["lines.solid_joinstyle"]), autolim=False)
        for k, p in enumerate(pts):
            if len(pts) <= 40:
                ax.text(1.08 * p[0] / rad, 1.08 * p[1] / rad, str(k), fontsize=7, ha="center", va="center")
        ax.plot(np.cos(t), np.sin(t), color="0.7", lw=0.5)
        counts[str(o.first)] = o.reflections
        ax.set_xlim(-1.3, 1.3)
        ax.set_ylim(-1.3, 1.3)
        ax.set_aspect("equal")
        cap = "" if iterated.get(str(o.first)) is not None or o.first not in (0, 1) else \
            f" ({MAX_DRAWN_REFLECTIONS} drawn)"
        ax.set_title(f"first surface {o.first}: {o.reflections} reflections{cap} (law: ceil(psi/beta))\n"
                     f"two reflections rotate v by 2 beta; bound N = ceil(pi/beta) = {res.bound}", fontsize=9)
        ax.legend(fontsize=7, loc="lower left")
    fig.suptitle(title or "The two-surface law in the plane of the two M-normals (iterate k; sec. III-C)", fontsize=10)
    _tight(fig)
    return fig, {"M": [_vs(Mx.row(i)) for i in range(Mx.shape[0])], "H": [_vs(Hx.row(i)) for i in range(2)],
                 "v0": _vs(vx), "counts": counts, "iterated_counts": iterated, "bound": res.bound,
                 "wedge_angle": str(res.as_dict()["wedge_angle"]), "kinetic_angle_cos": _s(res.kinetic_angle_cos),
                 "exits": {str(o.first): (_vs(o.velocity) if o.exact else [float(x) for x in o.velocity_float])
                           for o in res.outcomes}}


# --------------------------------------------------------------------------- valid domains
def domain_figure(scene: str, theta=None, tau=None):
    """The validity domain that :func:`impactsym.domains.validity_domain` returns, drawn (what
    ``impactsym domain --plot`` writes).

    ``chain3``: eq. 19's domain (the pool's curves at θ = 0); ``pool`` without θ: the small
    multiples of :func:`at_domain_over_theta`; ``pool`` at θ: :func:`at_fig3_domain` (the
    three-contact panel at θ = 2π/3); at ``τ ≠ 0`` the mapped curves ``g_tau``, ``h_tau`` as the
    library gives them (an empty domain is drawn empty, with its reason).

    Examples
    --------
    >>> fig, src = domain_figure("pool", "pi/4", "pi/6")
    >>> src["e"]
    ['4/7', '1']
    """
    from ..domains import alpha as A, plot_domain, validity_domain

    plt = _plt()
    if scene == "pool" and theta is None:
        if tau is not None:
            raise ImpactInputError("tau", "needs theta (the domain at one (theta, tau))")
        return at_domain_over_theta()
    dom = validity_domain(scene, theta, tau)
    src = {"scene": scene, "theta": None if dom.theta is None else _s(dom.theta),
           "tau": None if dom.tau is None else _s(dom.tau), "empty": bool(dom.region["empty"])}
    if scene == "chain3":
        fig, ax = plt.subplots(figsize=(6, 4.5))
        plot_domain(0, None, ax=ax)
        ax.set_title("Acary & Taha eq. 19: valid domain of the 3-ball chain (the pool's curves at theta = 0)",
                     fontsize=9)
        _tight(fig)
    elif tau is None or sp.sympify(tau) == 0:
        if len(dom.boundaries) == 4:
            return at_fig3_domain(dom.theta)
        fig, s2 = at_domain_over_theta([dom.theta])
    elif dom.region["empty"]:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        ax.text(0.5, 0.5, "empty domain:\n" + dom.region["description"], ha="center", va="center", wrap=True,
                fontsize=8, transform=ax.transAxes)
        ax.set_xlabel("alpha_12")
        ax.set_ylabel("e")
        _tight(fig)
        return fig, src
    else:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        xs = np.linspace(0, 1.5, 400)
        b = {x.name: x.expression for x in dom.boundaries}
        g = sp.lambdify(A, b["g_tau"], "numpy")(xs) * np.ones_like(xs)
        h = sp.lambdify(A, b["h_tau"], "numpy")(xs) * np.ones_like(xs)
        ax.plot(xs, g, label="g_tau: v1+ = 0 at this (theta, tau)")
        ax.plot(xs, h, ls="--", label="h_tau: Delta = 0")
        lo, hi = (float(sp.N(x, 17)) for x in dom.region["alpha"])
        m = (xs >= lo) & (xs <= hi)
        ax.fill_between(xs[m], g[m], 1, color="C2", alpha=0.3, label="valid domain")
        ax.set_xlim(0, 1.5)
        ax.set_ylim(0, 1.05)
        ax.set_xlabel("alpha_12")
        ax.set_ylabel("e")
        ax.legend(fontsize=8, loc="lower right")
        ax.set_title(f"valid domain of the pool, theta = {_s(dom.theta)}, tau = {_s(dom.tau)}", fontsize=10)
        _tight(fig)
    src.update(alpha=_vs(dom.region["alpha"]), e=_vs(dom.region["e"]))
    return fig, src


# --------------------------------------------------------------------------- laws side by side
#: the laws :func:`outcomes_per_law` asks, in order (CLI names)
LAWS = ("sequential", "two-surface", "newton", "poisson", "energetic", "han-gilmore", "impulse-ratio")


def outcomes_per_law(M, H, v, restitution=1, ratios=None) -> dict:
    """Every law's outcome(s) for one impact ``(M, H, v)``: ``{law: {"outcomes": [...], "note": ...}}``.

    Each law is called as the library defines it; a law that does not apply (two-surface needs
    exactly two rows; impulse-ratio needs ``ratios``) or refuses the input says why in ``note``
    and has no outcomes. Outcome velocities are exact when the input is. ``valid`` lists, per
    outcome, whether the law reports it admissible.

    Examples
    --------
    >>> out = outcomes_per_law("1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", ratios=["19/20"])
    >>> [list(o) for o in out["newton"]["outcomes"]], [list(o) for o in out["sequential"]["outcomes"]]
    ([[-1/3, 2/3, 2/3]], [[0, 0, 1]])
    >>> [list(o) for o in out["impulse-ratio"]["outcomes"]]
    [[-19/381, 20/381, 380/381]]
    """
    from ..lawbook import resolve_all
    from ..resolution import System

    system = System.from_matrices(M, H, v, restitution)
    opts = {law: {"allow_invalid": True} for law in ("newton", "poisson", "energetic", "impulse-ratio")}
    if ratios is not None:
        opts["impulse-ratio"]["ratios"] = list(ratios)
    out: dict = {}
    for law, r in resolve_all(system, laws=LAWS, options=opts).items():
        if isinstance(r, str):
            out[law] = {"outcomes": [], "valid": [], "note": r}
            continue
        outs = [o for o in r.outcomes if o.velocity is not None]
        note = "; ".join(r.notes[:1])
        if law == "sequential":
            note = f"selected: {[list(s.velocity) for s in r.selected]}"
        elif law == "two-surface":
            note = f"bound N = {r.details['bound']}"
        elif law == "han-gilmore":
            note = f"{len(outs)} outcome(s)"
        elif law == "impulse-ratio":
            note = ("no real solution (negative discriminant)" if not outs else
                    f"ratios {list(r.raw.ratios)}" + ("" if r.valid else ": outside the domain"))
        out[law] = {"outcomes": [o.velocity for o in outs], "valid": [o.valid for o in outs], "note": note}
    return out


def laws_figure_from_json(result: dict):
    """The picture of ``impactsym resolve --law all --json``'s answer: a panel per law, a bar per
    velocity component for each of its outcomes (hatched when invalid).

    >>> fig = laws_figure_from_json({"system": {"velocity_float": [1.0, 0.0], "coordinates": []},
    ...     "laws": {"newton": {"outcomes": [{"velocity_float": [0.0, 1.0], "valid": True}]},
    ...              "two-surface": {"refused": "does not apply"}}})
    >>> len(fig.axes)
    2
    """
    plt = _plt()
    v0 = result["system"]["velocity_float"]
    n = len(v0)
    laws = list(result["laws"])
    fig, axes = plt.subplots(1, len(laws), figsize=(2.3 * len(laws), 3.8), sharey=True, squeeze=False)
    for ax, law in zip(axes[0], laws):
        r = result["laws"][law]
        outs = [o for o in r.get("outcomes", []) if o.get("velocity_float") is not None][:6]
        w = 0.8 / max(1, len(outs))
        for j, o in enumerate(outs):
            ok = o.get("valid", True)
            vals = [np.nan if x is None else x for x in o["velocity_float"]]
            ax.bar(np.arange(n) + j * w, vals, w, color=f"C{j % 10}", alpha=1 if ok else 0.35,
                   hatch=None if ok else "//")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xticks(np.arange(n))
        names = result["system"].get("coordinates") or [f"q{i + 1}" for i in range(n)]
        ax.set_xticklabels(names, fontsize=6, rotation=90)
        ax.set_title(f"{law}\n{len(r.get('outcomes', []))} outcome(s)" if "refused" not in r else f"{law}\n(none)",
                     fontsize=8)
        if "refused" in r:
            ax.text(0.5, 0.5, r["refused"][:60], transform=ax.transAxes, fontsize=6, ha="center", wrap=True)
    axes[0][0].set_ylabel("exit velocity")
    fig.suptitle("impactsym resolve --law all: every law's outcomes (hatched: invalid)", fontsize=10)
    _tight(fig)
    return fig


def laws_side_by_side(scene="cradle", ratios=None, *, max_drawn: int = 6):
    """One scene under every law (:func:`outcomes_per_law`): a panel per law, a bar per velocity component.

    ``scene``: ``"cradle"`` (5 balls, 2 strikers), ``"two-balls-wall"`` (masses 11/10, 1) or
    ``"pool"`` (the planar break at θ = π/4, ratio α₁₂ = 1 by default), or a
    :class:`impactsym.scenes.Scene`. At most ``max_drawn`` outcomes per law are drawn (the source
    data hold them all).

    Examples
    --------
    >>> fig, src = laws_side_by_side("two-balls-wall")
    >>> src["laws"]["sequential"]["outcomes"]
    [['173/147', '278/147'], ['359/441', '922/441']]
    """
    from ..models import acary_taha, seghete_murphey
    from ..scenes import Scene

    plt = _plt()
    if isinstance(scene, Scene):
        sc, name = scene, scene.meta.get("scene", "scene")
    elif scene == "cradle":
        sc, name = seghete_murphey.cradle(5, 2), "5-ball cradle, 2 strikers"
    elif scene == "two-balls-wall":
        sc, name = seghete_murphey.two_balls_wall(masses=("11/10", 1)), "two balls (masses 11/10, 1) and a wall"
    elif scene == "pool":
        sc, name = acary_taha.pool(sp.pi / 4), "planar break: the pool at theta = pi/4"
        ratios = ["1"] if ratios is None else ratios
    else:
        raise ImpactInputError("scene", f"must be 'cradle', 'two-balls-wall', 'pool' or a Scene, got {scene!r}")
    res = outcomes_per_law(sc.M, sc.H, sc.v, 1, ratios)
    n = sc.M.shape[0]
    fig, axes = plt.subplots(1, len(LAWS), figsize=(2.3 * len(LAWS), 3.8), sharey=True)
    for ax, law in zip(axes, LAWS):
        r = res[law]
        shown = list(zip(r["outcomes"], r["valid"]))[:max_drawn]
        w = 0.8 / max(1, len(shown))
        for j, (o, ok) in enumerate(shown):
            ax.bar(np.arange(n) + j * w, _f(o), w, color=f"C{j % 10}", alpha=1 if ok else 0.35,
                   hatch=None if ok else "//")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xticks(np.arange(n))
        ax.set_xticklabels(sc.coordinates, fontsize=6, rotation=90)
        more = f" ({len(shown)} drawn)" if len(shown) < len(r["outcomes"]) else ""
        ax.set_title(f"{law}\n{len(r['outcomes'])} outcome(s){more}" if r["outcomes"] else f"{law}\n(none)", fontsize=8)
        if not r["outcomes"]:
            ax.text(0.5, 0.5, r["note"][:60], transform=ax.transAxes, fontsize=6, ha="center", wrap=True)
    axes[0].set_ylabel("exit velocity")
    fig.suptitle(f"Every law on one scene: {name} (v0 = {_vs(sc.v)}); hatched: invalid", fontsize=10)
    _tight(fig)
    src = {"scene": name, "v0": _vs(sc.v),
           "laws": {law: {"outcomes": [_vs(o) for o in r["outcomes"]], "valid": list(r["valid"]), "note": r["note"]}
                    for law, r in res.items()}}
    return fig, src


def resolve_figure(law: str, M, H, v, result: dict):
    """The picture for one ``impactsym resolve`` answer (what ``--plot`` writes).

    Two surfaces (``--law two-surface``, or ``--law sequential`` with two linearly independent
    rows): :func:`two_surface_figure`, the law in the plane of the two M-normals. Otherwise the
    velocities before and after, one bar group per coordinate, read from ``result`` (the CLI's JSON
    answer, so the picture shows exactly the outcomes printed).

    Examples
    --------
    >>> r = {"law": "newton", "velocity_float": [-1/3, 2/3, 2/3], "valid": True}
    >>> fig, src = resolve_figure("newton", "1,0,0;0,1,0;0,0,1", "-1,1,0;0,-1,1", "1,0,0", r)
    >>> src["kind"], src["outcomes_float"]
    ('velocities', [[-0.3333333333333333, 0.6666666666666666, 0.6666666666666666]])
    """
    Mx, Hx, vx = _exact_inputs(M, H, v)
    if law == "two-surface" or (law == "sequential" and Hx.shape[0] == 2 and Hx.rank() == 2):
        fig, src = two_surface_figure(Mx, Hx, vx, title=f"impactsym resolve --law {law}: the two surfaces in the "
                                                        "plane of their M-normals (iterate k)")
        src["kind"] = "two-surface"
        return fig, src
    plt = _plt()
    if result.get("outcomes"):
        outs = [o["velocity_float"] for o in result["outcomes"]]
    elif result.get("velocity_float") is not None:
        outs = [result["velocity_float"]]
    else:
        outs = []
    n = Mx.shape[0]
    fig, ax = plt.subplots(figsize=(max(5.0, 0.9 * n + 2), 4))
    groups = [("v- (before)", _f(vx))] + [(f"v+ outcome {j + 1}" if len(outs) > 1 else "v+ (after)", np.asarray(o, float))
                                          for j, o in enumerate(outs[:8])]
    w = 0.8 / len(groups)
    for j, (label, vals) in enumerate(groups):
        ax.bar(np.arange(n) + j * w, vals, w, label=label, color="0.6" if j == 0 else f"C{(j - 1) % 10}")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xticks(np.arange(n) + 0.4 - w / 2)
    ax.set_xticklabels([f"q{i + 1}" for i in range(n)])
    more = f" ({len(outs)} outcomes, 8 drawn)" if len(outs) > 8 else ""
    valid = result.get("valid")
    ax.set_title(f"impactsym resolve --law {law}{more}" + ("" if valid is None else f"; valid: {valid}"), fontsize=10)
    ax.legend(fontsize=7)
    _tight(fig)
    return fig, {"kind": "velocities", "law": law, "v0": _vs(vx), "outcomes_float": [list(map(float, o)) for o in outs]}


# --------------------------------------------------------------------------- benchmark
def speed_against_error(result):
    """The benchmark's plot: throughput against max relative error, per formula and backend.

    ``result`` is the dict of :func:`impactsym.bench.run` (or the committed
    ``benchmarks/results/bench.json``, a path or the parsed dict). Read it right to left for speed
    and bottom to top for accuracy: each backend's markers form a band.

    Examples
    --------
    >>> r = {"results": [{"formula": "f", "backend": "numpy-batched", "case_set": "uniform",
    ...                   "evals_per_second": 1e7, "max_rel_error": 2e-16}]}
    >>> fig, src = speed_against_error(r)
    >>> src["best"]["uniform"]["numpy-batched"]
    [10000000.0, 2e-16]
    """
    plt = _plt()
    if isinstance(result, (str, Path)):
        result = json.loads(Path(result).read_text())
    rows = result["results"]
    backends = sorted({r["backend"] for r in rows})
    formulas = sorted({r["formula"] for r in rows})
    markers = dict(zip(backends, "os^vDPXh*"))
    colors = {b: plt.cm.tab10.colors[i % 10] for i, b in enumerate(backends)}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    floor = 1e-18
    best: dict = {}
    for ax, case in zip(axes, ("uniform", "hard")):
        best[case] = {}
        for b in backends:
            pts = [(r["evals_per_second"], max(r["max_rel_error"], floor)) for r in rows
                   if r["case_set"] == case and r["backend"] == b and r.get("max_rel_error") is not None]
            if not pts:
                continue
            P = np.array(pts)
            ax.scatter(P[:, 0], P[:, 1], marker=markers[b], color=colors[b], s=45, alpha=0.85, label=b)
            med = [float(np.median(P[:, 0])), float(np.max(P[:, 1]))]
            best[case][b] = med
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axhline(float(np.finfo(float).eps), color="grey", ls=":", lw=0.8)
        ax.set_xlabel("throughput (evaluations / s)")
        ax.set_title(f"{case} case set ({len(formulas)} formulas)", fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("max relative error vs 50-digit reference")
    if axes[1].collections:
        axes[1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1))
    fig.suptitle("Speed against error of every evaluation path (dotted: machine epsilon)")
    _tight(fig)
    return fig, {"backends": backends, "formulas": formulas, "best": best}
