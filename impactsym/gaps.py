"""Gap-aware resolution: the impact ordering and outcome that given small gaps produce.

A simultaneous impact of balls on a line is the limit of nearby motions in which the touching
contacts are slightly open and close one at a time (Seghete & Murphey, sec. II-B, IV-A). Which
ordering happens, and so which outcome, depends on the gaps. :func:`resolve_with_gaps` opens
each closed contact of a scene by a given gap ``g_i ≥ 0``, runs the exact event-driven simulator
(:func:`impactsym.simulate.simulate_line`, Newton's law of restitution per collision, written
independently of impactsym's laws) and reports the ordering, the post-impact velocity, the
impulses and the kinetic energy, all exact and verified before return.

How the contacts are opened: every body (ball or wall) is sorted along the line; the leftmost
stays where it is and every body right of a closed contact moves right by the sum of the gaps
of the closed contacts to its left. Each closed contact then has exactly its gap, every open
gap of the scene is unchanged, and velocities are untouched. Walls move with the bodies around
them (a ball touching two walls needs one of them moved); positions do not enter the outcome.

Contacts that are open in the scene (balls not in the impact, walls not touched) are watched:
if one of them closes before the impact's last collision, the gaps are too large for that scene
and the resolution is refused.

Examples
--------
Two balls against a wall (Seghete & Murphey, fig. 3): the ball–ball gap smaller than the wall
gap makes ``1-2`` close first; equal masses, ``v⁻ = (−1, −2)``:

>>> from impactsym.models.seghete_murphey import two_balls_wall
>>> r = resolve_with_gaps(two_balls_wall(), ["1/100", "1/1000"])
>>> r.order_names, list(r.velocity), list(r.impulses)
(('1-2', 'wall@0-1', '1-2', 'wall@0-1'), [1, 2], [6, 4])
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .errors import DomainError, ImpactInputError, VerificationError
from .numbers import to_exact
from .scenes import Scene, balls_on_line, full_velocity
from .simulate import simulate_line

__all__ = ["resolve_with_gaps", "GapResolution"]


@dataclass(frozen=True)
class GapResolution:
    """The outcome that one set of gaps produces, exact.

    Attributes
    ----------
    contacts : tuple of str
        The scene's closed contacts (``scene.contacts``), in its order.
    gaps : tuple of sympy.Rational
        The gap opened at each contact.
    restitution : tuple of sympy.Rational
        Newton's coefficient of each contact.
    order : tuple of int
        The collisions in time order, as indices into ``contacts`` (a contact may recur).
    order_names : tuple of str
        The same, as contact names.
    times : tuple of sympy.Rational
        Time of each collision, from the opened configuration at ``t = 0``. Equal times are
        independent collisions (they share no ball) or follow each other at one instant.
    velocity : sympy.Matrix
        Post-impact velocity in the scene's coordinates (the involved balls, ``scene.coordinates``).
    all_velocities : list
        Post-impact velocity of every ball of the scene (the uninvolved ones unchanged).
    impulses : sympy.Matrix
        ``p`` (k×1) with ``M (v⁺ − v⁻) = Hᵀ p`` exactly and ``p ≥ 0``.
    impulses_unique : bool
        Whether ``H`` has full row rank (then ``p`` is the unique solution, and equals the
        simulator's accumulated impulses); otherwise ``p`` is the simulator's accumulated one,
        one of several that satisfy the balance.
    kinetic_energy_before, kinetic_energy_after : sympy.Rational
        ``½ vᵀ M v`` of the scene before and after.
    positions, walls : list of sympy.Rational
        The opened configuration that was simulated (every ball's centre, every wall).
    exact : bool
        Always ``True``.
    """

    contacts: tuple
    gaps: tuple
    restitution: tuple
    order: tuple
    order_names: tuple
    times: tuple
    velocity: sp.Matrix
    all_velocities: list
    impulses: sp.Matrix
    impulses_unique: bool
    kinetic_energy_before: sp.Expr
    kinetic_energy_after: sp.Expr
    positions: list
    walls: list
    exact: bool = True


# ---------------------------------------------------------------------------------------------
# Input
# ---------------------------------------------------------------------------------------------
def _rational(x, argument):
    if isinstance(x, (float, np.floating, sp.Float)):
        raise ImpactInputError(argument, f"must be exact (an integer, a rational or decimal text), got the float {x!r}")
    val = to_exact(x, argument)
    if not val.is_Rational:
        raise ImpactInputError(argument, f"must be rational (the gap simulator is exact rational), got {val}")
    return val


def _check_gaps(gaps, names):
    from .numbers import parse_vector

    k = len(names)
    if isinstance(gaps, str):
        gaps = list(parse_vector(gaps, "gaps"))
    if isinstance(gaps, sp.MatrixBase):
        gaps = list(gaps)
    if not hasattr(gaps, "__len__") or isinstance(gaps, Mapping):
        raise ImpactInputError("gaps", f"must be a sequence of {k} exact numbers, one per closed contact, got {gaps!r}")
    gaps = list(gaps)
    if len(gaps) != k:
        raise ImpactInputError("gaps", f"has {len(gaps)} entries, expected {k}: one per closed contact "
                                       f"({', '.join(names)})")
    out = []
    for i, g in enumerate(gaps):
        val = _rational(g, f"gaps[{i}] ({names[i]})")
        if val < 0:
            raise ImpactInputError("gaps", f"entry {i} ({names[i]}) must be >= 0, got {val}")
        out.append(val)
    return out


def _check_restitution(restitution, names):
    k = len(names)
    if isinstance(restitution, Mapping):
        unknown = [n for n in restitution if n not in names]
        if unknown:
            raise ImpactInputError("restitution", f"names no closed contact: {unknown[0]!r} (closed contacts: "
                                                  f"{', '.join(names)})")
        values = [restitution.get(n, 1) for n in names]
    elif isinstance(restitution, (list, tuple)):
        if len(restitution) != k:
            raise ImpactInputError("restitution", f"has {len(restitution)} entries, expected {k}: one per closed "
                                                  f"contact ({', '.join(names)})")
        values = list(restitution)
    else:
        values = [restitution] * k
    out = []
    for n, e in zip(names, values):
        val = _rational(e, f"restitution[{n!r}]")
        if not 0 <= val <= 1:
            raise ImpactInputError(f"restitution[{n!r}]", f"must satisfy 0 <= e <= 1, got {val}")
        out.append(val)
    return out


def _scene_of(system) -> tuple[Scene, bool]:
    """The balls-on-line scene to simulate, and whether its open contacts are watched (a scene
    with geometry) or not (a system rebuilt from ``(M, H, v)``, whose only contacts are H's rows)."""
    if isinstance(system, Scene):
        builder = system.meta.get("builder")
        if builder != "balls_on_line":
            raise ImpactInputError("scene", f"gaps need balls on a line (a scene from balls_on_line), this scene "
                                            f"comes from {builder or 'an explicit M, H, v'}: the gap simulator is "
                                            "one-dimensional")
        if not system.meta.get("exact", False):
            raise ImpactInputError("scene", "is a float scene; the gap simulator is exact: build the scene from "
                                            "integers, rationals or decimal text")
        return system, True
    if isinstance(system, (tuple, list)) and len(system) == 3:
        return _line_scene_from_system(*system), False
    raise ImpactInputError("scene", f"must be a Scene of balls on a line or a tuple (M, H, v), got "
                                    f"{type(system).__name__}")


def _line_scene_from_system(M, H, v) -> Scene:
    """Rebuild balls on a line from ``(M, H, v)`` when the system is one: ``M`` diagonal, each
    row of ``H`` a wall row (one entry ``±1``) or a pair row (``−1`` on the left ball, ``+1`` on
    the right one), each ball with at most one contact on each side, the contacts forming chains.
    Unit radii, chains laid out left to right 10 apart; the rebuilt scene's ``M``, ``H``, ``v``
    are checked to equal the given ones exactly."""
    from .numbers import is_exact, to_exact_matrix

    if not is_exact(M, H, v):
        raise ImpactInputError("mass_matrix/gradients/velocity", "contain floats; the gap simulator is exact: give "
                                                                 "integers, rationals or decimal text")
    why = "(a system without geometry has no gaps; only a system of balls on a line can be given as M, H, v)"
    Mx = to_exact_matrix(M, "mass_matrix")
    Hx = to_exact_matrix(H, "gradients")
    vx = to_exact_matrix(v, "velocity", vector=True)
    n = Mx.shape[0]
    if Mx.shape != (n, n) or Hx.shape[1] != n or vx.shape[0] != n or Hx.shape[0] == 0:
        raise ImpactInputError("mass_matrix/gradients/velocity", "shapes do not agree (M n×n, H k×n, v n)")
    if any(Mx[i, j] != 0 for i in range(n) for j in range(n) if i != j):
        raise ImpactInputError("mass_matrix", f"is not diagonal: not balls on a line {why}")
    masses = [Mx[i, i] for i in range(n)]
    if any(not m.is_Rational or m <= 0 for m in masses):
        raise ImpactInputError("mass_matrix", f"diagonal entries must be positive rationals, got {masses}")
    left, right, walls_left, walls_right = {}, {}, set(), set()
    for i in range(Hx.shape[0]):
        nz = {j: Hx[i, j] for j in range(n) if Hx[i, j] != 0}
        if len(nz) == 1 and list(nz.values())[0] in (1, -1):
            (b, s), = nz.items()
            side = (walls_left, left) if s == 1 else (walls_right, right)
            if b in side[0] or b in side[1]:
                raise ImpactInputError("gradients", f"row {i}: coordinate {b + 1} has two contacts on one side: "
                                                    f"not balls on a line {why}")
            side[0].add(b)
        elif len(nz) == 2 and sorted(nz.values()) == [-1, 1]:
            a = next(j for j, c in nz.items() if c == -1)
            b = next(j for j, c in nz.items() if c == 1)
            if a in right or a in walls_right or b in left or b in walls_left:
                raise ImpactInputError("gradients", f"row {i}: a coordinate has two contacts on one side: "
                                                    f"not balls on a line {why}")
            right[a], left[b] = b, a
        else:
            raise ImpactInputError("gradients", f"row {i} is neither a wall row (one entry ±1) nor a pair row "
                                                f"(−1 and +1): not balls on a line {why}")
    touched = set(left) | set(right) | walls_left | walls_right
    if len(touched) != n:
        free = sorted(set(range(n)) - touched)
        raise ImpactInputError("gradients", f"coordinate {free[0] + 1} is in no contact {why}")
    positions, walls = [None] * n, []
    offset = sp.Integer(0)
    for start in range(n):
        if start in left:
            continue
        if start in walls_left:  # the wall at the chain's left edge
            walls.append(offset)
        b = start
        while True:
            positions[b] = offset + 1
            offset += 2
            if b not in right:
                break
            b = right[b]
        if b in walls_right:
            walls.append(offset)
        offset += 10
    if any(p is None for p in positions):
        raise ImpactInputError("gradients", f"the pair rows form a cycle: not balls on a line {why}")
    scene = balls_on_line(masses, [1] * n, positions, list(vx), walls)
    rows = {name: scene.H.row(i) for i, name in enumerate(scene.contacts)}
    names = []
    for i in range(Hx.shape[0]):
        match = [name for name, row in rows.items() if row == Hx.row(i) and name not in names]
        if not match:  # pragma: no cover - the rebuilt scene closes exactly the given contacts
            raise VerificationError("resolve_with_gaps", f"row {i} was not rebuilt")
        names.append(match[0])
    if scene.M != Mx or scene.v != vx or len(names) != scene.k:  # pragma: no cover
        raise VerificationError("resolve_with_gaps", "the rebuilt balls-on-line scene differs from M, H, v")
    H = sp.Matrix([list(rows[name]) for name in names])
    return Scene(scene.M, H, scene.v, scene.coordinates, names, [bool((H.row(i) * scene.v)[0] < 0) for i in range(H.rows)],
                 scene.meta)


# ---------------------------------------------------------------------------------------------
# Opening the contacts
# ---------------------------------------------------------------------------------------------
def _open(scene: Scene, gaps):
    """Ball and wall positions with each closed contact opened by its gap (leftmost body fixed,
    every body shifted right by the gaps of the closed contacts to its left)."""
    meta = scene.meta
    x, r, walls = list(meta["positions"]), list(meta["radii"]), list(meta["walls"])
    gap_of = dict(zip(scene.contacts, gaps))
    bodies = sorted([(x[b], 1, b) for b in range(len(x))] + [(w, 0, i) for i, w in enumerate(walls)])
    used = set()
    shift = sp.Integer(0)
    new_x, new_w = list(x), list(walls)
    prev = None
    for pos, kind, idx in bodies:
        if prev is not None:
            (ppos, pkind, pidx) = prev
            if pkind == 1 and kind == 1:
                name = f"{min(pidx, idx) + 1}-{max(pidx, idx) + 1}"
            elif pkind == 1 and kind == 0:
                name = f"wall@{walls[idx]}-{pidx + 1}"
            elif pkind == 0 and kind == 1:
                name = f"wall@{walls[pidx]}-{idx + 1}"
            else:
                name = None
            if name in gap_of:
                shift += gap_of[name]
                used.add(name)
        if kind == 1:
            new_x[idx] = pos + shift
        else:
            new_w[idx] = pos + shift
        prev = (pos, kind, idx)
    missing = [c for c in scene.contacts if c not in used]
    if missing:
        raise ImpactInputError("scene", f"contact {missing[0]} is not between neighbouring bodies on the line "
                                        "(coincident zero-radius balls): its gap is not independent of the others")
    sim_name = {}
    for i, c in enumerate(scene.contacts):
        if c.startswith("wall@"):
            w_text, ball = c[5:].rsplit("-", 1)
            wi = next(j for j, w in enumerate(walls) if str(w) == w_text)
            sim_name[c] = f"wall@{new_w[wi]}-{ball}"
        else:
            sim_name[c] = c
    return new_x, new_w, sim_name


# ---------------------------------------------------------------------------------------------
# Resolution
# ---------------------------------------------------------------------------------------------
def resolve_with_gaps(scene_or_system, gaps, restitution=1, *, max_events: int | None = None) -> GapResolution:
    """The impact ordering and outcome that the given gaps produce (exact small-gap simulation).

    Parameters
    ----------
    scene_or_system : Scene or tuple (M, H, v)
        A scene of balls on a line (:func:`impactsym.scenes.balls_on_line`, or the models built
        on it: ``cradle``, ``two_balls_wall``, ...), exact. A tuple ``(M, H, v)`` is accepted only
        when it is a system of balls on a line (``M`` diagonal, rows of ``H`` wall rows ``±e_b``
        or pair rows ``e_b − e_a``, chains of contacts); it is rebuilt as one (unit radii, chains
        apart) and, having no geometry beyond its contacts, nothing else is watched.
    gaps : sequence of exact numbers ``≥ 0`` (or text ``"g1,g2,…"``)
        One per closed contact, in the order of ``scene.contacts`` (of the rows of ``H``). Zero
        leaves a contact touching; a touching contact that approaches closes at ``t = 0``.
    restitution : rational in ``[0, 1]``, a sequence of one per contact, or a mapping
        contact name → e (contacts not named are elastic)
    max_events : int, optional
        Cap on the collisions (see :func:`impactsym.simulate.simulate_line`).

    Returns
    -------
    GapResolution

    Raises
    ------
    ImpactInputError
        A scene that is not exact balls on a line, an ``(M, H, v)`` that is not a line of balls
        (a system without geometry has no gaps), gaps of the wrong count, negative, float,
        irrational or non-finite, a restitution outside ``[0, 1]``.
    DomainError
        The gaps make two contacts sharing a ball close at one instant (a simultaneous impact:
        choose other gaps), an open contact of the scene closes during the impact (gaps too
        large), or the collisions do not end (inelastic collapse, or the cap).
    VerificationError
        The impulses fail ``M (v⁺ − v⁻) = Hᵀ p`` exactly or ``p ≥ 0`` (a bug; never returned).

    Examples
    --------
    A three-ball cradle struck by one ball: whatever the gaps, ``1-2`` then ``2-3``. With
    ``e = 1/2`` at ``1-2`` the first two balls meet again:

    >>> from impactsym.models.seghete_murphey import three_ball_cradle
    >>> r = resolve_with_gaps(three_ball_cradle(), [0, "1/1000"], restitution={"1-2": "1/2"})
    >>> r.order_names, r.times, list(r.velocity)
    (('1-2', '2-3', '1-2'), (0, 1/750, 1/250), [1/16, 3/16, 3/4])
    >>> r.kinetic_energy_before - r.kinetic_energy_after
    51/256

    A system given as ``(M, H, v)`` is rebuilt as balls on a line when it is one, and refused
    otherwise:

    >>> resolve_with_gaps(("1,0;0,1", "1,0;-1,1", "-1,-2"), ["1/10", "1/100"]).order
    (1, 0, 1, 0)
    >>> resolve_with_gaps(("2,1;1,2", "1,0;-1,1", "-1,-2"), [1, 1])
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: mass_matrix: is not diagonal: not balls on a line (a system without geometry has no gaps; only a system of balls on a line can be given as M, H, v)
    """
    scene, watch = _scene_of(scene_or_system)
    names = list(scene.contacts)
    g = _check_gaps(gaps, names)
    e = _check_restitution(restitution, names)
    meta = scene.meta
    x, walls, sim_name = _open(scene, g)
    scene_name = {s: c for c, s in sim_name.items()}
    index = {c: i for i, c in enumerate(names)}
    contacts = list(sim_name.values())  # only these collide; with watch, the others must stay open
    try:
        sim = simulate_line(meta["masses"], meta["radii"], x, list(meta["all_velocities"]), walls,
                            restitution={sim_name[c]: ei for c, ei in zip(names, e)}, contacts=contacts,
                            watch=watch, max_events=max_events)
    except DomainError as err:
        msg = str(err)
        for s in sorted(scene_name, key=len, reverse=True):
            msg = msg.replace(s, scene_name[s])
        raise DomainError(f"gaps: with the gaps {', '.join(map(str, g))}: {msg}") from None
    order = tuple(index[scene_name[name]] for _, name in sim.events)
    v_all = list(sim.velocities)
    vplus = sp.Matrix([v_all[b - 1] for b in meta["bodies"]])
    M, H, v0 = scene.M, scene.H, scene.v
    p_sim = sp.Matrix([sim.impulses.get(sim_name[c], sp.Integer(0)) for c in names])
    dv = M * (vplus - v0)
    unique = H.rank() == H.rows
    if unique:
        p = (H * H.T).LUsolve(H * dv)
        if p != p_sim:
            raise VerificationError("resolve_with_gaps", f"the impulses solved from M(v+ - v-) = H^T p, {list(p)}, "
                                                         f"differ from the simulator's, {list(p_sim)}")
    else:
        p = p_sim
    if dv - H.T * p != sp.zeros(H.cols, 1):
        raise VerificationError("resolve_with_gaps", "M (v+ - v-) = H^T p does not hold exactly")
    if any(pi < 0 for pi in p):
        raise VerificationError("resolve_with_gaps", f"an impulse is negative: {list(p)}")
    half = sp.Rational(1, 2)
    ke0 = half * (v0.T * M * v0)[0, 0]
    ke1 = half * (vplus.T * M * vplus)[0, 0]
    if ke0 - ke1 != sim.energy_loss:
        raise VerificationError("resolve_with_gaps", "the kinetic energy lost differs from the collisions' losses")
    if full_velocity(scene, vplus) != v_all:
        raise VerificationError("resolve_with_gaps", "a ball outside the impact changed its velocity")
    return GapResolution(tuple(names), tuple(g), tuple(e), order, tuple(names[i] for i in order),
                         tuple(t for t, _ in sim.events), vplus, v_all, p, unique, ke0, ke1, list(x), list(walls))
