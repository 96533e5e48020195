"""Exact zero test of a rational function, in python-flint's multivariate polynomials.

A derivation often ends with "``a − b`` is identically zero" where ``a`` and ``b`` are rational
functions of a dozen symbols (the entries of a symbolic mass matrix, a covector, a velocity).
SymPy's ``cancel(together(a − b))`` decides it by gcds of large expressions: 8–13 s for the
energy-loss identity of the 3×3 Newton-restitution map. The test needs no gcd at all: write the
expression as one fraction ``N / D`` with ``D`` a product of non-zero polynomials, and the
expression is identically zero exactly when the expanded numerator ``N`` is the zero polynomial.
python-flint's ``fmpq_mpoly`` (exact rational coefficients, C arithmetic) expands ``N`` in
milliseconds.

:func:`is_zero_rational_function` returns ``None`` (undecided here) for anything that is not a
rational function of commutative symbols with rational coefficients (a square root, a function,
a float, a zero denominator); the caller then falls back to SymPy. It never guesses: ``True``
means the numerator polynomial is exactly 0 and the denominator polynomial exactly non-zero.

Examples
--------
>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> is_zero_rational_function(1 / (x - y) - 1 / (y - x) - 2 / (x - y))
True
>>> is_zero_rational_function((x**2 - y**2) / (x - y) - x)
False
>>> is_zero_rational_function(sp.sqrt(x) - x) is None  # not a rational function: undecided here
True
"""

from __future__ import annotations

import flint
import sympy as sp

from .memo import simplify

__all__ = ["is_zero_rational_function", "is_zero_algebraic", "is_zero", "nonzero_at_a_point", "cancel", "factor", "factored_numerator", "to_fraction"]


class _NotRational(TypeError):
    """The expression is not a rational function with rational coefficients."""


def _fraction_converter(one, leaf, root=None):
    """The converter ``e -> (N, D)`` (``e = N / D``, python-flint polynomials) that
    :func:`to_fraction` and :func:`is_zero_algebraic` share: ``leaf(e)`` gives the pair of an
    atom (or None), rationals, sums, products and integer powers are built without any gcd (sums
    over a common denominator only where the denominators are equal), and ``root(b)``, when given,
    is ``√b`` as a polynomial (or None), so that ``b**(k/2)`` is ``root(b)**k``."""
    memo: dict = {}

    def conv(e):
        hit = memo.get(e)
        if hit is not None:
            return hit
        out = leaf(e)
        if out is not None:
            pass
        elif e.is_Rational:
            out = (one * flint.fmpq(int(e.p), int(e.q)), one)
        elif e.is_Add:
            n, d = conv(e.args[0])
            for a in e.args[1:]:
                n2, d2 = conv(a)
                if d2 == d:
                    n = n + n2
                else:
                    n, d = n * d2 + n2 * d, d * d2
            out = (n, d)
        elif e.is_Mul:
            n, d = one, one
            for a in e.args:
                n2, d2 = conv(a)
                n, d = n * n2, d * d2
            out = (n, d)
        else:
            r = None
            if e.is_Pow and e.exp.is_Integer:
                n, d = conv(e.base)
                k = int(e.exp)
            elif (e.is_Pow and root is not None and e.exp.is_Rational and e.exp.q == 2
                  and (r := root(e.base)) is not None):
                n, d = r, one  # b**(k/2) = sqrt(b)**k, sqrt(b) a product of generators
                k = int(e.exp.p)
            else:
                raise _NotRational(f"not a rational function: {type(e).__name__}")
            if k < 0 and n == 0:
                raise _NotRational("division by the zero polynomial")
            out = (n ** k, d ** k) if k >= 0 else (d ** (-k), n ** (-k))
        memo[e] = out
        return out

    return conv


def to_fraction(expr, symbols):
    """``(N, D)``: ``expr = N / D`` with ``N, D`` python-flint ``fmpq_mpoly`` in ``symbols``, built
    without any gcd (sums over a common denominator only where the denominators are equal).

    Raises
    ------
    TypeError
        ``expr`` is not a rational function of ``symbols`` with rational coefficients.

    >>> x = sp.Symbol("x")
    >>> n, d = to_fraction(1 / x + 1, [x])
    >>> str(n), str(d)
    ('x + 1', 'x')
    """
    symbols = list(symbols)
    names = tuple(str(s) for s in symbols)
    if len(set(names)) < len(names):  # two symbols of one name (other assumptions): index them
        names = tuple(f"x{i}" for i in range(len(symbols)))
    ctx = flint.fmpq_mpoly_ctx.get(names or ("x0",), "lex")
    index = {s: i for i, s in enumerate(symbols)}
    one = ctx.from_dict({}) + 1
    gens = ctx.gens()

    def leaf(e):
        if not e.is_Symbol:
            return None
        if e not in index:
            raise _NotRational(f"symbol {e} not among the variables")
        return gens[index[e]], one

    conv = _fraction_converter(one, leaf)
    n, d = conv(sp.sympify(expr))
    if d == 0:
        raise _NotRational("the denominator is the zero polynomial")
    return n, d


def is_zero_rational_function(expr) -> bool | None:
    """Whether ``expr`` (a SymPy expression) is identically zero as a rational function.

    Returns
    -------
    True or False, decided exactly (numerator polynomial zero or not, denominator non-zero);
    None when ``expr`` is not a rational function of commutative symbols with rational
    coefficients (the caller decides it another way).
    """
    expr = sp.sympify(expr)
    if not expr.is_commutative:
        return None
    try:
        n, _d = to_fraction(expr, sorted(expr.free_symbols, key=str))
    except _NotRational:
        return None
    return n == 0


# --------------------------------------------------------------------------- algebraic generators
class _Gen:
    """A generator of the coefficient ring with its defining relation ``g² = value``: a square
    root of a positive rational (``value`` rational), the imaginary unit (``value`` −1), or the
    sine of an angle (``value`` ``1 − cos²``, the cosine being another generator)."""

    def __init__(self, kind, key):
        self.kind, self.key = kind, key


def _generators(expr):
    """The atoms of ``expr`` that become polynomial variables, or raise :class:`_NotRational`:
    symbols, ``√q`` (``q`` a positive rational), ``I``, ``cos x`` and ``sin x`` of a symbol, and
    ``√P`` of an expression ``P`` built from those (not from another ``√P``)."""
    symbols, roots, angles, polyroots, unit = set(), set(), set(), set(), False
    for node in sp.preorder_traversal(expr):
        if node.is_Symbol:
            symbols.add(node)
        elif node is sp.I:
            unit = True
        elif node.is_Pow and not node.exp.is_Integer:
            b, x = node.base, node.exp
            if not (x.is_Rational and x.q == 2):
                raise _NotRational(f"not an algebraic power: {node}")
            if b.is_Rational and b > 0:
                roots.update(_split_root(b)[1])
            elif b.is_Rational or any(not (y.exp.is_Integer or (y.base.is_Rational and y.base > 0))
                                      for y in b.atoms(sp.Pow)):
                raise _NotRational(f"nested or negative root: {node}")
            else:
                c, prim = _primitive(b)
                roots.update(_split_root(c)[1])
                polyroots.add(prim)
        elif isinstance(node, (sp.cos, sp.sin)):
            if not node.args[0].is_Symbol:
                raise _NotRational(f"trigonometric function of a non-symbol: {node}")
            angles.add(node.args[0])
        elif node.is_Function or node.is_Relational or isinstance(node, sp.MatrixBase):
            raise _NotRational(f"not a rational function: {type(node).__name__}")
    return (sorted(symbols - angles, key=str), sorted(roots), sorted(angles, key=str), unit,
            sorted(polyroots, key=sp.default_sort_key))


_MAX_FACTOR = 10**30


def _split_root(q):
    """``√q = r·√(p₁⋯p_k)`` for a positive rational ``q``: ``(r, (p₁, …, p_k))`` with ``r`` rational
    and the ``p_i`` the distinct primes of the square-free part of ``q``'s numerator times its
    denominator. The square roots of distinct primes are linearly independent over Q, so with them
    as generators (``√p² = p``) the reduced numerator is a canonical form: ``√6 − √2·√3`` reduces to
    0. A square-free part too large to factor stays one generator (still a true relation)."""
    hit = _SPLIT.get(q)
    if hit is None:
        a, b = int(q.p), int(q.q)
        n = a * b
        if n > _MAX_FACTOR:
            hit = (sp.Integer(1) / b, (sp.Integer(n),))
        else:
            square, primes = 1, []
            for p, e in flint.fmpz(n).factor():
                square *= int(p) ** (e // 2)
                if e % 2:
                    primes.append(sp.Integer(int(p)))
            hit = (sp.Rational(square, b), tuple(primes))
        _SPLIT[q] = hit
    return hit


_SPLIT: dict = {}


def _primitive(b):
    """``(c, P)`` with ``b = c·P``, ``c`` a positive rational content (so ``√b = √c·√P``) and ``P``
    primitive: ``√(10 + 10√2)`` and ``√(5 + 5√2)`` share the generator ``√(1 + √2)``."""
    c, prim = b.as_content_primitive()
    if not (c.is_Rational and c > 0):
        return sp.Integer(1), b
    return c, prim


def _reduce(poly, ctx, rel):
    """``poly`` with every ``g^k`` (``k ≥ 2``) of a generator rewritten by its relation
    ``g² = value`` (``rel``: generator index -> value as a polynomial of ``ctx``), until no
    generator occurs squared. Each rewrite replaces a polynomial by an equal one, so a result 0
    proves ``poly`` zero at the generators' values."""
    for gi, value in rel.items():
        out = ctx.from_dict({})
        pending = {}
        for exps, c in poly.to_dict().items():
            k = exps[gi]
            if k < 2:
                pending[exps] = pending.get(exps, 0) + c
                continue
            e = list(exps)
            e[gi] = k % 2
            out += ctx.from_dict({tuple(e): c}) * value ** (k // 2)
        poly = out + ctx.from_dict({e: c for e, c in pending.items() if c != 0})
    return poly


def is_zero_algebraic(expr) -> bool | None:
    """Whether ``expr`` is identically zero, proved exactly, for rational functions over
    ``Q(√q₁, √q₂, …, i)`` in symbols and in ``cos x``, ``sin x`` of symbols ``x``.

    The expression is written as one fraction ``N / D`` of polynomials in the symbols and in one
    generator per square root, ``i``, cosine and sine (no gcd, as :func:`to_fraction`); ``N`` is
    reduced by the true relations ``(√p)² = p`` (``p`` prime), ``(√P)² = P``, ``i² = −1``, ``sin²x = 1 − cos²x``. A reduced
    ``N`` equal to the zero polynomial proves ``N = 0`` at the generators' values; ``D`` is
    proved not identically zero by one certified evaluation (an Arb ball excluding 0 at an exact
    rational point). Then ``expr`` is identically zero.

    Returns
    -------
    True when proved zero; None otherwise (the expression may still be zero: ``√P`` generators and
    angles may be related in ways the reduction does not use, such as ``√(2 + √3)`` and
    ``(√6 + √2)/2``). Never False. Square roots of rationals are rewritten as a rational times
    roots of distinct primes (``√6 = √2·√3``), and a root of an expression as the root of its
    rational content times the root of its primitive part (``√(10 + 10√2) = √10·√(1 + √2)``), so
    relations among those are used.

    Examples
    --------
    >>> x, t = sp.symbols("x t", real=True)
    >>> is_zero_algebraic((sp.sqrt(3) * x + 1) * (sp.sqrt(3) * x - 1) - 3 * x**2 + 1)
    True
    >>> is_zero_algebraic(sp.cos(t)**2 + sp.sin(t)**2 - 1)
    True
    >>> is_zero_algebraic(sp.sqrt(3) / 3 - 1 / sp.sqrt(3))
    True
    >>> is_zero_algebraic(sp.sqrt(2 + sp.sqrt(3)) - (sp.sqrt(6) + sp.sqrt(2)) / 2) is None  # nested: undecided
    True
    >>> is_zero_algebraic(sp.sqrt(x) - 1) is None
    True
    """
    expr = sp.sympify(expr)
    if not expr.is_commutative or isinstance(expr, sp.MatrixBase):
        return None
    try:
        symbols, roots, angles, unit, polyroots = _generators(expr)
        atoms = list(symbols) + [sp.sqrt(q) for q in roots] + [f(x) for x in angles for f in (sp.cos, sp.sin)]
        atoms += [sp.I] if unit else []
        atoms += [sp.sqrt(b) for b in polyroots]
        if not atoms:
            return True if expr == 0 else None
        names = tuple(f"x{i}" for i in range(len(atoms)))
        ctx = flint.fmpq_mpoly_ctx.get(names, "lex")
        gens = ctx.gens()
        index = {a: i for i, a in enumerate(atoms)}
        n, d = _conv(expr, ctx, gens, index)
        rel = {}
        for b in polyroots:  # (√P)² = P, P a polynomial in the earlier generators
            pn, pd = _conv(b, ctx, gens, index)
            if pd != 1 or any(e[index[sp.sqrt(c)]] for c in polyroots for e in pn.to_dict()):
                raise _NotRational(f"the square root of a non-polynomial: {b}")
            rel[index[sp.sqrt(b)]] = pn
    except _NotRational:
        return None
    if d == 0:
        return None
    for q in roots:
        rel[index[sp.sqrt(q)]] = ctx.from_dict({}) + flint.fmpq(int(q.p), int(q.q))
    for x in angles:
        c = gens[index[sp.cos(x)]]
        rel[index[sp.sin(x)]] = 1 - c * c
    if unit:
        rel[index[sp.I]] = ctx.from_dict({}) - 1
    if _reduce(n, ctx, rel) != 0:
        return None
    return True if _certainly_nonzero(d, atoms, {index[sp.sqrt(b)]: rel[index[sp.sqrt(b)]] for b in polyroots}) else None


def _conv(expr, ctx, gens, index):
    """``(N, D)`` over ``ctx`` with the atoms of ``index`` as variables (as :func:`to_fraction`;
    half-integer powers of a root atom become powers of its generator)."""
    one = ctx.from_dict({}) + 1

    def _root_poly(b):
        """√b as a polynomial in the generators (a rational times prime roots, times the
        generator of b's primitive part), or None when b has none."""
        i = index.get(sp.sqrt(b))
        if i is not None and not b.is_Rational:
            return gens[i]
        if b.is_Rational:
            if b <= 0:
                return None
            r, primes = _split_root(b)
            c, rest = r, one
        else:
            c, prim = _primitive(b)
            j = index.get(sp.sqrt(prim))
            if j is None:
                return None
            r, primes = _split_root(c)
            c, rest = r, gens[j]
        out = rest * flint.fmpq(int(c.p), int(c.q))
        for p in primes:
            k = index.get(sp.sqrt(p))
            if k is None:
                return None
            out = out * gens[k]
        return out

    def leaf(e):
        i = index.get(e)
        return None if i is None else (gens[i], one)

    conv = _fraction_converter(one, leaf, _root_poly)
    return conv(expr)


def _certainly_nonzero(poly, atoms, squares=None) -> bool:
    """Whether the polynomial ``poly`` (variables ``atoms``) is certifiably non-zero at one point:
    symbols at distinct small rationals, angles at 2/7, 3/7, ..., square roots and ``i`` at their
    values, ``√P`` (``squares``: variable index -> ``P``) at the principal root of ``P`` there (an
    Arb ball, 128 bits, that excludes 0; complex balls throughout)."""
    squares = squares or {}
    ctx = flint.ctx
    old = ctx.prec
    try:
        ctx.prec = 128
        vals = []
        k = 0
        for i, a in enumerate(atoms):
            k += 1
            if i in squares:
                vals.append(_evaluate(squares[i], vals + [flint.acb(0)] * (len(atoms) - len(vals))).sqrt())
            elif a is sp.I:
                vals.append(flint.acb(0, 1))
            elif a.is_Symbol:
                vals.append(flint.acb(flint.arb(flint.fmpq(k + 2, 7 * k + 3))))
            elif a.is_Pow:
                vals.append(flint.acb(flint.arb(flint.fmpq(int(a.base.p), int(a.base.q))).sqrt()))
            else:
                ang = flint.arb(flint.fmpq(2 + index_of(atoms, a), 7))
                vals.append(flint.acb(ang.cos() if isinstance(a, sp.cos) else ang.sin()))
        return not _evaluate(poly, vals).contains(0)
    finally:
        ctx.prec = old


def _evaluate(poly, vals):
    """``poly`` at the complex balls ``vals`` (one per variable)."""
    total = flint.acb(0)
    for exps, c in poly.to_dict().items():
        term = flint.acb(flint.arb(c))
        for v, x in zip(vals, exps):
            if x:
                term *= v ** x
        total += term
    return total


def index_of(atoms, a) -> int:
    """The position of the angle of ``a`` (``cos x`` or ``sin x``) among the angles of ``atoms``:
    the cosine and sine of one angle are evaluated at the same point."""
    angles = []
    for b in atoms:
        if isinstance(b, (sp.cos, sp.sin)) and b.args[0] not in angles:
            angles.append(b.args[0])
    return angles.index(a.args[0])


def _point_value(s, k):
    """The value of symbol ``s`` (the ``k``-th) at the test point: ``(k + 2)/(7k + 3)``, a positive
    non-integer rational in (1/7, 2/3]; None when that value contradicts an assumption of ``s``
    (an integer, negative, ... symbol), so that the point always lies in the symbols' domain."""
    v = sp.Rational(k + 2, 7 * k + 3)
    for fact, holds in s.assumptions0.items():
        if getattr(v, f"is_{fact}", None) != holds:
            return None
    return v


def nonzero_at_a_point(expr) -> bool:
    """True when ``expr`` is proved non-zero at one exact rational point of its symbols' domain
    (each symbol at a distinct positive rational that satisfies its assumptions), by a rigorous
    enclosure (SymPy's ``evalf(strict=True)``, whose digits are guaranteed) that excludes 0. Then
    ``expr`` is not identically zero, so no simplification makes it 0: ``simplify(expr) == 0``
    is False. False means undecided (zero there, undefined there, or not certified).

    >>> x = sp.Symbol("x", positive=True)
    >>> nonzero_at_a_point(x**2 - x), nonzero_at_a_point(sp.sqrt(x**2) - x), nonzero_at_a_point(1 / (x - sp.Rational(2, 3)))
    (True, False, False)
    >>> nonzero_at_a_point(sp.Symbol("n", integer=True) - 1)  # no point of the domain chosen: undecided
    False
    """
    expr = sp.sympify(expr)
    if not isinstance(expr, sp.Expr):
        return False
    symbols = sorted(expr.free_symbols, key=sp.default_sort_key)
    point = {}
    for k, s in enumerate(symbols):
        v = _point_value(s, k)
        if v is None:
            return False
        point[s] = v
    try:
        val = expr.xreplace(point) if point else expr
        if val.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
            return False
        parts = val.as_real_imag() if not val.is_extended_real else (val, sp.Integer(0))
        for part in parts:
            if part.is_Rational:
                if part != 0:
                    return True
                continue
            if part.has(sp.zoo, sp.nan, sp.oo, -sp.oo) or part.free_symbols:
                return False
            approx = part.evalf(30, strict=True)
            if approx.is_Number and approx.is_finite and approx != 0:
                return True
    except Exception:  # noqa: BLE001 - PrecisionExhausted (maybe 0), undefined: undecided
        return False
    return False


def is_zero(expr) -> bool:
    """``simplify(expr) == 0``, decided first by the exact tests of this module: True when
    :func:`is_zero_algebraic` proves ``expr`` zero (or its ``expand_trig``, when a sine or cosine
    has a compound angle such as ``τ − θ``), False when :func:`is_zero_rational_function`
    proves it a non-zero rational function (which no simplification makes 0) or
    :func:`nonzero_at_a_point` proves it non-zero at one point of its domain, and otherwise
    SymPy's ``simplify(expr) == 0`` (memoized, :mod:`derivations.memo`).

    >>> x = sp.Symbol("x")
    >>> is_zero((x + sp.sqrt(2))**2 - x**2 - 2*sp.sqrt(2)*x - 2), is_zero(x**2 - x), is_zero(sp.sqrt(x**2) - x)
    (True, False, False)
    """
    expr = sp.sympify(expr)
    if is_zero_algebraic(expr) or (_compound_angles(expr) and _is_zero_expanded_trig(expr)):
        return True
    if is_zero_rational_function(expr) is False or nonzero_at_a_point(expr):
        return False
    return simplify(expr) == 0  # SymPy's simplify, remembered (derivations.memo)


def _is_zero_expanded_trig(expr) -> bool:
    """:func:`is_zero_algebraic` of ``expand_trig(expr)`` (the addition formulas, an identity), with
    each sine and cosine of a number (``sin(2/5)``, left by the expansion of ``sin(2/5 + π/6)``)
    read as the sine and cosine of a fresh real symbol ``u``: zero for every ``u`` is zero at the
    number. Only where those symbols occur in no denominator and no root, so that the
    denominator :func:`is_zero_algebraic` proves non-zero does not depend on them."""
    expanded = sp.expand_trig(expr)
    numbers = sorted({f.args[0] for f in expanded.atoms(sp.sin, sp.cos) if not f.args[0].free_symbols},
                     key=sp.default_sort_key)
    if numbers:
        fresh = {x: sp.Dummy("u", real=True) for x in numbers}
        expanded = expanded.xreplace({f: f.func(fresh[f.args[0]]) for f in expanded.atoms(sp.sin, sp.cos)
                                      if f.args[0] in fresh})
        dummies = list(fresh.values())
        if any(not (p.exp.is_Integer and p.exp > 0) and p.base.has(*dummies) for p in expanded.atoms(sp.Pow)):
            return False
    return bool(is_zero_algebraic(expanded))


def _compound_angles(expr) -> bool:
    """Whether ``expr`` has a sine or cosine of something other than a symbol (``sin(τ − θ)``,
    ``cos(τ + π/3)``): :func:`is_zero` then also tries :func:`is_zero_algebraic` on its
    ``expand_trig`` (the addition formulas, an identity), whose angles are symbols."""
    return any(not f.args[0].is_Symbol for f in expr.atoms(sp.sin, sp.cos))


def _flint_fraction(expr):
    """``expr`` as ``(gens, P, Q)``, flint polynomials in SymPy's order of its free symbols with
    ``gcd(P, Q) = 1``; ``0`` for zero; ``None`` when it is not a rational function with rational
    coefficients of at least one symbol (the callers then use SymPy's own function)."""
    expr = sp.sympify(expr)
    if not isinstance(expr, sp.Expr) or expr.is_Number or not expr.free_symbols or not expr.is_commutative:
        return None
    from sympy.polys.polyutils import _sort_gens

    gens = _sort_gens(list(expr.free_symbols))
    try:
        n, d = to_fraction(expr, gens)
    except _NotRational:
        return None
    if n == 0:
        return 0
    g = n.gcd(d)
    return gens, n / g, d / g


def cancel(expr):
    """SymPy's ``cancel(expr)`` (the same expression, term for term), computed with python-flint
    for rational functions with rational coefficients; anything else goes to ``sympy.cancel``.

    ``sympy.cancel`` of such a function returns ``P/Q`` with ``P, Q`` coprime integer polynomials
    in the free symbols (ordered as SymPy orders generators), ``gcd(cont P, cont Q) = 1`` and the
    leading coefficient of ``Q`` (lex) positive: a normal form, which is computed here by one
    flint gcd instead of SymPy's (often a second or more on a 3×3 symbolic derivation).

    >>> x, y = sp.symbols("x y")
    >>> e = (x**2 - y**2) / (2*y - 2*x) + x / 3
    >>> cancel(e), sp.cancel(e)
    (-x/6 - y/2, -x/6 - y/2)
    """
    parts = _flint_fraction(expr)
    if parts is None:
        return sp.cancel(expr)
    if parts == 0:
        return sp.Integer(0)
    from sympy.polys.domains import ZZ
    from sympy.polys.rings import PolyRing

    gens, p, q = parts
    # integer coefficients with coprime joint content, then the sign of Q's leading coefficient
    den, _, content = _integer_scale(list(p.coeffs()) + list(q.coeffs()))
    scale = flint.fmpq(den, content)
    if q.leading_coefficient() < 0:
        scale = -scale
    p, q = p * scale, q * scale
    ring = PolyRing(gens, ZZ)
    P = ring.from_dict({k: ZZ(int(c.p)) for k, c in p.to_dict().items()}).as_expr()
    Q = ring.from_dict({k: ZZ(int(c.p)) for k, c in q.to_dict().items()}).as_expr()
    return P / Q


def _integer_scale(coeffs):
    """``(den, nums, content)`` of rational ``coeffs``: the lcm of their denominators, the integer
    coefficients ``c·den``, and the gcd of those."""
    den = 1
    for c in coeffs:
        den = den * int(c.q) // _igcd(den, int(c.q))
    nums = [int(c.p) * (den // int(c.q)) for c in coeffs]
    content = 0
    for v in nums:
        content = _igcd(content, v)
    return den, nums, content


def _integer_primitive(f):
    """``(c, P)`` with ``f = c·P``: ``c`` rational, ``P`` a dict of integer coefficients with content 1
    and positive leading coefficient (lex), the normalization of SymPy's ``factor_list`` factors."""
    d = f.to_dict()
    den, nums, g = _integer_scale(list(d.values()))
    ints = dict(zip(d, nums))
    if ints[max(ints)] < 0:
        g = -g
    return sp.Rational(g, den), {k: v // g for k, v in ints.items()}


def factor(expr):
    """SymPy's ``factor(expr)`` (the same expression) for a rational function with rational
    coefficients, computed with python-flint; anything else goes to ``sympy.factor``.

    ``sympy.factor`` of ``N/D`` writes ``c · Π fᵢ^mᵢ / Π gⱼ^nⱼ``: common factors of ``N`` and ``D``
    cancelled, each factor an integer polynomial in the free symbols (ordered as SymPy orders
    generators) of content 1 and positive leading coefficient (lex), ``c`` rational and kept
    outside the product (``_keep_coeff``). Flint's gcd and multivariate factorization give the same
    factors, in a fraction of SymPy's time on the symbolic derivations (a 3×3 mass matrix).

    >>> x, y = sp.symbols("x y")
    >>> e = (2*x**2 - 2*y**2) / (3*x - 3*y) - x / 2
    >>> factor(e), sp.factor(e)
    ((x + 4*y)/6, (x + 4*y)/6)
    >>> factor(-(x*y - y**2) / (4*x**3))
    -y*(x - y)/(4*x**3)
    """
    fraction = _flint_fraction(expr)
    if fraction is None:
        return sp.factor(expr)
    if fraction == 0:
        return sp.Integer(0)
    from sympy.core.mul import _keep_coeff

    gens, num, den = fraction
    coeff, parts = sp.Integer(1), []
    for poly, sign in ((num, 1), (den, -1)):
        c, factors = poly.factor()
        coeff *= sp.Rational(int(c.p), int(c.q)) ** sign
        for f, m in factors:
            cf, ints = _integer_primitive(f)
            coeff *= cf ** (sign * m)
            parts.append(sp.Poly.from_dict(ints, gens).as_expr() ** (sign * m))
    return _keep_coeff(coeff, sp.Mul(*parts))


def _igcd(a: int, b: int) -> int:
    import math

    return math.gcd(a, b)


def factored_numerator(expr, free_of=()):
    """The numerator ``N`` of ``expr = N / D`` (:func:`to_fraction`: ``D`` the product of the
    denominators, no gcd), factored over Q by python-flint, as a SymPy product of expanded
    factors (generators in SymPy's order). What ``sympy.factor(sympy.numer(sympy.together(expr)))``
    computes, up to factors of ``D``, in a fraction of its time.

    ``free_of``: symbols that ``D`` must not contain (raises ``ValueError`` otherwise), so that
    the roots of ``N`` in them are exactly those of ``expr``.

    >>> x, y = sp.symbols("x y")
    >>> factored_numerator(x / y - y / x, free_of=[x])
    Traceback (most recent call last):
    ...
    ValueError: the denominator x*y involves x
    >>> factored_numerator((x**2 - y**2) / (x + 1) ** 2, free_of=[x])
    Traceback (most recent call last):
    ...
    ValueError: the denominator x^2 + 2*x + 1 involves x
    >>> factored_numerator((x**2 - y**2) / y, free_of=[x])
    (x - y)*(x + y)
    """
    from sympy.polys.polyutils import _sort_gens

    expr = sp.sympify(expr)
    gens = _sort_gens(list(expr.free_symbols))
    n, d = to_fraction(expr, gens)
    for s in free_of:
        if s in gens and d.degrees()[gens.index(s)] > 0:
            raise ValueError(f"the denominator {d} involves {s}")
    c, factors = n.factor()
    out = sp.Rational(int(c.p), int(c.q))
    for f, m in factors:
        poly = sp.Poly.from_dict({k: sp.Rational(int(v.p), int(v.q)) for k, v in f.to_dict().items()}, gens)
        out *= poly.as_expr() ** m
    return out
