"""The exact DAG search of the orderings (sec. III-B), and the exact replay that verifies an ordering.

States are memoized on the velocity (rational data: python-flint ``fmpq`` tuples, the hot path
of the benchmarks; algebraic data: SymPy numbers, every sign certified).
"""

from __future__ import annotations

import sympy as sp
from flint import fmpq, fmpq_mat

from ...arithmetic import certified_sign
from ...errors import NonTermination
from .. import _reflection as _r
from .common import MAX_STATE_BITS, _Algebraic, _Rational, _all_rational, _dot


# ---------------------------------------------------------------------------------------------
# The search
# ---------------------------------------------------------------------------------------------
class _Graph:
    def __init__(self):
        self.vel: list = []
        self.legal: list = []
        self.children: list = []
        self.parent: list = []
        self.fallback: list = []
        self.index: dict = {}
        self.root = 0
        self.terminal_key: dict = {}
        self.outcome_index: dict = {}
        #: collapse leaves (restitution < 1): node -> (cycle (X, Y), exact outcome key)
        self.collapse: dict = {}


class _ExactSystem:
    """Exact data of ``M``, ``H``, ``v0`` in one backend, in sparse form.

    ``restitution`` (optional): one exact number ``e_i`` per contact; each single impact then
    applies ``G_{H_i}(e_i)`` (``None``: the elastic law, ``e_i = 1``, with the code path it had
    before restitution existed)."""

    def __init__(self, M: sp.Matrix, H: sp.Matrix, v0: sp.Matrix, restitution=None):
        E = sp.Matrix(list(restitution)) if restitution is not None else sp.zeros(0, 1)
        self.F = F = _Rational if _all_rational(M, H, v0, E) else _Algebraic
        self.n, self.k = M.shape[0], H.shape[0]
        n, k = self.n, self.k
        self.M = [[F.num(M[i, j]) for j in range(n)] for i in range(n)]
        self.H = [[F.num(H[i, j]) for j in range(n)] for i in range(k)]
        self.v0 = tuple(F.num(x) for x in v0)
        if F is _Rational:
            Wm = fmpq_mat(self.M).solve(fmpq_mat([list(col) for col in zip(*self.H)]) if k else fmpq_mat(n, 0))
            self.W = [[Wm[j, i] for j in range(n)] for i in range(k)]
        else:
            Ws = M.LUsolve(H.T)
            self.W = [[F.norm(Ws[j, i]) for j in range(n)] for i in range(k)]
        self.s = [_dot(self.H[i], self.W[i], F) for i in range(k)]
        if restitution is None:
            self.e = None
            self.coef = [F.norm(_r.gain(s)) if F is _Algebraic else _r.gain(s, fmpq(1)) for s in self.s]
        else:
            self.e = [F.num(x) for x in restitution]
            self.coef = [F.norm(_r.gain(s, e)) for s, e in zip(self.s, self.e)]
        self.rows = [[(j, h) for j, h in enumerate(r) if F.sign(h) != 0] for r in self.H]
        self.wcols = [[(j, w) for j, w in enumerate(c) if F.sign(w) != 0] for c in self.W]
        #: column i of the Gram matrix H M^-1 H^T, sparse: how w = H v changes when surface i acts
        self.gcols = [[(j, a) for j in range(k) if F.sign(a := self.w(self.W[i], j)) != 0] for i in range(k)]

    def w(self, v, i):
        F = self.F
        return F.norm(sum((h * v[j] for j, h in self.rows[i]), F.zero))

    def reflect(self, v, i, wi=None):
        F = self.F
        if wi is None:
            wi = self.w(v, i)
        return _r.reflect_sparse(v, self.wcols[i], self.coef[i] * wi, F.norm)

    def replay(self, order):
        v = self.v0
        p = [self.F.zero] * self.k
        for i in order:
            v, pi = self.reflect(v, i)
            p[i] = self.F.norm(p[i] + pi)
        return v, p


def _state_bits_error(states):
    return NonTermination(
        f"max_reflections: the exact states of the search exceed MAX_STATE_BITS={MAX_STATE_BITS} bits "
        f"after {states} states (the rationals grow with every reflection); lower max_reflections, give "
        "floats, or use the two-surface closed form")


def _cycle_error(cap):
    return NonTermination(
        f"max_reflections: a velocity recurred on its own ordering, so that ordering never ends "
        f"(the sequence of single impacts cycles; cap {cap})")


def _cap_error(cap):
    return NonTermination(
        f"max_reflections: an ordering needs more than {cap} reflections (the configured cap "
        f"max_reflections={cap}); raise the cap or use the two-surface closed form")


def _postorder(g):
    order = []
    seen = set()
    stack = [(g.root, False)]
    while stack:
        node, done = stack.pop()
        if done:
            order.append(node)
            continue
        if node in seen:
            continue
        seen.add(node)
        stack.append((node, True))
        for _, child in g.children[node]:
            if child not in seen:
                stack.append((child, False))
    return order


def _aggregate(g, key_of):
    """Per node and outcome: ordering count, shortest and longest length, and a pointer to the
    representative ordering (shortest, then lexicographically first: among equally short ones
    the smallest first surface, then the child's representative). Returns the root's table as
    ``{outcome key: [count, min_len, max_len, rep_order]}``."""
    post = _postorder(g)

    def leaf_key(nd):
        c = g.collapse.get(nd)
        return key_of(g.vel[nd]) if c is None else ("collapse", c[1])

    terminals = {leaf_key(nd) for nd in post if not g.children[nd]}
    if len(terminals) == 1:  # one outcome (the cradles): plain lists instead of per-node dicts
        (key,) = terminals
        cnt = [0] * len(g.vel)
        lo = [0] * len(g.vel)
        hi = [0] * len(g.vel)
        nxt: list = [None] * len(g.vel)
        for node in post:
            kids = g.children[node]
            if not kids:
                g.terminal_key[node] = key
                cnt[node] = 1
                continue
            c, l, h, p = 0, None, 0, None
            for i, child in kids:
                c += cnt[child]
                if hi[child] + 1 > h:
                    h = hi[child] + 1
                if l is None or (lo[child] + 1, i) < (l, p[0]):
                    l, p = lo[child] + 1, (i, child)
            cnt[node], lo[node], hi[node], nxt[node] = c, l, h, p
        rep = []
        node = g.root
        while nxt[node] is not None:
            i, node = nxt[node]
            rep.append(i)
        return {key: [cnt[g.root], lo[g.root], hi[g.root], tuple(rep)]}
    table: dict[int, dict] = {}
    best: dict[int, dict] = {}
    ids: dict = {}
    keys: list = []
    for node in post:
        kids = g.children[node]
        if not kids:
            key = leaf_key(node)
            g.terminal_key[node] = key
            oid = ids.setdefault(key, len(ids))
            if oid == len(keys):
                keys.append(key)
            table[node] = {oid: [1, 0, 0]}
            best[node] = {oid: None}
            continue
        acc: dict = {}
        ptr: dict = {}
        for i, child in kids:
            for oid, (cnt, lo, hi) in table[child].items():
                a = acc.get(oid)
                if a is None:
                    acc[oid] = [cnt, lo + 1, hi + 1]
                    ptr[oid] = (lo + 1, i, child)
                else:
                    a[0] += cnt
                    if hi + 1 > a[2]:
                        a[2] = hi + 1
                    if lo + 1 < a[1]:
                        a[1] = lo + 1
                    if (lo + 1, i) < ptr[oid][:2]:
                        ptr[oid] = (lo + 1, i, child)
        table[node] = acc
        best[node] = ptr
    out = {}
    for oid, (cnt, lo, hi) in table[g.root].items():
        rep = []
        node = g.root
        while best[node][oid] is not None:
            _, i, node = best[node][oid]
            rep.append(i)
        out[keys[oid]] = [cnt, lo, hi, tuple(rep)]
    return out


def _verified_replay(system, order):
    """The exact outcome of ``order`` and its impulse, verified before it is used or returned:
    every reflection acts on an approached surface (``H_i v < 0``: the count is consistent with
    the order), and :func:`impactsym.verify.verify_exact` (``H v⁺ ≥ 0``, energy, momentum, ``p ≥ 0``)."""
    from ...errors import VerificationError
    from ...verify import verify_exact

    F = system.F
    v = system.v0
    p = [F.zero] * system.k
    for step, i in enumerate(order):
        wi = system.w(v, i)
        if F.sign(wi) >= 0:
            raise VerificationError("sequential", f"ordering {tuple(order)[:20]}: reflection {step + 1} acts on "
                                                  f"surface {i}, which is not approached (H_{i + 1} v = {wi})")
        v, pi = system.reflect(v, i, wi)
        p[i] = F.norm(p[i] + pi)
    if system.e is None:
        verify_exact("sequential", system.M, system.H, list(system.v0), list(v), p)
    else:  # restitution < 1: energy is not conserved, and never gained
        verify_exact("sequential", system.M, system.H, list(system.v0), list(v), p, energy_ratio=None,
                     energy_at_most=1)
    return v, p


def _rational_key(v):
    """A hashable key of an fmpq vector (hashing fmpq itself goes through ``Fraction``, slowly)."""
    return tuple((x.p, x.q) for x in v)


class _Reflector:
    def __init__(self, system):
        self.system = system
        self.k = system.k

    def __call__(self, state, i, wi):
        v, w = state
        sysm = self.system
        F = sysm.F
        c = sysm.coef[i] * wi
        if F is _Rational:  # no normalization needed: fmpq is canonical
            out = list(v)
            for j, wj in sysm.wcols[i]:
                out[j] = v[j] - c * wj
            wn = list(w)
            for j, a in sysm.gcols[i]:
                wn[j] = w[j] - c * a
            return (tuple(out), tuple(wn)), -c
        out = list(v)
        for j, wj in sysm.wcols[i]:
            out[j] = F.norm(v[j] - c * wj)
        wn = list(w)
        for j, a in sysm.gcols[i]:
            wn[j] = F.norm(w[j] - c * a)
        return (tuple(out), tuple(wn)), F.norm(-c)


def _merge_exact_keys(keys, F):
    """Map each outcome key to a canonical key; rational keys are canonical, algebraic ones are
    compared pairwise with certified signs."""
    if F is _Rational:
        return {k: k for k in keys}
    canon: dict = {}
    reps: list = []
    for key in keys:
        for r in reps:
            if all(certified_sign(a - b) == 0 for a, b in zip(key, r)):
                canon[key] = r
                break
        else:
            reps.append(key)
            canon[key] = key
    return canon


def _path_to(g, node):
    """The edges (surface indices) from the root to ``node``."""
    path = []
    while g.parent[node] is not None:
        node, i = g.parent[node]
        path.append(i)
    return tuple(reversed(path))


def _explore(sign_of, reflect, v0, cap, holder, key_of=lambda v: v, collapse=None, cap_error=None):
    """Depth-first construction of the DAG of states, memoized on the velocity.

    ``sign_of(v, i, node) -> (sign, w_i)``; the graph is published in ``holder["g"]`` so that
    ``sign_of`` can replay a node's ordering exactly (float mode).

    ``collapse(node, i)`` (restitution < 1): ``None``, or ``(leaf state, cycle, exact key)`` when
    the edge ``i`` out of ``node`` starts an infinite alternation (inelastic collapse) whose limit
    is certified: the edge then ends at a collapse leaf (``g.collapse``), never shared in the
    memo. ``cap_error(path)`` builds the exception raised when a path exceeds ``cap``."""
    g = _Graph()
    holder["g"] = g
    counters = {"tests": 0}

    def new_node(v, parent):
        idx = len(g.vel)
        g.vel.append(v)
        g.parent.append(parent)
        g.fallback.append(False)
        g.children.append([])
        legal = []
        ws = {}
        for i in range(reflect.k):
            counters["tests"] += 1
            s, wi = sign_of(v, i, idx)
            if s < 0:
                legal.append(i)
                ws[i] = wi
        g.legal.append((tuple(legal), ws))
        return idx

    root = new_node(v0, None)
    g.index[key_of(v0)] = [root]
    state = {root: 1}
    stack = [(root, iter(g.legal[root][0]))]
    while stack:
        node, it = stack[-1]
        i = next(it, None)
        if i is None:
            stack.pop()
            state[node] = 2
            continue
        if collapse is not None:
            term = collapse(node, i)
            if term is not None:
                leaf_state, cycle, exact_key = term
                leaf = len(g.vel)
                g.vel.append(leaf_state)
                g.parent.append((node, i))
                g.fallback.append(False)
                g.children.append([])
                g.legal.append(((), {}))
                g.collapse[leaf] = (cycle, exact_key)
                g.children[node].append((i, leaf))
                state[leaf] = 2
                continue
        child_v, _ = reflect(g.vel[node], i, g.legal[node][1][i])
        child = None
        ckey = key_of(child_v)
        for cand in g.index.get(ckey, ()):
            if not g.fallback[cand]:
                child = cand
                break
            # a node whose signs were decided exactly is shared only with the same exact state
            same_exact = holder.get("same_exact")
            if same_exact is not None and same_exact(node, i, cand):
                child = cand
                break
        if child is None:
            if len(stack) > cap:
                if cap_error is not None:
                    raise cap_error(_path_to(g, node) + (i,))
                raise _cap_error(cap)
            child = new_node(child_v, (node, i))
            g.index.setdefault(ckey, []).append(child)
            g.children[node].append((i, child))
            state[child] = 1
            stack.append((child, iter(g.legal[child][0])))
        else:
            if state.get(child) == 1:
                raise _cycle_error(cap)
            g.children[node].append((i, child))
    g.root = root
    return g, counters["tests"]


def _explore_rational(system, cap):
    """:func:`_explore` specialized to rational data (the hot path of the benchmarks): states are
    ``(v, w = H v)`` tuples of ``fmpq``, ``w`` is updated through the Gram matrix, the memo key is
    the tuple of numerators and denominators of ``v`` (hashing ``fmpq`` goes through ``Fraction``)."""
    k = system.k
    coef, wcols, gcols = system.coef, system.wcols, system.gcols
    g = _Graph()
    vel, legal_of, children, parent = g.vel, g.legal, g.children, g.parent
    ws_of = []
    index = {}
    tests = 0
    v0 = system.v0
    w0 = tuple(system.w(v0, i) for i in range(k))

    def new_node(v, w, par):
        nonlocal tests
        idx = len(vel)
        vel.append(v)
        ws_of.append(w)
        parent.append(par)
        children.append([])
        tests += k
        legal_of.append(tuple(i for i in range(k) if w[i] < 0))
        return idx

    root = new_node(v0, w0, None)
    index[tuple([(x.p, x.q) for x in v0])] = root
    stored = 0  # bits of the exact velocities kept (the numbers of a long ordering grow linearly)
    state = {root: 1}
    stack = [(root, iter(legal_of[root]))]
    while stack:
        node, it = stack[-1]
        i = next(it, None)
        if i is None:
            stack.pop()
            state[node] = 2
            continue
        v, w = vel[node], ws_of[node]
        c = coef[i] * w[i]
        out = list(v)
        for j, wj in wcols[i]:
            out[j] = v[j] - c * wj
        key = tuple([(x.p, x.q) for x in out])
        child = index.get(key)
        if child is None:
            if len(stack) > cap:
                raise _cap_error(cap)
            stored += sum(p.bit_length() + q.bit_length() for p, q in key)
            if stored > MAX_STATE_BITS:
                raise _state_bits_error(len(vel))
            wn = list(w)
            for j, a in gcols[i]:
                wn[j] = w[j] - c * a
            child = new_node(tuple(out), tuple(wn), (node, i))
            index[key] = child
            children[node].append((i, child))
            state[child] = 1
            stack.append((child, iter(legal_of[child])))
        else:
            if state[child] == 1:
                raise _cycle_error(cap)
            children[node].append((i, child))
    g.fallback = [False] * len(vel)
    g.root = root
    return g, tests
