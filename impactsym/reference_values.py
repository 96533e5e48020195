"""High-precision references for the generated float kernels, and their condition numbers.

A float kernel is judged against a reference computed from the *same SymPy expressions the
derivation emitted* (not from the generated code), in mpmath at ``dps ≥ 50`` digits:

* inputs enter as the exact binary values of the float inputs (``mpmath.mpf(float)`` is exact;
  no decimal text is ever re-read);
* the formulas are compiled from their DAG (:class:`_DagEvaluator`): each shared subexpression once per
  call, lazily through ``Piecewise``, with the operations lambdify's mpmath printer would emit (a
  two-surface kernel's lambdified text repeats its 363 distinct nodes into 136 kB);
* a precision ladder checks every reference: it is recomputed at twice the digits and must agree
  with itself to ``TARGET_DPS − GUARD_DIGITS`` (40) digits; if not, the ladder climbs (``dps → 2·dps``) until
  two rungs agree, up to ``MAX_DPS`` (then :class:`ReferenceUnstable` is raised, never a guess);
* the componentwise relative condition number of output ``f_i`` with respect to the inputs,
  ``κ_i = Σ_j |x_j ∂f_i/∂x_j| / |f_i|``, comes from central differences of the exact formula in
  relative steps ``10^(−dps/2)`` at the working precision (about ``dps/2`` correct digits, ample
  for a condition number; symbolic derivatives of the larger kernels cost tens of seconds), at the
  upper rung of the ladder only (the lower rung's values are all the agreement test reads).

The accuracy target of the generated kernels (issue 5) is stated with these numbers: for every
output component, ``|f̂_i − f_i| ≤ c · eps · (|f_i| + Σ_j |x_j ∂f_i/∂x_j|)``, i.e. a relative error
of at most ``c · eps · (1 + κ_i)``. :func:`error_ratio` returns the left side divided by
``eps · (|f_i| + Σ_j |x_j ∂_j f_i|)``, which is finite also where ``f_i = 0``.

Examples
--------
>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> ref = Reference([x, y], [x - y])
>>> r = ref.evaluate({"x": 1.0, "y": 1.0 - 2.0**-30})
>>> r.values[0] == mpmath.mpf(2)**-30, r.digits_agreed >= 40
(True, True)
>>> float(r.condition[0]) > 2e9     # x − y near x = y: ill-conditioned by nature
True
>>> error_ratio(r, [1.0 - (1.0 - 2.0**-30)])[0]
0.0
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Mapping, Sequence

import mpmath
import numpy as np
from mpmath import libmp
from mpmath.libmp import (ComplexResult, from_float, from_int, mpf_add, mpf_div, mpf_mul, mpf_mul_int,  # noqa: F401
                          mpf_abs, mpf_rdiv_int, mpf_sub, to_float)
import sympy as sp
from sympy.printing.pycode import MpmathPrinter

__all__ = ["Reference", "ReferenceValue", "ReferenceUnstable", "OutsideDomain", "error_ratio", "relative_error",
           "EPS", "GUARD_DIGITS", "MAX_DPS", "kernel_reference"]

EPS = float(np.finfo(float).eps)
#: digits a reference may lose between two rungs of the ladder and still count as agreeing
GUARD_DIGITS = 10
#: the highest precision the ladder climbs to
MAX_DPS = 800
#: two rungs must agree to ``TARGET_DPS - GUARD_DIGITS`` digits (40): a cancellation of k digits
#: costs k digits at every rung, so asking for ``dps - GUARD_DIGITS`` at the higher rungs would make a
#: reference that loses more than 10 digits (e.g. ``1 - (1 - 1e-24)``) unreachable at any precision
TARGET_DPS = 50


class _MpmathPrinter(MpmathPrinter):
    """lambdify's mpmath printer with ``%`` parenthesized: SymPy 1.14 prints ``2*Mod(ceiling(x), 2)*y``
    inside a longer product as ``2*ceil(x) % 2*y`` (read by Python as ``((2*ceil(x)) % 2)*y``)."""

    def _print_Mod(self, expr):
        return "(" + super()._print_Mod(expr) + ")"

    def _print(self, expr, **kwargs):
        """Each distinct subexpression printed once (a node's text does not depend on where it
        stands): the catalog's two_surface_resolution_2 has 363 distinct nodes in 51 532."""
        if kwargs or not isinstance(expr, sp.Basic) or not expr.args:
            return super()._print(expr, **kwargs)
        memo = self.__dict__.setdefault("_memo", {})
        text = memo.get(expr)
        if text is None:
            text = memo[expr] = super()._print(expr)
        return text

#: lambdify's settings of its mpmath printer
_MPMATH_SETTINGS = {"fully_qualified_modules": False, "inline": True, "allow_unknown_functions": True,
                    "user_functions": {}}


def _mpmath_printer() -> _MpmathPrinter:
    return _MpmathPrinter(dict(_MPMATH_SETTINGS))


class _DagEvaluator:
    """The outputs' expression DAG compiled to one straight-line Python function of the inputs that
    evaluates it in mpmath, each shared subexpression once per call, lazily: a Piecewise evaluates
    its conditions in order and only the chosen branch, and ``And``/``Or`` short-circuit, exactly
    as the lambdified code does (the same mpmath operations on the same subexpressions, in the same
    order: division by zero, a real function of a complex value, ``None`` where no condition holds
    behave alike). The lambdified text of a two-surface kernel repeats its shared subexpressions
    hundreds of times (136 kB for 363 distinct nodes); here each is one line, without a Python call
    per node (issue 15: the accuracy tests evaluate some 50,000 references).

    The code is the depth-first walk from the roots (children in order), each node emitted where
    the walk first needs it. A node first needed inside a branch (of a Piecewise, or past the first
    operand of ``And``/``Or``) may or may not have been computed when the walk meets it again, so
    every later use of it is guarded (``if v is _U:``, the variable set to ``_U`` on entry): it is
    computed once, at the first place the call needs it, as a memo would.

    The code runs on mpmath's raw values (``mpf._mpf_`` tuples, through the ``libmp`` functions
    that the ``mpf`` operators and mpmath's functions call for the same operand types, in the same
    order: the same values without an ``mpf`` object per operation); where a value leaves the reals
    (``ComplexResult``: a square root of a negative number) the same code on ``mpf`` objects runs
    instead, which carries on in ``mpc`` as lambdify's code does.

    Only the node types below are known; :meth:`compile` returns ``None`` for anything else, or for
    a DAG whose code would pass :data:`MAX_LINES` lines (the caller keeps lambdify).

    >>> x, y = sp.symbols("x y")
    >>> outs = [1 / x + sp.sqrt(y**2 + sp.Rational(1, 3)) * sp.pi, x * y,
    ...         sp.Piecewise((sp.sqrt(y), (x < 0) & (y > 0)), (sp.sqrt(-y), y < 0), (0, True))]
    >>> f = _DagEvaluator.compile([x, y], outs)
    >>> g = sp.lambdify([x, y], outs, modules="mpmath", printer=_mpmath_printer())
    >>> with mpmath.workdps(30):
    ...     all(f(*xs) == g(*xs) for xs in [(mpmath.mpf(-1), mpmath.mpf(2)), (mpmath.mpf(1), mpmath.mpf(-2)),
    ...                                     (mpmath.mpf(1), mpmath.mpf(2))])
    True
    >>> _DagEvaluator.compile([x], [sp.Function("f")(x)]) is None   # an unknown function: lambdify
    True
    """

    _REL = {"GreaterThan": lambda a, b: a >= b, "LessThan": lambda a, b: a <= b,
            "StrictGreaterThan": lambda a, b: a > b, "StrictLessThan": lambda a, b: a < b,
            "Equality": lambda a, b: a == b, "Unequality": lambda a, b: a != b}
    _FUN = {"atan2": mpmath.atan2, "sin": mpmath.sin, "cos": mpmath.cos, "tan": mpmath.tan, "atan": mpmath.atan,
            "exp": mpmath.exp, "log": mpmath.log, "ceiling": mpmath.ceil, "floor": mpmath.floor, "Abs": abs}
    #: the straight-line text is compiled up to this many lines (beyond: lambdify)
    MAX_LINES = 100_000

    def __init__(self, args, outputs):
        self.index: dict = {}
        self.nodes: list = []  # (kind, payload, children)
        self.roots = [self._add(o) for o in outputs]
        self.argpos = {a: i for i, a in enumerate(args)}
        for kind, payload, _ in self.nodes:
            if kind == "sym" and payload not in self.argpos:
                raise _Unsupported(f"free symbol {payload}")

    @classmethod
    def compile(cls, args, outputs):
        """The function ``f(*xs) -> list`` of the outputs (mpmath values at the inputs ``xs``, in
        the order of ``args``), or ``None`` where the DAG has a node this evaluator does not know or
        is too long to compile."""
        try:
            dag = cls(args, outputs)
            plain = dag._function()
        except _Unsupported:
            return None
        try:
            fast = dag._function(raw=True)
        except _Unsupported:
            fast = None
        if plain is None or fast is None:
            return plain

        def evaluate(*xs):
            try:
                raw = [x._mpf_ for x in xs]
            except AttributeError:  # an input that is not an mpf
                return plain(*xs)
            try:
                return fast(*raw)
            except (ComplexResult, _Fallback):  # a value left the reals: the mpf code carries on in mpc,
                return plain(*xs)  # as lambdify's does

        evaluate.dag, evaluate.plain = dag, plain
        return evaluate

    def dependencies(self) -> list:
        """Per node, the set of inputs (positions) its value depends on."""
        if "_deps" not in self.__dict__:
            deps: list = []
            for kind, p, ch in self.nodes:
                d = {self.argpos[p]} if kind == "sym" else set()
                for c in ch:
                    d |= deps[c]
                deps.append(frozenset(d))
            self._deps = deps
        return self._deps

    def record(self, raw_xs):
        """``(outputs, node values)`` of the raw code at ``raw_xs`` (``mpf._mpf_`` tuples), or
        ``None`` where the raw code cannot run (a value leaves the reals, or another exception:
        the caller then evaluates as it would without the record)."""
        if "_record" not in self.__dict__:
            try:
                self._record = self._function(raw=True, record=True)
            except _Unsupported:
                self._record = None
        if self._record is None:
            return None
        try:
            return self._record(*raw_xs)
        except (ComplexResult, _Fallback, ArithmeticError, TypeError, AttributeError, ValueError):
            return None

    def partial(self, j: int, known_values, raw_xs):
        """The raw outputs at ``raw_xs`` where only input ``j`` differs from the point whose node
        values :meth:`record` gave: every node that does not depend on input ``j`` is taken from
        there (or computed, where that call did not need it), the others computed, in the same
        order as the full code (the same values, the same first exception). ``ComplexResult``
        where a value leaves the reals (the caller runs the mpf code)."""
        fs = self.__dict__.setdefault("_partials", {})
        if j not in fs:
            deps = self.dependencies()
            try:
                fs[j] = self._function(raw=True, known=frozenset(k for k, d in enumerate(deps) if j not in d))
            except _Unsupported:
                fs[j] = None
        if fs[j] is None:
            raise _Fallback("no raw code")
        return fs[j](known_values, *raw_xs)

    def _add(self, e) -> int:
        k = self.index.get(e)
        if k is not None:
            return k
        from sympy.functions.elementary.piecewise import ExprCondPair

        name = type(e).__name__
        if isinstance(e, sp.Symbol):
            node = ("sym", e, ())
        elif e is sp.nan:
            node = ("const", "nan", ())
        elif e.is_Integer:
            node = ("const", int(e), ())
        elif e.is_Rational:
            node = ("rat", (int(e.p), int(e.q)), ())
        elif e is sp.pi:
            node = ("pi", None, ())
        elif e is sp.true or e is sp.false:
            node = ("const", bool(e), ())
        elif isinstance(e, sp.UnevaluatedExpr):
            k = self._add(e.args[0])
            self.index[e] = k
            return k
        elif e.is_Add:
            node = ("add", None, tuple(self._add(a) for a in e.args))
        elif e.is_Mul:
            num = [a for a in e.args if not (a.is_Pow and a.exp == -1)]
            den = [a.base for a in e.args if a.is_Pow and a.exp == -1]
            node = ("mul", len(num), tuple(self._add(a) for a in num + den))
        elif e.is_Pow:
            b = self._add(e.base)
            if e.exp == sp.S.Half:
                node = ("sqrt", None, (b,))
            elif e.exp == -sp.S.Half:
                node = ("rsqrt", None, (b,))
            elif e.exp == -1:
                node = ("inv", None, (b,))
            elif e.exp.is_Integer:
                node = ("ipow", int(e.exp), (b,))
            else:
                node = ("pow", None, (b, self._add(e.exp)))
        elif name == "Mod":
            node = ("mod", None, (self._add(e.args[0]), self._add(e.args[1])))
        elif name in self._FUN:
            node = ("fun", name, tuple(self._add(a) for a in e.args))
        elif name in self._REL:
            node = ("rel", name, (self._add(e.lhs), self._add(e.rhs)))
        elif name in ("And", "Or", "Not"):
            node = (name.lower(), None, tuple(self._add(a) for a in e.args))
        elif isinstance(e, sp.Piecewise):
            kids = []
            for pair in e.args:
                if not isinstance(pair, ExprCondPair):
                    raise _Unsupported(name)
                kids += [self._add(pair.cond), self._add(pair.expr)]
            node = ("piecewise", None, tuple(kids))
        else:
            raise _Unsupported(name)
        self.nodes.append(node)
        k = self.index[e] = len(self.nodes) - 1
        return k

    def _function(self, raw: bool = False, record: bool = False, known=frozenset()):
        """The compiled function; ``raw``: the same code on mpmath's raw values (``mpf._mpf_``
        tuples and the ``libmp`` functions the ``mpf`` operators call, with the same operands in
        the same order: the same results, without an ``mpf`` object and its type dispatch per
        operation). A raw function raises ``ComplexResult`` where an operation leaves the reals
        (the caller then runs the ``mpf`` one); ``_Unsupported`` where a node's operand types
        are not the ones it knows (Python ints on both sides, a mixed Piecewise as an operand).

        ``record``: the function also returns every node's value (``_U`` where the call did not
        need it); ``known``: nodes whose values the function takes from such a list (its first
        argument), computing them only where that list has none (see :meth:`partial`)."""
        nodes, argpos = self.nodes, self.argpos
        consts: list = []
        lines: list = []
        emitted: set = set(known)  # nodes whose code is somewhere above (in some branch, maybe not taken)
        guarded: set = set()  # nodes tested against _U: set to _U on entry
        types: dict = {}  # raw: node -> "f" (an mpf tuple), "i" (a Python int), "b" (bool), "m" (mixed/None)

        def const(obj) -> str:
            consts.append(obj)
            return f"K[{len(consts) - 1}]"

        def gen(k, done, ind):
            """The variable of node ``k``, emitting its code at indentation ``ind`` where it is not
            in ``done`` (the nodes computed on every path to this line)."""
            if k in done:
                return done[k]
            if len(lines) > self.MAX_LINES:
                raise _Unsupported("too long")
            v = f"v{k}"
            if k in emitted:  # computed above in a branch the call may have taken: compute it at most once
                guarded.add(k)
                lines.append("    " * ind + f"if {v} is _U:")
                body(k, dict(done), ind + 1)
                # past the guard, k is computed on every path, and so is every node its value needed
                done.update((d, f"v{d}") for d in eager(k))
            else:
                body(k, done, ind)
            done[k] = v
            return v

        # raw: arguments of both a sin and a cos node (each pair computed by one mpf_cos_sin, at the first
        # of the two the call needs; ``cs<k>`` set to _U on entry)
        trig: dict = {}
        for n_kind, n_fun, n_ch in nodes:
            if raw and n_kind == "fun" and n_fun in ("sin", "cos"):
                trig.setdefault(n_ch[0], set()).add(n_fun)
        paired = {c for c, ps in trig.items() if len(ps) == 2}
        pairs: set = set()
        closure: dict = {}

        def eager(k) -> set:
            """The nodes computed whenever ``k`` is: its operands, but of a Piecewise, ``And`` and
            ``Or`` only the first condition or operand, and theirs."""
            if k not in closure:
                kind, _, ch = nodes[k]
                out = set()
                for c in (ch[:1] if kind in ("piecewise", "and", "or") else ch):
                    out.add(c)
                    out |= eager(c)
                closure[k] = out
            return closure[k]

        def need(t, *ks):
            if any(types[c] != t for c in ks):
                raise _Unsupported("operand types")

        def fold(op, acc, ta, c, tc):
            """``acc op c`` (raw: what the mpf operator calls for these operand types) and its type."""
            if not raw:
                return f"{acc} {op} {c}", None
            if ta == "f" and tc == "f":
                return f"{_RAW_BINARY[op]}({acc}, {c}, prec, rnd)", "f"
            if ta == "f" and tc == "i":  # mpf op int
                return {"+": f"mpf_add({acc}, from_int({c}), prec, rnd)",
                        "*": f"_mul_int({acc}, {c}, prec, rnd)",
                        "/": f"mpf_div({acc}, from_int({c}), prec, rnd)"}[op], "f"
            if ta == "i" and tc == "f":  # int op mpf: the mpf's reflected operator
                return {"+": f"mpf_add({c}, from_int({acc}), prec, rnd)",
                        "*": f"_mul_int({c}, {acc}, prec, rnd)",
                        "/": f"mpf_rdiv_int({acc}, {c}, prec, rnd)"}[op], "f"
            if {ta, tc} <= {"f", "i", "fi"} and "fi" in (ta, tc):  # a Piecewise of an mpf or an int: at run time
                return f"{_DYNAMIC[op]}({acc}, {c}, prec, rnd)", "f" if "f" in (ta, tc) else "fi"
            raise _Unsupported("operand types")

        def body(k, done, ind):
            emitted.add(k)
            kind, p, ch = nodes[k]
            v = f"v{k}"
            pad = "    " * ind

            def emit(text, pad=pad):
                lines.append(pad + text)

            t = "f"
            if kind == "sym":
                emit(f"{v} = xs[{argpos[p]}]")
            elif kind == "const":
                if p == "nan":
                    emit(f"{v} = {const(libmp.fnan if raw else mpmath.nan)}")
                else:
                    emit(f"{v} = {const(p)}")
                    t = "b" if isinstance(p, bool) else "i"
            elif kind == "pi":
                emit(f"{v} = mpf_pi(prec, rnd)" if raw else f"{v} = +mpmath.pi")
            elif kind == "rat":
                emit(f"{v} = mpf_div(mpf_pos(from_int({const(p[0])}), prec, rnd), "
                     f"mpf_pos(from_int({const(p[1])}), prec, rnd), prec, rnd)" if raw else
                     f"{v} = mpmath.mpf({const(p[0])}) / mpmath.mpf({const(p[1])})")
            elif kind in ("add", "mul"):
                if kind == "mul" and not p:
                    acc, t = "1", "i"
                else:
                    acc, t = gen(ch[0], done, ind), types.get(ch[0])
                emit(f"{v} = {acc}")
                steps = [("+", c) for c in ch[1:]] if kind == "add" else \
                    [("*", c) for c in ch[1:p]] + [("/", c) for c in ch[p if p else 0:]]
                for op, c in steps:
                    c_v = gen(c, done, ind)
                    text, t = fold(op, v, t, c_v, types.get(c))
                    emit(f"{v} = {text}")
            elif kind in ("sqrt", "rsqrt", "inv", "ipow"):
                a = gen(ch[0], done, ind)
                if raw:
                    if kind in ("sqrt", "rsqrt") and types[ch[0]] == "i":  # mpmath.sqrt converts an int exactly
                        a = f"from_int({a})"
                    else:
                        need("f", ch[0])
                    emit(f"{v} = " + {"sqrt": f"mpf_sqrt({a}, prec, rnd)",
                                      "rsqrt": f"mpf_rdiv_int(1, mpf_sqrt({a}, prec, rnd), prec, rnd)",
                                      "inv": f"mpf_rdiv_int(1, {a}, prec, rnd)",
                                      "ipow": f"mpf_pow_int({a}, {const(p)}, prec, rnd)"}[kind])
                else:
                    emit(f"{v} = " + {"sqrt": f"mpmath.sqrt({a})", "rsqrt": f"1 / mpmath.sqrt({a})",
                                      "inv": f"1 / {a}", "ipow": f"{a} ** {const(p)}"}[kind])
            elif kind in ("pow", "mod"):
                a = gen(ch[0], done, ind)
                b = gen(ch[1], done, ind)
                if raw and kind == "mod" and types[ch[1]] == "i":  # mpf % int
                    need("f", ch[0])
                    emit(f"{v} = mpf_mod({a}, from_int({b}), prec, rnd)")
                elif raw:
                    need("f", *ch)
                    emit(f"{v} = {'mpf_pow' if kind == 'pow' else 'mpf_mod'}({a}, {b}, prec, rnd)")
                else:
                    emit(f"{v} = {a} {'**' if kind == 'pow' else '%'} {b}")
            elif kind == "fun":
                args = [gen(c, done, ind) for c in ch]
                if raw:  # (an int argument converted exactly, as mpmath's functions do; Python's abs keeps an int)
                    need("f", *[c for c in ch if p == "Abs" or types[c] != "i"])
                    args = [f"from_int({a})" if types[c] == "i" else a for a, c in zip(args, ch)]
                    if p in ("sin", "cos") and ch[0] in paired:  # cos and sin of one argument: one mpf_cos_sin
                        pair = f"cs{ch[0]}"  # (its (cos, sin) are mpf_cos's and mpf_sin's, which call it)
                        pairs.add(pair)
                        emit(f"if {pair} is _U:")
                        emit(f"    {pair} = mpf_cos_sin({args[0]}, prec, rnd)")
                        emit(f"{v} = {pair}[{1 if p == 'sin' else 0}]")
                    else:
                        emit(f"{v} = {_RAW_FUN[p]}({', '.join(args)}, prec, rnd)")
                else:
                    emit(f"{v} = {const(self._FUN[p])}({', '.join(args)})")
            elif kind == "rel":
                a, b = (gen(c, done, ind) for c in ch)
                t = "b"
                if not raw:
                    emit(f"{v} = {const(self._REL[p])}({a}, {b})")
                else:  # a op b: the left mpf's comparison, or the right one's reflected where a is an int
                    ta, tb = types[ch[0]], types[ch[1]]
                    if ta == "f" and tb in ("f", "i"):
                        emit(f"{v} = {_raw_compare(p, a, b if tb == 'f' else f'from_int({b})')}")
                    elif ta == "i" and tb == "f":
                        emit(f"{v} = {_raw_compare(_REFLECTED[p], b, f'from_int({a})')}")
                    else:
                        raise _Unsupported("operand types")
            elif kind == "not":
                a = gen(ch[0], done, ind)
                if raw:
                    need("b", ch[0])
                emit(f"{v} = not {a}")
                t = "b"
            elif kind in ("and", "or"):  # all(...) / any(...): an operand only where the ones before decide nothing
                emit(f"{v} = {kind == 'or'}")
                scope, depth = done, ind
                for c in ch:
                    c_v = gen(c, scope, depth)
                    if raw:
                        need("b", c)
                    lines.append("    " * depth + (f"if {c_v}:" if kind == "and" else f"if not {c_v}:"))
                    scope, depth = dict(scope), depth + 1
                lines.append("    " * depth + f"{v} = {kind == 'and'}")
                t = "b"
            else:  # piecewise: conditions in order, only the chosen branch; None where none holds
                emit(f"{v} = None")
                scope, depth = done, ind
                branch_types = set()
                for i in range(0, len(ch), 2):
                    c_v = gen(ch[i], scope, depth)
                    if raw:
                        need("b", ch[i])
                    lines.append("    " * depth + f"if {c_v}:")
                    e_v = gen(ch[i + 1], dict(scope), depth + 1)
                    branch_types.add(types.get(ch[i + 1]))
                    lines.append("    " * (depth + 1) + f"{v} = {e_v}")
                    lines.append("    " * depth + "else:")
                    scope, depth = dict(scope), depth + 1
                lines.append("    " * depth + "pass")
                always = nodes[ch[-2]][0] == "const" and nodes[ch[-2]][1] is True
                t = "m"  # (None where no condition holds, or a mix of types)
                if always and branch_types <= {"f", "i", "fi"}:
                    t = branch_types.pop() if len(branch_types) == 1 else "fi"
            types[k] = t

        try:
            top: dict = {}
            outs = [gen(r, top, 1) for r in self.roots]  # (1: the function body's indentation)
            if len(lines) > self.MAX_LINES:
                raise _Unsupported("too long")
            unset = sorted(set(range(len(nodes))) - set(known) if record else guarded - set(known))
            init = [f"    {' = '.join(f'v{k}' for k in chunk)} = _U"
                    for chunk in (unset[i:i + 50] for i in range(0, len(unset), 50))]
            init += [f"    v{k} = B[{k}]" for k in sorted(known)]
            if pairs:
                init.append(f"    {' = '.join(sorted(pairs))} = _U")
            if raw:  # (the outputs back as mpf: an mpf tuple boxed, an int or None as it is)
                init.insert(0, "    prec, rnd = _ctx._prec_rounding")
                outs = [f"_make({o})" if types[r] == "f" else f"_box({o})" if types[r] in ("m", "fi") else o
                        for o, r in zip(outs, self.roots)]
            ret = f"[{', '.join(outs)}]"
            if record:
                ret = f"{ret}, [{', '.join(f'v{k}' for k in range(len(nodes)))}]"
            text = f"def _straight({'B, ' if known else ''}*xs):\n" + "\n".join(init + lines) + f"\n    return {ret}\n"
            ns = {"mpmath": mpmath, "K": consts, "_U": _UNSET, **_RAW_NAMESPACE}
            exec(compile(text, "<reference straight line>", "exec"), ns)
        except (RecursionError, SyntaxError, MemoryError):
            return None
        return ns["_straight"]


def _raw_compare(name, a, b) -> str:
    """``a name b`` for mpf tuples, as the mpf operator computes it (``!=`` is ``not ==``)."""
    return {"GreaterThan": f"mpf_ge({a}, {b})", "LessThan": f"mpf_le({a}, {b})",
            "StrictGreaterThan": f"mpf_gt({a}, {b})", "StrictLessThan": f"mpf_lt({a}, {b})",
            "Equality": f"mpf_eq({a}, {b})", "Unequality": f"(not mpf_eq({a}, {b}))"}[name]


#: ``b op' a`` for ``a op b`` (Python's reflected comparison where ``a`` is an int)
_REFLECTED = {"GreaterThan": "LessThan", "LessThan": "GreaterThan", "StrictGreaterThan": "StrictLessThan",
              "StrictLessThan": "StrictGreaterThan", "Equality": "Equality", "Unequality": "Unequality"}
_RAW_BINARY = {"+": "mpf_add", "*": "mpf_mul", "/": "mpf_div"}
#: SymPy function -> the libmp function its mpmath counterpart applies to an mpf (``Abs``: ``mpf.__abs__``)
_RAW_FUN = {"atan2": "mpf_atan2", "sin": "mpf_sin", "cos": "mpf_cos", "tan": "mpf_tan", "atan": "mpf_atan",
            "exp": "mpf_exp", "log": "mpf_log", "ceiling": "mpf_ceil", "floor": "mpf_floor", "Abs": "mpf_abs"}


class _Fallback(Exception):
    """Raised by raw code where the mpf code computes something else than an mpf (``int / int``)."""


def _dynamic_add(a, b, prec, rnd):
    """``a + b`` of an mpf tuple or a Python int each, as the mpf operators compute it."""
    if type(a) is tuple:
        return mpf_add(a, b, prec, rnd) if type(b) is tuple else mpf_add(a, from_int(b), prec, rnd)
    return mpf_add(b, from_int(a), prec, rnd) if type(b) is tuple else a + b


def _dynamic_mul(a, b, prec, rnd):
    if type(a) is tuple:
        return mpf_mul(a, b, prec, rnd) if type(b) is tuple else _mul_int(a, b, prec, rnd)
    return _mul_int(b, a, prec, rnd) if type(b) is tuple else a * b


def _mul_int(s, n, prec, rnd):
    """``mpf_mul_int(s, n, prec, rnd)``; where ``n`` is ±1 or ±2 and ``s`` a normalized finite non-zero
    value (odd mantissa) of at most ``prec`` bits the product is exact, and its normalized tuple is
    written directly (``mpf_mul_int`` multiplies the mantissa, counts its bits and normalizes back to
    this): the emitted formulas' ``-1 * x`` of every subtraction (issue 15)."""
    sign, man, exp, bc = s
    if man & 1 and bc <= prec:
        if n == -1:
            return (sign ^ 1, man, exp, bc)
        if n == 2:
            return (sign, man, exp + 1, bc)
        if n == -2:
            return (sign ^ 1, man, exp + 1, bc)
        if n == 1:
            return s
    return mpf_mul_int(s, n, prec, rnd)


def _dynamic_div(a, b, prec, rnd):
    if type(a) is tuple:
        return mpf_div(a, b, prec, rnd) if type(b) is tuple else mpf_div(a, from_int(b), prec, rnd)
    if type(b) is tuple:
        return mpf_rdiv_int(a, b, prec, rnd)
    raise _Fallback("int / int")


_DYNAMIC = {"+": "_dynamic_add", "*": "_dynamic_mul", "/": "_dynamic_div"}


def _box(v):
    return mpmath.mp.make_mpf(v) if type(v) is tuple else v


_RAW_NAMESPACE = {"_ctx": mpmath.mp, "_make": mpmath.mp.make_mpf, "_box": _box, "_dynamic_add": _dynamic_add,
                  "_dynamic_mul": _dynamic_mul, "_dynamic_div": _dynamic_div, "_mul_int": _mul_int,
                  **{name: getattr(libmp, name) for name in
                     ("fnan", "from_int", "mpf_pi", "mpf_pos", "mpf_add", "mpf_mul", "mpf_mul_int", "mpf_div",
                      "mpf_rdiv_int", "mpf_sqrt", "mpf_pow_int", "mpf_pow", "mpf_mod", "mpf_ge", "mpf_le", "mpf_gt",
                      "mpf_lt", "mpf_eq", "mpf_cos_sin", *_RAW_FUN.values())}}


class _Unsupported(Exception):
    pass


_UNSET = object()


class OutsideDomain(ArithmeticError):
    """The exact value is not real (the inputs lie outside the formula's domain, e.g. D < 0):
    a float kernel must answer NaN there, in the components listed in ``nonreal``."""

    nonreal: list = []


class ReferenceUnstable(ArithmeticError):
    """Two rungs of the precision ladder never agreed up to :data:`MAX_DPS` digits."""


@dataclass
class ReferenceValue:
    """A checked reference: values, the first-order sensitivity ``Σ_j |x_j ∂f_i/∂x_j|`` and
    ``κ_i`` (``inf`` where ``f_i = 0``), the precision used and the digits the ladder agreed to."""

    values: list
    sensitivity: list
    condition: list
    dps: int
    digits_agreed: float


class Reference:
    """mpmath reference (with precision ladder and condition numbers) of SymPy expressions.

    Parameters
    ----------
    args : sequence of sympy.Symbol
        The inputs, in order; :meth:`evaluate` takes a mapping from their names to floats.
    outputs : sequence of sympy.Expr
        The exact formulas (as the derivation emitted them).
    """

    def __init__(self, args: Sequence[sp.Symbol], outputs: Sequence[sp.Expr]):
        self.args = list(args)
        self.names = [str(a) for a in self.args]
        self.outputs = [sp.sympify(o) for o in outputs]
        self._lambdified = None
        self._compiled = None

    @property
    def _f(self):
        """The function of the inputs that evaluates the outputs (mpmath): the compiled DAG, or
        lambdify's where the DAG has a node the compiler does not know; compiled on first use."""
        if self._compiled is None:
            self._compiled = _DagEvaluator.compile(self.args, self.outputs) or self.lambdified
        return self._compiled

    @_f.setter
    def _f(self, f):
        self._compiled = f
        for memo in ("_memo", "_checked_memo"):  # values of the previous function
            self.__dict__.pop(memo, None)

    @property
    def lambdified(self):
        """The outputs lambdified to mpmath (what :class:`_DagEvaluator`'s function computes, each
        shared subexpression once)."""
        if self._lambdified is None:
            self._lambdified = sp.lambdify(self.args, self.outputs, modules="mpmath", printer=_mpmath_printer())
        return self._lambdified

    def _values(self, xs, evaluate=None):
        try:
            raw = (evaluate or self._f)(*xs)
        except ZeroDivisionError:
            raise OutsideDomain("the exact value divides by zero at these inputs (degenerate input)") from None
        except (AttributeError, TypeError):  # a real-only mpmath function (atan2, ceil) given a complex value
            err = OutsideDomain("the exact value is not real at these inputs (a real function of a complex value)")
            err.nonreal = list(range(len(self.outputs)))
            raise err from None
        mpf, prec = mpmath.mpf, mpmath.mp.prec
        if all(type(v) is mpf and v._mpf_[3] <= prec for v in raw):  # real, and already at this precision:
            return list(raw)  # mpmath.mpf(v) would be v
        nonreal = [i for i, v in enumerate(raw) if isinstance(v, mpmath.mpc) and v.imag != 0]
        if nonreal:
            err = OutsideDomain(f"the exact value is not real at these inputs (e.g. D < 0): {raw}")
            err.nonreal = nonreal
            raise err
        return [mpmath.mpf(v.real if isinstance(v, mpmath.mpc) else v) for v in raw]

    #: how many points' values :meth:`_base` keeps (a point's screening by :meth:`values` is
    #: followed by :meth:`evaluate` at the same point and rungs)
    _MEMO_POINTS = 4

    def _base(self, xs):
        """``_values(xs)`` at the current precision, remembered for the last few points: the same
        operations at the same precision give the same values (a fresh list each time)."""
        key = (tuple(x._mpf_ for x in xs), *mpmath.mp._prec_rounding)  # (the values' tuples: hashed in C)
        memo = self.__dict__.setdefault("_memo", {})
        hit = memo.get(key)
        if hit is None:
            hit = self._values(xs)
            if len(memo) >= self._MEMO_POINTS * 4:
                memo.pop(next(iter(memo)))
            memo[key] = hit
        return list(hit)

    def _try(self, xs, evaluate=None):
        """``_values(xs)``, or ``None`` outside the domain (one evaluation, not a test and then another)."""
        try:
            return self._values(xs, evaluate)
        except OutsideDomain:
            return None

    #: :meth:`_moved` compiles the partial codes after this many calls per node of the DAG
    _PARTIAL_AFTER = 4

    def _moved(self, xs):
        """``j -> f(*ys)`` for points ``ys`` that differ from ``xs`` in input ``j`` alone: the
        nodes that do not depend on input ``j`` are reused from one evaluation at ``xs`` (at the
        current precision), the rest computed as the full code does (the same values and
        exceptions); ``None`` where that is not available (then every point is evaluated in full)."""
        dag = getattr(self._f, "dag", None)
        if dag is None:
            return None
        # each input's partial code is compiled once (about 0.1 ms per node) and saves 15-30 % of a
        # full evaluation: worth it only for a reference evaluated many times (the bench's grids; the
        # tests evaluate a two-surface reference some 100 times, against 4 x 339 here)
        self._moved_calls = getattr(self, "_moved_calls", 0) + 1
        if self._moved_calls <= self._PARTIAL_AFTER * len(dag.nodes):
            return None
        try:
            raw_xs = [x._mpf_ for x in xs]
        except AttributeError:
            return None
        rec = dag.record(raw_xs)
        if rec is None:
            return None
        known = rec[1]

        def at(j):
            def evaluate(*ys):
                try:
                    return dag.partial(j, known, [y._mpf_ for y in ys])
                except (ComplexResult, _Fallback):  # the mpf code, as the full evaluation would
                    return self._f.plain(*ys)
            return evaluate

        return at

    def _at(self, xs, dps):
        """Values, and ``Σ_j |x_j ∂f/∂x_j|`` by central differences in relative steps ``δ = 10^(−dps/2)``
        (``x_j ∂f/∂x_j ≈ (f(x_j(1+δ)) − f(x_j(1−δ)))/(2δ)``, accurate to about ``dps/2`` digits; a
        step function such as ``ceiling`` contributes 0 except within ``δ`` of its jumps)."""
        with mpmath.workdps(dps):
            vals = self._base(xs)
            delta = mpmath.mpf(10) ** (-(dps // 2))
            prec, rnd = mpmath.mp._prec_rounding
            sens = [libmp.fzero] * len(vals)  # (raw: s + |a - b| / width as the mpf operators compute it)
            moved = self._moved(xs) if any(xs) else None
            for j, x in enumerate(xs):
                if x == 0:
                    continue
                up, down = list(xs), list(xs)
                up[j], down[j] = x * (1 + delta), x * (1 - delta)
                ev = moved(j) if moved is not None else None
                fu, fd = self._try(up, ev), self._try(down, ev)
                if fu is not None and fd is not None:
                    width = 2 * delta
                elif fu is not None:  # on the domain's boundary: one-sided
                    fd, width = vals, delta
                elif fd is not None:
                    fu, width = vals, delta
                else:  # an isolated point of the domain along x_j (e.g. D = 0 exactly with D < 0 on
                    # both sides): no derivative, the condition number is infinite (not 0)
                    sens = [libmp.finf] * len(vals)
                    continue
                w = width._mpf_
                sens = [mpf_add(s, mpf_div(mpf_abs(mpf_sub(a._mpf_, b._mpf_, prec, rnd), prec, rnd), w, prec, rnd),
                                prec, rnd) for s, a, b in zip(sens, fu, fd)]
            return vals, [_make_mpf(s) for s in sens]

    #: how many checked results (:meth:`values`, :meth:`evaluate`) each reference keeps: a
    #: general-dimension kernel's grid is its closed form's, point for point, against the same
    #: reference (issue 15), and a screened point is evaluated again in full
    _CHECKED_POINTS = 4096

    def _checked(self, kind: str, xs: list, dps: int, compute):
        """``compute()`` remembered by ``(kind, inputs, dps, rounding)``: the result of the same
        operations on the same binary inputs at the same precisions (a fresh copy each time)."""
        key = (kind, tuple(xs), dps, mpmath.mp._prec_rounding[1])
        memo = self.__dict__.setdefault("_checked_memo", {})
        hit = memo.get(key)
        if hit is None:
            hit = compute()
            if len(memo) >= self._CHECKED_POINTS:
                memo.pop(next(iter(memo)))
            memo[key] = hit
        if kind == "values":
            return list(hit[0]), hit[1]
        return ReferenceValue(list(hit.values), list(hit.sensitivity), list(hit.condition), hit.dps, hit.digits_agreed)

    def values(self, inputs: Mapping[str, float], dps: int = 50) -> tuple[list, int]:
        """Values only (no condition numbers), checked by the same ladder: ``(values, dps_used)``.

        Cheap screening for large grids: where a float result is within ``c · eps · |f|`` of these
        values its error ratio is at most ``c`` whatever the condition number, so
        :meth:`evaluate` (``2n + 1`` evaluations per rung) is needed only at the other points.

        >>> x, y = sp.symbols("x y")
        >>> vals, d = Reference([x, y], [x - y]).values({"x": 1.0, "y": 0.5})
        >>> vals[0] == mpmath.mpf(0.5), d
        (True, 100)
        """
        fx = [float(inputs[n]) for n in self.names]
        return self._checked("values", fx, dps, lambda: self._ladder_values(fx, dps, inputs))

    def _ladder_values(self, fx, dps, inputs):
        xs = _exact(fx)
        lo = dps
        with mpmath.workdps(lo):
            vals = self._base(xs)
        while True:
            hi = 2 * lo
            with mpmath.workdps(hi):
                vals2 = self._base(xs)
            need = min(lo, TARGET_DPS) - GUARD_DIGITS
            if _surely_agree(vals, vals2, need):  # (the digits themselves are not returned)
                return vals2, hi
            agreed = _digits_agreed(vals, vals2, hi, [mpmath.mpf(0)] * len(vals))
            if agreed >= need:
                return vals2, hi
            if hi >= MAX_DPS:
                raise ReferenceUnstable(
                    f"reference at {lo} and {hi} digits agrees to only {agreed:.1f} digits (inputs {dict(inputs)})")
            lo, vals = hi, vals2

    def evaluate(self, inputs: Mapping[str, float], dps: int = 50) -> ReferenceValue:
        """Evaluate at the exact binary values of ``inputs`` (floats), checked by the ladder."""
        if dps < 50:
            raise ValueError(f"dps: references are computed with at least 50 digits, got {dps}")
        fx = [float(inputs[n]) for n in self.names]
        return self._checked("evaluate", fx, dps, lambda: self._ladder_evaluate(fx, dps, inputs))

    def _ladder_evaluate(self, fx, dps, inputs) -> ReferenceValue:
        xs = _exact(fx)
        lo = dps
        with mpmath.workdps(lo):  # the lower rung's sensitivity is never read: values only
            vals = self._base(xs)
        while True:
            hi = 2 * lo
            vals2, sens2 = self._at(xs, hi)
            agreed = _digits_agreed(vals, vals2, hi, sens2)
            if agreed >= min(lo, TARGET_DPS) - GUARD_DIGITS:
                break
            if hi >= MAX_DPS:
                raise ReferenceUnstable(
                    f"reference at {lo} and {hi} digits agrees to only {agreed:.1f} digits (inputs {dict(inputs)})")
            lo, vals = hi, vals2
        with mpmath.workdps(hi):
            cond = [s / abs(v) if v != 0 and not mpmath.isnan(v) else mpmath.inf for v, s in zip(vals2, sens2)]
        return ReferenceValue(vals2, sens2, cond, hi, agreed)


@lru_cache(maxsize=None)
def kernel_reference(name: str) -> Reference:
    """The reference of a generated closed-form kernel (by kernel or codegen name), built from the
    exact formulas the derivation emitted (recorded in ``impactsym/kernels/catalog.json``).

    >>> ref = kernel_reference("impulse-ratio-root")
    >>> [float(x) for x in ref.evaluate({"A": 1.0, "B": -3.0, "C": 2.0}).values]
    [2.0, 1.0]
    """
    for k in _catalog_kernels():
        if name in (k["name"], k["codegen_name"]) and k.get("sympy"):
            from sympy.functions.elementary.piecewise import ExprCondPair

            ns = {**vars(sp), "ExprCondPair": ExprCondPair}  # srepr text written by derivations/codegen.py
            args = [eval(a, ns) for a in k["sympy"]["args"]]
            return Reference(args, _eval_srepr(k["sympy"]["outputs"], ns))
    raise KeyError(f"no closed-form kernel {name!r} in the catalog")


@lru_cache(maxsize=1)
def _catalog_kernels() -> list:
    import json
    from pathlib import Path

    return json.loads((Path(__file__).resolve().parent / "kernels" / "catalog.json").read_text())["kernels"]


#: a call whose arguments contain no call: ``Name(...)`` without parentheses inside
_INNERMOST_CALL = re.compile(r"[A-Za-z_]\w*\([^()]*\)")


def _eval_srepr(texts, ns) -> list:
    """``[eval(t, ns) for t in texts]`` for ``srepr`` texts, each distinct call evaluated once: the
    innermost calls are evaluated and replaced by names, repeatedly (the same constructors on the same
    arguments, bottom up, as ``eval`` calls them). A kernel's srepr repeats its shared subexpressions:
    two_surface_resolution_2's six outputs are 338 kB for 339 distinct nodes (``eval`` 0.32 s, 0.15 s
    here). Texts with a parenthesis inside a string literal are evaluated as they are.

    >>> x = sp.Symbol("x", real=True)
    >>> texts = [sp.srepr(sp.sqrt(x**2 + 1) + x), sp.srepr(1 / sp.sqrt(x**2 + 1))]
    >>> _eval_srepr(texts, vars(sp)) == [eval(t, vars(sp)) for t in texts]
    True
    """
    texts = list(texts)
    if any("(" in lit or ")" in lit for t in texts for lit in re.findall(r"'([^']*)'", t)):
        return [eval(t, ns) for t in texts]
    env, names = dict(ns), {}

    def name(m) -> str:
        call = m.group(0)
        n = names.get(call)
        if n is None:
            n = names[call] = f"_srepr{len(names)}"
            env[n] = eval(call, env)
        return n

    while True:
        reduced = [_INNERMOST_CALL.sub(name, t) for t in texts]
        if reduced == texts:
            return [eval(t, env) for t in texts]
        texts = reduced


def _exact(fx) -> list:
    """The floats ``fx`` as mpf, exactly (their binary values, at any precision); each float converted
    once (the grids' inputs are a few corner values: 1.0, 1e-12, ...)."""
    out = []
    for x in fx:
        m = _EXACT.get(x)
        if m is None:
            if len(_EXACT) >= 4096:
                _EXACT.clear()
            m = _EXACT[x] = _make_mpf(from_float(x))  # (0.0 and -0.0 share a key, and an mpf: zero)
        out.append(m)
    return out


_EXACT: dict = {}


_make_mpf = mpmath.mp.make_mpf


def _surely_agree(a, b, digits) -> bool:
    """Whether :func:`_digits_agreed` of the rungs ``a`` and ``b`` is at least ``digits`` (whatever the
    sensitivities), read off the exponents alone: every pair of components is equal, or finite, non-zero
    and differs by less than ``2^-k`` times the larger, with ``2^(1-k) < 10^-(digits+1)``. ``False``
    where that does not settle it (the caller then counts the digits).

    >>> with mpmath.workdps(50):
    ...     a = mpmath.mpf(1) / 3
    >>> with mpmath.workdps(100):
    ...     b = mpmath.mpf(1) / 3
    >>> _surely_agree([a, mpmath.mpf(2)], [b, mpmath.mpf(2)], 40), _surely_agree([a], [b], 52)
    (True, False)
    """
    bits = math.ceil((digits + 1) * math.log2(10)) + 2
    for x, y in zip(a, b):
        x, y = x._mpf_, y._mpf_
        if x == y:  # (NaN in both as well: no digits to count)
            continue
        if not x[1] or not y[1]:  # a zero, an infinity or a NaN
            return False
        d = mpf_sub(x, y)  # (exact): |d| < 2^(exp + bc), |x| >= 2^(exp + bc - 1)
        if d[2] + d[3] > max(x[2] + x[3], y[2] + y[3]) - bits:
            return False
    return True


def _digits_agreed(a, b, dps, sens) -> float:
    """Digits to which two rungs agree, relative to ``max(|f|, Σ|x ∂f|)`` (so an exact zero, whose
    rungs differ by ~10^-dps, agrees as well as its sensitivity allows)."""
    worst = float(dps)
    with mpmath.workdps(dps):
        rel = [abs(x - y) / max(abs(x), abs(y), s) for x, y, s in zip(a, b, sens)
               if not (x == y or (mpmath.isnan(x) and mpmath.isnan(y)))]
        rel = [r for r in rel if not mpmath.isnan(r)]  # (a NaN against a number: no digits to count)
        if rel:  # the fewest digits are those of the largest relative difference: one logarithm
            worst = min(worst, float(-mpmath.log10(max(rel))))
    return worst


def relative_error(ref: ReferenceValue, computed: Sequence[float]) -> list[float]:
    """``|f̂_i − f_i| / |f_i|`` per component (``inf`` where ``f_i = 0 ≠ f̂_i``, 0 where both are 0)."""
    out = []
    with mpmath.workdps(ref.dps):
        for v, c in zip(ref.values, computed):
            if mpmath.isnan(v) and np.isnan(float(c)):
                out.append(0.0)
                continue
            d = abs(mpmath.mpf(float(c)) - v)
            out.append(0.0 if d == 0 else (float(d / abs(v)) if v != 0 else float("inf")))
    return out


def error_ratio(ref: ReferenceValue, computed: Sequence[float]) -> list[float]:
    """``|f̂_i − f_i| / (eps · (|f_i| + Σ_j |x_j ∂f_i/∂x_j|))`` per component: the error in units of
    what a backward-stable evaluation may commit (≈ ``rel_err / (eps · (1 + κ_i))``).

    A non-finite computed value gives ``inf``, and so does a number where the exact value is NaN
    (a branch that does not exist).
    """
    out = []
    with mpmath.workdps(ref.dps):
        prec, rnd = mpmath.mp._prec_rounding
    eps, fzero = from_float(EPS), libmp.fzero
    for v, s, c in zip(ref.values, ref.sensitivity, computed):
        c, v = float(c), v._mpf_
        if v == libmp.fnan:  # "no such branch" (NaN) in both; or a number where there is none
            out.append(0.0 if math.isnan(c) else math.inf)
            continue
        if not math.isfinite(c):
            out.append(math.inf)
            continue
        # |mpf(c) - v| / (EPS * (|v| + s)) at the reference's precision, on raw tuples: the steps the mpf
        # operators take (mpf(c) is exact), without an mpf object per step
        d = mpf_abs(mpf_sub(from_float(c), v, prec, rnd), prec, rnd)
        scale = mpf_mul(mpf_add(mpf_abs(v, prec, rnd), s._mpf_, prec, rnd), eps, prec, rnd)
        out.append(0.0 if d == fzero else (to_float(mpf_div(d, scale, prec, rnd), rnd=rnd) if scale != fzero else math.inf))
    return out
