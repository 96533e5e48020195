"""The neutral input every engine adapter builds from: balls and walls, plus the reduced coordinates.

An :class:`EngineScene` is what a physics engine needs to build a scene (each ball's mass, radius,
position and velocity; each wall as a point and a unit normal pointing to the side where the balls
are) together with what impactsym needs to compare the engine's answer with a law: the scene's
reduced coordinates (which ball and axis each generalized coordinate is), ``M``, ``H`` and ``v⁻``
in those coordinates.

:func:`engine_scene` accepts

* an :class:`impactsym.scenes.Scene` from :func:`~impactsym.scenes.balls_on_line` (and the models
  built with it: ``cradle``, ``three_ball_cradle``, ``two_balls_wall``, ``balls_against_wall``),
  whose ``meta`` holds every ball and wall;
* any other :class:`~impactsym.scenes.Scene` with a diagonal mass matrix whose rows are ball–ball
  or ball–wall contacts (``balls_in_plane``, ``chain3``, ``pool``, ``bernoulli``): the geometry is
  rebuilt from the gradient rows with unit radii (only the involved balls, which is all a
  law sees; row lengths do not change any law's velocity);
* a plain dict ``{"bodies": [{"mass", "radius", "position", "velocity"}, ...],
  "walls": [{"point", "normal"}, ...]}`` (positions and velocities numbers on a line, pairs in the
  plane; a wall's normal points to the balls' side);
* an :class:`EngineScene` (returned as it is).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ImpactInputError
from ..scenes import FLOAT_GAP_RTOL

__all__ = ["Ball", "Wall", "EngineScene", "engine_scene", "scene_to_dict", "CONTACT_RTOL"]

#: a pair counts as touching when |gap| is at most CONTACT_RTOL times the scene's length scale
#: (the scene builders' tolerance, :data:`impactsym.scenes.FLOAT_GAP_RTOL`)
CONTACT_RTOL = FLOAT_GAP_RTOL


@dataclass(frozen=True)
class Ball:
    """A ball: ``position`` and ``velocity`` are tuples of ``dim`` floats."""

    mass: float
    radius: float
    position: tuple
    velocity: tuple


@dataclass(frozen=True)
class Wall:
    """A fixed wall: the half-space ``(x − point)·normal ≥ 0`` is free (``normal`` a unit vector)."""

    point: tuple
    normal: tuple


@dataclass(frozen=True)
class EngineScene:
    """Balls and walls (what an engine builds) and the reduced coordinates (what a law sees).

    Attributes
    ----------
    dim : 1 (balls on a line, along x) or 2 (balls in the plane x–y)
    balls, walls : tuples of :class:`Ball` and :class:`Wall`
    coordinates : one ``(ball index, axis)`` per generalized coordinate of the scene
    names : the coordinates' names (``"x1"``, ``"y2"``, ...)
    M, H, v : the reduced mass matrix, gradient rows of the closed contacts and ``v⁻`` (floats)
    contacts : names of the closed contacts
    """

    dim: int
    balls: tuple
    walls: tuple
    coordinates: tuple
    names: tuple
    M: np.ndarray
    H: np.ndarray
    v: np.ndarray
    contacts: tuple

    def reduced(self, velocities) -> np.ndarray:
        """The scene's reduced velocity from every ball's velocity (``n_balls × dim`` floats)."""
        V = np.asarray(velocities, dtype=float).reshape(len(self.balls), self.dim)
        return np.array([V[b, a] for b, a in self.coordinates])

    def with_gaps(self, gaps) -> "EngineScene":
        """The same scene with the balls moved apart so that closed contact ``i`` (in the order of
        ``contacts``) opens by ``gaps[i] ≥ 0``; ``M``, ``H``, ``v⁻`` stay those of the touching scene,
        so the engine's answer is still compared with the laws at the impact instant.

        Balls on a line only. Every ball beyond a contact (away from the wall for a wall contact,
        right of the pair for a ball–ball contact) moves by that contact's gap, so a scene with
        walls on both sides (whose length is fixed) is refused.

        >>> from impactsym.models.seghete_murphey import three_ball_cradle
        >>> es = engine_scene(three_ball_cradle()).with_gaps([0.5, 0.25])
        >>> [b.position for b in es.balls]
        [(1.0,), (3.5,), (5.75,)]
        """
        if self.dim != 1:
            raise ImpactInputError("gaps", "are supported for balls on a line only")
        g = [_float(x, "gaps") for x in (gaps if hasattr(gaps, "__len__") and not isinstance(gaps, str) else [gaps])]
        if len(g) != len(self.contacts):
            raise ImpactInputError("gaps", f"has {len(g)} entries, expected {len(self.contacts)} (one per closed contact)")
        if any(x < 0 for x in g):
            raise ImpactInputError("gaps", f"must be non-negative, got {g}")
        if len({w.normal[0] for w in self.walls}) > 1:
            raise ImpactInputError("gaps", "walls on both sides fix the scene's length: it cannot open")
        x = [b.position[0] for b in self.balls]
        shift = [0.0] * len(x)
        for r, gap in enumerate(g):
            on = sorted({self.coordinates[c][0] for c in range(self.H.shape[1]) if self.H[r, c] != 0},
                        key=lambda b: x[b])
            if len(on) == 2:  # balls right of the pair's left ball move right
                moved = [b for b in range(len(x)) if x[b] >= x[on[1]]]
                sign = 1.0
            else:
                sign = float(self.walls[0].normal[0]) if self.walls else 1.0
                moved = [b for b in range(len(x)) if sign * (x[b] - x[on[0]]) >= 0]
            for b in moved:
                shift[b] += sign * gap
        balls = tuple(Ball(b.mass, b.radius, (b.position[0] + shift[i],), b.velocity) for i, b in enumerate(self.balls))
        return EngineScene(self.dim, balls, self.walls, self.coordinates, self.names, self.M, self.H, self.v,
                           self.contacts)

    def kinetic_distance(self, a, b) -> float:
        """``‖a − b‖_M / ‖v⁻‖_M`` for two reduced velocities (the metric of :mod:`impactsym.engines`)."""
        d = np.asarray(a, dtype=float).reshape(-1) - np.asarray(b, dtype=float).reshape(-1)
        return float(math.sqrt(d @ self.M @ d) / math.sqrt(self.v @ self.M @ self.v))


def _float(x, argument):
    try:
        import sympy as sp

        xf = float(sp.N(x, 17)) if isinstance(x, sp.Basic) else float(x)
    except (TypeError, ValueError):
        raise ImpactInputError(argument, f"entry {x!r} is not a number") from None
    if not math.isfinite(xf):
        raise ImpactInputError(argument, f"entry {xf} is not finite")
    return xf


def _vector(x, dim, argument):
    if dim == 1 and not hasattr(x, "__len__"):
        return (_float(x, argument),)
    if isinstance(x, str) or not hasattr(x, "__len__") or len(x) != dim:
        raise ImpactInputError(argument, f"must have {dim} component(s), got {x!r}")
    return tuple(_float(c, argument) for c in x)


def _pair_contact(balls, i, j, dim):
    """Gap and unit normal (from i to j) of balls i and j."""
    d = np.subtract(balls[j].position, balls[i].position)
    dist = float(np.linalg.norm(d))
    n = d / dist if dist > 0 else np.zeros(dim)
    return dist - balls[i].radius - balls[j].radius, n


def _wall_contact(ball, wall):
    x = np.subtract(ball.position, wall.point)
    return float(x @ np.asarray(wall.normal)) - ball.radius


def _build(dim, balls, walls, coordinates=None) -> EngineScene:
    """Close the touching contacts, pick the involved balls, and assemble ``M``, ``H``, ``v⁻``."""
    scale = max([1.0] + [abs(c) for b in balls for c in b.position] + [b.radius for b in balls])
    tol = CONTACT_RTOL * scale
    rows, names = [], []
    for i in range(len(balls)):
        for j in range(i + 1, len(balls)):
            gap, n = _pair_contact(balls, i, j, dim)
            if gap < -tol:
                raise ImpactInputError("bodies", f"balls {i + 1} and {j + 1} overlap (gap {gap:.3g} < 0)")
            if gap <= tol:
                rows.append({i: -n, j: n})
                names.append(f"{i + 1}-{j + 1}")
    for w, wall in enumerate(walls):
        for b, ball in enumerate(balls):
            gap = _wall_contact(ball, wall)
            if gap < -tol:
                raise ImpactInputError("walls", f"ball {b + 1} penetrates wall {w + 1} (gap {gap:.3g} < 0)")
            if gap <= tol:
                rows.append({b: np.asarray(wall.normal, dtype=float)})
                names.append(f"wall{w + 1}-{b + 1}")
    if not rows:
        raise ImpactInputError("bodies", "no contact is closed (every gap is positive): there is no impact")
    if coordinates is None:
        involved = sorted({b for r in rows for b in r})
        coordinates = tuple((b, a) for b in involved for a in range(dim))
    slot = {c: k for k, c in enumerate(coordinates)}
    H = np.zeros((len(rows), len(coordinates)))
    for r, row in enumerate(rows):
        for b, n in row.items():
            for a in range(dim):
                if (b, a) not in slot:
                    if abs(n[a]) > 0:
                        raise ImpactInputError("scene", f"contact {names[r]} moves ball {b + 1} along an axis "
                                                        "that is not one of the scene's coordinates")
                    continue
                H[r, slot[(b, a)]] = n[a]
    M = np.diag([balls[b].mass for b, _ in coordinates])
    v = np.array([balls[b].velocity[a] for b, a in coordinates])
    axis = "xy"
    return EngineScene(dim, tuple(balls), tuple(walls), tuple(coordinates),
                       tuple(f"{axis[a]}{b + 1}" for b, a in coordinates), M, H, v, tuple(names))


def _from_dict(d) -> EngineScene:
    if "restitution" in d:
        raise ImpactInputError("restitution", "a scene's own restitution is not read by the engines: pass "
                                              "restitution= to impactsym.engines.run (one value for every contact)")
    explicit = [k for k in ("mass_matrix", "gradients", "velocity") if k in d]
    if explicit:
        raise ImpactInputError(explicit[0], "the engines build bodies: give 'bodies' (and 'walls'), "
                                            "not the explicit M, H, v form")
    bodies = d.get("bodies")
    if not isinstance(bodies, (list, tuple)) or not bodies:
        raise ImpactInputError("bodies", "must be a non-empty list of {mass, radius, position, velocity}")
    first = bodies[0].get("position") if isinstance(bodies[0], dict) else None
    dim = 1 if not hasattr(first, "__len__") else len(first)
    if dim not in (1, 2):
        raise ImpactInputError("bodies", f"positions must be numbers (a line) or pairs (the plane), got {first!r}")
    balls = []
    for i, b in enumerate(bodies):
        if not isinstance(b, dict):
            raise ImpactInputError("bodies", f"entry {i + 1} must be a dict, got {b!r}")
        missing = [k for k in ("mass", "radius", "position", "velocity") if k not in b]
        if missing:
            raise ImpactInputError("bodies", f"entry {i + 1} lacks {', '.join(missing)}")
        m, r = _float(b["mass"], "mass"), _float(b["radius"], "radius")
        if m <= 0 or r <= 0:
            raise ImpactInputError("bodies", f"entry {i + 1}: mass and radius must be positive, got {m}, {r}")
        balls.append(Ball(m, r, _vector(b["position"], dim, "position"), _vector(b["velocity"], dim, "velocity")))
    walls = []
    for i, w in enumerate(d.get("walls", ()) or ()):
        if not isinstance(w, dict) or "point" not in w or "normal" not in w:
            raise ImpactInputError("walls", f"entry {i + 1} must be a dict with 'point' and 'normal', got {w!r}")
        p, n = _vector(w["point"], dim, "point"), np.array(_vector(w["normal"], dim, "normal"))
        norm = float(np.linalg.norm(n))
        if norm == 0:
            raise ImpactInputError("walls", f"entry {i + 1}: the normal is zero")
        walls.append(Wall(p, tuple(n / norm)))
    return _build(dim, balls, walls)


def _from_line_meta(scene) -> EngineScene:
    meta = scene.meta
    m, r, x = meta["masses"], meta["radii"], meta["positions"]
    v = meta["all_velocities"]
    balls = [Ball(_float(m[i], "masses"), _float(r[i], "radii"), (_float(x[i], "positions"),),
                  (_float(v[i], "velocities"),)) for i in range(len(m))]
    walls = []
    for w in meta.get("walls", ()):
        wf = _float(w, "walls")
        sides = {1 if b.position[0] > wf else -1 for b in balls}
        if len(sides) != 1:
            raise ImpactInputError("scene", f"balls lie on both sides of the wall at {w}: an engine's wall "
                                            "is a half-space with one free side")
        walls.append(Wall((wf,), (float(sides.pop()),)))
    coords = tuple((b - 1, 0) for b in meta["bodies"])
    es = _build(1, balls, walls, coords)
    return _match_scene(es, scene)


def _from_gradients(scene) -> EngineScene:
    """Rebuild balls (unit radii) and walls from a diagonal ``M`` and ball–ball / ball–wall rows."""
    M = _float_matrix(scene.M)
    H = _float_matrix(scene.H)
    v = np.array([_float(c, "velocity") for c in (list(scene.v) if not isinstance(scene.v, np.ndarray)
                                                   else scene.v.reshape(-1))])
    n = M.shape[0]
    if np.any(np.abs(M - np.diag(np.diag(M))) > 0):
        raise ImpactInputError("scene", "the engines build balls: the mass matrix must be diagonal")
    names = list(scene.coordinates) or [f"q{i + 1}" for i in range(n)]
    dim = 2 if any(str(c).startswith("y") for c in names) else 1
    if n % dim:
        raise ImpactInputError("scene", f"{n} coordinates do not split into balls of dimension {dim}")
    nb = n // dim
    mass = [M[dim * b, dim * b] for b in range(nb)]
    for b in range(nb):
        if any(M[dim * b + a, dim * b + a] != mass[b] for a in range(dim)):
            raise ImpactInputError("scene", f"ball {b + 1} has different masses along x and y")
    pos = [None] * nb
    pos[0] = np.zeros(dim)
    pairs, wall_rows = [], []
    for r in range(H.shape[0]):
        on = [b for b in range(nb) if np.any(H[r, dim * b:dim * b + dim] != 0)]
        if len(on) == 2:
            i, j = on
            ni, nj = H[r, dim * i:dim * i + dim], H[r, dim * j:dim * j + dim]
            if not np.allclose(ni, -nj, rtol=1e-12, atol=0):
                raise ImpactInputError("scene", f"row {r + 1} is not a ball–ball contact (opposite normals)")
            pairs.append((i, j, nj / np.linalg.norm(nj)))
        elif len(on) == 1:
            b = on[0]
            nb_ = H[r, dim * b:dim * b + dim]
            wall_rows.append((b, nb_ / np.linalg.norm(nb_)))
        else:
            raise ImpactInputError("scene", f"row {r + 1} acts on {len(on)} balls: not a ball–ball or ball–wall contact")
    changed = True
    while changed:  # place the balls along the contact graph: G_j = G_i + 2 n (unit radii)
        changed = False
        for i, j, nrm in pairs:
            if pos[i] is not None and pos[j] is None:
                pos[j], changed = pos[i] + 2 * nrm, True
            elif pos[j] is not None and pos[i] is None:
                pos[i], changed = pos[j] - 2 * nrm, True
    for b in range(nb):
        if pos[b] is None:  # a ball touching only walls: far from the others
            pos[b] = np.zeros(dim) + 10.0 * (b + 1) * nb
    for i, j, nrm in pairs:
        if not np.allclose(pos[j] - pos[i], 2 * nrm, atol=1e-9):
            raise ImpactInputError("scene", f"contacts {i + 1}-{j + 1} cannot all touch with equal radii")
    balls = [Ball(float(mass[b]), 1.0, tuple(float(c) for c in pos[b]), tuple(float(c) for c in v[dim * b:dim * b + dim]))
             for b in range(nb)]
    walls = [Wall(tuple(float(c) for c in pos[b] - nrm), tuple(float(c) for c in nrm)) for b, nrm in wall_rows]
    coords = tuple((b, a) for b in range(nb) for a in range(dim))
    es = _build(dim, balls, walls, coords)
    return _match_scene(es, scene)


def _float_matrix(A):
    if isinstance(A, np.ndarray):
        return A.astype(float)
    return np.array([[_float(x, "gradients") for x in row] for row in A.tolist()], dtype=float)


def _match_scene(es: EngineScene, scene) -> EngineScene:
    """The rebuilt geometry must close exactly the scene's contacts (same rows up to positive scale)."""
    H = _float_matrix(scene.H)
    if H.shape[0] != es.H.shape[0]:
        raise ImpactInputError("scene", f"the rebuilt geometry closes {es.H.shape[0]} contacts, the scene has {H.shape[0]}")
    for r in range(H.shape[0]):
        h = H[r] / np.linalg.norm(H[r])
        if not any(np.allclose(h, g / np.linalg.norm(g), atol=1e-9) for g in es.H):
            raise ImpactInputError("scene", f"contact row {r + 1} of the scene is not realized by its geometry")
    # keep the scene's own rows (and order) so that laws and engines see the same H
    return EngineScene(es.dim, es.balls, es.walls, es.coordinates, es.names, es.M, H, es.v,
                       tuple(scene.contacts) if scene.contacts else es.contacts)


def engine_scene(scene) -> EngineScene:
    """The neutral engine input of a scene (see the module docstring for what is accepted).

    Examples
    --------
    >>> from impactsym.models.seghete_murphey import three_ball_cradle
    >>> es = engine_scene(three_ball_cradle())
    >>> [b.position for b in es.balls], es.names, es.H.tolist()
    ([(1.0,), (3.0,), (5.0,)], ('x1', 'x2', 'x3'), [[-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])
    >>> es = engine_scene({"bodies": [{"mass": 1, "radius": 1, "position": 1, "velocity": -1}],
    ...                    "walls": [{"point": 0, "normal": 1}]})
    >>> es.contacts, es.H.tolist(), es.v.tolist()
    (('wall1-1',), [[1.0]], [-1.0])
    """
    from ..scenes import Scene

    if isinstance(scene, EngineScene):
        return scene
    if isinstance(scene, dict):
        return _from_dict(scene)
    if isinstance(scene, Scene):
        if scene.meta.get("builder") == "balls_on_line" and "masses" in scene.meta:
            return _from_line_meta(scene)
        return _from_gradients(scene)
    raise ImpactInputError("scene", f"must be an impactsym Scene, a dict {{'bodies', 'walls'}} or an EngineScene, "
                                    f"got {type(scene).__name__}")


def scene_to_dict(es: EngineScene) -> dict:
    """The plain dict form of an engine scene (the inverse of the dict branch of :func:`engine_scene`).

    >>> from impactsym.models.seghete_murphey import two_balls_wall
    >>> scene_to_dict(engine_scene(two_balls_wall()))["walls"]
    [{'point': 0.0, 'normal': 1.0}]
    """
    def out(t):
        return t[0] if es.dim == 1 else list(t)

    return {"bodies": [{"mass": b.mass, "radius": b.radius, "position": out(b.position), "velocity": out(b.velocity)}
                       for b in es.balls],
            "walls": [{"point": out(w.point), "normal": out(w.normal)} for w in es.walls]}
