"""Scenes: what a user describes (bodies, contacts, velocities), reduced to ``M``, ``H`` and ``v⁻``."""

from __future__ import annotations

from .builders import FLOAT_GAP_RTOL, balls_in_plane, balls_on_line, full_velocity
from .scene import Scene, check_restitution

__all__ = ["Scene", "check_restitution", "balls_on_line", "balls_in_plane", "full_velocity", "FLOAT_GAP_RTOL"]
