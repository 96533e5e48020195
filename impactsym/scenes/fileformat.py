"""Scene files: an impact scene written down in TOML or JSON, read with the standard library only
(``tomllib``, ``json``).

The format (``format = "impactsym-scene/1"``)
==============================================

A scene file is one table (TOML document, JSON object). It describes the scene in one of two
forms, or both:

**Bodies.** ``bodies`` is a non-empty array of balls, each a table with

* ``mass`` (> 0), ``radius`` (≥ 0 on a line, > 0 in the plane);
* ``position`` and ``velocity``: numbers for balls **on a line**, pairs ``[x, y]`` for balls
  **in the plane** (every ball of a file has the same dimension);
* ``name`` (optional text, shown only).

``walls`` (optional) is an array of fixed walls of infinite mass, each a half-space given by a
``point`` and a ``normal`` that points into the free side: on a line a number and a non-zero
number (its sign is the side: ``normal = 1`` keeps the balls at ``x ≥ point``), in the plane two
pairs. A normal need not have unit length: impactsym divides it by its exact length
``√(n·n)``, which is rational when ``n·n`` is a rational square (``[3, 4]`` → ``(3/5, 4/5)``) and a
square root kept exact otherwise. A ball behind a wall, or overlapping it, is refused.

impactsym closes exactly the contacts that touch: a gap of zero, decided exactly for exact input;
for float input a gap with ``|gap| ≤ gap_tolerance`` (the key ``gap_tolerance``, a number ≥ 0; by
default ``FLOAT_GAP_RTOL = 1e-9`` times the scene's length scale, the largest of 1, the
coordinates and the radii). A negative gap is an overlap (refused). ``gap_tolerance`` applies to
float input only and is refused with exact input. Only the balls that take part in a closed
contact enter ``M``, ``H`` and ``v`` (coordinates ``x1`` or ``x1, y1``, ... numbered by the ball's
place in ``bodies``, from 1). The contacts are named ``"i-j"`` (balls ``i < j``), ``"wall@P-i"`` on a
line (the wall at ``P``) and ``"wallJ-i"`` in the plane (the ``J``-th wall), in this order unless
``contacts`` (an array of those names, a permutation of the closed contacts) orders them.

**Explicit.** ``mass_matrix`` (n×n, symmetric positive definite), ``gradients`` (k×n, one non-zero
row per closed contact) and ``velocity`` (n), as arrays of rows and numbers (or as text in the
CLI's form, ``"1,0;0,1"``); optional ``contacts`` (k distinct names, default ``"1"``, ``"2"``, ...)
and ``coordinates`` (n names, default ``q1``, ...). Every row is a closed contact.

**Both.** When a file has ``bodies`` and the explicit form (``impactsym scene show --json``
writes both where the bodies are known), the bodies must reduce to exactly the explicit
``M``, ``H``, ``v`` (checked entry by entry, exactly), or the file is refused.

**Restitution** (optional): one number for every closed contact, an array of numbers in the
order of the contacts, or a table with an optional ``default`` and overrides by contact name
(``{default = "9/10", "1-2" = "1/2"}``); every closed contact needs a value, every name must be a
closed contact, and each value lies in ``[0, 1]``. Without the key the scene states no
restitution (``Scene.restitution is None``).

**Other keys.** ``format`` (optional; when given, ``"impactsym-scene/1"``), and the texts
``name``, ``description``, ``source``. ``impactsym scene show --json`` also writes the float twins
``mass_matrix_float``, ``gradients_float``, ``velocity_float``, ``restitution_float`` and the object
``reduced`` (approaching contacts, kinetic angles): these are output, accepted in a file and
**not read** (the exact keys are). Any other key is refused, naming it.

**Numbers.** An integer, or text following the conventions (exact): ``"11/10"``, ``"1.1"``
(= 11/10), ``"1e-3"`` (= 1/1000), ``"sqrt(3)/2"``, ``"2*cos(pi/5)"``. A float literal of JSON or TOML
(``1.1``, ``1e-3``) puts the whole scene on the float path (M, H, v become float arrays, contacts
close within ``gap_tolerance``): write ``"1.1"`` to stay exact. ``true``/``false``, NaN and
infinities are refused.

Errors are :class:`~impactsym.errors.ImpactInputError` naming the key at fault, arrays indexed
from 0: ``bodies[2].mass`` is the mass of ball 3.

Example (TOML)::

    format = "impactsym-scene/1"
    description = "Two balls in a row against a wall"
    source = "Seghete & Murphey, sec. II-C.1"

    [[bodies]]
    mass = "11/10"
    radius = 1
    position = 1
    velocity = -1

    [[bodies]]
    mass = 1
    radius = 1
    position = 3
    velocity = -2

    [[walls]]
    point = 0
    normal = 1

    [restitution]
    default = 1

Examples
--------
>>> sc = scene_from_dict({"bodies": [{"mass": 1, "radius": 1, "position": 0, "velocity": 1},
...                                  {"mass": "1/2", "radius": 1, "position": 2, "velocity": 0}],
...                       "restitution": "9/10"})
>>> sc.M, sc.H, sc.contacts, sc.restitution
(Matrix([
[1,   0],
[0, 1/2]]), Matrix([[-1, 1]]), ['1-2'], [9/10])
>>> scene_to_dict(sc)["gradients"]
[['-1', '1']]
>>> scene_from_dict({"bodies": [{"mass": -1, "radius": 1, "position": 0, "velocity": 1}]})
Traceback (most recent call last):
...
impactsym.errors.ImpactInputError: bodies[0].mass: must be positive (ball 1), got -1
"""

from __future__ import annotations

import math
import os
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..arithmetic import LazyModule, sympy_instance
from ..errors import ImpactInputError
from .scene import Scene, copy_scene

# SymPy is imported on first use: a float scene (and its checks) runs without it (issue 15)
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["FORMAT", "load_scene", "load_scene_file", "read_scene_file", "scene_from_dict", "scene_to_dict"]

#: the value of the ``format`` key this version reads and writes
FORMAT = "impactsym-scene/1"

_TEXT_KEYS = ("format", "name", "description", "source")
_BODY_KEYS = ("bodies", "walls", "gap_tolerance")
_EXPLICIT_KEYS = ("mass_matrix", "gradients", "velocity")
_SHARED_KEYS = ("contacts", "coordinates", "restitution")
#: keys ``scene show --json`` writes that the loader accepts and does not read
OUTPUT_ONLY_KEYS = ("mass_matrix_float", "gradients_float", "velocity_float", "restitution_float", "reduced")
KNOWN_KEYS = _TEXT_KEYS + _BODY_KEYS + _EXPLICIT_KEYS + _SHARED_KEYS + OUTPUT_ONLY_KEYS


# --------------------------------------------------------------------------- reading files
from .reading import read_scene_file  # noqa: E402 (the standard-library reader, shared with `scene list`)


def load_scene_file(path, *, name: str | None = None) -> Scene:
    """The scene of a file (see the module docstring for the format).

    >>> from impactsym.scenes.registry import SHIPPED_SCENES
    >>> sc = load_scene_file(SHIPPED_SCENES["newton-cradle-5-strikers-2"])
    >>> sc.v.T, sc.meta["scene_json"]["scene"]
    (Matrix([[1, 1, 0, 0, 0]]), 'newton-cradle-5-strikers-2')
    """
    p = Path(path)
    try:
        st = p.stat()
    except OSError:  # read_scene_file names the problem (argument ``scene``)
        return _load_scene_file(str(p), name)
    # a scene file is read once per (path as given, working directory, name, device, inode,
    # modification time, size); every caller gets its own copy (a Scene's matrices, lists and meta
    # are mutable) (issue 15)
    key = (os.getcwd(), st.st_dev, st.st_ino, st.st_mtime_ns, st.st_size)
    return copy_scene(_load_scene_file_cached(str(p), name, key))


@lru_cache(maxsize=256)
def _load_scene_file_cached(path: str, name, key: tuple) -> Scene:
    return _load_scene_file(path, name)


def _load_scene_file(path: str, name) -> Scene:
    from .registry import SCENE_FILES_DIR

    p = Path(path)
    sc = scene_from_dict(read_scene_file(p))
    sc.meta["file"] = str(p)
    sc.meta["name"] = name or sc.meta.get("name") or p.stem
    try:  # a shipped file is named by its place in the package, the same on every machine
        shown = "impactsym/scenes/files/" + p.resolve().relative_to(SCENE_FILES_DIR.resolve()).as_posix()
    except ValueError:
        shown = str(p)
    sc.meta["scene_json"] = {"scene": sc.meta["name"], "file": shown}
    return sc


def load_scene(source, params: dict | None = None) -> Scene:
    """A scene by built-in name, shipped-file name, or path to a ``.toml``/``.json`` file.

    Parameters
    ----------
    source : str or os.PathLike
        A name of :data:`~impactsym.scenes.registry.BUILTIN_SCENES` (built by
        :func:`~impactsym.scenes.registry.build_scene` with ``params``), a name of
        :data:`~impactsym.scenes.registry.SHIPPED_SCENES`, or a path. A string that is a name is
        a name; anything else is a path.
    params : dict, optional
        ``{parameter: text or None}`` for a built-in (see
        :data:`~impactsym.scenes.registry.SCENE_PARAMS`); a file takes none (a parameter given with
        a file is refused, naming it).

    Returns
    -------
    Scene

    Raises
    ------
    ImpactInputError
        Unknown name and no such file (argument ``scene``), a bad file or key (naming it), a
        parameter that does not apply.

    Examples
    --------
    >>> load_scene("cradle", {"n_balls": "4"}).H.shape
    (3, 4)
    >>> load_scene("billiard-break-rack-3").contacts
    ['1-2', '2-3', '2-4', '3-4']
    >>> load_scene("no-such-scene")
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: scene: unknown scene 'no-such-scene': not a built-in scene (chain3, ...), not a shipped scene file (...), and no file of that name
    """
    from .registry import BUILTIN_SCENES, SHIPPED_SCENES, build_scene, is_scene_name

    if isinstance(source, str) and is_scene_name(source):
        return build_scene(source, params)
    if not isinstance(source, (str, os.PathLike)):
        raise ImpactInputError("scene", f"must be a scene name or a path, got {type(source).__name__}")
    for key, val in (params or {}).items():
        if val is not None:
            opt = "--" + str(key).replace("_", "-")
            raise ImpactInputError(str(key), f"{opt} applies only to a built-in scene ({', '.join(BUILTIN_SCENES)}); "
                                             f"{str(source)!r} is a scene file, whose values are in the file")
    p = Path(source)
    if not p.exists():
        if isinstance(source, str) and p.suffix.lower() not in (".toml", ".json") and os.sep not in source:
            raise ImpactInputError("scene", f"unknown scene {source!r}: not a built-in scene "
                                            f"({', '.join(BUILTIN_SCENES)}), not a shipped scene file "
                                            f"({', '.join(SHIPPED_SCENES)}), and no file of that name")
        raise ImpactInputError("scene", f"no such scene file {str(source)!r}")
    return load_scene_file(p)


# --------------------------------------------------------------------------- numbers
def _number(x, key: str):
    """An exact SymPy number, or a float (the float path)."""
    from ..numbers import parse_number

    if isinstance(x, bool):
        raise ImpactInputError(key, f"must be a number, got {str(x).lower()}")
    if isinstance(x, float):
        if not math.isfinite(x):
            raise ImpactInputError(key, f"must be a finite real number, got {x}")
        return x
    if isinstance(x, int):
        return sp.Integer(x)
    if isinstance(x, str):
        try:
            return parse_number(x, key)
        except ImpactInputError as exc:
            raise ImpactInputError(key, exc.condition) from None
    raise ImpactInputError(key, f"must be a number (an integer or exact text such as \"11/10\"), "
                                f"got {_kind(x)}")


def _kind(x) -> str:
    return {dict: "a table", list: "an array", str: "text"}.get(type(x), type(x).__name__)


def _is_float(x) -> bool:
    return isinstance(x, float)


def _sign(x, exact: bool) -> int:
    from ..exact import certified_sign

    if exact:
        return certified_sign(x)
    x = float(x)
    return (x > 0) - (x < 0)


def _pair(x, key: str):
    if not isinstance(x, list) or len(x) != 2:
        raise ImpactInputError(key, f"must be a pair [x, y], got {_kind(x) if not isinstance(x, list) else x!r}")
    return [_number(x[0], f"{key}[0]"), _number(x[1], f"{key}[1]")]


def _text(d: dict, key: str):
    if key in d and not isinstance(d[key], str):
        raise ImpactInputError(key, f"must be text, got {_kind(d[key])}")
    return d.get(key)


def _names(x, key: str, length: int, what: str) -> list[str]:
    if not isinstance(x, list) or not all(isinstance(c, str) for c in x):
        raise ImpactInputError(key, f"must be an array of texts (the {what} names)")
    if len(x) != length:
        raise ImpactInputError(key, f"has {len(x)} names, expected {length} (one per {what})")
    if len(set(x)) != len(x):
        dup = next(c for c in x if x.count(c) > 1)
        raise ImpactInputError(key, f"names {dup!r} twice")
    return list(x)


# --------------------------------------------------------------------------- the bodies form
def _read_bodies(d: dict):
    """``(dim, masses, radii, positions, velocities, walls, any_float)`` with every key checked."""
    bodies = d["bodies"]
    if not isinstance(bodies, list) or not bodies:
        raise ImpactInputError("bodies", "must be a non-empty array of tables (one per ball)")
    dim = None
    m, r, x, v, any_float = [], [], [], [], False
    for b, body in enumerate(bodies):
        key = f"bodies[{b}]"
        if not isinstance(body, dict):
            raise ImpactInputError(key, f"must be a table with mass, radius, position, velocity, got {_kind(body)}")
        for k in body:
            if k not in ("mass", "radius", "position", "velocity", "name"):
                raise ImpactInputError(f"{key}.{k}", "unknown key (a body has mass, radius, position, velocity, name)")
        for k in ("mass", "radius", "position", "velocity"):
            if k not in body:
                raise ImpactInputError(f"{key}.{k}", f"is missing (ball {b + 1})")
        if "name" in body and not isinstance(body["name"], str):
            raise ImpactInputError(f"{key}.name", f"must be text, got {_kind(body['name'])}")
        here = 2 if isinstance(body["position"], list) else 1
        if dim is None:
            dim = here
        elif here != dim:
            raise ImpactInputError(f"{key}.position", f"is {'a pair' if here == 2 else 'a number'} but ball 1's is "
                                                      f"{'a pair' if dim == 2 else 'a number'} (every ball of a scene "
                                                      "is on the line or every ball is in the plane)")
        mass = _number(body["mass"], f"{key}.mass")
        radius = _number(body["radius"], f"{key}.radius")
        if dim == 1:
            pos = _number(body["position"], f"{key}.position")
            if isinstance(body["velocity"], list):
                raise ImpactInputError(f"{key}.velocity", "must be a number (the position is a number: a ball on a line)")
            vel = _number(body["velocity"], f"{key}.velocity")
            leaves = [mass, radius, pos, vel]
        else:
            pos = _pair(body["position"], f"{key}.position")
            if not isinstance(body["velocity"], list):
                raise ImpactInputError(f"{key}.velocity", "must be a pair [vx, vy] (the position is a pair: a ball in "
                                                          "the plane)")
            vel = _pair(body["velocity"], f"{key}.velocity")
            leaves = [mass, radius, *pos, *vel]
        any_float = any_float or any(_is_float(t) for t in leaves)
        m.append(mass), r.append(radius), x.append(pos), v.append(vel)
    walls = d.get("walls", [])
    if not isinstance(walls, list):
        raise ImpactInputError("walls", f"must be an array of tables with point and normal, got {_kind(walls)}")
    W = []
    for j, w in enumerate(walls):
        key = f"walls[{j}]"
        if not isinstance(w, dict):
            raise ImpactInputError(key, f"must be a table with point and normal, got {_kind(w)}")
        for k in w:
            if k not in ("point", "normal"):
                raise ImpactInputError(f"{key}.{k}", "unknown key (a wall has point and normal)")
        for k in ("point", "normal"):
            if k not in w:
                raise ImpactInputError(f"{key}.{k}", f"is missing (wall {j + 1})")
        if dim == 1:
            if isinstance(w["point"], list) or isinstance(w["normal"], list):
                bad = "point" if isinstance(w["point"], list) else "normal"
                raise ImpactInputError(f"{key}.{bad}", "must be a number (the balls are on a line)")
            pt, nr = _number(w["point"], f"{key}.point"), _number(w["normal"], f"{key}.normal")
            leaves = [pt, nr]
        else:
            pt, nr = _pair(w["point"], f"{key}.point"), _pair(w["normal"], f"{key}.normal")
            leaves = [*pt, *nr]
        any_float = any_float or any(_is_float(t) for t in leaves)
        W.append((pt, nr))
    exact = not any_float
    for b in range(len(m)):
        key = f"bodies[{b}]"
        if _sign(m[b], exact) <= 0:
            raise ImpactInputError(f"{key}.mass", f"must be positive (ball {b + 1}), got {m[b]}")
        s = _sign(r[b], exact)
        if s < 0 or (s == 0 and dim == 2):
            cond = "non-negative" if dim == 1 else "positive (a ball in the plane has a radius)"
            raise ImpactInputError(f"{key}.radius", f"must be {cond} (ball {b + 1}), got {r[b]}")
    for j, (pt, nr) in enumerate(W):
        nn = nr * nr if dim == 1 else nr[0] * nr[0] + nr[1] * nr[1]
        if _sign(nn, exact) == 0:
            raise ImpactInputError(f"walls[{j}].normal", f"must be non-zero (wall {j + 1})")
        if dim == 1:  # a wall on a line is a half-line: every ball must be on its free side
            for b in range(len(m)):
                side = _sign(nr * (x[b] - pt), exact)
                if side <= 0:
                    where = "is centred on" if side == 0 else "lies behind"
                    raise ImpactInputError(f"bodies[{b}].position", f"ball {b + 1} {where} wall {j + 1} (point {pt}, "
                                                                    f"normal {nr}: the free side is "
                                                                    f"x {'>' if _sign(nr, exact) > 0 else '<'} {pt})")
    return dim, m, r, x, v, W, any_float


def _gap_tolerance(d: dict, exact: bool):
    if "gap_tolerance" not in d:
        return None
    tol = _number(d["gap_tolerance"], "gap_tolerance")
    if exact:
        raise ImpactInputError("gap_tolerance", "applies to float input only (exact input closes a contact when its "
                                                "gap is exactly zero); remove it or give a float in the scene")
    tol = float(tol)
    if tol < 0:
        raise ImpactInputError("gap_tolerance", f"must be >= 0, got {tol}")
    return tol


def _from_bodies(d: dict) -> Scene:
    from .builders import balls_in_plane, balls_on_line

    dim, m, r, x, v, W, any_float = _read_bodies(d)
    tol = _gap_tolerance(d, not any_float)
    try:
        if dim == 1:
            sc = balls_on_line(m, r, x, v, [pt for pt, _ in W], gap_tolerance=tol)
        else:
            sc = balls_in_plane(m, r, [tuple(p) for p in x], [tuple(p) for p in v],
                                [(tuple(pt), tuple(nr)) for pt, nr in W], gap_tolerance=tol)
    except ImpactInputError as exc:
        balls = getattr(exc, "balls", None)
        if balls:
            raise ImpactInputError(f"bodies[{balls[-1]}].position", exc.condition) from None
        if exc.argument == "positions":  # no closed contact
            raise ImpactInputError("bodies", exc.condition) from None
        raise  # pragma: no cover - every other condition was checked above, naming its key
    sc.meta["gap_tolerance"] = tol
    sc.meta["body_names"] = [body.get("name") for body in d["bodies"]]
    if dim == 1:
        sc.meta["wall_normals"] = [nr for _, nr in W]
    if "contacts" in d:
        sc = _reorder(sc, d["contacts"])
    return sc


def _reorder(sc: Scene, names) -> Scene:
    names = _names(names, "contacts", sc.k, "closed contact")
    unknown = [c for c in names if c not in sc.contacts]
    if unknown:
        raise ImpactInputError("contacts", f"{unknown[0]!r} is not a closed contact of the bodies (closed: "
                                           f"{', '.join(sc.contacts)})")
    order = [sc.contacts.index(c) for c in names]
    H = sc.H.extract(order, list(range(sc.H.shape[1]))) if sympy_instance(sc.H, "MatrixBase") else sc.H[order]
    return Scene(sc.M, H, sc.v, sc.coordinates, names, [sc.approaching[i] for i in order], sc.meta)


# --------------------------------------------------------------------------- the explicit form
def _matrix(x, key: str, *, vector: bool = False):
    """Rows (or one row) of numbers, exact or float, from an array or the CLI's text form."""
    from ..numbers import parse_matrix, parse_vector

    if isinstance(x, str):
        try:
            m = parse_vector(x, key) if vector else parse_matrix(x, key)
        except ImpactInputError as exc:
            raise ImpactInputError(key, exc.condition) from None
        return [list(m)] if vector else m.tolist()
    if not isinstance(x, list) or not x:
        raise ImpactInputError(key, f"must be a non-empty array{'' if vector else ' of rows'}, got "
                                    f"{_kind(x) if not isinstance(x, list) else 'an empty array'}")
    if vector:
        return [[_number(t, f"{key}[{i}]") for i, t in enumerate(x)]]
    rows = []
    for i, row in enumerate(x):
        if not isinstance(row, list) or not row:
            raise ImpactInputError(f"{key}[{i}]", f"must be a non-empty array (a row), got {_kind(row)}")
        rows.append([_number(t, f"{key}[{i}][{j}]") for j, t in enumerate(row)])
    if len({len(r) for r in rows}) != 1:
        raise ImpactInputError(key, f"rows have different lengths {tuple(len(r) for r in rows)}")
    return rows


def _from_explicit(d: dict) -> Scene:
    from ..mechanics import check_gradients, check_mass_matrix, check_velocity
    from .builders import _approaching_exact

    missing = [k for k in _EXPLICIT_KEYS if k not in d]
    if missing:
        raise ImpactInputError(missing[0], "is missing (the explicit form needs mass_matrix, gradients and velocity)")
    Mr, Hr, vr = _matrix(d["mass_matrix"], "mass_matrix"), _matrix(d["gradients"], "gradients"), \
        _matrix(d["velocity"], "velocity", vector=True)[0]
    exact = not any(_is_float(t) for rows in (Mr, Hr, [vr]) for row in rows for t in row)
    if exact:
        M, H, v = sp.Matrix(Mr), sp.Matrix(Hr), sp.Matrix(vr)
    else:
        M, H, v = (np.array([[float(t) for t in row] for row in A], dtype=float) for A in (Mr, Hr, [vr]))
        v = v.reshape(-1)
    M = check_mass_matrix(M, "mass_matrix", exact=exact)
    n = M.shape[0]
    H = check_gradients(H, n, "gradients", exact=exact)
    v = check_velocity(v, n, "velocity", exact=exact)
    k = H.shape[0]
    contacts = _names(d["contacts"], "contacts", k, "closed contact") if "contacts" in d else \
        [str(i + 1) for i in range(k)]
    if "default" in contacts:
        raise ImpactInputError("contacts", "'default' is reserved (the restitution table's default), not a contact name")
    coords = _names(d["coordinates"], "coordinates", n, "coordinate") if "coordinates" in d else \
        [f"q{i + 1}" for i in range(n)]
    return Scene(M, H, v, coords, contacts, _approaching_exact(H, v, exact), {"exact": exact})


def _check_agree(from_bodies: Scene, explicit: Scene) -> None:
    """The bodies must reduce to exactly the explicit form (same shapes, names and entries)."""
    from ..exact import certified_sign

    if from_bodies.exact != explicit.exact:
        raise ImpactInputError("mass_matrix", "the explicit form and the bodies disagree on the number path (one has "
                                              "float literals, the other not)")
    for key, a, b in (("mass_matrix", from_bodies.M, explicit.M), ("gradients", from_bodies.H, explicit.H),
                      ("velocity", from_bodies.v, explicit.v)):
        if tuple(a.shape) != tuple(b.shape):
            raise ImpactInputError(key, f"has shape {tuple(b.shape)} but the bodies reduce to shape {tuple(a.shape)}")
        A, B = (np.asarray(a, dtype=object).ravel(), np.asarray(b, dtype=object).ravel()) if not explicit.exact \
            else (list(a), list(b))
        for idx, (p, q) in enumerate(zip(A, B)):
            same = (certified_sign(sp.sympify(p) - sp.sympify(q)) == 0) if explicit.exact else (float(p) == float(q))
            if not same:
                where = idx if key == "velocity" else divmod(idx, a.shape[1])
                raise ImpactInputError(key, f"entry {where} is {q} but the bodies reduce to {p} (a file with both "
                                            "bodies and the explicit form must agree)")
    if "coordinates" in explicit.meta.get("given", ()) and explicit.coordinates != from_bodies.coordinates:
        raise ImpactInputError("coordinates", f"are {explicit.coordinates} but the bodies' coordinates are "
                                              f"{from_bodies.coordinates}")


# --------------------------------------------------------------------------- restitution
def _restitution(x, contacts: list[str]) -> list:
    from .scene import check_restitution

    k = len(contacts)

    def one(val, key):
        e = _number(val, key)
        try:
            return check_restitution([e], 1, [key], argument=key)[0]
        except ImpactInputError as exc:
            raise ImpactInputError(key, exc.condition.replace(f"entry 1 (contact {key}) ", "")) from None

    if isinstance(x, dict):
        if not x:
            raise ImpactInputError("restitution", "is an empty table (give a default or one value per contact name)")
        for name in x:
            if name != "default" and name not in contacts:
                raise ImpactInputError(f"restitution.{name}", f"is not a closed contact (closed: {', '.join(contacts)})")
        default = one(x["default"], "restitution.default") if "default" in x else None
        out = []
        for c in contacts:
            if c in x:
                out.append(one(x[c], f"restitution.{c}"))
            elif default is not None:
                out.append(default)
            else:
                raise ImpactInputError("restitution", f"has no value for contact {c!r} and no default")
        return out
    if isinstance(x, list):
        if len(x) != k:
            raise ImpactInputError("restitution", f"has {len(x)} entries, expected {k} (one per closed contact: "
                                                  f"{', '.join(contacts)})")
        return [one(val, f"restitution[{i}]") for i, val in enumerate(x)]
    e = one(x, "restitution")
    return [e] * k


# --------------------------------------------------------------------------- dict <-> Scene
def scene_from_dict(d: dict) -> Scene:
    """A :class:`Scene` from the table of a scene file (the format is the module docstring's).

    Parameters
    ----------
    d : dict
        The parsed TOML/JSON table.

    Returns
    -------
    Scene
        Exact for exact input, float arrays when a float literal appears; ``meta`` holds
        ``name``, ``description``, ``source`` when given.

    Raises
    ------
    ImpactInputError
        Naming the key at fault (``bodies[2].mass``, ``walls[0].normal``, ``restitution.1-2``,
        ``mass_matrix``): a missing or unknown key, a wrong type, a non-positive mass, an
        overlap, no closed contact, a non-SPD mass matrix, a restitution outside ``[0, 1]``.

    Examples
    --------
    >>> sc = scene_from_dict({"mass_matrix": [[2, 0], [0, 1]], "gradients": [[-1, 1]],
    ...                       "velocity": [1, 0], "restitution": {"default": "1/2"}})
    >>> sc.contacts, sc.approaching, sc.restitution
    (['1'], [True], [1/2])
    >>> scene_from_dict({"bodies": [{"mass": 1, "radius": 1, "position": [0, 0], "velocity": [1, 0]},
    ...                             {"mass": 1, "radius": 1, "position": [1, 0], "velocity": [0, 0]}]})
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: bodies[1].position: balls 1 and 2 overlap (gap -1 < 0)
    """
    if not isinstance(d, dict):
        raise ImpactInputError("scene", f"must be a table (a JSON object), got {_kind(d)}")
    for key in d:
        if key not in KNOWN_KEYS:
            raise ImpactInputError(str(key), f"unknown key; a scene file has: {', '.join(KNOWN_KEYS)}")
    fmt = _text(d, "format")
    if fmt is not None and fmt != FORMAT:
        raise ImpactInputError("format", f"is {fmt!r}; this impactsym reads {FORMAT!r}")
    texts = {k: _text(d, k) for k in ("name", "description", "source")}
    has_bodies = "bodies" in d
    has_explicit = any(k in d for k in _EXPLICIT_KEYS)
    if not has_bodies:
        for key in ("walls", "gap_tolerance"):
            if key in d:
                raise ImpactInputError(key, "applies only with bodies")
        if not has_explicit:
            raise ImpactInputError("bodies", "is missing: a scene needs bodies (balls on a line or in the plane) or the "
                                             "explicit mass_matrix, gradients and velocity")
    if has_bodies:
        sc = _from_bodies(d)
        if has_explicit:
            ex = _from_explicit(d)
            if "coordinates" in d:
                ex.meta["given"] = ("coordinates",)
            _check_agree(sc, ex)
        elif "coordinates" in d:
            coords = _names(d["coordinates"], "coordinates", sc.n, "coordinate")
            if coords != sc.coordinates:
                raise ImpactInputError("coordinates", f"are {coords} but the bodies' coordinates are {sc.coordinates}")
    else:
        sc = _from_explicit(d)
    if "restitution" in d:
        sc.restitution = _restitution(d["restitution"], list(sc.contacts))
    sc.meta.update({k: v for k, v in texts.items() if v is not None})
    sc.meta["format"] = FORMAT
    return sc


def _out(x):
    """A number as it goes into a file: exact text, or a float."""
    from ..numbers import exact_str

    if isinstance(x, (float, np.floating)):
        return float(x)
    return exact_str(x)


def _line_wall_normals(meta) -> list | None:
    """The normal (±1) of each wall of a line scene: the side its balls are on; ``None`` when a
    wall has balls on both sides (a point obstacle, which a half-line cannot describe)."""
    if meta.get("wall_normals") is not None:
        return list(meta["wall_normals"])
    exact = meta.get("exact", True)
    out = []
    for w in meta.get("walls", []):
        sides = {_sign(x - w, exact) for x in meta["positions"]}
        if len(sides) != 1 or 0 in sides:
            return None
        out.append(sp.Integer(sides.pop()) if exact else float(sides.pop()))
    return out


def _bodies_of(scene: Scene) -> dict | None:
    meta = scene.meta
    builder = meta.get("builder")
    if builder not in ("balls_on_line", "balls_in_plane") or "all_velocities" not in meta:
        return None
    keys = ("masses", "radii", "positions")
    if any(k not in meta for k in keys):
        return None
    names = meta.get("body_names") or [None] * len(meta["masses"])
    bodies = []
    for b, (m, r, p, v) in enumerate(zip(meta["masses"], meta["radii"], meta["positions"], meta["all_velocities"])):
        body = {"mass": _out(m), "radius": _out(r)}
        if builder == "balls_on_line":
            body.update({"position": _out(p), "velocity": _out(v)})
        else:
            body.update({"position": [_out(t) for t in p], "velocity": [_out(t) for t in v]})
        if names[b]:
            body["name"] = names[b]
        bodies.append(body)
    out = {"bodies": bodies}
    if builder == "balls_on_line":
        normals = _line_wall_normals(meta)
        if normals is None:
            return None
        walls = [{"point": _out(w), "normal": _out(n)} for w, n in zip(meta.get("walls", []), normals)]
    else:
        walls = [{"point": [_out(t) for t in pt], "normal": [_out(t) for t in nr]} for pt, nr in meta.get("walls", [])]
    if walls:
        out["walls"] = walls
    if meta.get("gap_tolerance") is not None:
        out["gap_tolerance"] = float(meta["gap_tolerance"])
    return out


def scene_to_dict(scene: Scene) -> dict:
    """A scene as the table of a scene file: the explicit form (exact text, or floats on the float
    path), the contact and coordinate names, the restitution when stated, and the bodies when the
    scene was built from bodies. :func:`scene_from_dict` of the result is the same scene.

    Raises
    ------
    ImpactInputError
        (argument ``scene``) a scene with free symbols (a file holds numbers).

    Examples
    --------
    >>> from impactsym.models.acary_taha import chain3
    >>> d = scene_to_dict(chain3())
    >>> d["mass_matrix"], d["velocity"], d["contacts"], "bodies" in d
    ([['1', '0', '0'], ['0', '1', '0'], ['0', '0', '1']], ['1', '0', '0'], ['1-2', '2-3'], False)
    >>> scene_from_dict(d).H == chain3().H
    True
    """
    if scene.exact:
        free = set().union(*(A.free_symbols for A in (scene.M, scene.H, scene.v)))
        if free:
            raise ImpactInputError("scene", f"has free symbols {sorted(map(str, free))}; a scene file holds numbers")
    M = scene.M.tolist() if scene.exact else np.asarray(scene.M).tolist()
    H = scene.H.tolist() if scene.exact else np.atleast_2d(np.asarray(scene.H)).tolist()
    v = list(scene.v) if scene.exact else np.asarray(scene.v).reshape(-1).tolist()
    d: dict = {"format": FORMAT}
    for key in ("name", "description", "source"):
        if isinstance(scene.meta.get(key), str):
            d[key] = scene.meta[key]
    if "source" not in d and scene.meta.get("paper"):
        d["source"] = f"{scene.meta['paper']}, {scene.meta.get('ref', '')}".rstrip(", ")
    d["coordinates"] = list(scene.coordinates) if len(scene.coordinates) == scene.n else \
        [f"q{i + 1}" for i in range(scene.n)]
    d["contacts"] = list(scene.contacts) if len(scene.contacts) == scene.k else [str(i + 1) for i in range(scene.k)]
    d["mass_matrix"] = [[_out(t) for t in row] for row in M]
    d["gradients"] = [[_out(t) for t in row] for row in H]
    d["velocity"] = [_out(t) for t in v]
    if scene.restitution is not None:
        d["restitution"] = [_out(e) for e in scene.restitution]
    bodies = _bodies_of(scene)
    if bodies is not None:
        d.update(bodies)
    return d
