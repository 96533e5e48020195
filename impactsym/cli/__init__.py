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
* exit status 1 only for a bug (an unexpected exception, with its traceback);
* with ``--json``, an error (exit 2) is also one JSON object on stdout,
  ``{"error": {"argument": NAME or null, "message": TEXT}}`` (see :data:`JSON_CONTRACT`);
* JSON is strict: a float that overflows is ``null`` beside its exact string (never ``Infinity``);
* an option that does not apply to the subcommand or law is refused (exit 2), never ignored.
"""

from __future__ import annotations

import argparse
import importlib
import json
import re
import signal
import sys
import threading
from typing import Sequence

from .. import __version__
from ..errors import ImpactError

#: subcommand modules, in the order ``impactsym --help`` lists them
SUBCOMMANDS = ["reproduce", "reflect", "prove", "resolve", "scene", "domain", "codegen", "bench", "check", "batch",
               "suite"]

#: the JSON contract, as ``impactsym --help`` prints it
JSON_CONTRACT = """\
JSON contract (--json):
  success: exactly one JSON object on stdout, nothing else there (progress goes to stderr).
  Exact numbers are strings in SymPy's str form ("-1/3", "sqrt(3)/2"); each exact array X
  also comes as X_float (floats). JSON is strict: a float that overflows is null beside its
  exact string, never Infinity or NaN.
  error (exit status 2): the message on stderr, and one object on stdout:
    {"error": {"argument": "velocity", "message": "velocity: has length 1, expected 2"}}
  "argument" is the option or argument at fault (null when the error names none).
exit status: 0 success; 2 bad input, an option that does not apply, or a request the law
  cannot satisfy (no traceback); 1 only for a bug.
numbers: at most 1000 digits (and magnitude within 10^-1000..10^1000); 1e-3 and 1.1 are exact."""


class UsageError(Exception):
    """An argparse usage error (exit status 2), carrying its message and the argument at fault."""

    def __init__(self, message: str, argument: str | None):
        super().__init__(message)
        self.message = message
        self.argument = argument


_ARG_IN_MESSAGE = re.compile(r"argument (-{0,2}[A-Za-z][\w-]*)|arguments are required: (-{0,2}[A-Za-z][\w-]*)"
                             r"|unrecognized arguments: (\S+)")


class _Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors raise :class:`UsageError` (after printing the usage
    and message on stderr, as argparse does), so that ``main`` can also answer in JSON."""

    def error(self, message):  # noqa: D401 - argparse API
        self.print_usage(sys.stderr)
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        m = _ARG_IN_MESSAGE.search(message)
        name = next((g for g in m.groups() if g), None) if m else None
        if name == "SUBCOMMAND":
            name = "command"
        raise UsageError(message, name.lstrip("-").replace("-", "_") if name else None)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="impactsym",
        description="Derive, prove and evaluate laws for simultaneous impacts between rigid bodies.",
        epilog=JSON_CONTRACT,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"impactsym {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="SUBCOMMAND", parser_class=_Parser)
    sub.required = True
    for name in SUBCOMMANDS:
        module = importlib.import_module(f"{__name__}.{name.replace('-', '_')}")
        module.register(sub)
    for p in sub.choices.values():  # one time limit for every subcommand
        p.add_argument("--timeout", metavar="SECONDS",
                       help="stop with exit status 2 if the work takes longer than SECONDS")
    return parser


_PARSER: argparse.ArgumentParser | None = None


def _parser() -> argparse.ArgumentParser:
    """The parser, built once per process (2.7 ms a build): parsing reads it and never changes it,
    and ``main`` runs many times in one process (``batch``, the test suite, notebooks)."""
    global _PARSER
    if _PARSER is None:
        _PARSER = build_parser()
    return _PARSER


def _timeout_seconds(text: str | None) -> float | None:
    if text is None:
        return None
    from ..arithmetic.literals import plain_rational
    from ..errors import ImpactInputError

    try:
        value = plain_rational(text)  # plain text ("30", "0.5") needs no SymPy
    except ZeroDivisionError:
        value = None
    if value is not None:
        positive = value > 0
    else:
        from ..numbers import parse_number

        value = parse_number(text, "timeout")
        positive = value.is_positive
    if not positive:
        raise ImpactInputError("timeout", f"must be a positive number of seconds, got {text!r}")
    return float(value)


class _TimeLimit:
    """``--timeout``: a SIGALRM timer that raises :class:`~impactsym.errors.TimeLimitExceeded` in
    the main thread, re-armed every half second until the exception has left the computation
    (a broad ``except`` inside a law cannot swallow it for good)."""

    def __init__(self, seconds: float | None):
        self.seconds = seconds
        self.usable = seconds is not None and hasattr(signal, "setitimer") and \
            threading.current_thread() is threading.main_thread()

    def _fire(self, signum, frame):
        from ..errors import TimeLimitExceeded

        raise TimeLimitExceeded(f"timeout: the computation did not finish within {self.seconds:g} s (--timeout)")

    def __enter__(self):
        if self.usable:
            self.previous = signal.signal(signal.SIGALRM, self._fire)
            signal.setitimer(signal.ITIMER_REAL, self.seconds, 0.5)
        return self

    def __exit__(self, *exc):
        if self.usable:
            signal.setitimer(signal.ITIMER_REAL, 0, 0)
            signal.signal(signal.SIGALRM, self.previous)
        return False


def emit(result: dict | None, args: argparse.Namespace, module) -> None:
    if result is None:  # the subcommand wrote its own output (batch: JSON Lines on stdout)
        return
    from .common import dumps_strict

    if getattr(args, "json", False):
        sys.stdout.write(dumps_strict(result) + "\n")
        return
    render = getattr(module, "render", None)
    text = render(result) if render else dumps_strict(result, indent=2)
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


_ARG_PREFIX = re.compile(r"^([a-z][a-z0-9_]*): ")


def error_argument(exc: Exception) -> str | None:
    """The argument an error names: its ``argument`` attribute, or the ``name:`` its message starts with."""
    arg = getattr(exc, "argument", None)
    if arg:
        return arg
    m = _ARG_PREFIX.match(str(exc))
    return m.group(1) if m else None


def _json_error(argument: str | None, message: str) -> None:
    from .common import dumps_strict

    sys.stdout.write(dumps_strict({"error": {"argument": argument, "message": message}}) + "\n")


def main(argv: Sequence[str] | None = None) -> int:
    argv = join_negative_values(sys.argv[1:] if argv is None else list(argv))
    wants_json = "--json" in argv
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except UsageError as exc:
        if wants_json:
            _json_error(exc.argument, exc.message)
        return 2
    except SystemExit as exc:  # --help, --version
        return int(exc.code or 0)
    module = sys.modules[args.func.__module__]
    old_limit = sys.get_int_max_str_digits() if hasattr(sys, "get_int_max_str_digits") else None
    if old_limit is not None:  # exact results may grow beyond the inputs' 1000 digits
        sys.set_int_max_str_digits(0)
    try:
        with _TimeLimit(_timeout_seconds(args.timeout)):
            result = args.func(args)
        exit_code = 0
        if isinstance(result, tuple):  # (result, exit status) for subcommands that grade a run
            result, exit_code = result
        emit(result, args, module)
        return exit_code
    except ImpactError as exc:
        sys.stderr.write(f"impactsym {args.command}: error: {exc}\n")
        if getattr(args, "json", False):
            _json_error(error_argument(exc), str(exc))
        return 2
    finally:
        if old_limit is not None:
            sys.set_int_max_str_digits(old_limit)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
