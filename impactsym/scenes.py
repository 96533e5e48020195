"""Scenes: what a user describes (bodies, contacts, velocities), reduced to ``M``, ``H`` and ``v⁻``.

A :class:`Scene` holds only what the impact needs: the mass matrix of the bodies involved, the
gradient rows of the contacts that are closed at the impact instant, and the pre-impact
generalized velocity. Builders for balls on a line and in the plane live here too; canonical
scenes of the papers are in :mod:`impactsym.models`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

__all__ = ["Scene"]


@dataclass
class Scene:
    """An impact scene, reduced to the closed contacts.

    Attributes
    ----------
    M : mass matrix (n×n)
    H : gradient rows of the closed contacts (k×n), in the order of ``contacts``
    v : pre-impact generalized velocity (n×1)
    coordinates : names of the n generalized coordinates
    contacts : names of the k closed contacts (``"1-2"``, ``"wall-1"``, ...)
    approaching : for each closed contact, whether ``H_i v < 0`` (decided exactly for exact input)
    meta : free-form description (paper, equation, parameters)
    """

    M: object
    H: object
    v: object
    coordinates: list = field(default_factory=list)
    contacts: list = field(default_factory=list)
    approaching: list = field(default_factory=list)
    meta: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def k(self) -> int:
        return self.H.shape[0]

    def relative_velocity(self):
        """``w = H v`` (approaching when ``w_i < 0``)."""
        return self.H * self.v if isinstance(self.H, sp.MatrixBase) else self.H @ self.v
