"""The papers' figures, drawn from the laws (Seghete & Murphey; Acary & Taha).

One function per figure, named after it (``sm_`` Seghete & Murphey, ``at_`` Acary & Taha). Each
returns ``(figure, source)``: the matplotlib ``Figure`` and a small dict of the *source data* it
drew, exact numbers as strings (SymPy ``str``). Every number comes from a call into the library
(:mod:`impactsym.laws`, :mod:`impactsym.domains`, :mod:`impactsym.simulate`,
:mod:`impactsym.compliant`, the scenes of :mod:`impactsym.models`); no formula of a paper is typed
here. Matplotlib (Agg backend) is imported inside the functions, so ``import impactsym`` stays light.

``python -m impactsym.figures DIR`` writes the README's figures (:data:`README_FIGURES`) into
``DIR`` as PNGs, each with a ``.json`` of its source data beside it; ``tests/test_figures.py``
regenerates the source data and compares it with the committed JSON (not the pixels).

Examples
--------
>>> fig, src = sm_fig4_configuration_space()
>>> src["v4a"], src["v4b"]
(['173/147', '278/147'], ['359/441', '922/441'])
>>> src["claim_sector_t"]
['23/19', '439/40']
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import sympy as sp

from ..errors import ImpactInputError
from ..numbers import exact_str

__all__ = [
    "sm_fig1_convex_corner", "sm_fig2_concave_corner", "sm_fig4_configuration_space", "ordering_regions",
    "sm_fig5_cradle_kinetic_plane", "sm_sec3c_termination", "two_surface_figure", "sm_three_surface_overgeneration",
    "at_fig2_pool", "at_fig3_domain", "at_domain_over_theta", "domain_figure", "at_chain3_velocities", "at_fig4_bernoulli",
    "at_fig5_transmission", "at_fig5_planar_chain", "outcomes_per_law", "laws_side_by_side", "resolve_figure", "speed_against_error",
    "README_FIGURES", "write_readme_figures", "save", "show",
]


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _s(x) -> str:
    return exact_str(sp.sympify(x))


def _vs(v) -> list:
    return [_s(x) for x in v]


def _f(v) -> np.ndarray:
    return np.array([float(sp.N(x, 17)) for x in v], dtype=float)


def save(fig, path) -> str:
    """Write ``fig`` to ``path`` (the format from its suffix, 100 dpi) and close it; return the path as text.

    >>> import os, tempfile
    >>> fig, _ = at_fig3_domain()
    >>> os.path.getsize(save(fig, os.path.join(tempfile.mkdtemp(), "fig3.png"))) > 0
    True
    """
    fig.savefig(path, dpi=100)
    _plt().close(fig)
    return str(path)


def show(fig):
    """The figure as an ``IPython.display.Image`` (PNG), for a notebook cell's last line; closes ``fig``.

    With the Agg backend a bare ``Figure`` displays as text; this shows the picture, once.

    >>> fig, _ = sm_fig1_convex_corner()
    >>> show(fig).format
    'png'
    """
    import io

    from IPython.display import Image

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    _plt().close(fig)
    return Image(data=buf.getvalue(), format="png")


# --------------------------------------------------------------------------- kinetic coordinates
def _kinetic_frame(M):
    """``L`` with ``M = L Lᵀ`` (floats): ``x = Lᵀ v`` are coordinates in which the kinetic metric
    is Euclidean, so reflections ``G_u`` look like mirror images."""
    Mf = np.array(sp.Matrix(M).evalf(17).tolist(), dtype=float)
    return np.linalg.cholesky(Mf)


def _kin(L, v) -> np.ndarray:
    return L.T @ _f(v)


def _ray(ax, x, *, scale=1.0, **kw):
    ax.annotate("", xy=(scale * x[0], scale * x[1]), xytext=(0, 0),
                arrowprops=dict(arrowstyle="->", lw=kw.pop("lw", 1.6), color=kw.pop("color", "k"), **kw))


def _shade_cone(ax, L, H, *, either=False, color="C2", alpha=0.25, radius=2.5, label=None):
    """Shade, in kinetic coordinates, the velocities with ``H v ≥ 0`` (all rows; ``either``: any row)."""
    t = np.linspace(0, 2 * np.pi, 721)
    xs = np.stack([np.cos(t), np.sin(t)])
    v = np.linalg.solve(L.T, xs)  # back to velocities
    Hf = np.array(sp.Matrix(H).evalf(17).tolist(), dtype=float)
    w = Hf @ v
    ok = (w >= 0).any(axis=0) if either else (w >= 0).all(axis=0)
    for k in range(len(t) - 1):
        if ok[k] and ok[k + 1]:
            ax.fill([0, radius * xs[0, k], radius * xs[0, k + 1]], [0, radius * xs[1, k], radius * xs[1, k + 1]],
                    color=color, alpha=alpha, lw=0)
    if label:
        ax.fill([], [], color=color, alpha=alpha, label=label)


def _normal_cone_arc(M, H, v0, samples=61):
    """The energy-preserving exits with the momentum jump in the normal cone, ``{v0 + M⁻¹Hᵀp : p ≥ 0,
    ‖v‖_M = ‖v0‖_M}``: for ``p = (cos s, sin s)`` this is the single reflection across the covector
    ``pᵀH`` (:func:`impactsym.laws.reflection.reflect`). Floats, for drawing."""
    from ..laws.reflection import reflect

    Hf = np.array(sp.Matrix(H).evalf(17).tolist(), dtype=float)
    Mf = np.array(sp.Matrix(M).evalf(17).tolist(), dtype=float)
    vf = _f(v0)
    out = []
    for s in np.linspace(0, np.pi / 2, samples):
        h = np.cos(s) * Hf[0] + np.sin(s) * Hf[1]
        out.append(reflect(Mf, h, vf))
    return np.array(out)


def _corner(kind, M, H, v0):
    from ..laws.reflection import reflect
    from ..laws.sequential import resolve_sequential
    from ..mechanics import check_gradients, check_mass_matrix, check_velocity, kinetic_energy

    Mx = check_mass_matrix(M, exact=True)
    Hx = check_gradients(H, Mx.shape[0], exact=True)
    vx = check_velocity(v0, Mx.shape[0], exact=True)
    if Mx.shape[0] != 2 or Hx.shape[0] != 2:
        raise ImpactInputError("gradients", "the corner figures are planar: a 2x2 mass matrix and two rows")
    if not all(sp.sign(w) < 0 for w in Hx * vx):
        raise ImpactInputError("velocity", "must approach both surfaces (H v0 < 0) to hit the corner")
    plt = _plt()
    L = _kinetic_frame(Mx)
    single = [reflect(Mx, Hx[i, :], vx) for i in range(2)]  # one impact against face i
    dist = [kinetic_energy(Mx, s - vx) for s in single]
    fig, ax = plt.subplots(figsize=(5.6, 5.2))
    # the obstacle and the admissible region, in kinetic coordinates (positions drawn like velocities)
    if kind == "convex":
        _shade_cone(ax, L, -Hx, color="0.3", alpha=0.5, radius=3, label="obstacle (convex wedge)")
        _shade_cone(ax, L, Hx, either=True, color="C2", alpha=0.12, radius=3, label="valid exits: H_1 v >= 0 or H_2 v >= 0")
    else:
        _shade_cone(ax, L, -Hx, either=True, color="0.3", alpha=0.35, radius=3, label="walls (concave corner)")
        _shade_cone(ax, L, Hx, color="C2", alpha=0.12, radius=3, label="valid exits: H v >= 0")
    arc = np.array([L.T @ a for a in _normal_cone_arc(Mx, Hx, vx)])
    ax.plot(arc[:, 0], arc[:, 1], color="C2" if kind == "convex" else "C3", lw=4, alpha=0.8,
            label="feasible (energy, M dv in normal cone)" if kind == "convex" else "normal-cone set (too inclusive)")
    x0 = _kin(L, vx)
    ax.annotate("", xy=(0, 0), xytext=(-x0[0], -x0[1]), arrowprops=dict(arrowstyle="->", lw=2, color="k"))
    ax.text(-x0[0], -x0[1], "  v0 (incoming)", fontsize=8)
    src = {"kind": kind, "M": [_vs(Mx.row(i)) for i in range(2)], "H": [_vs(Hx.row(i)) for i in range(2)],
           "v0": _vs(vx), "single_impacts": [_vs(s) for s in single]}
    best = min(dist)
    if kind == "convex":
        # every point of the arc is a valid exit; the arc's point nearest v0 is an end point
        # (the arc does not contain v0's direction): the single impact with the smaller ||v - v0||_M
        chosen = [s for s, d in zip(single, dist) if d == best]
        for s in single:
            _ray(ax, _kin(L, s), color="C2", lw=1.2)
        for c in chosen:
            _ray(ax, _kin(L, c), color="C0", lw=2.4)
        ax.plot([], [], color="C0", lw=2.4, label="closest to v0 (kinetic metric)")
        src["closest"] = [_vs(c) for c in chosen]
        title = "Fig. 1: a point hits a convex corner"
    else:
        r = resolve_sequential(Mx, Hx, vx)
        naive = [s for s, d in zip(single, dist) if d == best]
        for c in naive:
            _ray(ax, _kin(L, c), color="C3", lw=2.0, linestyle="--")
        ax.plot([], [], color="C3", ls="--", label="naive projection (points into a wall)")
        outs = [o.velocity for o in r.outcomes]
        if len(outs) == 2:
            a0, a1 = (np.arctan2(*(_kin(L, o)[::-1])) for o in outs)
            if abs(a1 - a0) > np.pi:
                a1 += 2 * np.pi if a1 < a0 else -2 * np.pi
            t = np.linspace(a0, a1, 50)
            rad = float(np.linalg.norm(x0))
            ax.plot(rad * np.cos(t), rad * np.sin(t), color="C0", lw=4, alpha=0.6, label="feasible set from orderings")
        for o in outs:
            _ray(ax, _kin(L, o), color="C0", lw=1.2)
        for s in r.selected:
            _ray(ax, _kin(L, s), color="C0", lw=2.4)
        ax.plot([], [], color="C0", lw=2.4, label="selected (sequential law, energy reading)")
        src.update(naive_projection=[_vs(c) for c in naive],
                   naive_valid=[all(w >= 0 for w in Hx * c) for c in naive],
                   outcomes=[_vs(o) for o in outs], orders=[list(o.order) for o in r.outcomes],
                   selected=[_vs(s) for s in r.selected])
        title = "Fig. 2: a point hits a concave corner"
    lim = 1.25 * float(np.linalg.norm(x0))
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_title(title + " (kinetic coordinates)", fontsize=10)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    return fig, src


def sm_fig1_convex_corner(M="1,0;0,1", H="1,0;-1,1", v0="-1,-2"):
    """Seghete & Murphey Fig. 1: a point hits the tip of a convex wedge.

    The feasible exits (energy kept, momentum jump in the normal cone ``cone(Hᵀ)``) form the arc of
    single reflections across the covectors ``pᵀH``, ``p ≥ 0`` (:func:`impactsym.laws.reflection.reflect`);
    every one of them leaves the obstacle. The outcome closest to ``v0`` in the kinetic metric is
    an end of the arc: the single impact against one face (``kinetic_energy`` compares them exactly).

    Returns
    -------
    (Figure, dict) : ``single_impacts`` (``G_{H_i} v0``) and ``closest`` as exact strings.

    Examples
    --------
    >>> fig, src = sm_fig1_convex_corner()
    >>> src["single_impacts"], src["closest"]
    ([['1', '-2'], ['-2', '-1']], [['-2', '-1']])
    """
    return _corner("convex", M, H, v0)


def sm_fig2_concave_corner(M="11/10,0;0,1", H="1,0;-1,1", v0="-1,-2"):
    """Seghete & Murphey Fig. 2: the same corner from the inside (the two-balls-and-wall corner).

    The normal-cone set of Fig. 1 is too inclusive here: its point nearest ``v0`` is a single
    reflection, which still points into the other wall (``naive_valid`` False). The feasible set
    from the impact orderings (:func:`impactsym.laws.sequential.resolve_sequential`) and its
    selection are drawn instead.

    Examples
    --------
    >>> fig, src = sm_fig2_concave_corner()
    >>> src["naive_valid"], src["outcomes"]
    ([False], [['173/147', '278/147'], ['359/441', '922/441']])
    """
    return _corner("concave", M, H, v0)


# --------------------------------------------------------------------------- Fig. 4
def ordering_regions(M, H, depth: int | None = None) -> list[dict]:
    """The sectors of incoming velocities (2-D, two surfaces) on which every branch's ordering is fixed.

    A branch's ordering can change only where an iterate grazes a surface: ``H_j P v0 = 0`` for a
    partial product ``P`` of reflections (:func:`impactsym.laws.reflection.reflection_map`). Those
    rays cut the plane into sectors; a point strictly inside each (the sum of its bounding rays)
    is resolved exactly by :func:`impactsym.laws.two_surface.resolve_two_surfaces`.

    Returns
    -------
    list of dict, by angle: ``from``/``to`` (rays, exact), ``orders`` (first surface -> ordering),
    ``outcomes`` (first surface -> the outcome as the matrix applied to ``v0``), ``approaching``
    (which contacts ``H_i v0 < 0`` inside the sector).

    Examples
    --------
    >>> regs = ordering_regions("11/10,0;0,1", "1,0;-1,1")
    >>> [(r["from"], r["to"], {k: len(v) for k, v in r["orders"].items()}) for r in regs if all(r["approaching"])]
    [(['-1', '-1'], ['-19', '-23'], {0: 3, 1: 4}), (['-19', '-23'], ['-40', '-439'], {0: 4, 1: 4}), (['-40', '-439'], ['0', '-1'], {0: 4, 1: 3})]
    """
    from ..laws.reflection import reflection_map
    from ..laws.sequential import termination_bound
    from ..laws.two_surface import resolve_two_surfaces
    from ..mechanics import check_gradients, check_mass_matrix

    Mx = check_mass_matrix(M, exact=True)
    Hx = check_gradients(H, Mx.shape[0], exact=True)
    if Mx.shape[0] != 2 or Hx.shape[0] != 2:
        raise ImpactInputError("gradients", "ordering_regions is planar: a 2x2 mass matrix and two rows")
    depth = termination_bound(Mx, Hx) + 1 if depth is None else depth
    Gs = [reflection_map(Mx, Hx[i, :]) for i in range(2)]
    rays = {}
    for first in (0, 1):
        P = sp.eye(2)
        for k in range(depth):
            for j in (0, 1):
                row = Hx[j, :] * P
                r = sp.Matrix([-row[1], row[0]])
                if all(x.is_Rational for x in r):
                    den = sp.gcd(list(r))
                else:  # one representative per direction: scale the first non-zero entry to +-1
                    den = abs(next(x for x in r if x != 0))
                r = r.applyfunc(lambda x: sp.radsimp(x / den)) if den != 1 else r
                den = 1
                for s in (r / den, -r / den):
                    rays[tuple(s)] = s
            P = Gs[(first + k) % 2] * P
    ordered = sorted(rays.values(), key=lambda r: math.atan2(float(r[1]), float(r[0])))
    out = []
    for r1, r2 in zip(ordered, ordered[1:] + ordered[:1]):
        s = r1 + r2
        w = Hx * s
        if all(sp.sign(x) >= 0 for x in w):
            continue  # already valid: no impact
        res = resolve_two_surfaces(Mx, Hx, s)
        orders, maps = {}, {}
        for o in res.outcomes:
            orders[o.first] = list(o.order)
            T = sp.eye(2)
            for i in o.order:
                T = Gs[i] * T
            if any(sp.simplify(a - b) != 0 for a, b in zip(T * s, o.velocity)):  # pragma: no cover - a bug
                raise ArithmeticError(f"ordering {list(o.order)}: the closed form and the product of reflections differ")
            maps[o.first] = [_vs(T.row(0)), _vs(T.row(1))]
        out.append({"from": _vs(r1), "to": _vs(r2), "orders": orders, "maps": maps,
                    "approaching": [bool(sp.sign(x) < 0) for x in w]})
    return out


def sm_fig4_configuration_space(masses=("11/10", 1), v0=(-1, -2), *, gap_scale="1/2"):
    """Seghete & Murphey Fig. 4 (sec. II-C.1, III-B.3): two balls and a wall in configuration space.

    Three panels. (a) The configuration space ``(x₁, x₂)`` with both boundaries (``φ_u = 0``: ball 1
    on the wall, ``φ_v = 0``: the balls touch) and, for every ordering, the trajectory that small
    gaps realizing it actually follow (gaps from :func:`impactsym.simulate.realize_ordering`, the
    motion from :func:`impactsym.simulate.simulate_line`, exact). (b) The velocity iterates of each
    ordering in the velocity plane, ending at ``v4a`` and ``v4b``. (c) The regions of incoming
    velocities by ordering (:func:`ordering_regions`), with ``v0 = v1 (1, t)``: both branches
    take four reflections (and give the printed products ``v4a``, ``v4b``) exactly for
    ``23/19 ≤ t ≤ 439/40``.

    Returns
    -------
    (Figure, dict) : ``v4a``, ``v4b`` (the resolver's outcomes, exact), ``orders``,
    ``trajectories`` (event times and contacts), ``regions`` and ``claim_sector_t``.
    """
    from ..laws.reflection import reflect
    from ..laws.sequential import resolve_sequential
    from ..models.seghete_murphey import two_balls_wall
    from ..simulate import perturbed_scene_positions, realize_ordering, simulate_line

    plt = _plt()
    sc = two_balls_wall(masses=masses, velocities=v0)
    r = resolve_sequential(sc.M, sc.H, sc.v)
    fig, axes = plt.subplots(1, 3, figsize=(15, 5))
    ax = axes[0]
    rad = sc.meta["radii"][0]
    lo, hi = 0.0, 6.0
    xx = np.linspace(lo, hi, 2)
    ax.fill_between([float(rad), hi], [float(rad) + 2 * float(rad), hi + 2 * float(rad)], [hi + 4] * 2,
                    color="C2", alpha=0.15, label="feasible (no overlap)")
    ax.axvline(float(rad), color="k", lw=1.2, label="phi_u = x1 - r = 0 (ball 1 on the wall)")
    ax.plot(xx, xx + 2 * float(rad), color="0.4", lw=1.2, label="phi_v = x2 - x1 - 2r = 0 (balls touch)")
    corner = np.array([float(rad), 3 * float(rad)])
    vf = _f(sc.v)
    back = 1.2
    ax.plot([corner[0] - back * vf[0], corner[0]], [corner[1] - back * vf[1], corner[1]], "k--", lw=1,
            label="the corner impact (incoming)")
    trajs = []
    colors = ["C0", "C1"]
    for idx, o in enumerate(r.outcomes):
        gaps = realize_ordering(sc.M, sc.H, sc.v, o.order, scale=sp.sympify(gap_scale))
        pos = perturbed_scene_positions(sc, gaps)
        sim = simulate_line(sc.meta["masses"], sc.meta["radii"], pos, list(sc.meta["all_velocities"]), [0])
        # replay the path: between events the configuration moves on a line; at each event the
        # velocity is reflected across the contact that closed (the single-impact law)
        q = sp.Matrix(pos)
        v = sc.v
        t_prev = 0
        T0 = sp.Rational(6, 5)
        pts = [q - T0 * v, q]
        name_to_row = {c: i for i, c in enumerate(sc.contacts)}
        for t_ev, name in sim.events:
            q = q + (t_ev - t_prev) * v
            pts.append(q)
            v = reflect(sc.M, sc.H[name_to_row[name], :], v)
            t_prev = t_ev
        pts.append(q + T0 * v)
        if not list(v) == list(o.velocity) == list(sim.velocities):  # pragma: no cover - a bug
            raise ArithmeticError(f"ordering {list(o.order)}: simulation, replay and resolver disagree")
        P = np.array([_f(p) for p in pts])
        ax.plot(P[:, 0], P[:, 1], color=colors[idx % 2], lw=1.5,
                label=f"gaps {_vs(gaps)}: order {list(o.order)}")
        ax.plot(P[1, 0], P[1, 1], "o", color=colors[idx % 2], ms=4)
        trajs.append({"order": list(o.order), "gaps": _vs(gaps), "events": [[_s(t), n] for t, n in sim.events],
                      "exit": _vs(sim.velocities)})
    ax.set_xlim(0, 3.2)
    ax.set_ylim(1.2, 5.5)
    ax.set_aspect("equal")
    ax.set_xlabel("x1")
    ax.set_ylabel("x2")
    ax.set_title(f"(a) configuration space, masses {_vs(sc.meta['masses'])}", fontsize=10)
    ax.legend(fontsize=6, loc="lower right")
    # (b) velocity iterates
    ax = axes[1]
    L = _kinetic_frame(sc.M)
    _shade_cone(ax, L, sc.H, radius=3, label="valid: H v >= 0")
    _shade_cone(ax, L, -sc.H, radius=3, color="C3", alpha=0.08, label="both approaching")
    x0 = _kin(L, sc.v)
    _ray(ax, x0, color="k", lw=2)
    ax.text(*(1.05 * x0), "v0", fontsize=8)
    for idx, o in enumerate(r.outcomes):
        v = sc.v
        xs = [x0]
        for i in o.order:
            v = reflect(sc.M, sc.H[i, :], v)
            xs.append(_kin(L, v))
        X = np.array(xs)
        ax.plot(X[:, 0], X[:, 1], "o:", color=colors[idx % 2], ms=4, lw=0.5,
                label=f"order {list(o.order)}: v4{'ab'[idx] if len(r.outcomes) == 2 else ''}")
        for kk, p in enumerate(X[1:], 1):
            ax.text(p[0], p[1], f" {kk}", fontsize=7, color=colors[idx % 2])
        _ray(ax, X[-1], color=colors[idx % 2], lw=2)
    lim = 1.2 * float(np.linalg.norm(x0))
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_title("(b) velocity iterates (kinetic coordinates)", fontsize=10)
    ax.legend(fontsize=7, loc="lower left")
    # (c) incoming velocities by ordering
    ax = axes[2]
    regs = ordering_regions(sc.M, sc.H)
    inside = [g for g in regs if all(g["approaching"])]
    claim = []
    cmap = plt.cm.Pastel1.colors
    for k, g in enumerate(regs):
        a0 = math.atan2(float(sp.sympify(g["from"][1])), float(sp.sympify(g["from"][0])))
        a1 = math.atan2(float(sp.sympify(g["to"][1])), float(sp.sympify(g["to"][0])))
        if a1 < a0:
            a1 += 2 * math.pi
        t = np.linspace(a0, a1, 30)
        lens = {k2: len(v) for k2, v in g["orders"].items()}
        four = all(n == 4 for n in lens.values()) and len(lens) == 2
        ax.fill(np.r_[0, np.cos(t), 0], np.r_[0, np.sin(t), 0], color="C0" if four else cmap[k % len(cmap)],
                alpha=0.6 if four else 0.5, lw=0.3, ec="w")
        if a1 - a0 > 0.12:  # label the sectors wide enough to read
            mid = 0.72 * np.array([np.cos(t.mean()), np.sin(t.mean())])
            ax.text(mid[0], mid[1], "/".join(f"{'uv'[f]}:{n}" for f, n in sorted(lens.items())), fontsize=6,
                    ha="center", va="center")
        if four and g in inside:
            claim = [g["from"], g["to"]]
    for ray in claim:
        d = _f(ray) / np.linalg.norm(_f(ray))
        ax.plot([0, 1.1 * d[0]], [0, 1.1 * d[1]], "k-", lw=1)
        tv = sp.sympify(ray[1]) / sp.sympify(ray[0])
        ax.text(1.12 * d[0], 1.12 * d[1], f"t = {tv}", fontsize=8, ha="center")
    ax.set_xlim(-1.3, 1.3)
    ax.set_ylim(-1.3, 1.3)
    ax.set_aspect("equal")
    ax.set_title("(c) incoming velocity by ordering length\n(u:m / v:m; blue: both 4, the printed v4a, v4b)",
                 fontsize=9)
    fig.suptitle("Seghete & Murphey Fig. 4: two balls and a wall (sec. II-C.1, III-B.3)")
    fig.tight_layout()
    src = {"masses": _vs(sc.meta["masses"]), "v0": _vs(sc.v), "orders": [list(o.order) for o in r.outcomes],
           "trajectories": trajs, "regions": regs,
           "claim_sector_t": [_s(sp.sympify(x[1]) / sp.sympify(x[0])) for x in claim]}
    if len(r.outcomes) == 2:
        src["v4a"], src["v4b"] = (_vs(o.velocity) for o in r.outcomes)
    else:
        src["outcomes"] = [_vs(o.velocity) for o in r.outcomes]
    return fig, src


# --------------------------------------------------------------------------- Fig. 5 (3-ball cradle)
def _plane_basis(M, H):
    """An M-orthonormal basis ``(e₁, e₂)`` of ``span(M⁻¹H₁ᵀ, M⁻¹H₂ᵀ)``, from the M-normals
    (:func:`impactsym.mechanics.m_normal`), floats."""
    from ..mechanics import m_normal

    Mf = np.array(sp.Matrix(M).evalf(17).tolist(), dtype=float)
    n1 = _f(m_normal(M, H[0, :]))
    n2 = _f(m_normal(M, H[1, :]))
    e2 = n2 - (n2 @ Mf @ n1) * n1
    e2 /= math.sqrt(e2 @ Mf @ e2)
    return Mf, n1, e2


def sm_fig5_cradle_kinetic_plane(masses=(1, 1, 1), v0=(1, 0, 0)):
    """Seghete & Murphey Fig. 5 (sec. II-C.2, III-B.2): the 3-ball cradle seen in the kinetic metric.

    The two contact planes of the 3-D configuration space meet in a line; the impact lives in the
    plane spanned by the two M-normals (sec. III-C: any dimension reduces to it). The figure draws
    that plane in M-orthonormal coordinates: the two surfaces' traces, the valid wedge, and every
    ordering's iterates (:func:`impactsym.laws.sequential.resolve_sequential`, iterated with
    :func:`impactsym.laws.reflection.reflect`). The component of ``v`` along the line of the
    corner is never changed.

    Examples
    --------
    >>> fig, src = sm_fig5_cradle_kinetic_plane()
    >>> src["outcomes"], src["orders"]
    ([['0', '0', '1']], [[0, 1]])
    """
    from ..laws.reflection import reflect
    from ..laws.sequential import resolve_sequential
    from ..models.seghete_murphey import three_ball_cradle

    plt = _plt()
    sc = three_ball_cradle(velocities=v0, masses=masses)
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate")
    Mf, e1, e2 = _plane_basis(sc.M, sc.H)
    Hf = np.array(sc.H.evalf(17).tolist(), dtype=float)

    def coords(v):
        vf = _f(v)
        return np.array([vf @ Mf @ e1, vf @ Mf @ e2])

    fig, ax = plt.subplots(figsize=(5.8, 5.4))
    t = np.linspace(0, 2 * np.pi, 721)
    dirs = np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2)
    w = dirs @ Hf.T
    for k in range(len(t) - 1):
        if (w[k] >= 0).all() and (w[k + 1] >= 0).all():
            ax.fill([0, 2 * np.cos(t[k]), 2 * np.cos(t[k + 1])], [0, 2 * np.sin(t[k]), 2 * np.sin(t[k + 1])],
                    color="C2", alpha=0.2, lw=0)
    for i, name in enumerate(sc.contacts):
        # the trace of H_i x = 0 in the plane: the direction of the plane M-orthogonal to n_i
        a = np.array([Hf[i] @ e1, Hf[i] @ e2])
        d = np.array([-a[1], a[0]]) / np.linalg.norm(a)
        ax.plot([-2 * d[0], 2 * d[0]], [-2 * d[1], 2 * d[1]], color="k", lw=1)
        ax.text(1.6 * d[0], 1.6 * d[1], f"contact {name}", fontsize=8)
    x0 = coords(sc.v)
    ax.annotate("", xy=(0, 0), xytext=(-x0[0], -x0[1]), arrowprops=dict(arrowstyle="->", lw=2))
    ax.text(-x0[0], -x0[1], " v0 (in-plane part)", fontsize=8)
    orders = []
    for idx, (order, oi) in enumerate(r.iter_orderings()):
        v = sc.v
        xs = [x0]
        for i in order:
            v = reflect(sc.M, sc.H[i, :], v)
            xs.append(coords(v))
        X = np.array(xs)
        ax.plot(X[:, 0], X[:, 1], "o:", ms=4, lw=0.5, color=f"C{idx}", label=f"ordering {list(order)}")
        for kk, p in enumerate(X[1:], 1):
            ax.text(p[0], p[1], f" {kk}", fontsize=7, color=f"C{idx}")
        _ray(ax, X[-1], color=f"C{idx}", lw=2)
        orders.append(list(order))
    vf = _f(sc.v)
    along = vf - (vf @ Mf @ e1) * e1 - (vf @ Mf @ e2) * e2
    lim = 1.3 * max(1e-9, float(np.linalg.norm(x0)))
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_xlabel("along n_1 (M-normal of contact 1-2)")
    ax.set_ylabel("M-orthogonal to n_1 in the plane")
    ax.set_title(f"Fig. 5: 3-ball cradle, masses {_vs(masses)}, v0 = {_vs(sc.v)}\n"
                 f"plane of the two M-normals (part along the corner, unchanged: {np.round(along, 3).tolist()})",
                 fontsize=8)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    return fig, {"masses": _vs(masses), "v0": _vs(sc.v), "orders": [list(o.order) for o in r.outcomes],
                 "orderings": orders, "outcomes": [_vs(o.velocity) for o in r.outcomes]}


# --------------------------------------------------------------------------- sec. III-C
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
    reflections (:func:`impactsym.laws.reflection.reflect`), at most :data:`MAX_DRAWN_REFLECTIONS`
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
    from ..laws.reflection import reflect
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
        for k in range(len(t) - 1):
            if ok[k] and ok[k + 1]:
                ax.fill([0, 1.6 * np.cos(t[k]), 1.6 * np.cos(t[k + 1])], [0, 1.6 * np.sin(t[k]), 1.6 * np.sin(t[k + 1])],
                        color="C2", alpha=0.25, lw=0)
        ax.fill([], [], color="C2", alpha=0.25, label=f"valid wedge, opening beta = {beta:.6g} rad")
        pts = [x0]
        if o.first in (0, 1):
            w, i, m = vx, o.first, 0
            while not all(sp.sign(c) >= 0 for c in Hx * w) and m < MAX_DRAWN_REFLECTIONS:
                w = reflect(Mx, Hx[i, :], w)
                i, m = 1 - i, m + 1
                pts.append(coords(w))
            done = all(sp.sign(c) >= 0 for c in Hx * w)
            iterated[str(o.first)] = m if done else None
        if not iterated.get(str(o.first)):
            pts.append(np.array([o.velocity_float @ Mf @ e1, o.velocity_float @ Mf @ e2]))
        for k, p in enumerate(pts):
            ax.plot([0, p[0] / rad], [0, p[1] / rad], color=plt.cm.viridis(k / max(1, len(pts) - 1)), lw=1.2)
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
    fig.tight_layout()
    return fig, {"M": [_vs(Mx.row(i)) for i in range(Mx.shape[0])], "H": [_vs(Hx.row(i)) for i in range(2)],
                 "v0": _vs(vx), "counts": counts, "iterated_counts": iterated, "bound": res.bound,
                 "wedge_angle": str(res.as_dict()["wedge_angle"]), "kinetic_angle_cos": _s(res.kinetic_angle_cos),
                 "exits": {str(o.first): (_vs(o.velocity) if o.exact else [float(x) for x in o.velocity_float])
                           for o in res.outcomes}}


def sm_sec3c_termination(M="1,0;0,1", H="1,0;-3,1", v0="-2,-7"):
    """Seghete & Murphey sec. III-C: the termination argument as a picture (:func:`two_surface_figure`
    on a wedge of about 18.4°, so that the rotation by ``2β`` is visible step by step).

    Examples
    --------
    >>> fig, src = sm_sec3c_termination()
    >>> src["counts"], src["bound"], src["iterated_counts"] == src["counts"]
    ({'0': 9, '1': 10}, 10, True)
    """
    return two_surface_figure(M, H, v0, title="Seghete & Murphey sec. III-C: termination for two surfaces "
                                              "(kinetic coordinates; k = iterate)")


# --------------------------------------------------------------------------- three surfaces
def sm_three_surface_overgeneration(masses=(1, 3, 4), velocities=(-1, -3, 0),
                                    gap_draws=((1, 2, 3), (3, 2, 1), (1, 1000, 7), (500, 1, 3))):
    """The branching rule of sec. III-B over-generates for three surfaces (balls against a wall).

    Every outcome of the rule (:func:`impactsym.laws.sequential.resolve_sequential`, all
    orderings), how many orderings reach it, whether some small gaps realize one of them (exact LP,
    :func:`impactsym.simulate.realize_ordering`), and where exact small-gap simulations end
    (:func:`impactsym.simulate.simulate_line`).

    Examples
    --------
    >>> fig, src = sm_three_surface_overgeneration()
    >>> src["orderings"], len(src["outcomes"]), src["realized"], src["simulated"][0]
    (15, 5, [['1/7', '5/7', '18/7']], ['1/7', '5/7', '18/7'])
    """
    from ..laws.sequential import resolve_sequential
    from ..scenes import balls_on_line
    from ..simulate import perturbed_scene_positions, realize_ordering, simulate_line

    plt = _plt()
    n = len(masses)
    sc = balls_on_line(list(masses), [1] * n, [1 + 2 * i for i in range(n)], list(velocities), walls=[0])
    r = resolve_sequential(sc.M, sc.H, sc.v, two_surface="iterate", select=False)
    per = [0] * len(r.outcomes)
    realized = set()
    for order, idx in r.iter_orderings():
        per[idx] += 1
        if idx not in realized and realize_ordering(sc.M, sc.H, sc.v, order) is not None:
            realized.add(idx)
    sims = []
    for g in gap_draws:
        pos = perturbed_scene_positions(sc, [sp.Rational(x, 10**9) for x in g])
        sims.append(simulate_line(sc.meta["masses"], sc.meta["radii"], pos, list(sc.meta["all_velocities"]), [0]).velocities)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    width = 0.8 / len(r.outcomes)
    for j, o in enumerate(r.outcomes):
        ok = j in realized
        ax.bar(np.arange(n) + j * width, _f(o.velocity), width, color="C0" if ok else "0.75",
               edgecolor="k" if ok else "0.5", hatch=None if ok else "//",
               label=f"{_vs(o.velocity)}: {per[j]} ordering(s)" + (", realized by small gaps" if ok else ", no gaps"))
    for s in sims:
        ax.plot(np.arange(n) + 0.4 - width / 2, _f(s), "r*", ms=10)
    ax.plot([], [], "r*", label="exact small-gap simulations")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xticks(np.arange(n) + 0.4 - width / 2)
    ax.set_xticklabels([f"ball {i + 1} (m = {m})" for i, m in enumerate(masses)])
    ax.set_ylabel("exit velocity")
    ax.set_title(f"Three surfaces: balls of masses {list(masses)} against a wall, v0 = {list(velocities)}\n"
                 f"{r.orderings} orderings by the branching rule, {len(r.outcomes)} outcomes, "
                 f"{len(realized)} realized", fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    return fig, {"masses": _vs(masses), "v0": _vs(velocities), "orderings": r.orderings,
                 "outcomes": [_vs(o.velocity) for o in r.outcomes], "orderings_per_outcome": per,
                 "realized": [_vs(r.outcomes[j].velocity) for j in sorted(realized)],
                 "simulated": [_vs(s) for s in sims]}


# --------------------------------------------------------------------------- Acary & Taha
def at_fig2_pool(theta="pi/4", tau=0):
    """Acary & Taha Fig. 2: the pool, ball 1 striking balls 2 and 3 (sec. 4.1).

    The centres (:func:`impactsym.models.acary_taha.pool_positions`), ball 1's incoming velocity and
    the contact normals are those of the scene :func:`impactsym.models.acary_taha.pool` (its
    gradient rows); the kinetic angle between the two contacts is
    :func:`impactsym.mechanics.kinetic_angle_cos` (eq. 42).

    Examples
    --------
    >>> fig, src = at_fig2_pool("pi/3")
    >>> src["contacts"], src["cos_kinetic_angle_12"]
    (['1-2', '2-3'], '-1/4')
    """
    from ..mechanics import kinetic_angle_cos
    from ..models.acary_taha import pool, pool_positions

    plt = _plt()
    sc = pool(sp.sympify(theta), sp.sympify(tau))
    P = [_f(p) for p in pool_positions(sp.sympify(theta))]
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for i, c in enumerate(P):
        ax.add_patch(plt.Circle(c, 1, fill=False, lw=1.2))
        ax.text(c[0], c[1], str(i + 1), ha="center", va="center")
    vin = _f(sc.v)[:2]
    ax.annotate("", xy=P[0], xytext=P[0] - 1.6 * vin, arrowprops=dict(arrowstyle="->", lw=2, color="C0"))
    Hf = np.array(sc.H.evalf(17).tolist(), dtype=float)
    pairs = [tuple(int(x) - 1 for x in c.split("-")) for c in sc.contacts]
    for (i, j), row in zip(pairs, Hf):
        mid = (P[i] + P[j]) / 2
        d = row[2 * j:2 * j + 2]  # the gradient on ball j: the normal pushing j away from i
        ax.annotate("", xy=mid + 0.8 * d, xytext=mid, arrowprops=dict(arrowstyle="->", color="C3"))
    ax.plot([], [], color="C0", label="velocity of ball 1")
    ax.plot([], [], color="C3", label="contact normals (gradient rows)")
    cosk = kinetic_angle_cos(sc.M, sc.H[0, :], sc.H[1, :])
    ax.set_aspect("equal")
    ax.set_xlim(-5, 4)
    ax.set_ylim(-4, 2.5)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(f"Acary & Taha Fig. 2: the pool, theta = {_s(theta)}, tau = {_s(tau)}; "
                 f"cos(kinetic angle 1-2, 2-3) = {_s(cosk)}", fontsize=9)
    fig.tight_layout()
    return fig, {"theta": _s(theta), "tau": _s(tau), "contacts": list(sc.contacts), "v0": _vs(sc.v),
                 "cos_kinetic_angle_12": _s(cosk)}


def at_fig3_domain(theta="pi/4", *, printed_h=None, alpha_max=1.5):
    """Acary & Taha Fig. 3: the pool's valid domain in ``(α₁₂, e)`` at θ, from the derived curves.

    Drawn by :func:`impactsym.domains.plot_domain` (``g`` of eq. 29, ``h`` of eq. 31 corrected, the
    domain shaded). ``printed_h``: the paper's printed curve, a SymPy expression in ``alpha`` (for
    eq. 31 as printed, ``derivations.domains.printed_eq31_h(cos θ)``; the library never holds a
    transcription), drawn beside the corrected one.

    Returns
    -------
    (Figure, dict) : the region's extent and exact boundary expressions, plus ``boundary_points``:
    exact points ``(α, g(α))`` on the lower boundary (each in the domain, checked by the tests).

    Examples
    --------
    >>> fig, src = at_fig3_domain()
    >>> src["alpha"], src["e"]
    (['sqrt(2)/4', '1'], ['3/7', '1'])
    """
    from ..domains import alpha as A, plot_domain, validity_domain

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 4.5))
    out = plot_domain(theta, None, ax=ax, alpha_max=alpha_max)
    dom = validity_domain("pool", out["theta"])
    g = next(b for b in dom.boundaries if b.name == "g").expression
    src = {"theta": _s(out["theta"]), "alpha": _vs(dom.region["alpha"]), "e": _vs(dom.region["e"]),
           "boundaries": {b.name: _s(b.expression) for b in dom.boundaries}}
    pts = []
    lo = dom.region["alpha"][0]
    for a in (lo, (lo + 1) / 2, sp.Integer(1)):
        a = sp.expand(a)  # exact: no rounding
        pts.append([_s(a), _s(sp.radsimp(sp.simplify(g.subs(A, a))))])
    src["boundary_points"] = pts
    if printed_h is not None:
        expr = sp.sympify(printed_h).subs({s: A for s in sp.sympify(printed_h).free_symbols if s.name == "alpha"})
        f = sp.lambdify(A, expr, "numpy")
        xs = np.asarray(out["alpha"])
        ax.plot(xs, f(xs) * np.ones_like(xs), color="C3", ls=":", lw=1.5, label="h as printed (eq. 31)")
        ax.legend(loc="lower right", fontsize=8)
        src["printed_h"] = _s(expr)
    ax.set_title(f"Acary & Taha Fig. 3: valid domain of (alpha_12, e), theta = {_s(out['theta'])}", fontsize=10)
    fig.tight_layout()
    return fig, src


def at_domain_over_theta(thetas=None):
    """Acary & Taha sec. 4.1.1: the pool's domain as θ varies (small multiples over θ ∈ [0, 2π/3]).

    Panels below 2π/3 are :func:`impactsym.domains.plot_domain`; the panel at 2π/3 (three closed
    contacts, ``α₁₃ = α₁₂``) draws that domain's boundaries ``g1``, ``g3`` as the library gives them.

    Examples
    --------
    >>> fig, src = at_domain_over_theta(["0", "pi/2"])
    >>> [(r["theta"], r["e"][0]) for r in src["panels"]]
    [('0', '1/3'), ('pi/2', '1/2')]
    """
    from ..domains import THETA_SWEEP, alpha as A, plot_domain, validity_domain

    plt = _plt()
    thetas = list(THETA_SWEEP) if thetas is None else [sp.sympify(t) for t in thetas]
    cols = min(4, len(thetas))
    rows = -(-len(thetas) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 3.3 * rows), squeeze=False)
    panels = []
    for ax, t in zip(axes.flat, thetas):
        dom = validity_domain("pool", t)
        if len(dom.boundaries) == 4:
            plot_domain(t, None, ax=ax, alpha_max=1.5)
            ax.get_legend().remove()
        else:  # theta = 2 pi/3: three contacts
            xs = np.linspace(0, 1.5, 300)
            b = {x.name: x.expression for x in dom.boundaries}
            g1 = sp.lambdify(A, b["g1"], "numpy")(xs)
            g3 = sp.lambdify(A, b["g3"], "numpy")(xs)
            ax.plot(xs, g1, label="g1")
            ax.plot(xs, g3, label="g3")
            lo = np.maximum(g1, np.where((xs < 0.4) | (xs > 1), g3, 0))
            m = (xs <= 1)
            ax.fill_between(xs[m], np.minimum(lo[m], 1), 1, color="C2", alpha=0.3)
            ax.set_ylim(0, 1.05)
            ax.set_xlim(0, 1.5)
            ax.legend(fontsize=7)
        ax.set_title(f"theta = {_s(t)}: e >= {_s(dom.region['e'][0])}", fontsize=9)
        ax.set_xlabel("alpha_12", fontsize=8)
        panels.append({"theta": _s(t), "alpha": _vs(dom.region["alpha"]), "e": _vs(dom.region["e"])})
    for ax in list(axes.flat)[len(thetas):]:
        ax.axis("off")
    fig.suptitle("Acary & Taha: the pool's valid domain as theta varies")
    fig.tight_layout()
    return fig, {"panels": panels}


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
        fig.tight_layout()
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
        fig.tight_layout()
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
        fig.tight_layout()
    src.update(alpha=_vs(dom.region["alpha"]), e=_vs(dom.region["e"]))
    return fig, src


def at_chain3_velocities(restitutions=("1", "9/10", "2/3", "1/3"), alphas=None):
    """Acary & Taha eqs. 13–19: the 3-ball chain's post-impact velocities against ``α`` for several ``e``.

    Each point is :func:`impactsym.laws.impulse_ratio.impulse_ratio_law` on the chain (float path,
    ``allow_invalid``); solid where the law reports the solution valid, dotted where it does not
    (the validity boundary of eq. 19, whose exact extent :func:`impactsym.domains.validity_domain`
    gives). The paper's example (``e = 1``, ``α = 0.95``) is solved exactly.

    Examples
    --------
    >>> fig, src = at_chain3_velocities(("1",), np.linspace(0.4, 1.1, 8))
    >>> src["paper_example"]["velocity"], src["domain"]["alpha"]
    (['-19/381', '20/381', '380/381'], ['1/2', '1'])
    """
    from ..domains import validity_domain
    from ..laws.impulse_ratio import impulse_ratio_law
    from ..models.acary_taha import chain3

    plt = _plt()
    sc = chain3()
    Mf = np.array(sc.M.evalf(17).tolist(), dtype=float)
    Hf = np.array(sc.H.evalf(17).tolist(), dtype=float)
    vf = _f(sc.v)
    alphas = np.linspace(0.0, 1.5, 61) if alphas is None else np.asarray(alphas, dtype=float)
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.3), sharey=True)
    src = {"restitutions": list(restitutions), "valid_alpha": {}}
    for ci, e in enumerate(restitutions):
        ef = float(sp.sympify(e))
        V = np.full((len(alphas), 3), np.nan)
        ok = np.zeros(len(alphas), dtype=bool)
        for k, a in enumerate(alphas):
            res = impulse_ratio_law(Mf, Hf, vf, ef, [float(a)], allow_invalid=True)
            if res.velocity is not None:
                V[k] = res.velocity
                ok[k] = res.valid
        for j, ax in enumerate(axes):
            ax.plot(alphas, np.where(ok, V[:, j], np.nan), color=f"C{ci}", lw=1.8, label=f"e = {e}" if j == 0 else None)
            ax.plot(alphas, np.where(ok, np.nan, V[:, j]), color=f"C{ci}", lw=0.8, ls=":")
        va = alphas[ok]
        src["valid_alpha"][e] = [float(va.min()), float(va.max())] if va.size else None
    for j, ax in enumerate(axes):
        ax.set_title(f"q{j + 1}+ (ball {j + 1})", fontsize=10)
        ax.set_xlabel("alpha = p2/p1")
        ax.axhline(0, color="k", lw=0.5)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("post-impact velocity (solid: valid, dotted: outside eq. 19)")
    axes[0].legend(fontsize=8)
    ex = impulse_ratio_law(sc.M, sc.H, sc.v, 1, ["0.95"])
    dom = validity_domain("chain3")
    src["paper_example"] = {"e": "1", "alpha": "19/20", "velocity": _vs(ex.velocity), "impulses": _vs(ex.impulses)}
    src["domain"] = {"alpha": _vs(dom.region["alpha"]), "e": _vs(dom.region["e"])}
    fig.suptitle("Acary & Taha eqs. 13-19: the 3-ball chain under the impulse-ratio law")
    fig.tight_layout()
    return fig, src


def at_fig4_bernoulli(alpha="1/2", tau=None, restitution=1):
    """Acary & Taha Fig. 4: Bernoulli's problem (θ = 2π/3, three closed contacts, ``α₁₃ = α₁₂``).

    The balls at their contact configuration (:func:`impactsym.models.acary_taha.pool_positions`),
    ball 1's incoming velocity and every ball's exit velocity from
    :func:`impactsym.laws.impulse_ratio.impulse_ratio_law` on :func:`impactsym.models.acary_taha.bernoulli`.

    Examples
    --------
    >>> fig, src = at_fig4_bernoulli()
    >>> src["valid"], src["contacts"]
    (True, ['1-2', '2-3', '1-3'])
    """
    from ..laws.impulse_ratio import impulse_ratio_law
    from ..models.acary_taha import bernoulli, pool_positions

    plt = _plt()
    sc = bernoulli() if tau is None else bernoulli(sp.sympify(tau))
    res = impulse_ratio_law(sc.M, sc.H, sc.v, restitution, [alpha, alpha], allow_invalid=True)
    P = [_f(p) for p in pool_positions(2 * sp.pi / 3)]
    fig, ax = plt.subplots(figsize=(6, 5))
    for i, c in enumerate(P):
        ax.add_patch(plt.Circle(c, 1, fill=False, lw=1.2))
        ax.text(c[0], c[1] - 0.25, str(i + 1), ha="center")
    vin = _f(sc.v)
    ax.annotate("", xy=P[0], xytext=P[0] - 1.5 * vin[:2], arrowprops=dict(arrowstyle="->", lw=2, color="0.4"))
    if res.velocity is not None:
        vout = _f(res.velocity)
        for i, c in enumerate(P):
            d = vout[2 * i:2 * i + 2]
            ax.annotate("", xy=c + 1.5 * d, xytext=c, arrowprops=dict(arrowstyle="->", lw=2, color="C0"))
    ax.plot([], [], color="0.4", label="incoming velocity of ball 1")
    ax.plot([], [], color="C0", label=f"exit velocities (impulse-ratio law, alpha = {alpha}, e = {restitution})")
    ax.set_aspect("equal")
    ax.set_xlim(-5.5, 4)
    ax.set_ylim(-4, 4)
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title(f"Acary & Taha Fig. 4: Bernoulli's problem, tau = {_s(sc.meta['tau'])}, valid: {res.valid}", fontsize=10)
    fig.tight_layout()
    return fig, {"alpha": _s(alpha), "tau": _s(sc.meta["tau"]), "contacts": list(sc.contacts),
                 "velocity": None if res.velocity is None else _vs(res.velocity),
                 "impulses": None if res.impulses is None else _vs(res.impulses), "valid": res.valid}


def at_fig5_transmission(n_balls=5, stiffness=1.0):
    """Acary & Taha Fig. 5 (sec. 3.4, 5.2): how impulses travel along an open chain of balls.

    Ball 1 strikes ``n − 1`` resting balls. The compliant chains (:func:`impactsym.compliant.chain_impact`,
    Hertz eq. 20 and linear eq. 23) give the impulse at every contact; the impulse-ratio law
    (:func:`impactsym.laws.impulse_ratio.impulse_ratio_law`) with the Hertz ratios (eq. 21) and
    ``e = 1`` (the undamped run conserves energy; checked to 1e-6) gives its own impulses and exit
    velocities, drawn beside them.

    Examples
    --------
    >>> fig, src = at_fig5_transmission(3)
    >>> [round(x, 5) for x in src["hertz"]["ratios"]], src["law_matches_hertz_velocity"]
    ([1.0, 0.92866], True)
    """
    from ..compliant import chain_impact
    from ..laws.impulse_ratio import impulse_ratio_law
    from ..scenes import balls_on_line

    plt = _plt()
    n = int(n_balls)
    v0 = [1.0] + [0.0] * (n - 1)
    runs = {m: chain_impact([1.0] * n, v0, [stiffness] * (n - 1), model=m) for m in ("hertz", "linear")}
    sc = balls_on_line([1] * n, [1] * n, [1 + 2 * i for i in range(n)], [1] + [0] * (n - 1))
    Mf = np.array(sc.M.evalf(17).tolist(), dtype=float)
    Hf = np.array(sc.H.evalf(17).tolist(), dtype=float)
    e_run = runs["hertz"].energy_ratio  # T+/T- of the undamped run: 1 up to the integrator's tolerance
    if not 1 - 1e-6 <= e_run <= 1 + 1e-6:  # pragma: no cover - an undamped chain conserves energy
        raise ArithmeticError(f"the undamped Hertz chain lost energy: T+/T- = {e_run}")
    law = impulse_ratio_law(Mf, Hf, _f(sc.v), 1.0, list(runs["hertz"].ratios[1:]), allow_invalid=True)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    x = np.arange(1, n)
    w = 0.27
    axes[0].bar(x - w, runs["hertz"].impulses, w, label="Hertz (eq. 20)")
    axes[0].bar(x, runs["linear"].impulses, w, label="linear (eq. 23)")
    axes[0].bar(x + w, law.impulses, w, label="impulse-ratio law, Hertz ratios")
    axes[0].set_xlabel("contact i (between balls i and i+1)")
    axes[0].set_ylabel("impulse P_i")
    axes[0].set_title("impulses along the chain", fontsize=10)
    axes[0].legend(fontsize=8)
    xb = np.arange(1, n + 1)
    axes[1].bar(xb - w, runs["hertz"].velocity, w, label="Hertz")
    axes[1].bar(xb, runs["linear"].velocity, w, label="linear")
    axes[1].bar(xb + w, law.velocity, w, label="impulse-ratio law")
    axes[1].axhline(0, color="k", lw=0.5)
    axes[1].set_xlabel("ball")
    axes[1].set_ylabel("exit velocity")
    axes[1].set_title("exit velocities", fontsize=10)
    axes[1].legend(fontsize=8)
    fig.suptitle(f"Acary & Taha Fig. 5: transmission of impulses in an open chain of {n} balls")
    fig.tight_layout()
    match = bool(np.allclose(law.velocity, runs["hertz"].velocity, rtol=0, atol=1e-6))
    return fig, {"n_balls": n, "law_matches_hertz_velocity": match,
                 **{m: {"ratios": r.ratios.tolist(), "impulses": r.impulses.tolist(), "velocity": r.velocity.tolist(),
                        "energy_ratio": r.energy_ratio} for m, r in runs.items()},
                 "law": {"impulses": np.asarray(law.impulses).tolist(), "velocity": np.asarray(law.velocity).tolist(),
                         "valid": law.valid}}


#: a planar open chain (sec. 5.2): unit bonds turning by acos(4/5), acos(3/5), then π/2 (rational centres)
PLANAR_CHAIN = ((0, 0), (2, 0), ("18/5", "6/5"), ("18/5", "16/5"), ("8/5", "16/5"))


def at_fig5_planar_chain(positions=PLANAR_CHAIN, ratios=("3/4", "1/2", "1/2"), restitution=1):
    """Acary & Taha Fig. 5 in the plane (sec. 5.2, eqs. 43–45): how far an impulse travels along a bent chain.

    Ball 1 strikes a chain of resting balls (:func:`impactsym.scenes.balls_in_plane`). The kinetic
    angle between consecutive contacts (:func:`impactsym.laws.coupling.coupling_decision`) decides
    whether they are coupled (``cos θ < 0``, eq. 43); the impact degree (eq. 45,
    :func:`impactsym.laws.coupling.impact_degree`) counts the leading coupled contacts. The
    impulse-ratio law with the coupling criteria (``coupling=True``) sets the ratios of the
    uncoupled contacts to zero and gives the impulses and exit velocities drawn.

    Examples
    --------
    >>> fig, src = at_fig5_planar_chain()
    >>> src["cos_consecutive"], src["impact_degree"], src["ratios_used"]
    (['-2/5', '-3/10', '0'], 3, ['1', '3/4', '1/2', '0'])
    """
    from ..laws.coupling import coupling_decision, impact_degree
    from ..laws.impulse_ratio import impulse_ratio_law
    from ..scenes import balls_in_plane

    plt = _plt()
    nb = len(positions)
    sc = balls_in_plane([1] * nb, [1] * nb, [tuple(sp.sympify(c) for c in p) for p in positions],
                        [(1, 0)] + [(0, 0)] * (nb - 1))
    dec = coupling_decision(sc.M, sc.H, sc.v)
    deg = impact_degree(sc.M, sc.H, sc.v)
    res = impulse_ratio_law(sc.M, sc.H, sc.v, restitution, list(ratios), coupling=True, allow_invalid=True)
    P = [_f([sp.sympify(c) for c in p]) for p in positions]
    k = sc.H.shape[0]
    fig, ax = plt.subplots(figsize=(6.5, 5.5))
    pmax = max(float(x) for x in res.impulses) if res.impulses is not None else 1.0
    for i, c in enumerate(P):
        ax.add_patch(plt.Circle(c, 1, fill=False, lw=1))
        ax.text(c[0], c[1] - 0.3, str(i + 1), ha="center", fontsize=8)
    for j, name in enumerate(sc.contacts):
        a, b = (int(x) - 1 for x in name.split("-"))
        mid = (P[a] + P[b]) / 2
        pj = float(res.impulses[j]) if res.impulses is not None else 0.0
        ax.plot(*mid, "o", ms=4 + 14 * pj / pmax, color="C3", alpha=0.7)
        label = f"p{j + 1} = {_s(res.impulses[j])}" if res.impulses is not None else ""
        if j + 1 < k:
            cs = dec.cosines[(j, j + 1)]
            label += f"\ncos th{j + 1},{j + 2} = {_s(cs)}"
        ax.text(mid[0] + 0.15, mid[1] + 0.15, label, fontsize=7)
    vout = _f(res.velocity) if res.velocity is not None else np.zeros(2 * nb)
    for i, c in enumerate(P):
        d = vout[2 * i:2 * i + 2]
        if np.linalg.norm(d) > 1e-12:
            ax.annotate("", xy=c + 1.5 * d, xytext=c, arrowprops=dict(arrowstyle="->", color="C0", lw=1.6))
    ax.annotate("", xy=P[0], xytext=P[0] - np.array([1.5, 0]), arrowprops=dict(arrowstyle="->", color="0.5", lw=2))
    ax.plot([], [], color="0.5", label="incoming velocity of ball 1")
    ax.plot([], [], color="C0", label="exit velocities")
    ax.plot([], [], "o", color="C3", label="impulse at a contact (size)")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlim(min(c[0] for c in P) - 2.8, max(c[0] for c in P) + 2.5)
    ax.set_ylim(min(c[1] for c in P) - 2, max(c[1] for c in P) + 2)
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title(f"Acary & Taha Fig. 5 in the plane: impact degree {deg} (eq. 45); "
                 f"ratios {[_s(x) for x in res.ratios]}, valid: {res.valid}", fontsize=9)
    fig.tight_layout()
    return fig, {"positions": [[_s(c) for c in p] for p in positions], "contacts": list(sc.contacts),
                 "cos_consecutive": [_s(dec.cosines[(j, j + 1)]) for j in range(k - 1)],
                 "coupled_consecutive": [bool(dec.coupled[(j, j + 1)]) for j in range(k - 1)],
                 "impact_degree": deg, "ratios_used": [_s(x) for x in res.ratios],
                 "impulses": None if res.impulses is None else _vs(res.impulses),
                 "velocity": None if res.velocity is None else _vs(res.velocity), "valid": res.valid}


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
    from ..errors import ImpactError
    from ..laws.classical import energetic, han_gilmore, newton_moreau, poisson
    from ..laws.impulse_ratio import impulse_ratio_law
    from ..laws.sequential import resolve_sequential
    from ..laws.two_surface import resolve_two_surfaces
    from ..mechanics import check_gradients, check_mass_matrix

    k = check_gradients(H, check_mass_matrix(M).shape[0]).shape[0]
    out: dict = {}

    def ask(name, fn):
        try:
            outs, valid, note = fn()
            out[name] = {"outcomes": outs, "valid": valid, "note": note}
        except ImpactError as exc:
            out[name] = {"outcomes": [], "valid": [], "note": f"refused: {exc}"}

    def seq():
        r = resolve_sequential(M, H, v)
        return [o.velocity for o in r.outcomes], [True] * len(r.outcomes), f"selected: {[list(s) for s in r.selected]}"

    def two():
        if k != 2:
            return [], [], f"not applicable: {k} contacts (needs exactly two)"
        r = resolve_two_surfaces(M, H, v)
        return [o.velocity for o in r.outcomes], [True] * len(r.outcomes), f"bound N = {r.bound}"

    def classical(f):
        def run():
            r = f(M, H, v, restitution, allow_invalid=True)
            return [r.velocity], [r.valid], "; ".join(r.notes[:1])
        return run

    def hg():
        r = han_gilmore(M, H, v, restitution)
        return [o.velocity for o in r.outcomes], [True] * len(r.outcomes), f"{len(r.outcomes)} outcome(s)"

    def ir():
        if ratios is None and k > 1:
            return [], [], "not applicable: no impulse ratios given"
        r = impulse_ratio_law(M, H, v, restitution, ratios, allow_invalid=True)
        if r.velocity is None:
            return [], [], "no real solution (negative discriminant)"
        return [r.velocity], [r.valid], f"ratios {list(r.ratios)}" + ("" if r.valid else ": outside the domain")

    ask("sequential", seq)
    ask("two-surface", two)
    ask("newton", classical(newton_moreau))
    ask("poisson", classical(poisson))
    ask("energetic", classical(energetic))
    ask("han-gilmore", hg)
    ask("impulse-ratio", ir)
    return out


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
    fig.tight_layout()
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
    fig.tight_layout()
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
    fig.tight_layout()
    return fig, {"backends": backends, "formulas": formulas, "best": best}


# --------------------------------------------------------------------------- README figures
#: the figures shown in the README: file stem -> (function, keyword arguments)
README_FIGURES = {
    "sm_fig4_configuration_space": (sm_fig4_configuration_space, {}),
    "sm_sec3c_termination": (sm_sec3c_termination, {}),
    "at_fig3_domain": (at_fig3_domain, {}),
    "laws_side_by_side_cradle": (laws_side_by_side, {"scene": "cradle"}),
}


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.floating, np.integer, np.bool_)):
        return x.item()
    return x


def write_readme_figures(outdir, names=None, *, pixels: bool = True) -> dict:
    """Write each README figure as ``outdir/NAME.png`` with its source data as ``outdir/NAME.json``.

    ``pixels=False`` writes only the JSON (what the currency test regenerates). Returns
    ``{name: source data}``.

    >>> import tempfile
    >>> out = write_readme_figures(tempfile.mkdtemp(), ["at_fig3_domain"], pixels=False)
    >>> out["at_fig3_domain"]["e"]
    ['3/7', '1']
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    out = {}
    for name in names or README_FIGURES:
        fn, kw = README_FIGURES[name]
        fig, src = fn(**kw)
        src = _jsonable(src)
        if pixels:
            save(fig, outdir / f"{name}.png")
        else:
            _plt().close(fig)
        (outdir / f"{name}.json").write_text(json.dumps(src, indent=1, sort_keys=True) + "\n")
        out[name] = src
    return out


def main(argv=None) -> int:
    import argparse

    p = argparse.ArgumentParser(prog="python -m impactsym.figures",
                                description="Write the README's figures (PNG) and their source data (JSON).")
    p.add_argument("outdir", nargs="?", default="docs/figures")
    args = p.parse_args(argv)
    for name in write_readme_figures(args.outdir):
        print(Path(args.outdir) / f"{name}.png")
    return 0

