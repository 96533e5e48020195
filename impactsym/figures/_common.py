"""What every figure module shares: matplotlib loaded lazily (Agg), exact numbers as text, saving and
showing a figure, and the kinetic-coordinate drawing helpers.

Matplotlib is imported inside :func:`_plt` only, so ``import impactsym`` stays light.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..numbers import exact_str

__all__ = ["save", "show"]


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _s(x) -> str:
    return exact_str(sp.sympify(x))


def _vs(v) -> list:
    return [_s(x) for x in v]


def _f(v) -> np.ndarray:
    return np.array([float(sp.N(x, 17)) for x in v], dtype=float)


def _tight(fig) -> None:
    """Ask for matplotlib's tight layout when ``fig`` is drawn, not now.

    The layout measures every text of the figure, the bulk of building one; a caller that wants
    only a figure's source data (the README's currency test, the paper checks) never draws it, so
    never pays for it. :func:`save` and :func:`show` run it first, at the figure's own dpi, exactly as
    ``fig.tight_layout()`` did when it was called at the end of building (the same pixels); a
    figure drawn otherwise is laid out by the engine at its drawing.
    """
    fig.set_layout_engine("tight")


def tight_layout_once(fig):
    """``fig.tight_layout()``, then no layout engine at all, so that drawing ``fig`` does not lay it
    out again; returns ``fig``.

    ``tight_layout()`` leaves a placeholder engine (it lays out nothing), and while a figure has
    any engine ``savefig`` first draws it once without rendering, for an engine to lay it out, and
    then draws it again: with no engine the one drawing gives the same pixels (the PNG bytes are
    identical) for a third less work. An engine that the rcParams ask for (``figure.autolayout``,
    ``figure.constrained_layout.use``) is kept.
    """
    import matplotlib as mpl

    fig.tight_layout()
    if not (mpl.rcParams["figure.autolayout"] or mpl.rcParams["figure.constrained_layout.use"]):
        fig.set_layout_engine(None)  # with those rcParams off: no engine at all
    return fig


def _laid_out(fig):
    """Run the layout :func:`_tight` deferred (:func:`tight_layout_once`: ``fig.tight_layout()``,
    leaving no engine)."""
    from matplotlib.layout_engine import TightLayoutEngine

    if isinstance(fig.get_layout_engine(), TightLayoutEngine):
        tight_layout_once(fig)
    return fig


def save(fig, path) -> str:
    """Write ``fig`` to ``path`` (the format from its suffix, 100 dpi) and close it; return the path as text.

    >>> import os, tempfile
    >>> from impactsym.figures import at_fig3_domain
    >>> fig, _ = at_fig3_domain()
    >>> os.path.getsize(save(fig, os.path.join(tempfile.mkdtemp(), "fig3.png"))) > 0
    True
    """
    _laid_out(fig).savefig(path, dpi=100)
    _plt().close(fig)
    return str(path)


def show(fig):
    """The figure as an ``IPython.display.Image`` (PNG), for a notebook cell's last line; closes ``fig``.

    With the Agg backend a bare ``Figure`` displays as text; this shows the picture, once.

    >>> from impactsym.figures import sm_fig1_convex_corner
    >>> fig, _ = sm_fig1_convex_corner()
    >>> show(fig).format
    'png'
    """
    import io

    from IPython.display import Image

    buf = io.BytesIO()
    _laid_out(fig).savefig(buf, format="png", dpi=90)
    _plt().close(fig)
    return Image(data=buf.getvalue(), format="png")


# --------------------------------------------------------------------------- kinetic coordinates
def _kinetic_frame(M):
    """``L`` with ``M = L Lᵀ`` (floats): ``x = Lᵀ v`` are coordinates in which the kinetic metric
    is Euclidean, so reflections ``G_u`` look like mirror images."""
    Mf = np.array(sp.Matrix(M).evalf(17).tolist(), dtype=float)
    return np.linalg.cholesky(Mf)


def _kin(L, v) -> np.ndarray:
    return L.T @ _f(v)


def _ray(ax, x, *, scale=1.0, **kw):
    ax.annotate("", xy=(scale * x[0], scale * x[1]), xytext=(0, 0),
                arrowprops=dict(arrowstyle="->", lw=kw.pop("lw", 1.6), color=kw.pop("color", "k"), **kw))


def _shade_cone(ax, L, H, *, either=False, color="C2", alpha=0.25, radius=2.5, label=None):
    """Shade, in kinetic coordinates, the velocities with ``H v ≥ 0`` (all rows; ``either``: any row)."""
    t = np.linspace(0, 2 * np.pi, 721)
    xs = np.stack([np.cos(t), np.sin(t)])
    v = np.linalg.solve(L.T, xs)  # back to velocities
    Hf = np.array(sp.Matrix(H).evalf(17).tolist(), dtype=float)
    w = Hf @ v
    ok = (w >= 0).any(axis=0) if either else (w >= 0).all(axis=0)
    # the shaded wedges are the sample steps k -> k+1 with both ends valid; each run of consecutive
    # wedges is drawn as one fan (origin, then the arc), the same region as its wedges
    wedge = np.concatenate([[False], ok[:-1] & ok[1:], [False]])
    starts = np.flatnonzero(wedge[1:] & ~wedge[:-1])
    ends = np.flatnonzero(wedge[:-1] & ~wedge[1:])  # one past the run's last wedge
    for k0, k1 in zip(starts, ends):
        ax.fill(np.r_[0, radius * xs[0, k0:k1 + 1]], np.r_[0, radius * xs[1, k0:k1 + 1]], color=color, alpha=alpha,
                lw=0)
    if label:
        ax.fill([], [], color=color, alpha=alpha, label=label)


def _fill_wedges(ax, t, ok, radius, **style):
    """Shade the wedges ``(0, radius·u(t[k]), radius·u(t[k+1]))`` whose two ends are both ``ok`` (``u(s) =
    (cos s, sin s)``), as one :class:`~matplotlib.collections.PolyCollection`.

    The same triangles, in the same order and style, as one ``ax.fill`` per wedge (the PNG is
    byte-identical): a collection is built and drawn once instead of one patch per wedge (up to
    720 a figure). Returns the collection (``None`` when no wedge is shaded).
    """
    from matplotlib.collections import PolyCollection

    ks = np.flatnonzero(ok[:-1] & ok[1:])
    if not ks.size:
        return None
    c, s = radius * np.cos(t), radius * np.sin(t)
    tri = np.zeros((ks.size, 3, 2))
    tri[:, 1, 0], tri[:, 1, 1] = c[ks], s[ks]
    tri[:, 2, 0], tri[:, 2, 1] = c[ks + 1], s[ks + 1]
    coll = PolyCollection(tri, closed=True, **style)
    ax.add_collection(coll, autolim=True)
    return coll


def _normal_cone_arc(M, H, v0, samples=61):
    """The energy-preserving exits with the momentum jump in the normal cone, ``{v0 + M⁻¹Hᵀp : p ≥ 0,
    ‖v‖_M = ‖v0‖_M}``: for ``p = (cos s, sin s)`` this is the single reflection across the covector
    ``pᵀH`` (:func:`impactsym.laws.reflection.reflect`). Floats, for drawing."""
    from ..laws.reflection import reflect

    Hf = np.array(sp.Matrix(H).evalf(17).tolist(), dtype=float)
    Mf = np.array(sp.Matrix(M).evalf(17).tolist(), dtype=float)
    vf = _f(v0)
    out = []
    for s in np.linspace(0, np.pi / 2, samples):
        h = np.cos(s) * Hf[0] + np.sin(s) * Hf[1]
        out.append(reflect(Mf, h, vf))
    return np.array(out)


# --------------------------------------------------------------------------- kinetic plane (3 DOF)
def _plane_basis(M, H):
    """An M-orthonormal basis ``(e₁, e₂)`` of ``span(M⁻¹H₁ᵀ, M⁻¹H₂ᵀ)``, from the M-normals
    (:func:`impactsym.mechanics.m_normal`), floats."""
    from ..mechanics import m_normal

    Mf = np.array(sp.Matrix(M).evalf(17).tolist(), dtype=float)
    n1 = _f(m_normal(M, H[0, :]))
    n2 = _f(m_normal(M, H[1, :]))
    e2 = n2 - (n2 @ Mf @ n1) * n1
    e2 /= math.sqrt(e2 @ Mf @ e2)
    return Mf, n1, e2
