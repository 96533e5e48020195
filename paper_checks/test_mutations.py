"""Every verdict is chosen by a computation: under each mutation it declares, a claim must change
verdict or raise (``paper_checks/mutations.py``). Claims that are definitions, not checkable, or
readings of typography (``judgment``) are the only ones allowed to declare none."""

from __future__ import annotations

import pytest

from paper_checks import framework, mutations
from paper_checks.framework import REGISTRY, Finding, claim, evaluate, load_all

load_all()
IDS = sorted(REGISTRY, key=lambda k: REGISTRY[k].order)
EXEMPT = ("definition", "not-checkable")


def _memo_snapshot() -> dict:
    """The claim findings memoized so far, minus the test's own claim (computed by the original
    functions: a mutation's findings are never memoized past :func:`mutations.applied`)."""
    return {k: v for k, v in framework._MEMO.items() if k[0] in REGISTRY}


def _memo_restore(saved: dict) -> None:
    """Put the findings of :func:`_memo_snapshot` back after a cache clear: the rest of the
    session (``tests/test_cli_reproduce.py``'s audit) reuses them instead of evaluating every
    claim a second time."""
    framework._MEMO.update(saved)


def _needs_mutations(cid: str) -> bool:
    if REGISTRY[cid].expected in EXEMPT:
        return False
    return evaluate(cid).judgment is None


def _declaring(name: str) -> list[str]:
    return [cid for cid in IDS if name in REGISTRY[cid].mutations]


def test_every_decided_claim_declares_a_known_mutation():
    missing = [cid for cid in IDS if _needs_mutations(cid) and not REGISTRY[cid].mutations]
    assert not missing, f"claims whose verdict no mutation is declared to move: {missing}"
    unknown = {(cid, m) for cid in IDS for m in REGISTRY[cid].mutations if m not in mutations.MUTATIONS}
    assert not unknown, f"undeclared mutation names: {sorted(unknown)}"


def test_judgments_are_few_and_say_why():
    judged = [cid for cid in IDS if evaluate(cid).judgment is not None]
    for cid in judged:
        assert evaluate(cid).judgment.strip(), cid
    assert len(judged) <= 12, f"judgments must be few: {judged}"


@pytest.mark.parametrize("name", sorted(mutations.MUTATIONS))
def test_mutation_moves_every_claim_that_declares_it(name):
    ids = _declaring(name)
    assert ids, f"mutation {name!r} is declared by no claim: remove it or use it"
    still = []
    with mutations.applied(name):
        for cid in ids:
            c = evaluate(cid)
            if c.status != "raised" and c.verdict == c.expected:
                still.append(cid)
    assert not still, f"under mutation {name!r} these claims kept their pinned verdict: {still}"
    # the mutation is undone: the claims, computed afresh, are back at their pins
    saved = _memo_snapshot()
    mutations.clear_caches()
    for cid in ids[:3]:
        c = evaluate(cid)
        assert c.status == "ok", (cid, c.verdict, c.error)
    _memo_restore(saved)


def test_the_mutation_test_catches_a_fixed_verdict():
    """A claim that returns a fixed string would keep its verdict under its mutation: detected."""

    @claim("test-fixed", paper="seghete-murphey", ref="sec. II-A", quantity="fixed", expect="erratum",
           mutations=("reflection_map",))
    def _fixed():
        return Finding("erratum", "x", corrected="y")

    try:
        with mutations.applied("reflection_map"):
            c = evaluate("test-fixed")
        assert c.status == "ok" and c.verdict == "erratum"  # unmoved: the parametrized test would fail
    finally:
        del REGISTRY["test-fixed"]
        saved = _memo_snapshot()
        mutations.clear_caches()
        _memo_restore(saved)


# `assert` in claim modules (stripped by python -O) is refused by tests/test_no_assert.py.


def test_caches_kept_across_mutations_call_sympy_alone():
    """``clear_caches`` keeps the caches marked ``sympy_only``. Each must be a memo of SymPy alone:
    its function reads no global but the ``sp`` module (so no mutated function of ours can run
    inside it); every other cache is cleared."""
    import sys

    import sympy as sp

    from derivations import memo
    from impactsym.arithmetic import remembered
    from impactsym.laws.delassus import _tidy_remembered, tidy

    kept = [v for name, mod in list(sys.modules.items()) if mod is not None and mutations._in_scope(name)
            for v in vars(mod).values() if callable(getattr(v, "cache_clear", None)) and getattr(v, "sympy_only", False)]
    # derivations.memo simplifies through the first; the derivations and paper checks solve
    # through the others
    assert set(kept) == {remembered._simplify_cached, remembered._solveset_cached, remembered._solve_cached}
    for cache in kept:
        code = cache.__wrapped__.__code__
        assert set(code.co_names) <= {"sp", "simplify", "solveset", "solve"} and not code.co_freevars, (cache, code.co_names)
    saved = _memo_snapshot()
    memo.simplify(sp.Symbol("kept") * 2 / 3)
    tidy(sp.sqrt(8) / 3)
    mutations.clear_caches()
    assert remembered._simplify_cached.cache_info().currsize >= 1 and _tidy_remembered.cache_info().currsize == 0
    _memo_restore(saved)
