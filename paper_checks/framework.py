"""The claim framework of the paper audit: one record per published item, and the checks that
decide its verdict.

A *claim* is one item that a paper states: a numbered equation, an unnumbered display, a numeric
example, or a statement that something holds. Each claim is a function in
``paper_checks/<paper>.py``, registered with :func:`claim`, that *computes* its record: it
transcribes the published form (misprints included), asks impactsym for the derived form, and
decides the verdict with the checks below (symbolic identity, decimal comparison at ≥ 50 digits,
conservation laws, extremum tests). The verdict each claim is expected to reach is pinned in the
decorator, so that a regression in the package, or in the check, changes a verdict and fails
both ``pytest`` and ``impactsym reproduce``.

Verdicts
--------
``exact-match``
    The published form equals the derived one (proved symbolically, or exactly for numbers).
``match-at-published-precision``
    Published decimals agree with the derived value at the printed precision (the note says
    whether by rounding or by truncation).
``convention-difference``
    Equal after a stated mapping of conventions (the note explains it).
``supported-by-samples``
    Agreement that was *sampled*, not proved: a symbolic identity checked exactly at random
    rational points (simplify did not close it), a statement checked at a few angles or masses, or
    an ODE integration. The note says what was sampled and how many points.
``erratum``
    The published form is wrong; ``corrected`` holds the right form and the check proves it.
``refuted``
    The statement is false: a counterexample or a violated law is given.
``definition``
    A definition: nothing to check, recorded so that nothing is silently passed over.
``not-checkable``
    Cannot be checked (the note says why).

Examples
--------
>>> import sympy as sp
>>> x = sp.Symbol("x", positive=True)
>>> identical(sp.sin(x)**2 + sp.cos(x)**2, 1).equal
True
>>> compare_decimal(sp.Rational(2, 3), "0.67")["agreement"]
'rounding'
>>> compare_decimal(sp.Rational(2, 3), "0.66")["agreement"]
'truncation'
"""

from __future__ import annotations

import random
import time
import traceback
from dataclasses import dataclass, field
from decimal import ROUND_DOWN, ROUND_HALF_EVEN, Decimal, localcontext
from typing import Any, Callable

import mpmath
import sympy as sp

from derivations.memo import simplify
from impactsym.arithmetic.remembered import solve_remembered

__all__ = [
    "VERDICTS", "EVIDENCE_KINDS", "PAPERS", "DIGITS", "Finding", "Claim", "Registered", "REGISTRY", "claim",
    "evaluate", "evaluate_all", "identical", "Identity", "Inconclusive", "compare_decimal", "compare_decimals",
    "conservation", "extremum", "text",
]

VERDICTS = (
    "exact-match",
    "match-at-published-precision",
    "convention-difference",
    "supported-by-samples",
    "erratum",
    "refuted",
    "definition",
    "not-checkable",
)

PAPERS = {
    "seghete-murphey": "Seghete & Murphey, Variational Solutions to Simultaneous Collisions Between "
    "Multiple Rigid Bodies",
    "acary-taha": "Acary & Taha, Concurrent Multiple Impacts in Rigid Bodies: Formulation and Simulation",
}

#: how a verdict was reached (``Claim.evidence_kind``):
#:
#: ``proof``      symbolic identity (``simplify(a - b) == 0``, structural rewriting) or exact
#:                arithmetic on rationals and algebraic numbers (minimal polynomials);
#: ``certified``  interval (Arb / rigorous ``evalf``) enclosures that exclude the other verdict;
#: ``decimal``    published decimals compared with the exact value at ``DIGITS`` digits;
#: ``samples``    exact evaluation at sampled points, or an integration: evidence, not proof;
#: ``judgment``   a reading of typography (a label, a name, a signature), with its reason;
#: ``definition`` nothing to decide;  ``none``  not checkable.
EVIDENCE_KINDS = ("proof", "certified", "decimal", "samples", "judgment", "definition", "none")

#: working precision of every decimal comparison and every numerical identity fallback
DIGITS = 50


# --------------------------------------------------------------------------- records
@dataclass
class Finding:
    """What a claim function returns: the evidence and the verdict it reached.

    ``published`` is the faithful transcription as text; ``published_expr`` the same as a SymPy
    object where it is a formula. ``derived`` is what impactsym computed (a SymPy object or a
    plain value), never retyped. ``corrected`` is required for an erratum.
    """

    verdict: str
    published: str
    derived: Any = None
    published_expr: Any = None
    corrected: Any = None
    note: str = ""
    digits: int | None = None
    evidence: dict = field(default_factory=dict)
    #: the reason, when the verdict is a reading of typography rather than a computation
    judgment: str | None = None
    #: one of :data:`EVIDENCE_KINDS`; inferred when not given (see :meth:`kind`)
    evidence_kind: str | None = None

    def __post_init__(self):
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict: must be one of {VERDICTS}, got {self.verdict!r}")
        if self.verdict == "erratum" and self.corrected is None:
            raise ValueError("corrected: an erratum needs the corrected form")
        if self.judgment is not None and not str(self.judgment).strip():
            raise ValueError("judgment: a judgment needs its reason")
        if self.evidence_kind is not None and self.evidence_kind not in EVIDENCE_KINDS:
            raise ValueError(f"evidence_kind: must be one of {EVIDENCE_KINDS}, got {self.evidence_kind!r}")
        if self.verdict == "supported-by-samples" and self.kind() != "samples":
            raise ValueError("evidence_kind: supported-by-samples rests on samples")
        if self.kind() == "samples" and self.verdict == "exact-match":
            raise ValueError("verdict: exact-match means proved; sampled agreement is supported-by-samples")

    def kind(self) -> str:
        """The evidence kind: explicit, else inferred from the verdict, the judgment and ``digits``."""
        if self.evidence_kind is not None:
            return self.evidence_kind
        if self.judgment is not None:
            return "judgment"
        if self.verdict == "definition":
            return "definition"
        if self.verdict == "not-checkable":
            return "none"
        if self.verdict == "supported-by-samples":
            return "samples"
        if self.digits is not None:
            return "decimal"
        return "proof"


@dataclass
class Claim:
    """The full record of one claim, as reported by ``impactsym reproduce``."""

    id: str
    paper: str
    ref: str
    quantity: str
    expected: str
    verdict: str | None = None
    published: str = ""
    published_expr: Any = None
    derived: Any = None
    corrected: Any = None
    note: str = ""
    digits: int | None = None
    evidence: dict = field(default_factory=dict)
    judgment: str | None = None
    evidence_kind: str | None = None
    status: str = "ok"  # ok | verdict-differs | raised
    error: str = ""
    seconds: float = 0.0
    #: the JSON record, rendered where the claim was evaluated (set by :meth:`rendered_copy`)
    rendered: dict | None = None

    @property
    def section(self) -> str:
        return section_of(self.ref, self.paper)

    def rendered_copy(self) -> "Claim":
        """A copy that carries its JSON record (:meth:`as_dict`, rendered here) in place of the SymPy
        objects: what a worker process of ``reproduce -j N`` sends back (plain strings pickle
        cheaply and always; the record is the one a serial run prints)."""
        return Claim(self.id, self.paper, self.ref, self.quantity, self.expected, self.verdict, self.published,
                     note=self.note, digits=self.digits, judgment=self.judgment, evidence_kind=self.evidence_kind,
                     status=self.status, error=self.error, seconds=self.seconds, rendered=self.as_dict())

    def as_dict(self) -> dict:
        if self.rendered is not None:
            return dict(self.rendered)
        return {
            "id": self.id, "paper": self.paper, "ref": self.ref, "section": self.section,
            "quantity": self.quantity, "published": self.published,
            "published_expr": text(self.published_expr), "derived": text(self.derived),
            "verdict": self.verdict, "expected": self.expected,
            "corrected": text(self.corrected),
            "corrected_latex": latex(self.corrected),
            "note": self.note, "digits": self.digits,
            "precision": "exact" if self.digits is None else f"{self.digits} digits",
            "evidence": {k: text(v) for k, v in self.evidence.items()},
            "judgment": self.judgment is not None, "judgment_reason": self.judgment,
            "evidence_kind": self.evidence_kind,
            "status": self.status, "error": self.error, "seconds": round(self.seconds, 4),
        }


def text(obj) -> Any:
    """A JSON-friendly text form: SymPy objects in ``str`` form, containers recursively."""
    if obj is None or isinstance(obj, (bool, int, str)):
        return obj
    if isinstance(obj, float):
        return obj
    if isinstance(obj, dict):
        return {str(k): text(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [text(x) for x in obj]
    if isinstance(obj, sp.MatrixBase):
        return [[str(x) for x in obj.row(i)] for i in range(obj.rows)]
    return str(obj)


def latex(obj) -> str | None:
    if obj is None:
        return None
    if isinstance(obj, str):
        return obj
    if isinstance(obj, dict):
        return ", \\quad ".join(f"{k} = {latex(v)}" for k, v in obj.items())
    if isinstance(obj, (list, tuple)):
        return ", ".join(latex(x) for x in obj)
    try:
        return sp.latex(obj)
    except Exception:  # pragma: no cover - a non-SymPy object
        return str(obj)


#: the section of every numbered equation, in each paper's own numbering (for grouping)
EQUATION_SECTIONS = {
    "seghete-murphey": {"1a": "sec. II-A", "1b": "sec. II-A", "2a": "sec. II-B", "2b": "sec. II-B", "3": "sec. III-A",
                        "4": "sec. III-B.2", "5": "sec. III-C", "6a": "sec. III-C", "6b": "sec. III-C"},
    "acary-taha": {**{str(k): "sec. 2.1" for k in range(1, 9)}, **{str(k): "sec. 2.2" for k in range(9, 13)},
                   **{str(k): "sec. 3.2" for k in range(13, 17)}, **{str(k): "sec. 3.3" for k in range(17, 20)},
                   **{str(k): "sec. 3.4" for k in range(20, 24)}, **{str(k): "sec. 4.1" for k in range(24, 27)},
                   **{str(k): "sec. 4.1.1" for k in range(27, 35)}, **{str(k): "sec. 4.2" for k in range(35, 38)},
                   **{str(k): "sec. 5" for k in range(38, 42)}, **{str(k): "sec. 5.1" for k in range(42, 44)},
                   **{str(k): "sec. 5.2" for k in range(44, 46)}},
}

#: the sections of each paper in reading order
SECTION_ORDER = {
    "seghete-murphey": ["sec. II-A", "sec. II-B", "sec. II-C.1", "sec. II-C.2", "sec. III-A", "sec. III-B",
                        "sec. III-B.1", "sec. III-B.2", "sec. III-B.3", "sec. III-C", "sec. IV-B"],
    "acary-taha": ["sec. 2.1", "sec. 2.2", "sec. 3.2", "sec. 3.3", "sec. 3.4", "sec. 4.1", "sec. 4.1.1", "sec. 4.2",
                   "sec. 5", "sec. 5.1", "sec. 5.2"],
}


def section_of(ref: str, paper: str | None = None) -> str:
    """The section a reference lives in, for grouping: ``sec. X`` refs name it; ``eq. N`` refs are
    looked up in :data:`EQUATION_SECTIONS`.

    >>> section_of("sec. III-B.3"), section_of("eq. 18", "acary-taha"), section_of("eq. 1a", "seghete-murphey")
    ('sec. III-B.3', 'sec. 3.3', 'sec. II-A')
    """
    if ref.startswith("sec."):
        return ref.split(",")[0]
    m = ref.split("eq. ")[-1].strip()
    return EQUATION_SECTIONS.get(paper or "", {}).get(m, "equations")


def section_rank(paper: str, section: str) -> int:
    order = SECTION_ORDER.get(paper, [])
    return order.index(section) if section in order else len(order)


# --------------------------------------------------------------------------- registry
@dataclass
class Registered:
    id: str
    paper: str
    ref: str
    quantity: str
    expected: str
    func: Callable[[], Finding]
    order: int
    mutations: tuple = ()


#: every claim of both papers, in registration order (id -> Registered)
REGISTRY: dict[str, Registered] = {}


def claim(id: str, *, paper: str, ref: str, quantity: str, expect: str, mutations=()):
    """Register a claim function and pin the verdict it must reach.

    Parameters
    ----------
    id : stable unique identifier (``sm-…`` / ``at-…``)
    paper : ``"seghete-murphey"`` or ``"acary-taha"``
    ref : ``eq. N`` for a numbered equation, else the section in the paper's numbering
    quantity : what is checked
    expect : the pinned verdict (one of :data:`VERDICTS`)
    mutations : names in :data:`paper_checks.mutations.MUTATIONS` that this claim's verdict
        depends on: under each, ``paper_checks/test_mutations.py`` asserts that the claim changes
        verdict or raises (a claim that no mutation moves is not decided by a computation).
        Required for every verdict except ``definition`` and ``not-checkable`` and judgments.

    Returns
    -------
    The decorator; the function (no arguments, returns a :class:`Finding`) is stored in
    :data:`REGISTRY`.

    >>> @claim("doc-example", paper="acary-taha", ref="eq. 0", quantity="x", expect="definition")
    ... def _example():
    ...     return Finding("definition", "x := 1")
    >>> evaluate("doc-example").status
    'ok'
    >>> del REGISTRY["doc-example"]
    """
    if paper not in PAPERS:
        raise ValueError(f"paper: must be one of {sorted(PAPERS)}, got {paper!r}")
    if expect not in VERDICTS:
        raise ValueError(f"expect: must be one of {VERDICTS}, got {expect!r}")

    def register(func):
        if id in REGISTRY:
            raise ValueError(f"id: {id!r} registered twice")
        REGISTRY[id] = Registered(id, paper, ref, quantity, expect, func, len(REGISTRY), tuple(mutations))
        func.claim_id = id
        return func

    return register


#: findings already computed in this process, keyed by (claim id, claim function): a claim is a
#: pure computation, so ``impactsym reproduce`` and the tests share one evaluation per process
_MEMO: dict = {}


def evaluate(claim_id: str) -> Claim:
    """Run one claim function; never raises (a raising check is recorded with status ``raised``).

    Parameters
    ----------
    claim_id : a key of :data:`REGISTRY`

    Returns
    -------
    Claim
        ``status`` is ``"ok"`` (verdict equals the pin), ``"verdict-differs"`` or ``"raised"``.
    """
    reg = REGISTRY[claim_id]
    c = Claim(reg.id, reg.paper, reg.ref, reg.quantity, reg.expected)
    t0 = time.perf_counter()
    saved = mpmath.mp.prec
    try:
        key = (reg.id, reg.func)
        f = _MEMO.get(key)
        if f is None:
            f = reg.func()
        if isinstance(f, Finding):
            _MEMO[key] = f
        if not isinstance(f, Finding):
            raise TypeError(f"claim {claim_id} returned {type(f).__name__}, not Finding")
        c.verdict, c.published, c.published_expr = f.verdict, f.published, f.published_expr
        c.derived, c.corrected, c.note, c.digits, c.evidence = (
            f.derived, f.corrected, f.note, f.digits, f.evidence)
        c.judgment, c.evidence_kind = f.judgment, f.kind()
        c.status = "ok" if c.verdict == c.expected else "verdict-differs"
    except Exception as exc:  # recorded, reported, and fails the run
        c.status = "raised"
        c.error = f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=6)}"
    finally:
        mpmath.mp.prec = saved
    c.seconds = time.perf_counter() - t0
    return c


def load_all() -> None:
    """Import the per-paper modules (registration happens at import)."""
    from . import seghete_murphey  # noqa: F401  (registration order: Seghete & Murphey first)
    from . import acary_taha  # noqa: F401


def evaluate_all(paper: str | None = None) -> list[Claim]:
    load_all()
    regs = sorted(REGISTRY.values(), key=lambda r: r.order)
    return [evaluate(r.id) for r in regs if paper is None or r.paper == paper]


# --------------------------------------------------------------------------- symbolic identity
@dataclass
class Identity:
    """The outcome of :func:`identical`: whether two expressions are equal, and how it was decided.

    ``status`` is one of

    * ``"proved"``: equal, by ``simplify(a − b) == 0`` or an exact zero test (``equal`` is True);
    * ``"different"``: a point where ``a − b`` is exactly, or certifiably, non-zero;
    * ``"samples"``: ``a − b`` is exactly zero at every sampled rational point, but no proof
      closed it: evidence for ``supported-by-samples``, never for ``exact-match``;
    * ``"inconclusive"``: neither proved equal nor certifiably different.

    Only ``"proved"`` is ``equal`` (and truthy).
    """

    equal: bool
    method: str
    counterexample: dict | None = None
    status: str = ""

    def __post_init__(self):
        if not self.status:
            self.status = "proved" if self.equal else "different"
        if self.equal != (self.status == "proved"):
            raise ValueError(f"status: {self.status!r} contradicts equal={self.equal}")

    def __bool__(self) -> bool:
        return self.equal

    @property
    def different(self) -> bool:
        return self.status == "different"

    def decide(self, equal: str = "exact-match", different: str = "refuted") -> str:
        """The verdict this identity supports: ``equal`` when proved, ``different`` when refuted,
        ``supported-by-samples`` when only sampled; an inconclusive identity raises
        :class:`Inconclusive` (a claim never guesses).

        >>> x = sp.Symbol("x")
        >>> identical((x + 1)**2, x**2 + 2*x + 1).decide()
        'exact-match'
        >>> identical(x**2, x).decide(different="erratum")
        'erratum'
        """
        if self.status == "proved":
            return equal
        if self.status == "different":
            return different
        if self.status == "samples":
            return "supported-by-samples"
        raise Inconclusive(self.method)


class Inconclusive(ArithmeticError):
    """An identity that is neither proved nor certifiably refuted (a claim must not guess)."""


def _random_point(symbols, domain, rng):
    point = {}
    for s in symbols:
        lo, hi = domain.get(s, (sp.Rational(1, 7), sp.Rational(13, 7)))
        lo, hi = sp.Rational(lo), sp.Rational(hi)
        k = rng.randint(1, 997)
        point[s] = lo + (hi - lo) * sp.Rational(k, 998)
    return point


def _exact_sign(x) -> int | None:
    """The sign of a closed-form number, decided exactly or by a certified enclosure; ``None``
    when it cannot be decided (never a guess)."""
    from impactsym.errors import UndecidableSign
    from impactsym.exact import certified_sign

    x = sp.sympify(x)
    if not x.is_number:
        return None
    if x.is_real is False:
        re_, im_ = x.as_real_imag()
        try:
            return 1 if certified_sign(im_) != 0 else certified_sign(re_)
        except UndecidableSign:
            return None
    try:
        return certified_sign(x, max_digits=400)
    except (UndecidableSign, TypeError, ValueError):
        return None


def identical(a, b, *, domain: dict | None = None, points: int = 8, seed: int = 20240611) -> Identity:
    """Decide ``a == b`` for expressions or matrices, and say how.

    Parameters
    ----------
    a, b : SymPy expressions or matrices (same shape)
    domain : ``{symbol: (lo, hi)}`` for the random rational points (default ``(1/7, 13/7)``)
    points : number of random points of the sampled fallback
    seed : seed of the point generator (reproducible)

    Returns
    -------
    Identity
        ``status`` (``proved``, ``different``, ``samples`` or ``inconclusive``), the ``method``
        that decided it, and a counterexample point when different.

    First an exact zero test of ``a − b`` (:func:`derivations.rational_zero.is_zero_algebraic`:
    its numerator, reduced by ``(√q)² = q``, ``sin² = 1 − cos²``, is the zero polynomial), then
    ``simplify(a − b) == 0`` (both proofs), skipped when ``a − b`` is proved non-zero at one point
    of its domain (:func:`derivations.rational_zero.nonzero_at_a_point`; simplify cannot close it). For numbers, an exact zero test or a certified
    sign (:func:`impactsym.exact.certified_sign`: rationals exactly, algebraic numbers by their
    minimal polynomial, others by rigorous enclosures). For expressions with symbols,
    ``a − b`` is evaluated *exactly* at ``points`` random rational points of ``domain``: an
    exactly or certifiably non-zero value is a counterexample (``different``, a proof of
    inequality); zero at every point is ``samples`` (evidence, not proof); a value whose sign
    cannot be certified is ``inconclusive``. No floating-point band ever counts as equal.

    >>> x = sp.Symbol("x")
    >>> r = identical(x**2, x)
    >>> r.equal, r.status, r.method.split(" ")[0]
    (False, 'different', 'counterexample')
    >>> identical(sp.Rational(1, 3) + sp.Rational(1, 10**30), sp.Rational(1, 3)).status
    'different'
    >>> identical(sp.sqrt(8), 2 * sp.sqrt(2)).status
    'proved'
    """
    A, B = sp.sympify(a), sp.sympify(b)
    if isinstance(A, sp.MatrixBase) or isinstance(B, sp.MatrixBase):
        A, B = sp.Matrix(A), sp.Matrix(B)
        if A.shape != B.shape:
            return Identity(False, f"shapes differ: {A.shape} vs {B.shape}", status="different")
        diffs = list(A - B)
    else:
        diffs = [A - B]
    from derivations.rational_zero import is_zero_algebraic, is_zero_rational_function, nonzero_at_a_point

    rest = []
    simplified = False
    for d in diffs:
        # exact zero tests first (python-flint, milliseconds): a rational function over Q(√q, i)
        # in symbols and cos/sin of symbols whose reduced numerator is the zero polynomial is 0;
        # a rational function over Q with a non-zero numerator is not (simplify cannot close it)
        if is_zero_algebraic(d):
            continue
        if is_zero_rational_function(d) is False or nonzero_at_a_point(d):
            rest.append(d)  # proved not identically zero: simplify cannot close it either
            continue
        simplified = True
        try:
            if simplify(d) == 0:
                continue
        except Exception:
            pass
        rest.append(d)
    if not rest:
        return Identity(True, "simplify(a - b) == 0" if simplified else
                        "a - b is exactly zero (exact zero test)", status="proved")
    free = sorted(set().union(*[d.free_symbols for d in rest]), key=str)
    if not free:
        undecided = []
        for d in rest:
            sgn = _exact_sign(d)
            if sgn is None:
                undecided.append(d)
            elif sgn != 0:
                return Identity(False, f"a - b = {sp.N(d, 20)} (sign certified non-zero)", status="different")
        if undecided:
            return Identity(False, f"sign of a - b not certified: {undecided[0]}", status="inconclusive")
        return Identity(True, "a - b is exactly zero (exact zero test)", status="proved")
    rng = random.Random(seed)
    domain = domain or {}
    for _ in range(points):
        pt = _random_point(free, domain, rng)
        for d in rest:
            val = d.subs(pt)
            sgn = _exact_sign(val) if val.is_number else None
            if sgn is None:
                return Identity(False, f"inconclusive at {pt}: sign of a - b = {val} not certified",
                                pt, status="inconclusive")
            if sgn != 0:
                return Identity(False, f"counterexample at {pt}: a - b = {sp.N(val, 20)} (exact)", pt,
                                status="different")
    return Identity(False, f"simplify did not close it; a - b is exactly 0 at {points} random rational points "
                           f"(sampled, not proved)", status="samples")


# --------------------------------------------------------------------------- decimals
def _printed_places(printed: str) -> int:
    s = printed.strip().lstrip("+-")
    return len(s.split(".")[1]) if "." in s else 0


def compare_decimal(value, printed: str, digits: int = DIGITS) -> dict:
    """Compare an exact (or high-precision) value with a published decimal.

    Parameters
    ----------
    value : exact SymPy number (or anything ``sympify`` accepts)
    printed : the published decimal, as printed
    digits : significant digits of the evaluation (≥ 50)

    Returns
    -------
    dict
        ``value`` (at ``digits``), ``places``, ``rounded``, ``truncated``, ``agreement``, ``error``.

    The value is evaluated at ``digits`` significant digits, then rounded half-even and truncated
    toward zero to the printed number of decimal places. ``agreement`` is ``"exact"`` when the
    value equals the printed decimal, ``"rounding"``, ``"truncation"``, ``"rounding and
    truncation"`` (both give the print), or ``"neither"``.

    >>> compare_decimal(sp.Rational(1, 3), "0.33")["agreement"]
    'rounding and truncation'
    >>> compare_decimal(sp.Rational(1, 2), "0.5")["agreement"]
    'exact'
    """
    v = sp.N(sp.sympify(value), digits)
    places = _printed_places(printed)
    with localcontext() as ctx:
        ctx.prec = digits + 10
        d = Decimal(str(v))
        p = Decimal(printed.strip())
        q = Decimal(1).scaleb(-places)
        rounded = d.quantize(q, rounding=ROUND_HALF_EVEN)
        truncated = d.quantize(q, rounding=ROUND_DOWN)
        if d == p:
            agreement = "exact"
        elif rounded == p and truncated == p:
            agreement = "rounding and truncation"
        elif rounded == p:
            agreement = "rounding"
        elif truncated == p:
            agreement = "truncation"
        else:
            agreement = "neither"
        error = d - p
    return {"value": str(v), "printed": printed, "places": places, "rounded": str(rounded),
            "truncated": str(truncated), "agreement": agreement,
            "error": f"{error:.3e}"}


def compare_decimals(values, printed) -> dict:
    """Compare many values; summary ``agreement`` is the set of per-entry agreements."""
    rows = [compare_decimal(v, p) for v, p in zip(values, printed)]
    kinds = sorted({r["agreement"] for r in rows})
    return {"rows": rows, "kinds": kinds, "all_agree": "neither" not in kinds}


# --------------------------------------------------------------------------- conservation
def conservation(M, H, vminus, vplus, e=1, *, values: bool = True) -> dict:
    """Check a post-impact state against the impact equations, exactly.

    Parameters
    ----------
    M, H : mass matrix (n×n) and gradient rows (k×n), exact entries
    vminus, vplus : pre- and post-impact velocities (n), exact entries
    e : energetic coefficient in force (``T⁺ = e T⁻``)
    values : also return the simplified values (``p``, ``T_minus``, ``T_plus``,
        ``energy_residual``, ``Hv_plus``). With ``values=False`` only the four decisions and
        ``holds`` are returned, decided as exactly but without simplifying what no one reads
        (:func:`_conservation_decisions`): ``p`` by exact row reduction in the number field of
        the data instead of ``sympy.solve``, the signs certified on the unsimplified numbers.

    Returns
    -------
    dict
        ``momentum`` (bool: ``M(v⁺ − v⁻) = Hᵀp`` has an exact solution ``p``), ``p`` (the
        impulses, or ``None``), ``impulses_nonnegative`` (bool, or ``None`` without ``p``),
        ``energy_residual`` (``T⁺ − eT⁻``, exact), ``energy`` (bool: the residual is exactly 0),
        ``T_minus``, ``T_plus``, ``Hv_plus``, ``contacts`` (bool: ``H v⁺ ≥ 0``) and ``holds``
        (all four).

    Every sign is decided exactly or certified (:func:`impactsym.exact.certified_sign`); no
    rounding (``nsimplify``) touches the numbers, so a residual of ``10⁻⁴⁰`` is ``10⁻⁴⁰``.

    >>> c = conservation(sp.eye(3), sp.Matrix([[-1, 1, 0], [0, -1, 1]]), sp.Matrix([1, 0, 0]),
    ...                  sp.Matrix([0, 0, 1]))
    >>> c["momentum"], c["energy_residual"], c["p"], c["impulses_nonnegative"], c["holds"]
    (True, 0, [1, 1], True, True)
    >>> conservation(sp.eye(1), sp.Matrix([[1]]), sp.Matrix([-1]),
    ...              sp.Matrix([1 + sp.Rational(1, 10**20)]))["energy"]
    False
    >>> h = sp.sqrt(2) / 2
    >>> conservation(sp.eye(2), sp.Matrix([[-h, -h]]), sp.Matrix([h, h]), sp.Matrix([-h, -h]), values=False)
    {'momentum': True, 'impulses_nonnegative': True, 'energy': True, 'contacts': True, 'holds': True}
    """
    from derivations.rational_zero import is_zero_algebraic
    from impactsym.exact import certified_sign

    M, H = sp.Matrix(M), sp.Matrix(H)
    vm, vp = sp.Matrix(vminus), sp.Matrix(vplus)
    if not values:
        decided = _conservation_decisions(M, H, vm, vp, e)
        if decided is not None:
            return decided
        full = conservation(M, H, vm, vp, e)
        return {k: full[k] for k in ("momentum", "impulses_nonnegative", "energy", "contacts", "holds")}
    rhs = M * (vp - vm)
    p_syms = sp.symbols(f"p0:{H.rows}")
    rational = _rational_unique_solution(H.T, rhs)
    if rational is not None:  # rational data, H^T of full column rank: the one solution, or none
        momentum = rational is not False
        p = list(rational) if momentum else None
    else:
        sol = solve_remembered(list(H.T * sp.Matrix(p_syms) - rhs), p_syms, dict=True)
        momentum = bool(sol)
        p = [sp.radsimp(simplify(sol[0].get(s, s))) for s in p_syms] if sol else None
    free = bool(p) and any(x.free_symbols for x in p)
    nonneg = None if (p is None or free) else all(certified_sign(x) >= 0 for x in p)
    Tm = simplify((vm.T * M * vm)[0, 0] / 2)
    Tp = simplify((vp.T * M * vp)[0, 0] / 2)
    res = sp.Integer(0) if is_zero_algebraic(Tp - e * Tm) else sp.radsimp(simplify(Tp - e * Tm))
    energy = certified_sign(res) == 0 if not res.free_symbols else None
    w = [sp.radsimp(simplify(x)) for x in H * vp]
    contacts = all(certified_sign(x) >= 0 for x in w) if not any(x.free_symbols for x in w) else None
    return {"momentum": momentum, "p": p, "impulses_nonnegative": nonneg, "energy_residual": res,
            "energy": energy, "T_minus": Tm, "T_plus": Tp, "Hv_plus": w, "contacts": contacts,
            "holds": bool(momentum and nonneg and energy and contacts)}


def _conservation_decisions(M, H, vm, vp, e):
    """The decisions of :func:`conservation` (``momentum``, ``impulses_nonnegative``, ``energy``,
    ``contacts``, ``holds``) for data free of symbols, or None when a symbol occurs (the caller then
    takes the symbolic path). ``H^T p = M(v⁺ − v⁻)`` is row-reduced exactly in the data's field
    (:func:`impactsym.arithmetic.linalg.solve_columns`: flint for rationals, a SymPy number field
    or certified signs otherwise); ``p`` is unique when the reduction leaves no free column, as
    ``sympy.solve`` then finds it; every sign is certified."""
    from derivations.rational_zero import is_zero_algebraic
    from impactsym.arithmetic.fields import field_of
    from impactsym.arithmetic.linalg import solve_columns
    from impactsym.exact import certified_sign

    e = sp.sympify(e)
    if any(x.free_symbols for x in (*M, *H, *vm, *vp, e)):
        return None
    rhs = M * (vp - vm)
    F = field_of(H, rhs)
    solved = solve_columns([[F.num(H[j, i]) for i in range(H.cols)] for j in range(H.rows)],
                           [F.num(x) for x in rhs], F)
    momentum = solved is not None
    nonneg = None
    if momentum:
        p, free = solved
        nonneg = None if free else all(F.sign(x) >= 0 for x in p)
    balance = (vp.T * M * vp)[0, 0] / 2 - e * (vm.T * M * vm)[0, 0] / 2
    energy = True if is_zero_algebraic(balance) else certified_sign(balance) == 0
    contacts = all(certified_sign(x) >= 0 for x in H * vp)
    return {"momentum": momentum, "impulses_nonnegative": nonneg, "energy": energy, "contacts": contacts,
            "holds": bool(momentum and nonneg and energy and contacts)}


def _rational_unique_solution(A: sp.Matrix, b: sp.Matrix):
    """For rational ``A`` (of full column rank) and ``b``: the solution ``x`` of ``A x = b`` as a
    list of Rationals, or False when there is none (exact row reduction over QQ, SymPy's
    ``DomainMatrix``). None when the data are not all rational or ``A`` is rank-deficient (the
    caller then solves symbolically)."""
    from sympy.polys.matrices import DomainMatrix

    if not all(x.is_Rational for x in list(A) + list(b)):
        return None
    aug = DomainMatrix.from_Matrix(A.row_join(b)).convert_to(sp.QQ)
    rref, pivots = aug.rref()
    k = A.cols
    if len(pivots) > 0 and pivots[-1] == k:
        return False  # a pivot in the right-hand column: inconsistent
    if list(pivots) != list(range(k)):
        return None  # rank-deficient: free parameters, solved symbolically
    R = rref.to_Matrix()
    return [R[i, k] for i in range(k)]


# --------------------------------------------------------------------------- extrema
def _normal_form(expr):
    """A rational function with rational coefficients in lowest terms (``sympy.cancel``: its normal
    form, no search), anything else simplified."""
    from derivations.rational_zero import is_zero_rational_function

    expr = sp.sympify(expr)
    if expr.free_symbols and is_zero_rational_function(expr) is not None:
        return sp.cancel(expr)
    return simplify(expr)


def extremum(f, x, x0, *, kind: str = "min") -> dict:
    """First- and second-order test of a claimed extremum of ``f(x)`` at ``x0``.

    Parameters
    ----------
    f : expression in ``x``;  x : the variable;  x0 : the claimed extremum (exact)
    kind : ``"min"`` or ``"max"``

    Returns
    -------
    dict
        ``f'(x0)``, ``f''(x0)``, ``stationary``, ``second_order_sign``, ``holds``.

    >>> x = sp.Symbol("x")
    >>> extremum((x - 1)**2, x, 1)["holds"]
    True
    """
    d1 = _normal_form(sp.diff(f, x).subs(x, x0))
    d2 = _normal_form(sp.diff(f, x, 2).subs(x, x0))
    stationary = identical(d1, 0).equal
    sign = None
    if not d2.free_symbols:
        sign = 1 if d2 > 0 else (-1 if d2 < 0 else 0)
    holds = stationary and ((sign == 1) if kind == "min" else (sign == -1))
    return {"f'(x0)": d1, "f''(x0)": d2, "stationary": stationary, "second_order_sign": sign,
            "holds": holds}
