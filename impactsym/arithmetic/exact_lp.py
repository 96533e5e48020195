"""Small linear programs over the rationals, solved exactly and certified by duality.

:func:`maximize` runs a two-phase simplex (Bland's rule, so it terminates) on sparse rows of
flint ``fmpq`` and returns the optimum only after checking, independently of the simplex, a primal
point and a dual point whose objectives are equal: primal feasibility, dual feasibility and equal
objectives prove optimality (weak duality), so a bug in the pivoting can only raise, never return a
wrong value. It serves the few-variable LPs of the paper checks (:func:`impactsym.simulate.ordering_realizable`),
where SymPy's ``linprog`` on ``Rational`` matrices costs tenths of a second per problem.

>>> from fractions import Fraction as F
>>> r = maximize([1, 1], [[1, 2], [3, 1]], [4, 6])   # max x + y, x + 2y <= 4, 3x + y <= 6, x, y >= 0
>>> r.value, r.x
(Fraction(14, 5), [Fraction(8, 5), Fraction(6, 5)])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from flint import fmpq

from ..errors import VerificationError

__all__ = ["LPResult", "maximize"]


@dataclass(frozen=True)
class LPResult:
    """Outcome of :func:`maximize`: ``status`` is ``"optimal"``, ``"infeasible"`` or ``"unbounded"``;
    for ``"optimal"``, ``value`` = ``c·x``, the primal point ``x`` and the dual multipliers ``y_ub``
    (≥ 0) and ``y_eq`` that certify it (``A_ubᵀy_ub + A_eqᵀy_eq ≥ c``, ``b·y = c·x``)."""

    status: str
    value: Fraction | None = None
    x: list | None = None
    y_ub: list | None = None
    y_eq: list | None = None


def _q(x) -> Fraction:
    if isinstance(x, Fraction):
        return x
    if isinstance(x, int):
        return Fraction(x)
    p, q = getattr(x, "p", None), getattr(x, "q", None)  # SymPy Rational/Integer, flint fmpq
    if p is not None and q is not None:
        return Fraction(int(p), int(q))
    if hasattr(x, "numerator") and hasattr(x, "denominator") and not isinstance(x, float):
        return Fraction(int(x.numerator), int(x.denominator))
    raise TypeError(f"maximize: entries must be exact rationals, got {x!r} ({type(x).__name__})")


def maximize(c, A_ub=(), b_ub=(), A_eq=(), b_eq=()) -> LPResult:
    """Maximize ``c·x`` subject to ``A_ub x ≤ b_ub``, ``A_eq x = b_eq``, ``x ≥ 0``, exactly.

    Parameters
    ----------
    c : sequence of exact rationals (int, Fraction, SymPy Rational, flint fmpq), length ``n``
    A_ub, b_ub : rows of length ``n`` and their bounds (may be empty)
    A_eq, b_eq : rows of length ``n`` and their right-hand sides (may be empty)

    Returns
    -------
    LPResult
        ``"optimal"`` results are certified (primal and dual feasible, equal objectives) before
        they are returned; ``"infeasible"`` and ``"unbounded"`` are the simplex's exact verdicts,
        without a separate certificate (a caller that rests a claim on them must check one).

    Raises
    ------
    VerificationError
        The certificate fails (a pivoting bug; never a wrong optimum).

    Examples
    --------
    >>> maximize([0, 1], [[1, 1]], [1], [[1, -1]], [0]).value       # x = y, x + y <= 1
    Fraction(1, 2)
    >>> maximize([1], [[-1]], [-1]).status, maximize([1], [[1]], [-1]).status
    ('unbounded', 'infeasible')
    """
    cq = [_q(v) for v in c]
    n = len(cq)
    Aub = [[_q(v) for v in row] for row in A_ub]
    bub = [_q(v) for v in b_ub]
    Aeq = [[_q(v) for v in row] for row in A_eq]
    beq = [_q(v) for v in b_eq]
    if len(Aub) != len(bub) or len(Aeq) != len(beq) or any(len(r) != n for r in Aub + Aeq):
        raise ValueError("maximize: the constraint rows must have len(c) entries and one bound each")
    m1, m2 = len(Aub), len(Aeq)
    m = m1 + m2
    # Tableau rows over flint fmpq. Columns: x (n), one slack per <= row (m1), then one artificial
    # per row that cannot start on its slack (an equality, or b < 0: the row is negated first,
    # sign[i] = -1). init[i] is the column of row i's initial (identity) basis variable, from which
    # B^-1 is read at the end.
    zero, one = fmpq(0), fmpq(1)
    rows, rhs, sign, basis, init = [], [], [], [], []
    art = []
    for i, (r, b) in enumerate(zip(Aub + Aeq, bub + beq)):
        s_ = -1 if b < 0 else 1
        row = {j: fmpq(s_ * v.numerator, v.denominator) for j, v in enumerate(r) if v != 0}
        if i < m1:
            row[n + i] = fmpq(s_)
        rows.append(row)
        rhs.append(fmpq(s_ * b.numerator, b.denominator))
        sign.append(s_)
        if i < m1 and s_ == 1:
            basis.append(n + i)
        else:
            col = n + m1 + len(art)
            art.append(col)
            row[col] = one
            basis.append(col)
        init.append(basis[-1])
    N = n + m1 + len(art)
    artificial = set(art)

    def pivot(r, col):
        piv = rows[r][col]
        inv = one / piv
        prow = {j: v * inv for j, v in rows[r].items()}
        rows[r] = prow
        rhs[r] = rhs[r] * inv
        for i in range(m):
            f = rows[i].get(col)
            if i != r and f is not None:
                row = rows[i]
                for j, v in prow.items():
                    t = row.get(j, zero) - f * v
                    if t == 0:
                        row.pop(j, None)
                    else:
                        row[j] = t
                rhs[i] = rhs[i] - f * rhs[r]
        basis[r] = col

    def run(cost, allowed):
        """Simplex with Bland's rule (smallest improving column, smallest leaving basic index);
        False when unbounded."""
        while True:
            red = {j: cost[j] for j in allowed if cost[j] != 0}
            for i in range(m):
                cb = cost[basis[i]]
                if cb != 0:
                    for j, v in rows[i].items():
                        red[j] = red.get(j, zero) - cb * v
            inb = set(basis)
            enter = min((j for j, v in red.items() if v > 0 and j in allowed and j not in inb), default=None)
            if enter is None:
                return True
            best = None
            for i in range(m):
                a = rows[i].get(enter)
                if a is not None and a > 0:
                    key = (rhs[i] / a, basis[i])
                    if best is None or key < best[0]:
                        best = (key, i)
            if best is None:
                return False
            pivot(best[1], enter)

    if artificial:
        phase1 = [zero] * N
        for j in artificial:
            phase1[j] = -one
        run(phase1, set(range(N)))
        if any(rhs[i] != 0 for i in range(m) if basis[i] in artificial):
            return LPResult("infeasible")
        # drive the artificials left in the basis (at level 0) out where a real column can replace them
        for i in range(m):
            if basis[i] in artificial:
                inb = set(basis)
                j = min((j for j in rows[i] if j < n + m1 and j not in inb), default=None)
                if j is not None:
                    pivot(i, j)
    cost = [fmpq(v.numerator, v.denominator) for v in cq] + [zero] * (N - n)
    if not run(cost, set(range(n + m1))):
        return LPResult("unbounded")
    xq = [zero] * N
    for i, b in enumerate(basis):
        xq[b] = rhs[i]
    xq = xq[:n]
    # duals: y = c_B B^-1, B^-1 read from the initial identity columns; a negated row's multiplier
    # changes sign back
    cb = [cost[b] for b in basis]
    yq = [sign[k] * sum((cb[i] * rows[i].get(init[k], zero) for i in range(m)), zero) for k in range(m)]
    # the certificate, checked on the input data alone (in fmpq, over the rows' nonzero entries)
    Aq = [[(j, fmpq(v.numerator, v.denominator)) for j, v in enumerate(r) if v != 0] for r in Aub + Aeq]
    bq = [fmpq(v.numerator, v.denominator) for v in bub + beq]
    lhs = [sum((a * xq[j] for j, a in row), zero) for row in Aq]
    dual = [zero] * n  # A_ubᵀ y_ub + A_eqᵀ y_eq
    for row, yi in zip(Aq, yq):
        if yi != 0:
            for j, a in row:
                dual[j] += a * yi
    value_q = sum((cost[j] * xq[j] for j in range(n)), zero)
    ok = all(v >= 0 for v in xq) and all(v >= 0 for v in yq[:m1])
    ok = ok and all(lhs[i] <= bq[i] for i in range(m1)) and all(lhs[i] == bq[i] for i in range(m1, m))
    ok = ok and all(dual[j] >= cost[j] for j in range(n))
    ok = ok and sum((b * y for b, y in zip(bq, yq)), zero) == value_q
    if not ok:
        raise VerificationError("maximize", "the simplex's primal and dual points do not certify its optimum")
    xs = [Fraction(int(v.p), int(v.q)) for v in xq]
    y = [Fraction(int(v.p), int(v.q)) for v in yq]
    return LPResult("optimal", Fraction(int(value_q.p), int(value_q.q)), xs, y[:m1], y[m1:])
