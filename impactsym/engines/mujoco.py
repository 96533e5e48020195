"""MuJoCo adapter: spheres on slide joints (x, and y in the plane), planes for walls, no gravity.

Settings (defaults read from a fresh ``mujoco.MjModel``, except ``condim``):

==================  ========================  ==================================================
``timestep``        0.002                     ``option/timestep``
``integrator``      ``"Euler"``               ``option/integrator`` (Euler, RK4, implicit, implicitfast)
``solver``          ``"Newton"``              ``option/solver`` (PGS, CG, Newton)
``iterations``      100                       ``option/iterations``
``tolerance``       1e-8                      ``option/tolerance``
``solref``          (0.02, 1)                 every geom's ``solref`` (timeconst, dampratio), or
                                              (−stiffness, −damping) (the "direct" form)
``solimp``          (0.9, 0.95, 0.001, 0.5, 2) every geom's ``solimp``
``condim``          1                         every geom's ``condim``: 1 is frictionless, as the
                                              laws are (MuJoCo's own default is 3)
``friction``        1                         sliding friction (acts only with ``condim`` ≥ 3)
``cone``            ``"pyramidal"``           ``option/cone`` (with ``condim`` ≥ 3)
``impratio``        1                         ``option/impratio`` (with ``condim`` ≥ 3, elliptic cone)
==================  ========================  ==================================================

Restitution. MuJoCo has no restitution coefficient: a contact follows a reference
spring–damper ``a_ref = −b (J v) − k r`` in constraint space, reached to the extent of the
impedance ``d ∈ [0.0001, 0.9999]`` set by ``solimp`` (MuJoCo documentation, Modeling → Solver
parameters, and Computation → Soft constraints; google-deepmind/mujoco issue #2080 asks how to turn
restitution into solref/solimp). With the positive form ``(timeconst, dampratio)``,
``b = 2/(d_max·timeconst)`` and ``k = d(r)/(d_max²·timeconst²·dampratio²)``: ``dampratio`` is the
damping ratio of that oscillator, and ``dampratio = 0`` (elastic) is out of reach (``k`` diverges). The direct form
``solref = (−k, −b)`` gives the stiffness and damping themselves, and ``b = 0`` is an undamped,
elastic contact. ``restitution = e`` is therefore mapped to the direct form

    ``solref = (−1/τ², −2ζ/τ)``,  ``τ = 0.02`` (MuJoCo's default timeconst),
    ``ζ = −ln e / √(π² + ln² e)``,

the damping ratio whose damped linear oscillator rebounds, after half a period, with ``e`` times
its speed (the textbook spring–dashpot restitution ``e = exp(−πζ/√(1 − ζ²))``). ``e = 0`` maps to
``ζ = 1`` (critical damping, MuJoCo's default dampratio). The measured restitution departs from
``e`` by the impedance ``solimp`` (``d < 1`` softens the reference) and the time discretization;
``restitution=None`` leaves ``solref`` at MuJoCo's default (a critically damped contact).

Measured (one ball of mass 1 and radius 1 against a wall at speed 1, default settings otherwise;
pinned in ``tests/test_engines.py``): ``e = 1, 0.5, 0.1, 0`` rebound at ``1.0012, 0.5600, 0.2608,
0.1405``. The mapping is right at ``e = 1`` and too bouncy below: the contact cannot pull, so it is
released before the half period of the oscillator, with speed left (the usual unilateral
spring–dashpot defect), and the impedance ``d < 1`` softens the reference further.
"""

from __future__ import annotations

import math

import numpy as np

from .driver import EngineNotInstalled

__all__ = ["defaults", "restitution_settings", "damping_ratio", "build", "TIMECONST"]

#: the time constant of the restitution mapping (MuJoCo's default solref timeconst)
TIMECONST = 0.02


def _mujoco():
    try:
        import mujoco
    except ImportError as exc:
        raise EngineNotInstalled("mujoco", "mujoco", str(exc)) from None
    return mujoco


_DEFAULTS = None


def defaults() -> dict:
    """Every setting with its default (MuJoCo's, read from a fresh model; ``condim`` is 1)."""
    global _DEFAULTS
    if _DEFAULTS is None:
        mujoco = _mujoco()
        m = mujoco.MjModel.from_xml_string("<mujoco><worldbody><geom type='sphere' size='1'/></worldbody></mujoco>")
        o = m.opt
        _DEFAULTS = {
            "timestep": float(o.timestep),
            "integrator": mujoco.mjtIntegrator(o.integrator).name.removeprefix("mjINT_").lower(),
            "solver": {"PGS": "PGS", "CG": "CG", "NEWTON": "Newton"}[mujoco.mjtSolver(o.solver).name.removeprefix("mjSOL_")],
            "iterations": int(o.iterations),
            "tolerance": float(o.tolerance),
            "solref": tuple(float(x) for x in m.geom_solref[0]),
            "solimp": tuple(float(x) for x in m.geom_solimp[0]),
            "condim": 1,
            "friction": float(m.geom_friction[0][0]),
            "cone": mujoco.mjtCone(o.cone).name.removeprefix("mjCONE_").lower(),
            "impratio": float(o.impratio),
        }
    return dict(_DEFAULTS)


def damping_ratio(e: float) -> float:
    """``ζ`` with ``exp(−πζ/√(1 − ζ²)) = e`` (``e = 0`` → 1, critical damping).

    >>> damping_ratio(1.0), round(damping_ratio(0.5), 6)
    (0.0, 0.215454)
    """
    if e <= 0:
        return 1.0
    if e >= 1:
        return 0.0
    le = math.log(e)
    return -le / math.sqrt(math.pi ** 2 + le * le)


def restitution_settings(e: float, settings: dict) -> dict:
    """The settings that ``restitution = e`` decides: ``solref`` in the direct form (see the module)."""
    z = damping_ratio(e)
    return {"solref": (-1.0 / TIMECONST ** 2, -2.0 * z / TIMECONST)}


def _vec3(t):
    return " ".join(repr(float(c)) for c in (list(t) + [0.0, 0.0, 0.0])[:3])


def _xml(es, s) -> str:
    integrator = {"euler": "Euler", "rk4": "RK4", "implicit": "implicit", "implicitfast": "implicitfast"}
    if str(s["integrator"]).lower() not in integrator:
        from ..errors import ImpactInputError

        raise ImpactInputError("settings", f"integrator must be one of {', '.join(integrator.values())}, "
                                           f"got {s['integrator']!r}")
    axes = ["1 0 0", "0 1 0"][:es.dim]
    bodies = []
    for i, b in enumerate(es.balls):
        joints = "".join(f'<joint name="b{i}_{a}" type="slide" axis="{ax}" damping="0" armature="0"/>'
                         for a, ax in enumerate(axes))
        bodies.append(f'<body name="b{i}" pos="{_vec3(b.position)}">{joints}'
                      f'<geom name="g{i}" type="sphere" size="{b.radius!r}" mass="{b.mass!r}"/></body>')
    walls = [f'<geom name="w{k}" type="plane" pos="{_vec3(w.point)}" zaxis="{_vec3(w.normal)}" size="0 0 1"/>'
             for k, w in enumerate(es.walls)]
    geom_defaults = (f'condim="{int(s["condim"])}" solref="{" ".join(map(repr, map(float, s["solref"])))}" '
                     f'solimp="{" ".join(map(repr, map(float, s["solimp"])))}" friction="{float(s["friction"])!r} 0 0"')
    return (f'<mujoco model="impactsym"><option gravity="0 0 0" timestep="{float(s["timestep"])!r}" '
            f'integrator="{integrator[str(s["integrator"]).lower()]}" solver="{s["solver"]}" '
            f'iterations="{int(s["iterations"])}" tolerance="{float(s["tolerance"])!r}" cone="{s["cone"]}" '
            f'impratio="{float(s["impratio"])!r}"/>'
            f'<default><geom {geom_defaults}/></default>'
            f'<worldbody>{"".join(walls)}{"".join(bodies)}</worldbody></mujoco>')


class _Sim:
    def __init__(self, es, s):
        from ..errors import ImpactInputError

        mujoco = _mujoco()
        self._mj = mujoco
        self.xml = _xml(es, s)
        try:
            self.model = mujoco.MjModel.from_xml_string(self.xml)
        except ValueError as exc:
            raise ImpactInputError("settings", f"MuJoCo cannot build the scene: {exc}") from None
        self.data = mujoco.MjData(self.model)
        self.dim = es.dim
        self.origin = np.array([b.position for b in es.balls], dtype=float)
        self.data.qvel[:] = np.array([b.velocity for b in es.balls], dtype=float).reshape(-1)
        mujoco.mj_forward(self.model, self.data)

    def step(self):
        self._mj.mj_step(self.model, self.data)

    def state(self):
        n = len(self.origin)
        P = self.origin + self.data.qpos.reshape(n, self.dim)
        V = self.data.qvel.reshape(n, self.dim).copy()
        return P, V

    def close(self):
        pass


def build(es, settings: dict):
    """The MuJoCo model of ``es`` (its MJCF is the ``xml`` attribute), ready to step."""
    return _Sim(es, settings)
