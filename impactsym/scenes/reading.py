"""Reading a scene file's table (TOML or JSON) with the standard library alone: what ``impactsym
scene list`` needs of the shipped files, without the scene format's numbers (SymPy, NumPy), which
:mod:`impactsym.scenes.fileformat` reads from this table."""

from __future__ import annotations

import json
from pathlib import Path

from ..errors import ImpactInputError

__all__ = ["read_scene_file"]


def _no_duplicates(pairs):
    out = {}
    for k, v in pairs:
        if k in out:
            raise ImpactInputError(str(k), "is given twice in the JSON object")
        out[k] = v
    return out


def read_scene_file(path) -> dict:
    """The table of a scene file (``.toml`` or ``.json``), parsed by the standard library.

    Raises
    ------
    ImpactInputError
        (argument ``scene``) an unreadable file, another suffix, or text that is not TOML/JSON or
        not one table; a key given twice in JSON (naming the key).
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in (".toml", ".json"):
        raise ImpactInputError("scene", f"{str(p)!r}: a scene file must end with .toml or .json")
    try:
        raw = p.read_bytes()
    except IsADirectoryError:
        raise ImpactInputError("scene", f"{str(p)!r} is a directory, expected a scene file") from None
    except OSError as exc:
        raise ImpactInputError("scene", f"cannot read {str(p)!r}: {exc.strerror or exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise ImpactInputError("scene", f"{str(p)!r} is not UTF-8 text") from None
    if suffix == ".toml":
        import tomllib

        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ImpactInputError("scene", f"{str(p)!r} is not valid TOML: {exc}") from None
    else:
        try:
            data = json.loads(text, object_pairs_hook=_no_duplicates)
        except json.JSONDecodeError as exc:
            raise ImpactInputError("scene", f"{str(p)!r} is not valid JSON: {exc}") from None
        except RecursionError:
            raise ImpactInputError("scene", f"{str(p)!r}: JSON nested too deeply") from None
    if not isinstance(data, dict):
        raise ImpactInputError("scene", f"{str(p)!r} must hold one table (a JSON object), got {type(data).__name__}")
    return data
