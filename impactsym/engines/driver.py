"""What every adapter shares: the result type, the settings check, and the loop that steps an
engine until the impact is over.

When is an impact over in an engine? After the last contact force, every ball flies freely. The
loop steps the engine and stops once, for ``hold_steps`` consecutive steps,

* no ball's velocity changed by more than ``rest_tol`` times the pre-impact speed (no contact
  force acted), and
* no pair will meet again if every ball keeps its velocity (no two balls approach on a course
  that brings them within the sum of their radii; no ball moves into a wall).

Then every contact has separated (or rests, touching, with zero relative normal velocity and no
force) and stays so: the result is final for free flight. The loop gives up after ``max_steps``
steps and says so (``separated`` is ``False``); it never returns a capped run as a finished one
silently.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ImpactError, ImpactInputError
from .scene import EngineScene

__all__ = ["EngineResult", "EngineNotInstalled", "settle", "check_settings",
           "DEFAULT_HOLD_STEPS", "DEFAULT_MAX_STEPS", "DEFAULT_REST_TOL", "INSTALL_HINT"]

DEFAULT_HOLD_STEPS = 20
DEFAULT_MAX_STEPS = 200_000
DEFAULT_REST_TOL = 1e-9
INSTALL_HINT = "pip install 'impactsym[engines]'"


class EngineNotInstalled(ImpactError, ImportError):
    """The physics engine's Python package is not importable (install the ``engines`` extra)."""

    def __init__(self, engine: str, package: str, reason: str):
        self.engine = engine
        self.package = package
        super().__init__(f"engine: {engine} needs the Python package {package!r}, which cannot be imported "
                         f"({reason}); install it with {INSTALL_HINT}")


@dataclass
class EngineResult:
    """The answer of a physics engine on a scene.

    Attributes
    ----------
    engine : ``"mujoco"``, ``"pybullet"`` or ``"pymunk"``
    scene : the :class:`~impactsym.engines.scene.EngineScene` that was built
    restitution : the restitution asked for (``None``: the engine's own contact defaults)
    settings : every engine setting that decides the outcome, with the value used (defaults filled in)
    defaults : the same settings at the engine's defaults (what ``settings`` changed is what differs)
    velocities : every ball's final velocity (a float on a line, ``[vx, vy]`` in the plane)
    velocity : the final velocity in the scene's reduced coordinates (compare it with a law's ``v⁺``)
    steps : engine steps run; ``time`` the simulated time
    separated : whether the run ended because every contact separated and stayed separated for
        ``hold_steps`` steps; ``False`` means ``max_steps`` was hit (``note`` says so)
    note : how the run ended
    """

    engine: str
    scene: EngineScene
    restitution: float | None
    settings: dict
    velocities: list
    velocity: np.ndarray
    steps: int
    time: float
    separated: bool
    note: str = ""
    defaults: dict | None = None

    def distance(self, v_law) -> float:
        """``‖v_engine − v_law‖_M / ‖v⁻‖_M`` in the scene's reduced coordinates."""
        return self.scene.kinetic_distance(self.velocity, _floats(v_law))

    def energy_ratio(self) -> float:
        """``T⁺ / T⁻`` of the reduced velocities."""
        M, v = self.scene.M, self.scene.v
        return float(self.velocity @ M @ self.velocity / (v @ M @ v))

    def as_json(self) -> dict:
        return {"engine": self.engine, "restitution": self.restitution, "settings": _jsonable(self.settings),
                "defaults": _jsonable(self.defaults or {}),
                "velocities": self.velocities, "velocity": [float(x) for x in self.velocity],
                "coordinates": list(self.scene.names), "steps": self.steps, "time": self.time,
                "separated": self.separated, "note": self.note}


def _floats(v):
    if hasattr(v, "tolist") and not isinstance(v, np.ndarray):  # SymPy matrix
        import sympy as sp

        return np.array([float(sp.N(x, 17)) for x in v], dtype=float)
    return np.asarray(v, dtype=float).reshape(-1)


def _jsonable(d):
    out = {}
    for k, v in d.items():
        if isinstance(v, (tuple, list, np.ndarray)):
            out[k] = [float(x) if isinstance(x, (int, float, np.floating)) else x for x in v]
        elif isinstance(v, np.floating):
            out[k] = float(v)
        else:
            out[k] = v
    return out


def check_settings(engine: str, defaults: dict, settings) -> dict:
    """``defaults`` updated with ``settings``; an unknown name is refused (never ignored)."""
    if settings is None:
        return dict(defaults)
    if not isinstance(settings, dict):
        raise ImpactInputError("settings", f"must be a dict of setting names to values, got {type(settings).__name__}")
    unknown = sorted(set(settings) - set(defaults))
    if unknown:
        raise ImpactInputError("settings", f"{engine} has no setting {', '.join(map(repr, unknown))}; "
                                           f"its settings are {', '.join(sorted(defaults))}")
    out = dict(defaults)
    out.update(settings)
    return out


def _will_meet(es: EngineScene, P, V, wtol) -> bool:
    """Whether two balls, or a ball and a wall, meet again if every ball keeps its velocity."""
    nb = len(es.balls)
    for i in range(nb):
        for j in range(i + 1, nb):
            d, u = P[j] - P[i], V[j] - V[i]
            dist = float(np.linalg.norm(d))
            du = float(d @ u)
            if du >= -wtol * dist:  # not approaching
                continue
            uu = float(u @ u)
            closest = d - (du / uu) * u
            if float(np.linalg.norm(closest)) < es.balls[i].radius + es.balls[j].radius:
                return True
    for wall in es.walls:
        n = np.asarray(wall.normal)
        if any(float(V[b] @ n) < -wtol for b in range(nb)):
            return True
    return False


def settle(es: EngineScene, sim, *, hold_steps: int, max_steps: int, rest_tol: float):
    """Step ``sim`` until the impact is over (see the module docstring).

    ``sim`` has ``step()`` and ``state() -> (positions, velocities)`` (arrays ``n_balls × dim``).
    Returns ``(velocities, steps, separated)``.
    """
    for name, value, low in (("hold_steps", hold_steps, 1), ("max_steps", max_steps, 1)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
            raise ImpactInputError(name, f"must be an integer >= {low}, got {value!r}")
    if not (isinstance(rest_tol, (int, float)) and math.isfinite(rest_tol) and rest_tol > 0):
        raise ImpactInputError("rest_tol", f"must be a positive number, got {rest_tol!r}")
    _, V = sim.state()
    speed = max(float(np.max(np.abs(V))), 1e-300)
    vtol = rest_tol * speed
    quiet = 0
    for step in range(1, max_steps + 1):
        sim.step()
        P, V2 = sim.state()
        if float(np.max(np.abs(V2 - V))) <= vtol and not _will_meet(es, P, V2, vtol):
            quiet += 1
            if quiet >= hold_steps:
                return V2, step, True
        else:
            quiet = 0
        V = V2
    return V, max_steps, False
