"""``--plot FILE`` on ``resolve``, ``domain`` and ``bench``: write the figure of what was just computed.

The path is checked before any work (its directory must exist and be writable, the suffix must be
one matplotlib writes): a bad path is exit 2 naming ``plot``, and nothing is computed. The figure
itself comes from :mod:`impactsym.figures` (``resolve``: :func:`~impactsym.figures.resolve_figure`;
``domain``: :func:`~impactsym.figures.domain_figure`) or :func:`impactsym.benchmark.plot` (``bench``).
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import ImpactInputError

__all__ = ["PLOT_SUFFIXES", "add_plot_option", "plot_path", "write_figure"]

#: the file types ``--plot`` writes (by suffix)
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def add_plot_option(parser, what: str) -> None:
    parser.add_argument("--plot", metavar="FILE",
                        help=f"also write {what} to FILE ({', '.join(s[1:] for s in PLOT_SUFFIXES)}; "
                             "checked before the work)")


def plot_path(args) -> Path | None:
    """The checked ``--plot`` path, or ``None`` when not given. Raises ``ImpactInputError("plot", ...)``
    for a path that cannot be written, before anything is computed.

    >>> import argparse
    >>> plot_path(argparse.Namespace(plot="/nonexistent/dir/x.png"))
    Traceback (most recent call last):
    ...
    impactsym.errors.ImpactInputError: plot: cannot write '/nonexistent/dir/x.png': directory '/nonexistent/dir' does not exist
    """
    text = getattr(args, "plot", None)
    if text is None:
        return None
    if not text.strip():
        raise ImpactInputError("plot", "is empty; give a file name such as fig.png")
    path = Path(text)
    if path.suffix.lower() not in PLOT_SUFFIXES:
        raise ImpactInputError("plot", f"cannot write {text!r}: the suffix must be one of {', '.join(PLOT_SUFFIXES)}")
    if path.is_dir():
        raise ImpactInputError("plot", f"cannot write {text!r}: it is a directory")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise ImpactInputError("plot", f"cannot write {text!r}: directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ImpactInputError("plot", f"cannot write {text!r}: directory {str(parent)!r} is not writable")
    try:
        import matplotlib  # noqa: F401
    except ImportError:  # pragma: no cover - matplotlib is a dependency
        raise ImpactInputError("plot", "needs matplotlib (pip install matplotlib)") from None
    return path


def write_figure(fig, path: Path) -> None:
    """Save ``fig`` to ``path`` (the format from its suffix) and close it."""
    from ..figures import save

    save(fig, path)
