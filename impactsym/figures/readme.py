"""The README's figures: :data:`README_FIGURES`, written with their source data by
:func:`write_readme_figures` (``python -m impactsym.figures DIR``).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ._common import _plt, save
from .acary_taha import at_fig3_domain
from .laws import laws_side_by_side
from .seghete_murphey import sm_fig4_configuration_space, sm_sec3c_termination

__all__ = ["README_FIGURES", "write_readme_figures", "main"]


# --------------------------------------------------------------------------- README figures
#: the figures shown in the README: file stem -> (function, keyword arguments)
README_FIGURES = {
    "sm_fig4_configuration_space": (sm_fig4_configuration_space, {}),
    "sm_sec3c_termination": (sm_sec3c_termination, {}),
    "at_fig3_domain": (at_fig3_domain, {}),
    "laws_side_by_side_cradle": (laws_side_by_side, {"scene": "cradle"}),
}


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.floating, np.integer, np.bool_)):
        return x.item()
    return x


def write_readme_figures(outdir, names=None, *, pixels: bool = True) -> dict:
    """Write each README figure as ``outdir/NAME.png`` with its source data as ``outdir/NAME.json``.

    ``pixels=False`` writes only the JSON (what the currency test regenerates). Returns
    ``{name: source data}``.

    >>> import tempfile
    >>> out = write_readme_figures(tempfile.mkdtemp(), ["at_fig3_domain"], pixels=False)
    >>> out["at_fig3_domain"]["e"]
    ['3/7', '1']
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    out = {}
    for name in names or README_FIGURES:
        fn, kw = README_FIGURES[name]
        fig, src = fn(**kw)
        src = _jsonable(src)
        if pixels:
            save(fig, outdir / f"{name}.png")
        else:
            _plt().close(fig)
        (outdir / f"{name}.json").write_text(json.dumps(src, indent=1, sort_keys=True) + "\n")
        out[name] = src
    return out


def main(argv=None) -> int:
    import argparse

    p = argparse.ArgumentParser(prog="python -m impactsym.figures",
                                description="Write the README's figures (PNG) and their source data (JSON).")
    p.add_argument("outdir", nargs="?", default="docs/figures")
    args = p.parse_args(argv)
    for name in write_readme_figures(args.outdir):
        print(Path(args.outdir) / f"{name}.png")
    return 0
