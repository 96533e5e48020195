"""Seghete & Murphey's figures: Figs. 1, 2 (corners), 4 (configuration space), 5 (cradle), the
termination of sec. III-C, and three-surface overgeneration.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..errors import ImpactInputError
from ._common import _f, _plt, _s, _tight, _vs, _kinetic_frame, _kin, _ray, _shade_cone, _normal_cone_arc, _plane_basis, _fill_wedges
from .laws import two_surface_figure

__all__ = [
    "sm_fig1_convex_corner", "sm_fig2_concave_corner", "ordering_regions", "sm_fig4_configuration_space",
    "sm_fig5_cradle_kinetic_plane", "sm_sec3c_termination", "sm_three_surface_overgeneration"
]


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
    _tight(fig)
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
    from ..arithmetic.closed_form import certified_sign
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
        # the signs of H s and the agreement of the two exits below are decided exactly by
        # certified_sign (a rational at once; else an enclosure, or an exact zero test), not by
        # SymPy's sign and simplify on the radicals of irrational gradients
        sw = [certified_sign(x) for x in w]
        if all(x >= 0 for x in sw):
            continue  # already valid: no impact
        res = resolve_two_surfaces(Mx, Hx, s)
        orders, maps = {}, {}
        for o in res.outcomes:
            orders[o.first] = list(o.order)
            T = sp.eye(2)
            for i in o.order:
                T = Gs[i] * T
            if any(certified_sign(a - b) != 0 for a, b in zip(T * s, o.velocity)):  # pragma: no cover - a bug
                raise ArithmeticError(f"ordering {list(o.order)}: the closed form and the product of reflections differ")
            maps[o.first] = [_vs(T.row(0)), _vs(T.row(1))]
        out.append({"from": _vs(r1), "to": _vs(r2), "orders": orders, "maps": maps,
                    "approaching": [x < 0 for x in sw]})
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
    _tight(fig)
    src = {"masses": _vs(sc.meta["masses"]), "v0": _vs(sc.v), "orders": [list(o.order) for o in r.outcomes],
           "trajectories": trajs, "regions": regs,
           "claim_sector_t": [_s(sp.sympify(x[1]) / sp.sympify(x[0])) for x in claim]}
    if len(r.outcomes) == 2:
        src["v4a"], src["v4b"] = (_vs(o.velocity) for o in r.outcomes)
    else:
        src["outcomes"] = [_vs(o.velocity) for o in r.outcomes]
    return fig, src


# --------------------------------------------------------------------------- Fig. 5 (3-ball cradle)
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
    _fill_wedges(ax, t, ((dirs @ Hf.T) >= 0).all(axis=1), 2, facecolor="C2", edgecolor="C2", alpha=0.2, linewidth=0)
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
    _tight(fig)
    return fig, {"masses": _vs(masses), "v0": _vs(sc.v), "orders": [list(o.order) for o in r.outcomes],
                 "orderings": orders, "outcomes": [_vs(o.velocity) for o in r.outcomes]}


# --------------------------------------------------------------------------- sec. III-C
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
    _tight(fig)
    return fig, {"masses": _vs(masses), "v0": _vs(velocities), "orderings": r.orderings,
                 "outcomes": [_vs(o.velocity) for o in r.outcomes], "orderings_per_outcome": per,
                 "realized": [_vs(r.outcomes[j].velocity) for j in sorted(realized)],
                 "simulated": [_vs(s) for s in sims]}
