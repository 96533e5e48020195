"""Acary & Taha's figures: Figs. 2 (pool), 3 (valid domain, also over theta), 4 (Bernoulli), 5
(transmission, planar chain), and the 3-ball chain's velocities.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ._common import _f, _plt, _s, _tight, _vs

__all__ = [
    "at_fig2_pool", "at_fig3_domain", "at_domain_over_theta", "at_chain3_velocities", "at_fig4_bernoulli",
    "at_fig5_transmission", "at_fig5_planar_chain", "PLANAR_CHAIN"
]


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
    _tight(fig)
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
    _tight(fig)
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
            plot_domain(t, None, ax=ax, alpha_max=1.5, legend=False)
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
    _tight(fig)
    return fig, {"panels": panels}


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
    _tight(fig)
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
    _tight(fig)
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
    _tight(fig)
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
    _tight(fig)
    return fig, {"positions": [[_s(c) for c in p] for p in positions], "contacts": list(sc.contacts),
                 "cos_consecutive": [_s(dec.cosines[(j, j + 1)]) for j in range(k - 1)],
                 "coupled_consecutive": [bool(dec.coupled[(j, j + 1)]) for j in range(k - 1)],
                 "impact_degree": deg, "ratios_used": [_s(x) for x in res.ratios],
                 "impulses": None if res.impulses is None else _vs(res.impulses),
                 "velocity": None if res.velocity is None else _vs(res.velocity), "valid": res.valid}
