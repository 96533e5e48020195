"""pybullet adapter: spheres and static planes in DIRECT mode, no gravity, no damping, no friction.

Every ball is a free sphere (``createMultiBody``); a scene on a line or in the plane stays there
because every contact normal lies in it. Every body, walls included, gets ``lateralFriction``,
``spinningFriction``, ``rollingFriction``, ``linearDamping`` and ``angularDamping`` 0 (pybullet's
own damping default is 0.04).

Settings (passed to ``setPhysicsEngineParameter`` for every run, so the run does not depend on
hidden state):

================================  ======  =================================================
``fixedTimeStep``                 1/240   read from ``getPhysicsEngineParameters``
``numSolverIterations``           50      read from ``getPhysicsEngineParameters``
``numSubSteps``                   0       read from ``getPhysicsEngineParameters``
``restitutionVelocityThreshold``  0.2     below this relative speed a contact gets no restitution
``erp``                           0.2     Baumgarte error reduction (non-contact rows)
``contactERP``                    0.08    error reduction of contact rows (measured, see below)
``contactSlop``                   1e-5    allowed penetration before error reduction (measured)
``useSplitImpulse``               1       position correction kept out of the velocities
``splitImpulsePenetrationThreshold`` −0.04  penetration beyond which split impulse applies
``contactBreakingThreshold``      0.02    distance under which contact points are kept
``globalCFM``                     0.0     constraint force mixing
``warmStartingFactor``            0.85    warm start of the iterative solver
``restitution``                   0.0     every body's ``restitution`` (set by ``restitution=e``)
================================  ======  =================================================

The values not readable through pybullet are Bullet's ``btContactSolverInfo`` constructor values
(bulletphysics/bullet3, ``src/BulletDynamics/ConstraintSolver/btContactSolverInfo.h``) and
``gContactBreakingThreshold``, except ``contactERP`` and ``contactSlop``: pybullet's server
overrides those two, and the values above are the ones that reproduce an untouched pybullet 3.2.7
bit for bit (``contactERP = 0.2`` or ``contactSlop = 0`` do not; 0.079 and 0.081 do not either).
``tests/test_engines.py`` checks that passing every declared default gives the same velocities,
bit for bit, as leaving pybullet alone, on the cradle and two balls and a wall.

Restitution. Bullet combines the restitution of two bodies as the product
(``btManifoldResult::calculateCombinedRestitution``), so ``restitution = e`` sets every body's
(walls included) ``restitution`` to ``√e``: every contact then has ``e``. The recorded setting
``restitution`` is ``e`` (the per-contact value); ``restitution=None`` keeps pybullet's default 0.
"""

from __future__ import annotations

import math

import numpy as np

from .driver import EngineNotInstalled

__all__ = ["defaults", "restitution_settings", "build"]


def _pybullet():
    try:
        import pybullet
    except ImportError as exc:
        raise EngineNotInstalled("pybullet", "pybullet", str(exc)) from None
    return pybullet


_READ = ("fixedTimeStep", "numSolverIterations", "numSubSteps")
_BULLET = {"restitutionVelocityThreshold": 0.2, "erp": 0.2, "contactERP": 0.08, "contactSlop": 1e-5,
           "useSplitImpulse": 1, "splitImpulsePenetrationThreshold": -0.04, "contactBreakingThreshold": 0.02,
           "globalCFM": 0.0, "warmStartingFactor": 0.85}
_DEFAULTS = None


def defaults() -> dict:
    """Every setting with its default (see the module docstring)."""
    global _DEFAULTS
    if _DEFAULTS is None:
        pb = _pybullet()
        cid = pb.connect(pb.DIRECT)
        try:
            got = pb.getPhysicsEngineParameters(physicsClientId=cid)
        finally:
            pb.disconnect(cid)
        d = {k: got[k] for k in _READ}
        d.update(_BULLET)
        d["restitution"] = 0.0
        _DEFAULTS = d
    return dict(_DEFAULTS)


def restitution_settings(e: float, settings: dict) -> dict:
    """``restitution = e`` sets every body's restitution to ``√e`` (recorded as the per-contact ``e``)."""
    return {"restitution": float(e)}


class _Sim:
    def __init__(self, es, s, explicit=True):
        from ..errors import ImpactInputError

        pb = _pybullet()
        self.pb = pb
        self.cid = pb.connect(pb.DIRECT)
        c = self.cid
        try:
            pb.setGravity(0, 0, 0, physicsClientId=c)
            params = {k: v for k, v in s.items() if k != "restitution"}
            if explicit:
                pb.setPhysicsEngineParameter(physicsClientId=c, **params)
            rest = math.sqrt(float(s["restitution"]))
            self.ids = []
            for b in es.balls:
                shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=b.radius, physicsClientId=c)
                pos = (list(b.position) + [0.0, 0.0])[:3]
                body = pb.createMultiBody(baseMass=b.mass, baseCollisionShapeIndex=shape, basePosition=pos,
                                          physicsClientId=c)
                vel = (list(b.velocity) + [0.0, 0.0])[:3]
                pb.resetBaseVelocity(body, linearVelocity=vel, angularVelocity=[0, 0, 0], physicsClientId=c)
                self.ids.append(body)
            walls = []
            for w in es.walls:
                normal = (list(w.normal) + [0.0, 0.0])[:3]
                shape = pb.createCollisionShape(pb.GEOM_PLANE, planeNormal=normal, physicsClientId=c)
                walls.append(pb.createMultiBody(baseMass=0, baseCollisionShapeIndex=shape,
                                                basePosition=(list(w.point) + [0.0, 0.0])[:3], physicsClientId=c))
            for body in self.ids + walls:
                pb.changeDynamics(body, -1, restitution=rest, lateralFriction=0, spinningFriction=0,
                                  rollingFriction=0, linearDamping=0, angularDamping=0, physicsClientId=c)
        except pb.error as exc:
            pb.disconnect(c)
            raise ImpactInputError("settings", f"pybullet cannot build the scene: {exc}") from None
        self.dim = es.dim

    def step(self):
        self.pb.stepSimulation(physicsClientId=self.cid)

    def state(self):
        pb, c, d = self.pb, self.cid, self.dim
        P = np.array([pb.getBasePositionAndOrientation(b, physicsClientId=c)[0][:d] for b in self.ids])
        V = np.array([pb.getBaseVelocity(b, physicsClientId=c)[0][:d] for b in self.ids])
        return P, V

    def close(self):
        self.pb.disconnect(self.cid)


def build(es, settings: dict, *, explicit: bool = True):
    """The pybullet world of ``es``; ``explicit=False`` leaves the engine parameters untouched
    (pybullet's hidden defaults; used to check the declared ones)."""
    return _Sim(es, settings, explicit)
