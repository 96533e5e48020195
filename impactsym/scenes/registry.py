"""One registry of named scenes: the built-in scenes of the papers, with their parameters given as
CLI text, and the scene files shipped in ``impactsym/scenes/files``.

* :data:`BUILTIN_SCENES` (name → one-line description) and :data:`SCENE_PARAMS` (name → the
  parameters it takes) list the built-ins; :func:`build_scene` builds one from its parameters,
  each a string in the CLI's exact form (``"11/10,1"``, ``"pi/4"``, ``"5"``) or ``None`` (not
  given), with the validation and the messages ``impactsym resolve --scene`` has always had.
* :data:`SHIPPED_SCENES` (name → path) lists the shipped files; :func:`build_scene` also loads
  one by name (a shipped file takes no parameters).

The built scene's ``meta["scene_json"]`` is the ``scene`` object the resolve JSON reports
(``{"scene": "cradle", "n_balls": 5, "strikers": 2}``; for a file ``{"scene": NAME, "file": PATH}``).

Examples
--------
>>> sc = build_scene("cradle", {"n_balls": "5", "strikers": "2"})
>>> sc.v.T, sc.meta["scene_json"]
(Matrix([[1, 1, 0, 0, 0]]), {'scene': 'cradle', 'n_balls': 5, 'strikers': 2})
>>> build_scene("chain3", {"masses": "1,2,4"}).M
Matrix([
[1, 0, 0],
[0, 2, 0],
[0, 0, 4]])
>>> build_scene("pool", {"theta": "pi/4", "n_balls": "3"})
Traceback (most recent call last):
...
impactsym.errors.ImpactInputError: n_balls: --n-balls does not apply to --scene pool (it takes: --theta, --tau)
>>> SCENE_PARAMS["cradle"]
('n_balls', 'strikers', 'masses')
"""

from __future__ import annotations

import re
from fractions import Fraction
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ImpactInputError

if TYPE_CHECKING:  # the registry's names and parameters are read without SymPy (the CLI's start-up)
    from .scene import Scene

__all__ = ["int_option", "BUILTIN_SCENES", "SCENE_PARAMS", "ALL_PARAMS", "SHIPPED_SCENES", "SCENE_FILES_DIR", "build_scene",
           "build_rational_scene", "RATIONAL_SCENES", "scene_names", "is_scene_name"]

#: built-in scene name -> one-line description (paper and section)
BUILTIN_SCENES: dict[str, str] = {
    "chain3": "three balls touching on a line, ball 1 strikes (Acary & Taha sec. 3.2, eqs. 13-14)",
    "pool": "planar pool: ball 1 strikes balls 2 and 3 at angle theta, incidence tau (Acary & Taha sec. 4)",
    "bernoulli": "Bernoulli's problem: the pool at theta = 2*pi/3, three closed contacts (Acary & Taha sec. 4.2)",
    "two-balls-wall": "two balls in a row against a wall at 0 (Seghete & Murphey sec. II-C.1, III-B.1, III-B.3)",
    "three-ball-cradle": "Newton's cradle with three balls (Seghete & Murphey sec. II-C.2, III-B.2)",
    "cradle": "an n-ball Newton's cradle whose first k balls strike together (Seghete & Murphey sec. III-B.2, "
              "generalized)",
    "balls-against-wall": "n balls in a row against a wall at 0, the last one strikes (Seghete & Murphey "
                          "sec. II-C.1, generalized)",
}

#: built-in scene name -> the parameters it takes (CLI options without the leading ``--``, with ``_``)
SCENE_PARAMS: dict[str, tuple[str, ...]] = {
    "chain3": ("masses", "velocities"),
    "pool": ("theta", "tau"),
    "bernoulli": ("tau",),
    "two-balls-wall": ("masses", "velocities"),
    "three-ball-cradle": ("masses", "velocities"),
    "cradle": ("n_balls", "strikers", "masses"),
    "balls-against-wall": ("n_balls", "masses", "velocities"),
}

#: every scene parameter any built-in takes
ALL_PARAMS: tuple[str, ...] = ("masses", "velocities", "theta", "tau", "n_balls", "strikers")

#: the folder of the shipped scene files
SCENE_FILES_DIR = Path(__file__).resolve().parent / "files"


def _shipped() -> dict[str, Path]:
    out = {}
    if SCENE_FILES_DIR.is_dir():
        for p in sorted(SCENE_FILES_DIR.iterdir()):
            if p.suffix in (".toml", ".json") and p.is_file():
                out[p.stem] = p
    return out


#: shipped scene name (the file's stem) -> path of the file
SHIPPED_SCENES: dict[str, Path] = _shipped()


def scene_names() -> list[str]:
    """Every name :func:`build_scene` and :func:`~impactsym.scenes.load_scene` accept: the
    built-ins, then the shipped files.

    >>> scene_names()[:3]
    ['chain3', 'pool', 'bernoulli']
    """
    return list(BUILTIN_SCENES) + list(SHIPPED_SCENES)


def is_scene_name(text) -> bool:
    """Whether ``text`` names a built-in or a shipped scene."""
    return isinstance(text, str) and (text in BUILTIN_SCENES or text in SHIPPED_SCENES)


def _option(name: str) -> str:
    return "--" + name.replace("_", "-")


_PLAIN_INT = re.compile(r"[+-]?[0-9]{1,30}")


def int_option(text, argument, minimum, maximum=None):
    """An integer parameter, given as an integer or an exact integer expression (``10**2``).

    >>> int_option("10**2", "n_balls", 2)
    100
    >>> int_option("1000000000000", "n_balls", 2, 200)
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: n_balls: must be at most 200, got 1000000000000
    """
    plain = str(text).strip()
    if _PLAIN_INT.fullmatch(plain):  # a plain integer needs no parser (nor SymPy)
        value = int(plain)
    else:
        from ..numbers import parse_number

        value = parse_number(str(text), argument)
        if not value.is_Integer:
            raise ImpactInputError(argument, f"must be an integer, got {text!r}")
        value = int(value)
    if value < minimum:
        raise ImpactInputError(argument, f"must be >= {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise ImpactInputError(argument, f"must be at most {maximum}, got {value}")  # before any work
    return value


def _given(name: str, params) -> dict:
    """The parameters given (value not None), each checked to be known and to apply to ``name``."""
    if params is None:
        params = {}
    if not isinstance(params, dict):
        raise ImpactInputError("params", f"must be a dict of parameter name -> text, got {type(params).__name__}")
    given = {}
    for key, val in params.items():
        if val is None:
            continue
        if key not in ALL_PARAMS:
            raise ImpactInputError(str(key), f"unknown scene parameter {key!r}; known: {', '.join(ALL_PARAMS)}")
        if not isinstance(val, (str, int)) or isinstance(val, bool):
            raise ImpactInputError(key, f"must be given as text (the CLI's form, e.g. '1,2,4'), got {val!r}")
        given[key] = val
    if name in SHIPPED_SCENES and name not in BUILTIN_SCENES:
        for key in given:
            raise ImpactInputError(key, f"{_option(key)} does not apply to --scene {name} (a shipped scene file "
                                        "takes no parameters; copy it and edit the copy)")
        return given
    allowed = SCENE_PARAMS[name]
    for key in given:
        if key not in allowed:
            raise ImpactInputError(key, f"{_option(key)} does not apply to --scene {name} (it takes: "
                                        f"{', '.join(_option(a) for a in allowed)})")
    return given


def build_scene(name: str, params: dict | None = None) -> Scene:
    """A built-in scene from its parameters, or a shipped scene file by name.

    Parameters
    ----------
    name : a key of :data:`BUILTIN_SCENES` or :data:`SHIPPED_SCENES`
    params : ``{parameter: text or None}``, the parameters of :data:`SCENE_PARAMS` ``[name]``
        (``None`` means not given: the scene's default). Text follows the CLI: vectors
        ``"1,2,4"``, numbers ``"pi/4"``, integers ``"5"``.

    Returns
    -------
    Scene
        Exact. ``meta["scene_json"]`` is the ``scene`` object of the resolve JSON.

    Raises
    ------
    ImpactInputError
        Unknown scene (argument ``scene``), a parameter that does not apply (naming it), or a
        parameter value the scene refuses.

    Examples
    --------
    >>> build_scene("two-balls-wall", {"masses": "11/10,1"}).contacts
    ['wall@0-1', '1-2']
    >>> build_scene("bernoulli").meta["scene_json"]["tau"]
    '-pi/6'
    >>> build_scene("nope")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: scene: unknown scene 'nope'; known: chain3, pool, bernoulli, ...
    """
    if not isinstance(name, str) or not is_scene_name(name):
        known = ", ".join(scene_names())
        raise ImpactInputError("scene", f"unknown scene {name!r}; known: {known}")
    given = _given(name, params)
    if name not in BUILTIN_SCENES:
        from .fileformat import load_scene_file

        return load_scene_file(SHIPPED_SCENES[name], name=name)
    try:
        frozen = tuple(sorted(given.items()))
        hash(frozen)
    except TypeError:  # an unhashable parameter value: built afresh
        return _build_builtin(name, given)
    # a built-in scene is a pure function of its parameters: built once, and every caller gets its
    # own copy (a Scene's matrices, lists and meta are mutable) (issue 15)
    from .scene import copy_scene

    return copy_scene(_build_builtin_cached(name, frozen))


@lru_cache(maxsize=256)
def _build_builtin_cached(name: str, frozen: tuple) -> Scene:
    return _build_builtin(name, dict(frozen))


def _build_builtin(name: str, given: dict) -> Scene:
    if name in ("chain3", "pool", "bernoulli"):
        sc, desc = _acary_taha(name, given)
    else:
        sc, desc = _seghete_murphey(name, given)
    sc.meta["scene_json"] = desc
    sc.meta.setdefault("name", name)
    sc.meta.setdefault("description", BUILTIN_SCENES[name])
    return sc


#: the built-in scenes whose data are rational for rational parameters (balls on a line), and the
#: pool at θ = 0 and θ = π/2 (with θ − τ a multiple of π/2): what :func:`build_rational_scene`
#: builds. Every other pool, and Bernoulli's problem (θ = 2π/3), is not: their gradient rows and
#: velocity hold cos and sin of the angles (``sqrt(3)/2`` at θ = π/3, ``sqrt(2)/2`` at π/4), irrational
#: for every angle in π·Q but the multiples of π/2 (Niven).
RATIONAL_SCENES = ("chain3", "pool", "two-balls-wall", "three-ball-cradle", "cradle", "balls-against-wall")

#: an angle given as a plain multiple of pi: ``pi``, ``-pi/2``, ``3*pi/2``
_PI_MULTIPLE = re.compile(r"([+-]?)(?:([0-9]{1,30})\*)?pi(?:/([0-9]{1,30}))?")


def _pi_turns(text):
    """``k`` with ``text`` = ``k·π`` (a Fraction), for ``0`` and plain multiples of ``pi``; else None."""
    from ..arithmetic.literals import plain_rational

    t = str(text).strip()
    m = _PI_MULTIPLE.fullmatch(t)
    if m:
        sign, p, q = m.groups()
        if q is not None and int(q) == 0:
            return None
        return Fraction(int(p or 1) * (-1 if sign == "-" else 1), int(q or 1))
    try:
        x = plain_rational(t)
    except ZeroDivisionError:
        return None
    return x if x == 0 else None  # a non-zero rational angle (radians) has an irrational cosine


def _pi_text(k: Fraction) -> str:
    """SymPy's ``str`` of ``k·π``: ``0``, ``pi``, ``-pi/2``, ``3*pi/2``."""
    if k == 0:
        return "0"
    p, q = k.numerator, k.denominator
    head = "pi" if p == 1 else "-pi" if p == -1 else f"{p}*pi"
    return head if q == 1 else f"{head}/{q}"


def build_rational_scene(name: str, params: dict | None = None):
    """The built-in scene ``name`` with ``M``, ``H``, ``v`` as
    :class:`~impactsym.resolution.RationalMatrix`, built without SymPy, or ``None``.

    The rational twin of :func:`build_scene` for the float path of the command line (issue 15):
    the same entries, contacts, coordinates and ``meta["scene_json"]``, when ``name`` is one of
    :data:`RATIONAL_SCENES` and every parameter given is plain rational text
    (:func:`impactsym.arithmetic.literals.plain_vector`; integers for ``n_balls``, ``strikers``).
    ``None`` for anything else (a pool at any angle but 0 and π/2, ``sqrt(2)``, ``2*3``, a shipped
    file) and for any
    parameter the scene refuses: the caller then takes :func:`build_scene`, which reads every
    text and words every error as it always has.

    Examples
    --------
    >>> sc = build_rational_scene("cradle", {"n_balls": "4", "masses": "1,2,3,1/2"})
    >>> sc.M.tolist()[3][3], sc.contacts, sc.meta["scene_json"]
    (Fraction(1, 2), ['1-2', '2-3', '3-4'], {'scene': 'cradle', 'masses': ['1', '2', '3', '1/2'], 'n_balls': 4})
    >>> build_rational_scene("pool", {"theta": "pi/3"}) is None, build_rational_scene("chain3", {"masses": "1,0,1"})
    (True, None)
    """
    from ..errors import ImpactError

    if name not in RATIONAL_SCENES:
        return None
    try:
        given = _given(name, params)
        built = _rational_builtin(name, given)
    except ImpactError:
        return None
    if built is None:
        return None
    sc, desc = built
    sc.meta["scene_json"] = desc
    sc.meta.setdefault("name", name)
    sc.meta.setdefault("description", BUILTIN_SCENES[name])
    return sc


def _rational_builtin(name, given):
    """``(scene, description)`` as :func:`_acary_taha` / :func:`_seghete_murphey` give them, from
    plain rational text, or None (text that is not plain)."""
    from ..arithmetic.literals import plain_vector
    from ..resolution import _fraction_text

    kw = {}
    for key in ("masses", "velocities"):
        if given.get(key) is not None:
            vals = plain_vector(str(given[key]))
            if vals is None:
                return None
            kw[key] = vals
    for key in ("n_balls", "strikers"):
        if given.get(key) is not None:
            if not _PLAIN_INT.fullmatch(str(given[key]).strip()):
                return None
            kw[key] = given[key]
    if name == "pool":
        from ..models import acary_taha

        if given.get("theta") is None:
            return None
        theta, tau = _pi_turns(given["theta"]), _pi_turns(given["tau"]) if given.get("tau") else Fraction(0)
        if theta is None or tau is None:
            return None
        sc = acary_taha.pool_rational(theta, tau)
        if sc is None:
            return None
        return sc, {"scene": "pool", "theta": _pi_text(theta), "tau": _pi_text(tau), "contacts": sc.contacts}
    if name == "chain3":
        from ..models import acary_taha

        masses, vels = kw.get("masses", [1, 1, 1]), kw.get("velocities", [1, 0, 0])
        if len(masses) != 3 or len(vels) != 3:
            return None
        sc = acary_taha.chain3(masses, vels, rational=True)
        return sc, {"scene": "chain3", "masses": [_fraction_text(Fraction(m)) for m in masses],
                    "velocities": [_fraction_text(Fraction(x)) for x in vels]}
    from ..laws.sequential import MAX_COORDINATES
    from ..models import seghete_murphey as sm

    for key in ("n_balls", "strikers"):
        if key in kw:
            kw[key] = int_option(kw[key], key, 1, MAX_COORDINATES)
    sc = sm.SCENES[name](**kw, rational=True)
    desc = {"scene": name, **{k: (v if isinstance(v, int) else [_fraction_text(x) for x in v]) for k, v in kw.items()}}
    return sc, desc


def _acary_taha(name, given):
    """Copied from ``cli/scene_args.read_scene`` (same checks, same messages)."""
    import sympy as sp

    from ..exact import certified_sign
    from ..models import acary_taha
    from ..numbers import exact_str, parse_number, parse_vector

    if name == "chain3":
        masses = list(parse_vector(given["masses"], "masses")) if given.get("masses") else [1, 1, 1]
        vels = list(parse_vector(given["velocities"], "velocities")) if given.get("velocities") else [1, 0, 0]
        if len(masses) != 3:
            raise ImpactInputError("masses", f"chain3 needs three masses, got {len(masses)}")
        if len(vels) != 3:
            raise ImpactInputError("velocities", f"chain3 needs three velocities, got {len(vels)}")
        for m in masses:
            if certified_sign(m) <= 0:
                raise ImpactInputError("masses", f"must be positive, got {m}")
        sc = acary_taha.chain3(masses, vels)
        desc = {"scene": "chain3", "masses": [exact_str(m) for m in masses],
                "velocities": [exact_str(x) for x in vels]}
    elif name == "pool":
        if given.get("theta") is None:
            raise ImpactInputError("theta", "is required with --scene pool (e.g. --theta pi/4)")
        theta = parse_number(given["theta"], "theta")
        tau = parse_number(given["tau"], "tau") if given.get("tau") else sp.Integer(0)
        sc = acary_taha.pool(theta, tau)
        desc = {"scene": "pool", "theta": exact_str(theta), "tau": exact_str(tau), "contacts": sc.contacts}
    else:
        tau = parse_number(given["tau"], "tau") if given.get("tau") else -sp.pi / 6
        sc = acary_taha.bernoulli(tau)
        desc = {"scene": "bernoulli", "theta": "2*pi/3", "tau": exact_str(tau), "contacts": sc.contacts}
    return sc, desc


def _seghete_murphey(name, given):
    """Copied from ``cli/resolve_sequential._read`` (same checks, same messages)."""
    from ..laws.sequential import MAX_COORDINATES
    from ..models import seghete_murphey as sm
    from ..numbers import exact_str, parse_vector

    kw = {}
    if given.get("masses") is not None:
        kw["masses"] = list(parse_vector(given["masses"], "masses"))
    if given.get("velocities") is not None:
        kw["velocities"] = list(parse_vector(given["velocities"], "velocities"))
    if given.get("n_balls") is not None:
        kw["n_balls"] = int_option(given["n_balls"], "n_balls", 1, MAX_COORDINATES)
    if given.get("strikers") is not None:
        kw["strikers"] = int_option(given["strikers"], "strikers", 1, MAX_COORDINATES)
    try:
        sc = sm.SCENES[name](**kw)
    except TypeError as exc:  # pragma: no cover - guarded by SCENE_PARAMS
        raise ImpactInputError("scene", str(exc)) from None
    desc = {"scene": name, **{k: (v if isinstance(v, int) else [exact_str(x) for x in v]) for k, v in kw.items()}}
    return sc, desc
