"""``impactsym reproduce``: the audit of both papers, end to end.

Every claim of ``paper_checks/`` (every numbered equation, unnumbered display, numeric example and
stated property of Seghete & Murphey and of Acary & Taha) is evaluated, together with the
single-impact derivation of ``G_u`` and its machine-checked properties, and the high-precision
cross-check of the numeric solvers (exact vs float path vs generated kernels): all of it by
:func:`paper_checks.run_audit`, the one function this module calls; it only renders the result.

Output: a table grouped by paper and section with counts per verdict; ``--json`` prints one object
``{"claims": [...], "summary": {...}}``; ``--report DIR`` also writes ``DIR/report.md`` (the same
content, every erratum's corrected form typeset, and the regenerated Fig. 3).

Exit status: 0 when every claim was evaluated and reached its pinned verdict and every cross-check
is within its bound (errata are findings, not failures); 1 when a check raised, a verdict differs
from the one pinned in ``paper_checks/``, or a cross-check fails.

SymPy's cache: unless ``SYMPY_CACHE_SIZE`` is set in the environment, the audit runs with an
unbounded SymPy cache (``SYMPY_CACHE_SIZE=none``, set in this process before SymPy is imported and
inherited by the forked workers; :func:`use_audit_sympy_cache`). It spares the evictions and the
bookkeeping of SymPy's default 1000-entry cache: about 0.7 s of the audit's CPU, for some 10 MB of
memory. Set the variable to choose otherwise (``SYMPY_CACHE_SIZE=1000`` is SymPy's default).

The garbage collector: the audit collects cyclic garbage less often than CPython's default
(:data:`AUDIT_GC_THRESHOLDS`, set for the audit and put back after it; :func:`audit_gc_thresholds`).
Nothing is left uncollected: only the collections, each a walk of the audit's large heap of
long-lived objects (SymPy's cache, the claims' memo), are fewer.
"""

from __future__ import annotations

from collections import OrderedDict
from contextlib import contextmanager
from pathlib import Path

from .common import add_json_flag, writable_dir

PAPER_ORDER = ("seghete-murphey", "acary-taha")


def register(sub) -> None:
    p = sub.add_parser(
        "reproduce",
        help="audit both papers: every equation, display, example and claim, with verdicts",
        description="Evaluate every claim of paper_checks/ (both papers), the G_u derivation and proofs, and "
                    "the high-precision cross-check of the numeric solvers.",
    )
    p.add_argument("--paper", choices=PAPER_ORDER, help="audit one paper only")
    p.add_argument("--report", metavar="DIR", help="also write DIR/report.md (and the figures) ")
    p.add_argument("-j", "--jobs", metavar="N",
                   help="evaluate the claims on N processes (default: the CPUs this process may use; 1 = serial, "
                        "in this process); the records are the same for every N")
    add_json_flag(p)
    p.set_defaults(func=run)


def default_jobs() -> int:
    """The CPUs this process may use (its affinity mask where the OS has one)."""
    import os

    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - no affinity on this OS
        return max(1, os.cpu_count() or 1)


def jobs_arg(text: str | None) -> int:
    """``--jobs``: a positive integer (checked before the work), the CPU count when not given.

    >>> jobs_arg("3"), jobs_arg(None) >= 1
    (3, True)
    """
    from ..errors import ImpactInputError

    if text is None:
        return default_jobs()
    try:
        n = int(text)
    except ValueError:
        raise ImpactInputError("jobs", f"must be a positive integer, got {text!r}") from None
    if n < 1:
        raise ImpactInputError("jobs", f"must be a positive integer, got {text!r}")
    return n


class AuditOutput(dict):
    """What :func:`run` returns: the JSON object ``{"claims": [...], "summary": {...}}`` that
    ``--json`` prints, carrying the :class:`paper_checks.AuditResult` it was made from (paper titles,
    verdict order, section order) for the text and Markdown renderings."""

    def __init__(self, audit):
        super().__init__(audit.as_dict())
        self.audit = audit


#: SymPy's cache size for the audit (``SYMPY_CACHE_SIZE``, read once when SymPy is imported): the
#: audit meets the same subexpressions in many claims, and an unbounded cache (``none``) spares
#: both the evictions of SymPy's default 1000-entry LRU cache and its bookkeeping (measured: about
#: 5-8 % of the audit's CPU). The process ends with the audit, so the cache's growth is bounded by it.
AUDIT_SYMPY_CACHE_SIZE = "none"


#: the garbage collector's thresholds for the audit (``gc.set_threshold``): a generation-0 pass
#: every 50,000 net container allocations instead of 700, and full passes a tenth as often as
#: generation-1 ones (CPython's default is (700, 10, 10)). The audit allocates millions of
#: short-lived SymPy objects beside a heap of long-lived ones (SymPy's cache, the claims' memo) that
#: the default thresholds walk again and again. Measured on ``reproduce -j 1`` (``gc.callbacks``
#: timing every collection, two runs each): 660 collections took 0.41-0.43 s with the defaults, 21
#: took 0.23-0.25 s with these, of about 6 s of CPU. The test process collects with the same
#: thresholds (``conftest.py``).
AUDIT_GC_THRESHOLDS = (50_000, 20, 100)


@contextmanager
def audit_gc_thresholds():
    """Collect cyclic garbage at :data:`AUDIT_GC_THRESHOLDS` inside the block (the audit, its forked
    workers inherit them), and at the thresholds found on entry after it, however it ends.

    >>> import gc
    >>> before = gc.get_threshold()
    >>> with audit_gc_thresholds():
    ...     gc.get_threshold() == AUDIT_GC_THRESHOLDS
    True
    >>> gc.get_threshold() == before
    True
    """
    import gc

    saved = gc.get_threshold()
    gc.set_threshold(*AUDIT_GC_THRESHOLDS)
    try:
        yield
    finally:
        gc.set_threshold(*saved)


def use_audit_sympy_cache() -> bool:
    """Set ``SYMPY_CACHE_SIZE`` to :data:`AUDIT_SYMPY_CACHE_SIZE` for this process (and the audit's
    forked workers), unless the user set it or SymPy is already imported (then the setting could
    not take effect, and nothing is changed). Returns whether it was set.

    Once SymPy is imported it is too late:

    >>> import sympy
    >>> use_audit_sympy_cache()
    False
    """
    import os
    import sys

    if "SYMPY_CACHE_SIZE" in os.environ or "sympy" in sys.modules:
        return False
    os.environ["SYMPY_CACHE_SIZE"] = AUDIT_SYMPY_CACHE_SIZE
    return True


def run(args):
    use_audit_sympy_cache()  # before paper_checks imports SymPy
    report_dir = writable_dir(args.report, "report")  # checked before the 1-2 minute audit
    jobs = jobs_arg(args.jobs)
    with audit_gc_thresholds():  # its imports (SymPy, the derivations) and the audit
        from paper_checks import run_audit

        audit = run_audit(args.paper, jobs=jobs)
    result = AuditOutput(audit)
    if report_dir is not None:
        result["summary"]["report"] = str(write_report(result, report_dir))
    return result, (0 if audit.ok else 1)


# --------------------------------------------------------------------------- text
def verdict_table(summary: dict) -> str:
    """The README's verdict table (Markdown), from a run's ``summary``: one row per paper and a
    total, one column per verdict. ``tests/test_readme_verdicts.py`` checks the README against it.
    """
    verdicts = tuple(summary["per_verdict"])  # the audit's verdict order
    rows = ["| paper | claims | " + " | ".join(verdicts) + " |", "|---|---|" + "---|" * len(verdicts)]
    for paper, pp in summary["per_paper"].items():
        rows.append(f"| {paper} | {pp['claims']} | " + " | ".join(str(pp[v]) for v in verdicts) + " |")
    rows.append(f"| **total** | **{summary['claims']}** | "
                + " | ".join(str(summary["per_verdict"][v]) for v in verdicts) + " |")
    return "\n".join(rows)


def _short(s, width):
    s = "" if s is None else str(s).replace("\n", " ")
    return s if len(s) <= width else s[: width - 1] + "…"


def _grouped(result):
    """Claims grouped by paper, then by section in the paper's reading order (registration order inside)."""
    audit = result.audit
    groups = OrderedDict()
    for paper in audit.papers:
        cs = [c for c in result["claims"] if c["paper"] == paper]
        for c in sorted(cs, key=lambda c: audit.section_rank(paper, c["section"])):
            groups.setdefault(paper, OrderedDict()).setdefault(c["section"], []).append(c)
    return groups


def render(result: AuditOutput) -> str:
    PAPERS, VERDICTS = result.audit.papers, result.audit.verdicts
    s = result["summary"]
    out = []
    for paper, sections in _grouped(result).items():
        out.append(f"{PAPERS[paper]}")
        out.append("=" * min(100, len(PAPERS[paper])))
        for section, cs in sections.items():
            out.append(f"  {section}")
            for c in cs:
                flag = "" if c["status"] == "ok" else f"  [{c['status'].upper()}: pinned {c['expected']}]"
                if c.get("judgment"):
                    flag = "  (judgment)" + flag
                out.append(f"    {c['verdict'] or 'ERROR':<29} {_short(c['ref'], 22):<22} {_short(c['quantity'], 52)}{flag}")
        pp = s["per_paper"][paper]
        out.append("  counts: " + ", ".join(f"{v} {pp[v]}" for v in VERDICTS if pp[v]) + f"  (total {pp['claims']})")
        out.append("")
    out.append("G_u derivation (Seghete & Murphey eqs. 1a-1b) and properties, machine-checked:")
    for d in s["G_u_derivation"]["derivations"]:
        out.append(f"  {d['law']:<30} n={d['dimension']}: lambda matches print {d['lambda_matches_printed']}, "
                   f"G matches print {d['G_matches_printed']}")
    by_name = OrderedDict()
    for p in s["G_u_derivation"]["properties"]:
        by_name.setdefault(p["name"], []).append(p)
    for name, ps in by_name.items():
        dims = ", ".join(f"n={p['dimension']} {'proven' if p['proven'] else 'NOT PROVEN'}" for p in ps)
        out.append(f"  {name:<40} {dims}")
    out.append("")
    out.append(f"Cross-check of the numeric solvers (exact vs float path vs generated kernels, {s['crosscheck']['digits']} digits):")
    for e in s["crosscheck"]["examples"]:
        errs = ", ".join(f"{k.replace('_error', '')} {e[k]:.1e}" for k in ("float_path_error", "kernel_error", "mpmath_error")
                         if e[k] is not None)
        out.append(f"  {'ok ' if e['ok'] else 'FAIL'} {e['example']:<42} {errs}  (bound {e['bound']:.1e})")
    out.append("")
    out.append("Totals: " + ", ".join(f"{v} {n}" for v, n in s["per_verdict"].items() if n) + f"  ({s['claims']} claims, "
               f"{s['seconds']} s)")
    out.append("Evidence: " + ", ".join(f"{k} {n}" for k, n in s["per_evidence_kind"].items())
               + f"; (judgment) marks a reading of typography, {len(s['judgments'])} claims (reasons in --json)")
    if s["raised"]:
        out.append(f"RAISED: {s['raised']}")
    if s["verdict_differs"]:
        out.append(f"VERDICT DIFFERS FROM PIN: {s['verdict_differs']}")
    out.append("audit ok" if s["ok"] else "audit FAILED")
    if s.get("report"):
        out.append(f"report written to {s['report']}")
    return "\n".join(out)


# --------------------------------------------------------------------------- Markdown report
def _md_escape(s) -> str:
    return ("" if s is None else str(s)).replace("|", "\\|").replace("\n", " ")


def write_report(result: AuditOutput, outdir: Path) -> Path:
    """Write ``outdir/report.md`` (and ``outdir/fig3.png``); return the report's path."""
    PAPERS = result.audit.papers
    outdir.mkdir(parents=True, exist_ok=True)
    figs = []
    try:
        from impactsym.domains import plot_domain

        plot_domain("pi/4", outdir / "fig3.png")
        figs.append(("Acary & Taha, Figure 3: valid domain of (α₁₂, e) for θ = π/4, regenerated by "
                     "`impactsym.domains.plot_domain`", "fig3.png"))
    except Exception as exc:  # a figure is optional; its absence is stated
        figs.append((f"Figure 3 could not be drawn: {exc}", None))
    s = result["summary"]
    L = ["# impactsym reproduce: audit of both papers", ""]
    L.append(f"{s['claims']} claims; " + ", ".join(f"{v}: {n}" for v, n in s["per_verdict"].items() if n) +
             f". Audit {'ok' if s['ok'] else 'FAILED'} ({s['seconds']} s).")
    L += ["", verdict_table(s)]
    for paper, sections in _grouped(result).items():
        L += ["", f"## {PAPERS[paper]}", ""]
        for section, cs in sections.items():
            L += [f"### {section}", "", "| id | ref | quantity | verdict | note |", "|---|---|---|---|---|"]
            for c in cs:
                L.append(f"| `{c['id']}` | {_md_escape(c['ref'])} | {_md_escape(c['quantity'])} | **{c['verdict']}**{' (judgment)' if c.get('judgment') else ''} | "
                         f"{_md_escape(c['note'])} |")
            L.append("")
    L += ["## Errata and their corrections", ""]
    for c in result["claims"]:
        if c["verdict"] != "erratum":
            continue
        L.append(f"### `{c['id']}` ({c['paper']}, {c['ref']}): {c['quantity']}")
        L.append("")
        L.append(f"Published: `{_md_escape(c['published'])}`")
        L.append("")
        corr = c["corrected_latex"] or c["corrected"]
        if isinstance(corr, str) and any(ch in corr for ch in "\\^_{}"):
            L.append(f"Corrected: $${corr}$$")
        else:
            L.append(f"Corrected: {corr}")
        L.append("")
        L.append(f"Proof: {c['note']}")
        L.append("")
    L += ["## Refuted statements", ""]
    for c in result["claims"]:
        if c["verdict"] == "refuted":
            L.append(f"- `{c['id']}` ({c['paper']}, {c['ref']}): {c['quantity']}. {c['note']}")
    L += ["", "## Cross-check of the numeric solvers", "",
          "| example | float path error | kernel error | mpmath error | bound | ok |", "|---|---|---|---|---|---|"]
    for e in s["crosscheck"]["examples"]:
        f = lambda x: "—" if x is None else f"{x:.2e}"  # noqa: E731
        L.append(f"| {e['example']} | {f(e['float_path_error'])} | {f(e['kernel_error'])} | {f(e['mpmath_error'])} | "
                 f"{f(e['bound'])} | {e['ok']} |")
    L += ["", "## Figures", ""]
    for caption, path in figs:
        L.append(f"![{caption}]({path})" if path else caption)
        L.append("")
    L += ["## G_u derivation and proofs", ""]
    for d in s["G_u_derivation"]["derivations"]:
        L.append(f"- {d['law']}, n = {d['dimension']}: λ matches the print {d['lambda_matches_printed']}, "
                 f"G matches the print {d['G_matches_printed']}")
    for p in s["G_u_derivation"]["properties"]:
        L.append(f"- {p['name']} (n = {p['dimension']}): {'proven' if p['proven'] else 'NOT proven'}")
    path = outdir / "report.md"
    path.write_text("\n".join(L) + "\n")
    return path
