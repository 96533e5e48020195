"""The whole audit of both papers as one call: :func:`run_audit` evaluates every claim, the
single-impact derivation of ``G_u`` with its machine-checked properties, and the cross-check of the
numeric solvers, and returns an :class:`AuditResult`. ``impactsym reproduce`` only renders it.

Examples
--------
>>> counts = count_verdicts([])
>>> counts["claims"], dict(counts["per_paper"]), counts["per_verdict"]["erratum"]
(0, {}, 0)
"""

from __future__ import annotations

import time
from collections import Counter, OrderedDict
from dataclasses import dataclass, field

from .framework import PAPERS, VERDICTS, Claim, evaluate_all, section_of, section_rank

__all__ = ["PAPER_ORDER", "AuditResult", "run_audit", "count_verdicts", "derivation_summary"]

#: the papers in the order the audit reports them
PAPER_ORDER = ("seghete-murphey", "acary-taha")


@dataclass
class AuditResult:
    """One run of the audit.

    Attributes
    ----------
    claims : the evaluated :class:`~paper_checks.framework.Claim` records, in registration order
    summary : counts per paper, per verdict and per evidence kind, the judgments, the claims that
        raised or reached another verdict than the pinned one, the cross-check (``crosscheck``), the
        ``G_u`` derivation summary (``G_u_derivation``), ``all_evaluated``, ``ok`` and ``seconds``
    papers : paper id -> title, in :data:`PAPER_ORDER`
    verdicts : the verdict vocabulary, in reporting order
    """

    claims: list
    summary: dict
    papers: dict = field(default_factory=lambda: {p: PAPERS[p] for p in PAPER_ORDER})
    verdicts: tuple = VERDICTS

    @property
    def ok(self) -> bool:
        """Every claim evaluated and reached its pinned verdict, every cross-check within its bound,
        every ``G_u`` property proved."""
        return bool(self.summary["ok"])

    def as_dict(self) -> dict:
        """The JSON form ``{"claims": [...], "summary": {...}}`` (the summary is shared, not copied)."""
        return {"claims": [c.as_dict() for c in self.claims], "summary": self.summary}

    def section_rank(self, paper: str, section: str) -> int:
        """Position of ``section`` in ``paper``'s reading order (unknown sections last)."""
        return section_rank(paper, section)


def count_verdicts(claims: list[Claim]) -> dict:
    """``claims``, ``per_paper`` and ``per_verdict`` counts of evaluated claims (papers in
    :data:`PAPER_ORDER`, verdicts in :data:`paper_checks.framework.VERDICTS` order)."""
    per_paper = OrderedDict()
    for paper in PAPER_ORDER:
        cs = [c for c in claims if c.paper == paper]
        if not cs:
            continue
        counts = Counter(c.verdict for c in cs if c.verdict)
        per_paper[paper] = {"claims": len(cs), **{v: counts.get(v, 0) for v in VERDICTS}}
    totals = Counter(c.verdict for c in claims if c.verdict)
    return {"claims": len(claims), "per_paper": per_paper, "per_verdict": {v: totals.get(v, 0) for v in VERDICTS}}


def derivation_summary() -> dict:
    """The single-impact derivation (Seghete & Murphey eqs. 1a–1b) for n = 2, 3, and every
    property of ``G_u`` for n = 2, 3 and general n (the proofs the claims use, memoized)."""
    from derivations.reflection import PROPERTIES, derive_restitution, derive_single_impact

    from .seghete_murphey import _proof

    derivations = []
    for n in (2, 3):
        d = derive_single_impact(n)
        derivations.append({"law": "G_u (elastic, eqs. 1a-1b)", "dimension": n,
                            "lambda_matches_printed": bool(d.matches_printed_lambda),
                            "G_matches_printed": bool(d.matches_printed_G),
                            "discarded_roots": [str(r) for r, _ in d.discarded_roots]})
        r = derive_restitution(n)
        derivations.append({"law": "G_u(e) (Newton restitution)", "dimension": n,
                            "lambda_matches_printed": bool(r.matches_printed_lambda),
                            "G_matches_printed": bool(r.matches_printed_G),
                            "energy_loss_matches": bool(r.matches_printed_energy_loss)})
    proofs = []
    for name in PROPERTIES:
        for dim in (2, 3, "n"):
            p = _proof(name, dim)
            proofs.append({"name": p.name, "dimension": p.dimension, "proven": bool(p.proven),
                           "seconds": round(p.seconds, 4)})
    ok = all(p["proven"] for p in proofs) and all(d["lambda_matches_printed"] and d["G_matches_printed"]
                                                 for d in derivations)
    return {"derivations": derivations, "properties": proofs, "all_proven": ok}


# --------------------------------------------------------------------------- processes
def _task(task):
    """One unit of work of a worker process: a list of claim ids, and with them the ``G_u``
    derivation summary and/or the cross-check when the task carries them."""
    ids, with_derivation, with_crosscheck = task
    from .framework import evaluate

    claims = [evaluate(cid).rendered_copy() for cid in ids]
    derivation = derivation_summary() if with_derivation else None
    if with_crosscheck:
        from .crosscheck import run_crosschecks

        cross = run_crosschecks()
    else:
        cross = None
    return claims, derivation, cross


def _groups(paper: str | None) -> list[list[str]]:
    """The claim ids in registration order, cut where the section changes: claims of one section
    share their derivations (one worker computes them once)."""
    from .framework import REGISTRY, load_all

    load_all()
    groups: list[list[str]] = []
    last = None
    for r in sorted(REGISTRY.values(), key=lambda r: r.order):
        if paper is not None and r.paper != paper:
            continue
        key = (r.paper, section_of(r.ref, r.paper))
        if key != last:
            groups.append([])
            last = key
        groups[-1].append(r.id)
    return groups


def _tasks(paper: str | None, jobs: int) -> tuple[list[list[str]], list[tuple]]:
    """The section groups and the worker tasks ``(claim ids, with the G_u derivation, with the
    cross-check)``, largest first.

    Claims of one paper share memoized derivations across sections (the G_u derivation of
    Seghete & Murphey sec. II-A is used again in sec. III; the pool closed forms of Acary & Taha
    sec. 4 again in sec. 5), and a worker computes a shared derivation once for every claim it
    evaluates. So with ``jobs`` up to the number of papers, each paper is one task (Seghete &
    Murphey's with the G_u derivation summary, which reuses the same derivations; Acary & Taha's
    with the cross-check): ``-j 2`` then costs about the CPU of ``-j 1``. With more processes
    than papers, the section groups are the tasks (more parallel, some derivations computed in
    more than one worker).
    """
    groups = _groups(paper)
    from .framework import REGISTRY

    papers = [p for p in PAPER_ORDER if paper in (None, p)]
    if jobs <= len(papers):
        by_paper = {p: [cid for g in groups for cid in g if REGISTRY[cid].paper == p] for p in papers}
        tasks = [(by_paper[p], p == "seghete-murphey", p == "acary-taha") for p in papers]
        if paper == "seghete-murphey":
            tasks.append(([], False, True))
        elif paper == "acary-taha":
            tasks.append(([], True, False))
    else:
        tasks = [([], True, False), ([], False, True)] + [(g, False, False) for g in groups]
    tasks.sort(key=lambda t: -len(t[0]))
    return groups, tasks


def _run_parallel(paper: str | None, jobs: int):
    import multiprocessing

    groups, tasks = _tasks(paper, jobs)
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    by_id, derivation, cross = {}, None, None
    # a Pool's exit terminates its workers: an exception here (--timeout's) stops them at once
    with multiprocessing.get_context(method).Pool(min(jobs, len(tasks))) as pool:
        for claims, d, c in pool.imap_unordered(_task, tasks):
            by_id.update((cl.id, cl) for cl in claims)
            derivation = d if d is not None else derivation
            cross = c if c is not None else cross
    claims = [by_id[cid] for g in groups for cid in g]
    return claims, derivation, cross


def run_audit(paper: str | None = None, jobs: int = 1) -> AuditResult:
    """Evaluate every claim (of one paper, or both), the ``G_u`` derivation and proofs, and the
    cross-check of the numeric solvers: the public entry point of ``impactsym reproduce``.

    Parameters
    ----------
    paper : ``"seghete-murphey"``, ``"acary-taha"`` or None (both)
    jobs : number of processes. With ``jobs > 1`` the claims are evaluated on that many worker
        processes (each paper's claims together while ``jobs`` is at most the number of papers, so
        that they share their derivations; else each section's), and so are the ``G_u``
        derivation and the cross-check; the records are the same as a serial
        run's, in registration order (each is rendered to JSON in the process that evaluated it).

    Returns
    -------
    AuditResult
        ``ok`` is False when a claim raised, a verdict differs from its pin, a cross-check left its
        bound, or a ``G_u`` property was not proved.

    Raises
    ------
    ValueError
        an unknown paper.
    """
    if paper is not None and paper not in PAPER_ORDER:
        raise ValueError(f"paper: unknown {paper!r}; known: {', '.join(PAPER_ORDER)}")
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs: must be a positive integer, got {jobs!r}")
    from .crosscheck import run_crosschecks

    t0 = time.perf_counter()
    if jobs == 1:
        claims = evaluate_all(paper)
        derivation = derivation_summary()
        cross = run_crosschecks()
    else:
        claims, derivation, cross = _run_parallel(paper, jobs)
    seconds = time.perf_counter() - t0

    counted = count_verdicts(claims)
    raised = [c.id for c in claims if c.status == "raised"]
    differs = [c.id for c in claims if c.status == "verdict-differs"]
    ok = not raised and not differs and cross["ok"] and derivation["all_proven"]
    kinds = Counter(c.evidence_kind for c in claims if c.evidence_kind)
    summary = {
        "claims": len(claims),
        "per_paper": counted["per_paper"],
        "per_verdict": counted["per_verdict"],
        "per_evidence_kind": dict(sorted(kinds.items())),
        "judgments": [c.id for c in claims if c.judgment is not None],
        "raised": raised,
        "verdict_differs": differs,
        "crosscheck": cross,
        "G_u_derivation": derivation,
        "all_evaluated": not raised,
        "ok": ok,
        "seconds": round(seconds, 2),
    }
    return AuditResult(claims, summary)
