"""Mutations used by the claims of ``paper_checks/seghete_murphey.py`` (see :mod:`paper_checks.mutations`)."""

from __future__ import annotations

from .mutations import corrupting, mutation  # noqa: F401
