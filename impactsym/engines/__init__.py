"""Physics engines as impactsym sees them: build a scene in a real engine, run it until every
contact separates, and read the post-impact velocity in the scene's reduced coordinates, to be
compared with a law's ``v⁺``.

Engines (the optional extra ``pip install 'impactsym[engines]'``):

``mujoco``    spheres on slide joints, planes for walls (:mod:`impactsym.engines.mujoco`)
``pybullet``  spheres and static planes in DIRECT mode (:mod:`impactsym.engines.pybullet`)
``pymunk``    circles and static segments, line or plane (:mod:`impactsym.engines.pymunk`)

Each adapter exposes the settings that decide the outcome, with their defaults
(:func:`settings_of`), and maps a restitution coefficient to the engine's own parameters (its
module docstring says how, and where the mapping comes from). ``restitution=None`` keeps the
engine's own contact defaults.

Examples
--------
>>> from impactsym.engines import run
>>> from impactsym.models.seghete_murphey import three_ball_cradle
>>> r = run("mujoco", three_ball_cradle())                          # doctest: +SKIP
>>> r.velocity.round(3), r.separated                                # doctest: +SKIP
(array([-0.338,  0.633,  0.706]), True)
"""

from __future__ import annotations

import importlib
import math

from ..errors import ImpactInputError
from .driver import (DEFAULT_HOLD_STEPS, DEFAULT_MAX_STEPS, DEFAULT_REST_TOL, EngineNotInstalled, EngineResult,
                     check_settings, settle)
from .scene import Ball, EngineScene, Wall, engine_scene, scene_to_dict

__all__ = ["ENGINES", "run", "sweep", "settings_of", "available", "EngineResult", "EngineNotInstalled",
           "EngineScene", "Ball", "Wall", "engine_scene", "scene_to_dict"]

#: engine name -> adapter module
ENGINES = {"mujoco": "impactsym.engines.mujoco", "pybullet": "impactsym.engines.pybullet",
           "pymunk": "impactsym.engines.pymunk"}


def _adapter(engine):
    if engine not in ENGINES:
        raise ImpactInputError("engine", f"must be one of {', '.join(ENGINES)}, got {engine!r}")
    return importlib.import_module(ENGINES[engine])


def settings_of(engine: str) -> dict:
    """Every setting of ``engine`` that decides the outcome, with its default.

    Raises :class:`EngineNotInstalled` when the engine's package cannot be imported.
    """
    return _adapter(engine).defaults()


def available(engine: str) -> bool:
    """Whether ``engine``'s Python package can be imported here."""
    try:
        settings_of(engine)
    except EngineNotInstalled:
        return False
    return True


def _restitution(e):
    if e is None:
        return None
    try:
        ef = float(e)
    except (TypeError, ValueError):
        raise ImpactInputError("restitution", f"must be a number in [0, 1] or None, got {e!r}") from None
    if not (math.isfinite(ef) and 0 <= ef <= 1):
        raise ImpactInputError("restitution", f"must lie in [0, 1], got {e!r}")
    return ef


def run(engine: str, scene, *, restitution=1, settings=None, hold_steps: int = DEFAULT_HOLD_STEPS,
        max_steps: int = DEFAULT_MAX_STEPS, rest_tol: float = DEFAULT_REST_TOL) -> EngineResult:
    """Run ``scene`` in ``engine`` until every contact separates; return the post-impact velocities.

    Parameters
    ----------
    engine : ``"mujoco"``, ``"pybullet"`` or ``"pymunk"``
    scene : an :class:`impactsym.scenes.Scene`, a dict ``{"bodies": [...], "walls": [...]}`` or an
        :class:`EngineScene` (see :func:`impactsym.engines.scene.engine_scene`)
    restitution : ``e ∈ [0, 1]`` on every contact, mapped to the engine's parameters by the
        adapter (see its module docstring), or ``None`` to keep the engine's contact defaults.
        A setting that the mapping decides cannot also be given in ``settings``.
    settings : dict of engine settings (:func:`settings_of` lists them and their defaults)
    hold_steps, max_steps, rest_tol : the stopping rule of :func:`impactsym.engines.driver.settle`

    Returns
    -------
    EngineResult
        ``velocity`` in the scene's reduced coordinates, ``velocities`` of every ball,
        ``settings`` with every value used, ``steps``, and ``separated`` (``False`` when
        ``max_steps`` was hit first).

    Raises
    ------
    ImpactInputError
        Unknown engine, unknown setting, a setting given twice (by ``restitution`` and by
        ``settings``), restitution outside [0, 1], a scene the engine cannot build.
    EngineNotInstalled
        The engine's package is not installed (the message names ``pip install 'impactsym[engines]'``).

    Examples
    --------
    >>> run("bullet", {"bodies": [{"mass": 1, "radius": 1, "position": 1, "velocity": -1}]})
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: engine: must be one of mujoco, pybullet, pymunk, got 'bullet'
    """
    mod = _adapter(engine)
    es = engine_scene(scene)
    e = _restitution(restitution)
    defaults = mod.defaults()
    used = check_settings(engine, defaults, settings)
    if e is not None:
        mapped = mod.restitution_settings(e, used)
        clash = sorted(k for k in mapped if settings and k in settings)
        if clash:
            raise ImpactInputError("settings", f"{', '.join(clash)} is decided by restitution={restitution!r}; "
                                               "pass restitution=None to set it directly")
        used.update(mapped)
    sim = mod.build(es, used)
    try:
        V, steps, separated = settle(es, sim, hold_steps=hold_steps, max_steps=max_steps, rest_tol=rest_tol)
    finally:
        sim.close()
    velocities = [float(v[0]) if es.dim == 1 else [float(c) for c in v] for v in V]
    note = (f"every contact separated and stayed separated for {hold_steps} steps" if separated else
            f"max_steps={max_steps} reached before every contact separated: the velocities are the last ones")
    return EngineResult(engine, es, e, used, velocities, es.reduced(V), steps, steps * _timestep(used), separated,
                        note, defaults)


def _timestep(settings):
    return float(settings.get("timestep", settings.get("fixedTimeStep", 0.0)))


_UNSET = object()


def sweep(engine: str, scene, setting: str, values, *, restitution=_UNSET, settings=None, **run_options) -> list:
    """:func:`run` once per value of one setting (the other settings as given or default).

    Returns the list of :class:`EngineResult`, one per value, in order. ``restitution`` is 1
    unless given. Sweeping a setting that ``restitution`` decides needs ``restitution=None``;
    sweeping ``"restitution"`` itself runs with each value as ``restitution`` (and refuses a
    ``restitution`` argument).

    >>> sweep("mujoco", {"bodies": [{"mass": 1, "radius": 1, "position": 1, "velocity": -1}],
    ...                  "walls": [{"point": 0, "normal": 1}]}, "timestep", [])
    []
    """
    if not isinstance(setting, str):
        raise ImpactInputError("setting", f"must be a setting name, got {setting!r}")
    if setting == "restitution" and restitution is not _UNSET:
        raise ImpactInputError("restitution", "cannot be given when sweeping 'restitution' itself")
    if restitution is _UNSET:
        restitution = 1
    out = []
    for value in list(values):
        if setting == "restitution":
            out.append(run(engine, scene, restitution=value, settings=settings, **run_options))
        else:
            s = dict(settings or {})
            s[setting] = value
            out.append(run(engine, scene, restitution=restitution, settings=s, **run_options))
    return out
