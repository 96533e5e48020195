"""``impactsym codegen``: list the generated kernels, or print one in a language.

The code comes from the committed catalog (``impactsym/kernels/catalog.json``), which
``python -m derivations`` writes together with every language's files; nothing is derived here.

What is printed is a complete unit that compiles (or runs) as printed: the C form with its
``#include`` lines and the family's static helpers it calls; the Python and NumPy forms with their
imports (the plain-Python form with a ``sqrt`` that gives nan below zero, and ``ceil``/``floor`` that
pass nan and infinities through, as C, NumPy and the documentation say); the Fortran form inside a
module with its ``iso_c_binding``. ``--out DIR`` writes the unit's files (for C also the header) and
``BUILD``, the command that compiles or runs them; ``tests/test_codegen_units.py`` does exactly that
for every kernel and every language this machine has.

Examples
--------
>>> from impactsym.cli import main
>>> main(["codegen", "impulse-ratio-root", "--lang", "c"])  # doctest: +ELLIPSIS
#include <math.h>
#include <stddef.h>
<BLANKLINE>
/* Roots of A p^2 + B p + C = 0 ...
void impulse_ratio_root(double A, double B, double C, double *p1, double *p1_partner)
...
0
"""

from __future__ import annotations

import json
import re
import sys
from functools import lru_cache
from pathlib import Path

from ..errors import ImpactInputError
from .common import add_json_flag, refuse_inapplicable, writable_dir

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
    p.add_argument("--out", metavar="DIR", help="with NAME: also write the unit's files and BUILD (the command "
                                                "that compiles or runs them) into DIR")
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
    if k["code"].get(args.lang) is None:
        raise ImpactInputError("lang", f"kernel {k['codegen_name']!r} has no {args.lang} form "
                                       f"(available: {', '.join(_languages(k))})")
    out_dir = writable_dir(args.out, "out")
    u = unit(k, args.lang)
    result = {"name": k["codegen_name"], "kernel": k["name"], "family": k["family"], "lang": args.lang,
              "code": u["files"][u["main"]], "build": u["build"]}
    if out_dir is not None:
        out_dir.mkdir(parents=True, exist_ok=True)
        written = []
        for fname, text in {**u["files"], "BUILD": u["build"] + "\n"}.items():
            (out_dir / fname).write_text(text)
            written.append(str(out_dir / fname))
        result["files"] = written
        if not args.json:  # stdout stays the unit, exactly as written
            sys.stderr.write(f"wrote {', '.join(written)}\n")
    return result


# --------------------------------------------------------------------------- complete units
_C_INCLUDES = "#include <math.h>\n#include <stddef.h>\n"
_C_DEFINITION = re.compile(r"^((?:int|void|double)\s+(\w+)\s*\([^)]*\))\s*\{", re.M)
_C_STATIC = re.compile(r"^static\s[^\n]*?\b(\w+)\s*\(.*?^\}\n", re.M | re.S)

#: the plain-Python form's math, with C's (and NumPy's) answers where Python's ``math`` raises
_PY_PRELUDE = '''import math


def _sqrt(x):
    """math.sqrt, but nan below zero (no real root), as C and NumPy give."""
    return math.sqrt(x) if x >= 0 else math.nan


def _ceil(x):
    """math.ceil as a float, passing nan and infinities through (C's ceil)."""
    return float(math.ceil(x)) if math.isfinite(x) else x


def _floor(x):
    """math.floor as a float, passing nan and infinities through (C's floor)."""
    return float(math.floor(x)) if math.isfinite(x) else x
'''


def _c_helpers(family: str, code: str) -> str:
    """The static functions of the family's committed C file that ``code`` calls (and that they
    call), in file order."""
    path = CATALOG.parent / "c" / f"{family}.c"
    if not path.is_file():
        return ""
    defined = {m.group(1) for m in _C_STATIC.finditer(code + "\n")}
    helpers = [(m.group(1), m.group(0)) for m in _C_STATIC.finditer(path.read_text()) if m.group(1) not in defined]
    needed, text = set(), code
    changed = True
    while changed:
        changed = False
        for name, body in helpers:
            if name not in needed and re.search(rf"\b{name}\s*\(", text):
                needed.add(name)
                text += body
                changed = True
    return "".join(body + "\n" for name, body in helpers if name in needed)


def _family_dependencies(k: dict, code: str) -> list[str]:
    """The NumPy forms of the other kernels of ``k``'s family that ``code`` calls (and that they
    call), in catalog order: a general-n kernel may call a closed form of its family."""
    family = [o for o in catalog()["kernels"] if o["family"] == k["family"] and o["name"] != k["name"]
              and o["code"].get("numpy") is not None]
    needed, text, changed = set(), code, True
    while changed:
        changed = False
        for o in family:
            if o["name"] not in needed and re.search(rf"(?<![\w.]){o['name']}\s*\(", text):
                needed.add(o["name"])
                text += o["code"]["numpy"]
                changed = True
    return [o["code"]["numpy"] for o in family if o["name"] in needed]


def _python_unit(code: str) -> str:
    """The plain-Python form, made runnable: its ``math`` calls that raise where C returns nan go
    through the prelude's helpers."""
    body = code.split("\n", 1)[1].lstrip("\n") if code.startswith("import math\n") else code
    for f in ("sqrt", "ceil", "floor"):
        body = body.replace(f"math.{f}(", f"_{f}(")
    return _PY_PRELUDE + "\n\n" + body + "\n"


def unit(k: dict, lang: str) -> dict:
    """The complete unit of kernel ``k`` (a catalog entry) in ``lang``: ``files`` (name -> text),
    ``main`` (the file printed on stdout) and ``build`` (the command that compiles or runs it).

    >>> u = unit(next(k for k in catalog()["kernels"] if k["codegen_name"] == "chain3-alpha-max"), "c")
    >>> sorted(u["files"]), u["build"]
    (['chain3_alpha_max.c', 'chain3_alpha_max.h'], 'cc -std=c99 -O2 -fPIC -shared -o libchain3_alpha_max.so chain3_alpha_max.c -lm')
    """
    code, name = k["code"][lang], k["name"]
    if lang == "c":
        src = _C_INCLUDES + "\n" + _c_helpers(k["family"], code) + code + "\n"
        guard = f"IMPACTSYM_{name.upper()}_H"
        protos = "".join(f"{m.group(1)};\n" for m in _C_DEFINITION.finditer(code))
        header = f"#ifndef {guard}\n#define {guard}\n\n#include <stddef.h>\n\n{protos}\n#endif /* {guard} */\n"
        return {"files": {f"{name}.c": src, f"{name}.h": header}, "main": f"{name}.c",
                "build": f"cc -std=c99 -O2 -fPIC -shared -o lib{name}.so {name}.c -lm"}
    if lang in ("python", "numpy"):
        if "numpy." in code and not code.startswith("import math"):
            deps = _family_dependencies(k, code)
            src = "import numpy\n\n\n" + "".join(d + "\n\n\n" for d in deps) + code + "\n"
        else:
            src = _python_unit(code)
        return {"files": {f"{name}.py": src}, "main": f"{name}.py",
                "build": f"python -c \"from {name} import {name}\""}
    if lang == "fortran":
        src = (f"module {name}_kernel\n    use, intrinsic :: iso_c_binding, only: c_double\n"
               f"    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan\n    implicit none\n"
               f"contains\n{code}\nend module {name}_kernel\n")
        return {"files": {f"{name}.f90": src}, "main": f"{name}.f90",
                "build": f"gfortran -std=f2008 -O2 -c {name}.f90  # then: use {name}_kernel"}
    if lang == "octave":
        return {"files": {f"{name}.m": code + "\n"}, "main": f"{name}.m",
                "build": f"octave --eval \"addpath('.'); help {name}\"  # a function file: call {name}(...)"}
    if lang == "rust":
        return {"files": {f"{name}.rs": code + "\n"}, "main": f"{name}.rs",
                "build": f"rustc --edition 2021 --crate-type lib -O {name}.rs"}
    return {"files": {f"{name}.jl": code + "\n"}, "main": f"{name}.jl",  # julia
            "build": f"julia -e 'include(\"{name}.jl\")'"}


def render(result: dict) -> str:
    if "kernels" in result:
        rows = result["kernels"]
        w = max(len(r["name"]) for r in rows)
        f = max(len(r["family"]) for r in rows)
        out = [f"{'name'.ljust(w)}  {'family'.ljust(f)}  languages"]
        out += [f"{r['name'].ljust(w)}  {r['family'].ljust(f)}  {','.join(r['languages'])}" for r in rows]
        return "\n".join(out)
    return result["code"]
