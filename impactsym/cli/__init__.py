"""The ``impactsym`` command line.

Every subcommand lives in its own module of this package and is listed in :data:`SUBCOMMANDS`.
A subcommand module defines ``register(subparsers)``, which adds its parser and sets
``func=run`` on it, and ``run(args) -> dict``. The result is printed as one JSON object with
``--json``, and as readable text otherwise (the module's optional ``render(result) -> str``).

The contract (``CONVENTIONS.md``) is enforced here, once, for every subcommand:

* exit status 0 on success;
* exit status 2 for bad input or a request the law cannot satisfy: an
  :class:`~impactsym.errors.ImpactError` prints ``impactsym SUBCOMMAND: error: MESSAGE`` on
  stderr, with no traceback; argparse usage errors also exit with 2;
* exit status 1 only for a bug (an unexpected exception, with its traceback).
"""

from __future__ import annotations

import argparse
import importlib
import json
import re
import sys
from typing import Sequence

from ..errors import ImpactError

#: subcommand modules, in the order ``impactsym --help`` lists them
SUBCOMMANDS = ["reproduce", "reflect", "prove", "resolve", "domain", "codegen", "bench"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="impactsym",
        description="Derive, prove and evaluate laws for simultaneous impacts between rigid bodies.",
    )
    sub = parser.add_subparsers(dest="command", metavar="SUBCOMMAND")
    sub.required = True
    for name in SUBCOMMANDS:
        module = importlib.import_module(f"{__name__}.{name.replace('-', '_')}")
        module.register(sub)
    return parser


def emit(result: dict, args: argparse.Namespace, module) -> None:
    if getattr(args, "json", False):
        sys.stdout.write(json.dumps(result, indent=None, sort_keys=False) + "\n")
        return
    render = getattr(module, "render", None)
    text = render(result) if render else json.dumps(result, indent=2)
    sys.stdout.write(text.rstrip("\n") + "\n")


_NEGATIVE_VALUE = re.compile(r"^-(?:[0-9.(]|sqrt|pi|cos|sin|tan|exp|log|Rational)")


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """Join ``--option -1,2`` into ``--option=-1,2``: argparse would read ``-1,2`` as an option.

    >>> join_negative_values(["reflect", "--gradient", "-1,1", "--json"])
    ['reflect', '--gradient=-1,1', '--json']
    """
    out: list[str] = []
    for tok in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and _NEGATIVE_VALUE.match(tok):
            out[-1] = f"{out[-1]}={tok}"
        else:
            out.append(tok)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(join_negative_values(sys.argv[1:] if argv is None else list(argv)))
    module = sys.modules[args.func.__module__]
    try:
        result = args.func(args)
        exit_code = 0
        if isinstance(result, tuple):  # (result, exit status) for subcommands that grade a run
            result, exit_code = result
        emit(result, args, module)
        return exit_code
    except ImpactError as exc:
        sys.stderr.write(f"impactsym {args.command}: error: {exc}\n")
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
