"""Scenes: what a user describes (bodies, walls, velocities, restitution), reduced to ``M``, ``H``
and ``v⁻``.

A :class:`Scene` holds only what the impact needs: the mass matrix of the bodies involved, the
gradient rows of the contacts that are closed at the impact instant, the pre-impact generalized
velocity and, optionally, one restitution coefficient per closed contact.

==========================  ==================================================================
:mod:`.scene`               :class:`Scene`, :func:`check_restitution`
:mod:`.builders`            :func:`balls_on_line`, :func:`balls_in_plane` (with walls),
                            :func:`full_velocity`
:mod:`.fileformat`          the scene file format (TOML/JSON; its prose spec is that module's
                            docstring): :func:`load_scene`, :func:`scene_from_dict`,
                            :func:`scene_to_dict`
:mod:`.registry`            the named scenes: :data:`BUILTIN_SCENES`, :data:`SCENE_PARAMS`,
                            :func:`build_scene`, :data:`SHIPPED_SCENES` (files in ``files/``)
:mod:`.describe`            what ``impactsym scene show`` reports: :func:`describe_scene`
==========================  ==================================================================

Canonical scenes of the papers are built in :mod:`impactsym.models`.

The names are imported on first use (PEP 562), so that ``impactsym scene list`` and the
command line's reading of scene names and parameters (:mod:`.registry`) cost no SymPy.

Examples
--------
>>> from impactsym.scenes import load_scene
>>> sc = load_scene("newton-cradle-5-strikers-1")
>>> sc.contacts, sc.approaching
(['1-2', '2-3', '3-4', '4-5'], [True, False, False, False])
>>> load_scene("cradle", {"n_balls": "5"}).H == sc.H
True
"""

from __future__ import annotations

from .._lazy import lazy_attributes

#: every public name -> the submodule it lives in
_LAZY = {
    **{name: "builders" for name in ("FLOAT_GAP_RTOL", "balls_in_plane", "balls_on_line", "full_velocity")},
    **{name: "scene" for name in ("Scene", "check_restitution")},
    **{name: "fileformat" for name in ("FORMAT", "load_scene", "load_scene_file", "scene_from_dict",
                                       "scene_to_dict")},
    "read_scene_file": "reading",
    **{name: "registry" for name in ("ALL_PARAMS", "BUILTIN_SCENES", "SCENE_PARAMS", "SHIPPED_SCENES", "build_scene",
                                     "scene_names")},
    **{name: "describe" for name in ("describe_scene", "kinetic_angles")},
}

__all__ = ["Scene", "check_restitution", "balls_on_line", "balls_in_plane", "full_velocity", "FLOAT_GAP_RTOL",
           "FORMAT", "load_scene", "load_scene_file", "read_scene_file", "scene_from_dict", "scene_to_dict",
           "ALL_PARAMS", "BUILTIN_SCENES", "SCENE_PARAMS", "SHIPPED_SCENES", "build_scene", "scene_names",
           "describe_scene", "kinetic_angles"]


__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, globals())
