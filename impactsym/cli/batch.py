"""``impactsym batch``: answer many requests in one process (JSON Lines in, JSON Lines out).

Each input line is one request, in one of two forms (:func:`impactsym.oracle.request_argv`):

* ``{"argv": ["resolve", "--law", "newton", "--scene", "chain3"]}``: a subcommand and its arguments
  exactly as on the command line;
* ``{"command": "resolve", "args": {"law": "newton", "scene": "chain3"}}``: option names (``_`` or
  ``-``) and values; ``true`` is a flag.

Both take an optional ``"id"``, echoed in the answer. ``--json`` is implied. Each answer is one line:
``{"schema": "impactsym.batch/1", "id": …, "exit_status": S, "result": {…}, "line": N}`` where
``result`` is exactly the JSON object the subcommand prints with ``--json`` and ``S`` its exit status
(``check``: 0 or 3), or, for a bad request, ``{"schema", "id", "exit_status": 2, "error":
{"argument", "message"}, "line"}`` (exit status 1 for a bug). One bad line never stops the batch;
blank lines are skipped. The batch itself exits with 0 once every line is answered (2 when the input
or output file cannot be opened).
"""

from __future__ import annotations

import sys

from ..errors import ImpactInputError


def register(sub) -> None:
    import argparse

    p = sub.add_parser(
        "batch",
        help="answer many requests (JSON Lines) in one process",
        description="JSON Lines in, JSON Lines out: one request per line, each answered in this process with "
                    "the JSON its subcommand prints with --json.",
        epilog='request forms:\n  {"argv": ["resolve", "--law", "newton", "--scene", "chain3"], "id": 1}\n'
               '  {"command": "check", "args": {"scene": "chain3", "observed": "0,0,1"}}\n'
               'answer: {"schema": "impactsym.batch/1", "id": 1, "exit_status": 0, "result": {...}, "line": 1}\n'
               '  or {..., "exit_status": 2, "error": {"argument": ..., "message": ...}} for a bad request',
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--input", metavar="FILE", default="-", help="requests, one JSON object per line (default - : stdin)")
    p.add_argument("--output", metavar="FILE", default="-", help="answers, one JSON object per line (default - : stdout)")
    p.set_defaults(func=run)


def run(args):
    from ..oracle import iter_answers
    from .common import dumps_strict, writable_file

    if args.input != "-":
        try:
            src = open(args.input, encoding="utf-8")
        except OSError as exc:
            raise ImpactInputError("input", f"cannot read {args.input!r}: {exc.strerror}") from None
    else:
        src = sys.stdin
    if args.output != "-":
        writable_file(args.output, "output")
        dst = open(args.output, "w", encoding="utf-8")
    else:
        dst = sys.stdout
    counts = {0: 0}
    try:
        for answer in iter_answers(src):
            dst.write(dumps_strict(answer) + "\n")
            dst.flush()
            counts[answer["exit_status"]] = counts.get(answer["exit_status"], 0) + 1
    finally:
        if src is not sys.stdin:
            src.close()
        if dst is not sys.stdout:
            dst.close()
    summary = {"answered": sum(counts.values()), "exit_statuses": {str(k): v for k, v in sorted(counts.items())}}
    sys.stderr.write(f"impactsym batch: answered {summary['answered']} request(s); exit statuses "
                     f"{summary['exit_statuses']}\n")
    return None if args.output == "-" else summary


def render(result) -> str:
    return f"answered {result['answered']} request(s); exit statuses {result['exit_statuses']}"
