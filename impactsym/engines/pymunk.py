"""pymunk adapter (Chipmunk2D): circles and static segments in the plane (a line scene is the
x axis of the plane), no gravity, no damping, no friction, no rotation (infinite moment).

Settings:

==================  ==========  =======================================================
``timestep``        1/60        ``Space.step(dt)`` (pymunk has no default; 1/60 is the usual frame)
``iterations``      10          ``Space.iterations`` (read from a fresh ``Space``)
``collision_slop``  0.1         ``Space.collision_slop``: allowed overlap (read)
``collision_bias``  0.0018      ``Space.collision_bias``: overlap left after 1 s (read; exactly
                                ``(1 − 0.1)^60``)
``elasticity``      0.0         every shape's ``elasticity`` (set by ``restitution=e``)
==================  ==========  =======================================================

Restitution. Chipmunk combines two shapes' elasticities as the product (``cpArbiter``:
``arb->e = a->e * b->e``), so ``restitution = e`` sets every shape's elasticity to ``√e``;
the recorded setting ``elasticity`` is ``e`` (the per-contact value). ``restitution=None`` keeps
the default 0.

Contacts. Chipmunk makes a contact only where two shapes overlap. Balls that touch exactly
(gap 0, as the scene builders place them) are no contact at the first step, so Newton's cradle goes
one pair per step: the sequential outcome (0, 0, 1). The same cradle with overlaps of 1e-9 has both
contacts at the first step, which the solver treats together: Newton's outcome. Measured and pinned
in ``tests/test_engines.py``.

A wall is a static segment (radius 0) of length ``1e4`` times the scene's size along the wall,
centred on the wall's point: a plane for every ball of the scene.
"""

from __future__ import annotations

import math

import numpy as np

from .driver import EngineNotInstalled

__all__ = ["defaults", "restitution_settings", "build"]


def _pymunk():
    try:
        import pymunk
    except ImportError as exc:
        raise EngineNotInstalled("pymunk", "pymunk", str(exc)) from None
    return pymunk


_DEFAULTS = None


def defaults() -> dict:
    """Every setting with its default (see the module docstring)."""
    global _DEFAULTS
    if _DEFAULTS is None:
        pm = _pymunk()
        s = pm.Space()
        _DEFAULTS = {"timestep": 1 / 60, "iterations": int(s.iterations), "collision_slop": float(s.collision_slop),
                     "collision_bias": float(s.collision_bias), "elasticity": 0.0}
    return dict(_DEFAULTS)


def restitution_settings(e: float, settings: dict) -> dict:
    """``restitution = e`` sets every shape's elasticity to ``√e`` (recorded as the per-contact ``e``)."""
    return {"elasticity": float(e)}


class _Sim:
    def __init__(self, es, s):
        from ..errors import ImpactInputError

        pm = _pymunk()
        space = pm.Space()
        try:
            space.gravity = (0.0, 0.0)
            space.damping = 1.0
            space.iterations = int(s["iterations"])
            space.collision_slop = float(s["collision_slop"])
            space.collision_bias = float(s["collision_bias"])
        except (ValueError, TypeError, AssertionError) as exc:
            raise ImpactInputError("settings", f"pymunk refuses a setting: {exc}") from None
        self.dt = float(s["timestep"])
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ImpactInputError("settings", f"timestep must be positive, got {s['timestep']!r}")
        el = math.sqrt(float(s["elasticity"]))
        self.bodies = []
        for b in es.balls:
            body = pm.Body(b.mass, float("inf"))
            body.position = tuple((list(b.position) + [0.0])[:2])
            body.velocity = tuple((list(b.velocity) + [0.0])[:2])
            shape = pm.Circle(body, b.radius)
            shape.elasticity, shape.friction = el, 0.0
            space.add(body, shape)
            self.bodies.append(body)
        size = max([1.0] + [abs(c) + b.radius for b in es.balls for c in b.position])
        for w in es.walls:
            p = np.array((list(w.point) + [0.0])[:2])
            n = np.array((list(w.normal) + [0.0])[:2])
            t = np.array([-n[1], n[0]]) * 1e4 * size
            seg = pm.Segment(space.static_body, tuple(p - t), tuple(p + t), 0.0)
            seg.elasticity, seg.friction = el, 0.0
            space.add(seg)
        self.space = space
        self.dim = es.dim

    def step(self):
        self.space.step(self.dt)

    def state(self):
        d = self.dim
        P = np.array([tuple(b.position)[:d] for b in self.bodies])
        V = np.array([tuple(b.velocity)[:d] for b in self.bodies])
        return P, V

    def close(self):
        pass


def build(es, settings: dict):
    """The pymunk space of ``es``, ready to step."""
    return _Sim(es, settings)
