"""``--plot FILE`` on ``resolve``, ``domain`` and ``bench``: write the figure of what was just computed.

The path is checked before any work by the CLI's one output-path check
(:func:`impactsym.cli.common.writable_file`: its directory must exist and be writable, the suffix
must be one matplotlib writes): a bad path is exit 2 naming ``plot``, and nothing is computed. The figure
itself comes from :mod:`impactsym.figures` (``resolve``: :func:`~impactsym.figures.resolve_figure`;
``domain``: :func:`~impactsym.figures.domain_figure`) or :func:`impactsym.bench.plot` (``bench``).
"""

from __future__ import annotations

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
    from .common import writable_file

    path = writable_file(getattr(args, "plot", None), "plot", suffixes=PLOT_SUFFIXES)
    if path is None:
        return None
    try:
        import matplotlib  # noqa: F401
    except ImportError:  # pragma: no cover - matplotlib is a dependency
        raise ImpactInputError("plot", "needs matplotlib (pip install matplotlib)") from None
    return path


def write_figure(fig, path: Path) -> None:
    """Save ``fig`` to ``path`` (the format from its suffix) and close it."""
    from ..figures import save

    save(fig, path)
