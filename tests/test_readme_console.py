"""Every ``console`` block of README.md is the real output of the command it shows.

(The README's Python block is a doctest, run by ``--doctest-glob=README.md``.)

How a block is read
-------------------
A block fenced with three backticks and ``console`` is a sequence of commands, each a line
``$ impactsym ARGS  [# comment]`` followed by the lines it prints. The comment is dropped and
``ARGS`` is split as a POSIX shell would (``shlex``). Every command runs in this process through
:func:`impactsym.cli.main` (no subprocess, so the suite stays fast), and its output is compared
with the lines under it:

* A command whose shown output starts with ``impactsym SUBCOMMAND: error:`` is an error example:
  it must exit with status 2, print nothing on stdout, and print the shown lines on stderr (the
  contract of CONVENTIONS.md). Every other command must exit with status 0, print nothing on
  stderr, and print the shown lines on stdout.
* A line that is only ``...`` (indentation aside) stands for any number of real lines, none
  included; ``...`` inside a line stands for any text within that line (doctest's ELLIPSIS, but
  never across lines). The README uses it where output is elided or depends on time or load.
* Trailing whitespace of each line is ignored; nothing else is.

On failure the message shows a line diff that knows ``...``, and then the full real output, ready
to paste into the README.

``impactsym reproduce`` (the whole audit) is run here like every other command. The claim
framework keeps each finding per process (``paper_checks.framework._MEMO``), so after
``tests/test_cli_reproduce.py`` has run the audit in the same pytest process, running it again
costs well under a second (0.09 s measured); run alone, this file pays for one audit.
"""

from __future__ import annotations

import contextlib
import io
import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest

from impactsym.cli import main

README = Path(__file__).resolve().parents[1] / "README.md"

_FENCE = re.compile(r"^```(\w*)\s*$")
_ERROR_LINE = re.compile(r"^impactsym [\w-]+: error: ")


@dataclass
class Command:
    line: int  # 1-based line of README.md holding the ``$ impactsym ...`` line
    text: str  # the command as written, comment included
    argv: list[str]  # the arguments after ``impactsym``, comment dropped
    expected: list[str]  # the lines shown under it

    @property
    def is_error_example(self) -> bool:
        return bool(self.expected) and bool(_ERROR_LINE.match(self.expected[0]))

    @property
    def id(self) -> str:
        args = " ".join(self.argv)
        return f"L{self.line}-{args if len(args) <= 60 else args[:59] + '…'}"


def console_blocks(text: str) -> list[tuple[int, list[str]]]:
    """The ``console`` blocks of a Markdown text: (line of the first content line, its lines).

    >>> console_blocks("a\\n```console\\n$ impactsym x\\nout\\n```\\n```python\\n>>> 1\\n```\\n")
    [(3, ['$ impactsym x', 'out'])]
    """
    blocks, current, start, lang = [], None, 0, None
    for i, line in enumerate(text.splitlines(), start=1):
        m = _FENCE.match(line)
        if current is None:
            if m:
                current, start, lang = [], i + 1, m.group(1)
        elif line.strip() == "```":
            if lang == "console":
                blocks.append((start, current))
            current = None
        else:
            current.append(line)
    if current is not None:
        raise ValueError(f"README.md: the block opened at line {start - 1} is never closed")
    return blocks


def parse_commands(blocks) -> list[Command]:
    """Split console blocks into commands with the output each shows.

    >>> [(c.argv, c.expected) for c in parse_commands([(5, ["$ impactsym prove --json  # note", "{}"])])]
    [(['prove', '--json'], ['{}'])]
    """
    commands = []
    for start, lines in blocks:
        if not lines or not lines[0].startswith("$ "):
            raise ValueError(f"README.md line {start}: a console block must start with a '$ ' command line")
        for offset, line in enumerate(lines):
            if line.startswith("$ "):
                words = shlex.split(line[2:], comments=True)
                if not words or words[0] != "impactsym":
                    raise ValueError(f"README.md line {start + offset}: only 'impactsym' commands are "
                                     f"checked, got {line!r}")
                commands.append(Command(start + offset, line, words[1:], []))
            else:
                commands[-1].expected.append(line)
    return commands


def output_pattern(expected: list[str]) -> re.Pattern:
    """A regex for the real output (lines joined by ``\\n``, trailing whitespace stripped).

    >>> bool(output_pattern(["a", "...", "t = ... s"]).fullmatch("a\\nb\\nc\\nt = 1.5 s\\n"))
    True
    >>> bool(output_pattern(["a", "...", "c"]).fullmatch("a\\nc\\n"))
    True
    >>> bool(output_pattern(["a", "c"]).fullmatch("a\\nb\\nc\\n"))
    False
    >>> bool(output_pattern(["x = ..."]).fullmatch("x = 1\\ny\\n"))
    False
    """
    parts = []
    for line in expected:
        line = line.rstrip()
        if line.strip() == "...":
            parts.append(r"(?:[^\n]*\n)*?")
        else:
            parts.append("[^\\n]*?".join(re.escape(p) for p in line.split("...")) + r"\n")
    return re.compile("".join(parts))


def _is_ellipsis(line: str) -> bool:
    return line.strip() == "..."


def _line_matches(shown: str, real: str) -> bool:
    return bool(re.fullmatch("[^\\n]*?".join(re.escape(p) for p in shown.rstrip().split("...")), real))


def ellipsis_diff(expected: list[str], real: list[str]) -> str:
    """A line diff that knows ``...``: a least-edit alignment in which a ``...`` line absorbs any
    run of real lines at no cost (shown as ``  ...  [N lines]``); ``-`` marks a README line with
    no real counterpart, ``+`` a real line the README lacks.

    >>> print(ellipsis_diff(["a", "...", "x = ... s", "z"], ["a", "b", "c", "x = 1 s", "y"]))
      a
      ...  [2 lines]
      x = ... s
    - z
    + y
    """
    # an edit costs EDIT, a line absorbed by ``...`` costs 1: among least-edit alignments, the one
    # that matches the most lines (absorbs the fewest)
    EDIT = len(real) + 1
    E, R = len(expected), len(real)
    INF = (E + R + 1) * EDIT
    cost = [[INF] * (R + 1) for _ in range(E + 1)]
    cost[0][0] = 0
    for i in range(E + 1):
        for j in range(R + 1):
            if i == j == 0:
                continue
            best = INF
            if i and _is_ellipsis(expected[i - 1]):
                best = cost[i - 1][j]  # the ellipsis ends after real line j - 1
                if j:
                    best = min(best, cost[i][j - 1] + 1)  # ... and absorbs it
            else:
                if i and j and _line_matches(expected[i - 1], real[j - 1]):
                    best = min(best, cost[i - 1][j - 1])
                if i:
                    best = min(best, cost[i - 1][j] + EDIT)
                if j:
                    best = min(best, cost[i][j - 1] + EDIT)
            cost[i][j] = best
    ops, i, j = [], E, R
    while i or j:
        if i and _is_ellipsis(expected[i - 1]):
            k = j
            while k and cost[i][k] != cost[i - 1][k]:
                k -= 1
            ops.append(f"  {expected[i - 1].rstrip()}  [{j - k} lines]")
            i, j = i - 1, k
        elif i and j and _line_matches(expected[i - 1], real[j - 1]) and cost[i][j] == cost[i - 1][j - 1]:
            ops.append(f"  {expected[i - 1].rstrip()}")
            i, j = i - 1, j - 1
        elif j and cost[i][j] == cost[i][j - 1] + EDIT:  # (walking backwards: '-' before '+')
            ops.append(f"+ {real[j - 1]}")
            j -= 1
        else:
            ops.append(f"- {expected[i - 1].rstrip()}")
            i -= 1
    return "\n".join(reversed(ops))


def normalize(out: str) -> str:
    return "".join(line.rstrip() + "\n" for line in out.splitlines())


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """Run ``impactsym ARGV`` in this process: (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(list(argv))
        except SystemExit as exc:  # argparse usage errors
            code = exc.code if isinstance(exc.code, int) else 1
    return code, out.getvalue(), err.getvalue()


COMMANDS = parse_commands(console_blocks(README.read_text(encoding="utf-8")))


def test_the_readme_has_console_blocks_to_check():
    # a parser that silently found nothing would make every check below vacuous
    assert len(console_blocks(README.read_text(encoding="utf-8"))) >= 8
    assert {c.argv[0] for c in COMMANDS} >= {"reproduce", "reflect", "prove", "resolve", "domain", "codegen"}
    assert all(c.expected for c in COMMANDS), [c.text for c in COMMANDS if not c.expected]


@pytest.mark.parametrize("cmd", COMMANDS, ids=[c.id for c in COMMANDS])
def test_console_block_is_the_real_output(cmd: Command):
    code, out, err = run_cli(cmd.argv)
    if cmd.is_error_example:
        want_code, shown, other, other_name = 2, err, out, "stdout"
    else:
        want_code, shown, other, other_name = 0, out, err, "stderr"
    real = normalize(shown)
    problems = []
    if code != want_code:
        problems.append(f"exit status {code}, expected {want_code}")
    if other:
        problems.append(f"unexpected {other_name}:\n{other}")
    if not output_pattern(cmd.expected).fullmatch(real):
        diff = ellipsis_diff(cmd.expected, real.splitlines())
        problems.append("output differs from the README ('-' README only, '+' real only, "
                        f"'...  [N lines]' elided):\n{diff}")
    if problems:
        pytest.fail(f"README.md line {cmd.line}: {cmd.text}\n" + "\n\n".join(problems)
                    + "\n\nfull real output (paste into README.md, '...' where elided or time-dependent):\n"
                    + real, pytrace=False)
