"""The exact DAG search of the orderings (sec. III-B), and the exact replay that verifies an ordering.

States are memoized on the velocity (rational data: python-flint ``fmpq`` tuples, the hot path
of the benchmarks; algebraic data: SymPy numbers, every sign certified).
"""

from __future__ import annotations

from flint import fmpq, fmpq_mat

from ...arithmetic import certified_sign
from ...errors import NonTermination
from .. import _reflection as _r
from .common import MAX_STATE_BITS, _Algebraic, _Rational, _all_rational, _dot

# SymPy and mpmath are imported on first use: the float path (and rational data) runs without them
from ...arithmetic import LazyModule
sp = LazyModule("sympy", globals(), "sp")


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
    before restitution existed).

    :meth:`from_sparse` builds the rational system from checked sparse data
    (:class:`~impactsym.laws.sequential.sparse.SparseRational`) without forming a dense matrix;
    the dense lists ``M``, ``H`` and ``W`` are then made on first use (the selection among
    several outcomes and the collapse test need them, the search does not)."""

    def __init__(self, M: sp.Matrix, H: sp.Matrix, v0: sp.Matrix, restitution=None):
        E = sp.Matrix(list(restitution)) if restitution is not None else sp.zeros(0, 1)
        self.F = F = _Rational if _all_rational(M, H, v0, E) else _Algebraic
        self.n, self.k = M.shape[0], H.shape[0]
        self.sparse = None
        n, k = self.n, self.k
        self._M = [[F.num(M[i, j]) for j in range(n)] for i in range(n)]
        self._H = [[F.num(H[i, j]) for j in range(n)] for i in range(k)]
        self.v0 = tuple(F.num(x) for x in v0)
        if F is _Rational:
            Wm = fmpq_mat(self._M).solve(fmpq_mat([list(col) for col in zip(*self._H)]) if k else fmpq_mat(n, 0))
            self._W = [[Wm[j, i] for j in range(n)] for i in range(k)]
        else:
            Ws = M.LUsolve(H.T)
            self._W = [[F.norm(Ws[j, i]) for j in range(n)] for i in range(k)]
        self.rows = [[(j, h) for j, h in enumerate(r) if F.sign(h) != 0] for r in self._H]
        self.wcols = [[(j, w) for j, w in enumerate(c) if F.sign(w) != 0] for c in self._W]
        self._finish(restitution)

    @classmethod
    def from_rationals(cls, M, H, v0, restitution=None):
        """The rational system of dense ``fmpq`` rows (``M``, ``H``), ``v0`` and optional ``fmpq``
        restitutions: the same data as ``_ExactSystem(Mx, Hx, vx)`` of the SymPy rationals with
        those values, built without SymPy (the float path's exact binary values)."""
        self = cls.__new__(cls)
        self.F = F = _Rational
        self.n, self.k = n, k = len(M), len(H)
        self.sparse = None
        self._M = [list(row) for row in M]
        self._H = [list(row) for row in H]
        self.v0 = tuple(v0)
        Wm = fmpq_mat(self._M).solve(fmpq_mat([list(col) for col in zip(*self._H)]) if k else fmpq_mat(n, 0))
        self._W = [[Wm[j, i] for j in range(n)] for i in range(k)]
        self.rows = [[(j, h) for j, h in enumerate(r) if F.sign(h) != 0] for r in self._H]
        self.wcols = [[(j, w) for j, w in enumerate(c) if F.sign(w) != 0] for c in self._W]
        self._finish(None if restitution is None else list(restitution))
        return self

    @classmethod
    def from_sparse(cls, data, restitution=None):
        """The rational system of checked sparse data: ``W_i = M⁻¹H_iᵀ`` by sparse solves with
        ``M``'s factor, the Gram columns by sparse products; O(non-zeros) for a diagonal or
        block-diagonal ``M``."""
        self = cls.__new__(cls)
        self.F = _Rational
        self.n, self.k = data.n, data.k
        self.sparse = data
        self._M = self._H = self._W = None
        self.v0 = data.v0
        self.rows = data.H
        self.wcols = data.solve_rows(data.H)
        self._finish(None if restitution is None else [_Rational.num(x) for x in restitution])
        return self

    def _finish(self, restitution):
        F, k = self.F, self.k
        self.s = [F.norm(sum((h * w for (_, h), (_, w) in _matched(self.rows[i], self.wcols[i])), F.zero))
                  for i in range(k)]
        if restitution is None:
            self.e = None
            self.coef = [F.norm(_r.gain(s)) if F is _Algebraic else _r.gain(s, fmpq(1)) for s in self.s]
        else:
            self.e = [F.num(x) for x in restitution]
            self.coef = [F.norm(_r.gain(s, e)) for s, e in zip(self.s, self.e)]
        # column i of the Gram matrix H M^-1 H^T, sparse: how w = H v changes when surface i acts;
        # only the contacts that share a coordinate with W_i can have a non-zero entry
        touching = _touching(self.rows)
        self.gcols = []
        for i in range(k):
            acc: dict = {}
            for c, w in self.wcols[i]:
                for j in touching.get(c, ()):
                    acc[j] = acc.get(j, F.zero) + _row_entry(self.rows[j], c) * w
            self.gcols.append([(j, F.norm(a)) for j, a in sorted(acc.items()) if F.sign(F.norm(a)) != 0])

    @property
    def M(self):
        if self._M is None:
            n, Z = self.n, self.F.zero
            self._M = [[row.get(j, Z) for j in range(n)] for row in self.sparse.M]
        return self._M

    @property
    def H(self):
        if self._H is None:
            self._H = [_dense(r, self.n, self.F.zero) for r in self.rows]
        return self._H

    @property
    def W(self):
        if self._W is None:
            self._W = [_dense(c, self.n, self.F.zero) for c in self.wcols]
        return self._W

    def w(self, v, i):
        F = self.F
        return F.norm(sum((h * v[j] for j, h in self.rows[i]), F.zero))

    def reflect(self, v, i, wi=None):
        F = self.F
        if wi is None:
            wi = self.w(v, i)
        return _r.reflect_sparse(v, self.wcols[i], self.coef[i] * wi, F.norm)

    def verify(self, law, v, p, energy="equal"):
        """Check an exact outcome ``v`` with impulse ``p`` before it is used or returned:
        :func:`impactsym.verify.verify_exact` (``energy="equal"``: energy conserved; ``"at_most"``:
        not gained (restitution < 1); ``None``: not checked), or its sparse form
        (:func:`~impactsym.laws.sequential.sparse.verify_outcome`) for sparse data."""
        if self.sparse is not None:
            from .sparse import verify_outcome

            verify_outcome(law, self.sparse, v, p, energy=energy)
            return
        from ...verify import verify_exact

        kw = {"energy_ratio": 1} if energy == "equal" else {"energy_ratio": None, "energy_at_most": 1} \
            if energy == "at_most" else {"energy_ratio": None}
        verify_exact(law, self.M, self.H, list(self.v0), list(v), p, **kw)

    def replay(self, order):
        v = self.v0
        p = [self.F.zero] * self.k
        for i in order:
            v, pi = self.reflect(v, i)
            p[i] = self.F.norm(p[i] + pi)
        return v, p


def _touching(rows):
    """``{coordinate c: [contacts j whose row H_j has a non-zero entry c]}`` of sparse rows: the
    contacts whose ``w_j = H_j v`` a change of ``v_c`` can change."""
    touching: dict = {}
    for j, r in enumerate(rows):
        for c, _ in r:
            touching.setdefault(c, []).append(j)
    return touching


def _dense(pairs, n, zero):
    out = [zero] * n
    for j, x in pairs:
        out[j] = x
    return out


def _row_entry(row, c):
    """Entry ``c`` of a sparse row ``[(j, x), ...]`` (``j`` increasing)."""
    lo, hi = 0, len(row)
    while lo < hi:
        mid = (lo + hi) // 2
        if row[mid][0] < c:
            lo = mid + 1
        else:
            hi = mid
    return row[lo][1]


def _matched(a, b):
    """The pairs of entries of two sparse rows at the same index."""
    bd = dict(b)
    return [((j, x), (j, bd[j])) for j, x in a if j in bd]


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
    system.verify("sequential", v, p, "equal" if system.e is None else "at_most")
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


def _explore(sign_of, reflect, v0, cap, holder, key_of=lambda v: v, collapse=None, cap_error=None,
             affected=None):
    """Depth-first construction of the DAG of states, memoized on the velocity.

    ``sign_of(v, i, node) -> (sign, w_i)``; the graph is published in ``holder["g"]`` so that
    ``sign_of`` can replay a node's ordering exactly (float mode).

    ``collapse(node, i)`` (restitution < 1): ``None``, or ``(leaf state, cycle, exact key)`` when
    the edge ``i`` out of ``node`` starts an infinite alternation (inelastic collapse) whose limit
    is certified: the edge then ends at a collapse leaf (``g.collapse``), never shared in the
    memo. ``cap_error(path)`` builds the exception raised when a path exceeds ``cap``.

    ``affected`` (optional, the float search): per contact ``i``, the contacts whose decision a
    reflection on ``i`` can change (those whose ``w_j`` changes: :attr:`_ExactSystem.gcols` and
    the float support, see :func:`~impactsym.laws.sequential.float_search._float_search`). A new
    state then re-decides only those and keeps its parent's other decisions, each equal to what
    deciding it again would give (the same ``w_j``, float and exact). ``sign_of`` returns
    ``(sign, w_i, exact)`` in this mode, ``exact`` saying the decision was re-made exactly; a state
    with an exactly made decision, inherited or not, is marked in ``g.fallback``, and
    ``holder["inherit_exact"](count)`` (when given) is told how many such decisions each new
    state inherited. The count of sign tests is of the decisions made (re-made ones in this mode)."""
    g = _Graph()
    holder["g"] = g
    counters = {"tests": 0}
    k = reflect.k
    #: incremental mode: per open state, which of its decisions were made exactly (1) or in floats
    exact_of: dict = {}
    inherit_exact = holder.get("inherit_exact")

    def new_node(v, parent):
        idx = len(g.vel)
        g.vel.append(v)
        g.parent.append(parent)
        g.fallback.append(False)
        g.children.append([])
        if affected is None:
            legal = []
            ws = {}
            for i in range(k):
                counters["tests"] += 1
                s, wi = sign_of(v, i, idx)
                if s < 0:
                    legal.append(i)
                    ws[i] = wi
            g.legal.append((tuple(legal), ws))
            return idx
        if parent is None:
            redo = range(k)
            legal_set: set = set()
            ws = {}
            ex = bytearray(k)
        else:
            pnode, pi = parent
            redo = affected[pi]
            plegal, pws = g.legal[pnode]
            legal_set = set(plegal)
            ws = dict(pws)
            ex = bytearray(exact_of[pnode])
            kept = ex.count(1) - sum(ex[j] for j in redo)
            if kept:
                g.fallback[idx] = True
                if inherit_exact is not None:
                    inherit_exact(kept)
        for i in redo:
            counters["tests"] += 1
            s, wi, exact = sign_of(v, i, idx)
            ex[i] = 1 if exact else 0
            if s < 0:
                legal_set.add(i)
                ws[i] = wi
            else:
                legal_set.discard(i)
                ws.pop(i, None)
        exact_of[idx] = ex
        g.legal.append((tuple(sorted(legal_set)), ws))
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
            exact_of.pop(node, None)  # a closed state makes no more children
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


def _explore_rational(system, cap, allowed=None):
    """:func:`_explore` specialized to rational data (the hot path): a state costs what its
    reflection changes, not the number of bodies.

    * A state is stored as the entries of ``v`` and of ``w = H v`` that differ from ``v0`` and
      ``w0`` (dicts). A reflection on contact ``i`` changes ``v`` only on the support of
      ``W_i = M⁻¹H_iᵀ`` (two entries for a chain with a diagonal ``M``) and ``w`` only on the
      non-zero entries of column ``i`` of the Gram matrix ``H M⁻¹ Hᵀ``.
    * Sign tests are incremental: the legal surfaces of the child are the parent's, re-decided
      only for the contacts whose ``w`` changed (``sign_tests`` counts those decisions).
    * The memo is keyed on a hash of the state updated with the changed entries only (each entry
      of ``v`` that differs from ``v0`` is stored with a mixed hash of ``(j, numerator,
      denominator)``, :func:`_mix`, the state's hash is their sum); states with equal hashes are compared
      exactly (their dicts of ``fmpq``) before they are shared, so a collision costs a
      comparison, never a wrong merge. An entry that returns to its value in ``v0`` is dropped:
      equal velocities have equal dicts.

    ``g.vel`` holds the dicts (``{j: (v_j, hash)}``); :func:`_diff_key` makes an outcome key.

    ``allowed`` (a set of contacts closed under the Gram graph, a component of
    :func:`impactsym.laws.sequential.independence.components`): only those contacts act; the
    others never change sign, since no allowed reflection changes their ``w``."""
    k = system.k
    coef, wcols, gcols = system.coef, system.wcols, system.gcols
    v0 = system.v0
    w0 = tuple(system.w(v0, i) for i in range(k))
    g = _Graph()
    vel, legal_of, children, parent = g.vel, g.legal, g.children, g.parent
    wdiff: list = [{}]
    hashes = [0]
    root_legal = tuple(i for i in range(k) if w0[i] < 0 and (allowed is None or i in allowed))
    tests = k if allowed is None else len(allowed)
    vel.append({})
    parent.append(None)
    children.append([])
    legal_of.append(root_legal)
    index: dict = {0: 0}  # state hash -> node (a list of nodes after a collision)
    stored = 0  # bits of the exact entries kept (the numbers of a long ordering grow linearly)
    state = [1]
    stack = [(0, iter(root_legal))]
    mask = (1 << 64) - 1
    while stack:
        node, it = stack[-1]
        i = next(it, None)
        if i is None:
            stack.pop()
            state[node] = 2
            continue
        vd, wd = vel[node], wdiff[node]
        c = coef[i] * wd.get(i, w0[i])
        nvd = dict(vd)
        h = hashes[node]
        bits = 0
        for j, wj in wcols[i]:
            x0 = v0[j]
            old = nvd.get(j)
            if old is None:
                x = x0 - c * wj
            else:
                h -= old[1]
                x = old[0] - c * wj
            if x == x0:
                nvd.pop(j, None)
            else:
                p, q = x.p, x.q
                hx = _mix((hash((p, q)) + j * 0x9E3779B97F4A7C15) & mask)
                h += hx
                nvd[j] = (x, hx)
                bits += p.bit_length() + q.bit_length()
        h &= mask
        found = index.get(h)
        child = None
        if found is not None:
            for cand in (found if isinstance(found, list) else (found,)):
                if vel[cand] == nvd:
                    child = cand
                    break
        if child is None:
            if len(stack) > cap:
                raise _cap_error(cap)
            stored += bits
            if stored > MAX_STATE_BITS:
                raise _state_bits_error(len(vel))
            nwd = dict(wd)
            legal = set(legal_of[node])
            for j, a in gcols[i]:
                y0 = w0[j]
                y = nwd.get(j, y0) - c * a
                if y == y0:
                    nwd.pop(j, None)
                else:
                    nwd[j] = y
                if y < 0:
                    legal.add(j)
                else:
                    legal.discard(j)
            tests += len(gcols[i])
            child = len(vel)
            vel.append(nvd)
            wdiff.append(nwd)
            hashes.append(h)
            parent.append((node, i))
            children.append([])
            legal_of.append(tuple(sorted(legal)))
            state.append(1)
            if found is None:
                index[h] = child
            elif isinstance(found, list):
                found.append(child)
            else:
                index[h] = [found, child]
            children[node].append((i, child))
            stack.append((child, iter(legal_of[child])))
        else:
            if state[child] == 1:
                raise _cycle_error(cap)
            children[node].append((i, child))
    g.fallback = [False] * len(vel)
    g.root = 0
    return g, tests


def _mix(z):
    """splitmix64's finalizer: the sum of the entries' mixed hashes is the state's hash (a plain
    tuple hash summed over the entries of permuted velocities collides by the thousand)."""
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & 0xFFFFFFFFFFFFFFFF
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & 0xFFFFFFFFFFFFFFFF
    return z ^ (z >> 31)


def _diff_key(vd):
    """The outcome key of a state of :func:`_explore_rational`: exact and canonical."""
    return frozenset((j, x.p, x.q) for j, (x, _) in vd.items())
