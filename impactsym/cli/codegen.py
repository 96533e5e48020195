"""``impactsym codegen``: list the generated kernels, or print one in a language.

The code comes from the committed catalog (``impactsym/kernels/catalog.json``), which
``python -m derivations`` writes together with every language's files; nothing is derived here.

Examples
--------
>>> from impactsym.cli import main
>>> main(["codegen", "impulse-ratio-root", "--lang", "c"])  # doctest: +ELLIPSIS
/* Roots of A p^2 + B p + C = 0 ...
void impulse_ratio_root(double A, double B, double C, double *p1, double *p1_partner)
...
0
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

from ..errors import ImpactInputError
from .common import add_json_flag, refuse_inapplicable

LANGS = ("c", "python", "numpy", "julia", "octave", "fortran", "rust")
CATALOG = Path(__file__).resolve().parent.parent / "kernels" / "catalog.json"


@lru_cache(maxsize=1)
def catalog() -> dict:
    """The committed catalog of generated kernels: ``{"kernels": [{name, codegen_name, code, ...}]}``."""
    return json.loads(CATALOG.read_text())


def register(sub) -> None:
    p = sub.add_parser(
        "codegen",
        help="list the generated kernels or print one as C, NumPy, Python, Julia, Octave, Fortran or Rust",
        description="Print generated code. NAME is a kernel's kebab-case codegen name "
                    "(e.g. chain3-impulse-ratio); --list shows them all.",
    )
    p.add_argument("name", nargs="?", metavar="NAME", help="kernel codegen name (see --list)")
    p.add_argument("--lang", metavar="LANG", help=f"with NAME: one of {', '.join(LANGS)} (default numpy)")
    p.add_argument("--list", action="store_true", help="list every kernel with its family and languages")
    add_json_flag(p)
    p.set_defaults(func=run, _codegen_parser=p)


def _languages(k: dict) -> list[str]:
    return [lang for lang in LANGS if k["code"].get(lang) is not None]


def run(args) -> dict:
    kernels = catalog()["kernels"]
    if args.list or args.name is None:
        if args.name is not None:
            raise ImpactInputError("name", "give either NAME or --list, not both")
        # the one option check of the CLI: --lang applies with NAME (one kernel), not to the listing
        refuse_inapplicable(args, args._codegen_parser, ("list",), "the kernel listing (--lang applies with NAME)")
        return {"kernels": [{"name": k["codegen_name"], "kernel": k["name"], "family": k["family"],
                             "kind": k["kind"], "args": k["args"], "outputs": k["outputs"],
                             "languages": _languages(k), "summary": k["summary"]} for k in kernels]}
    if args.lang is None:
        args.lang = "numpy"
    if args.lang not in LANGS:
        raise ImpactInputError("lang", f"must be one of {', '.join(LANGS)}, got {args.lang!r}")
    by_name = {k["codegen_name"]: k for k in kernels}
    k = by_name.get(args.name) or by_name.get(args.name.replace("_", "-"))
    if k is None:
        raise ImpactInputError("name", f"no kernel {args.name!r}; known: {', '.join(sorted(by_name))}")
    code = k["code"].get(args.lang)
    if code is None:
        raise ImpactInputError("lang", f"kernel {k['codegen_name']!r} has no {args.lang} form "
                                       f"(available: {', '.join(_languages(k))})")
    return {"name": k["codegen_name"], "kernel": k["name"], "family": k["family"], "lang": args.lang, "code": code}


def render(result: dict) -> str:
    if "kernels" in result:
        rows = result["kernels"]
        w = max(len(r["name"]) for r in rows)
        f = max(len(r["family"]) for r in rows)
        out = [f"{'name'.ljust(w)}  {'family'.ljust(f)}  languages"]
        out += [f"{r['name'].ljust(w)}  {r['family'].ljust(f)}  {','.join(r['languages'])}" for r in rows]
        return "\n".join(out)
    return result["code"]
