"""``impactsym resolve --law LAW ...``: resolve a (simultaneous) impact with one law.

Each law lives in its own module and answers through :data:`LAWS`, a table from the law's
CLI name to ``"module:function"``; the function takes the parsed ``args`` and returns the JSON
result (a dict). The options below are shared; a law ignores the ones that do not concern it.
"""

from __future__ import annotations

import importlib

from ..errors import ImpactInputError
from .common import add_json_flag

#: CLI law name -> "module:function" (module relative to impactsym)
LAWS: dict[str, str] = {
}


def register(sub) -> None:
    p = sub.add_parser(
        "resolve",
        help="resolve a simultaneous impact with one law",
        description="Resolve an impact given matrices (--mass-matrix, --gradients, --velocity) or --scene.",
    )
    p.add_argument("--law", required=True, metavar="LAW", help="one of: " + ", ".join(LAWS) if LAWS else "law")
    p.add_argument("--mass-matrix", metavar="M", help='mass matrix "a,b;c,d"')
    p.add_argument("--gradients", metavar="H", help='gradient rows of the closed contacts "a,b;c,d"')
    p.add_argument("--velocity", metavar="v", help='pre-impact velocity "a,b"')
    p.add_argument("--restitution", metavar="e", help="restitution coefficient")
    p.add_argument("--scene", metavar="NAME", help="a canonical scene instead of matrices")
    add_json_flag(p)
    p.set_defaults(func=run, _resolve_parser=p)


def run(args) -> dict:
    if args.law not in LAWS:
        raise ImpactInputError("law", f"unknown law {args.law!r}; known: {', '.join(LAWS) or '(none yet)'}")
    module_name, func_name = LAWS[args.law].split(":")
    module = importlib.import_module(f"impactsym.{module_name}")
    return getattr(module, func_name)(args)
