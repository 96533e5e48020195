"""Independent impacts: the search split into groups of contacts that never affect each other.

The condition
-------------
Two single impacts ``G_u = I − 2 M⁻¹uᵀu/s_u`` and ``G_w`` (``s_u = u M⁻¹ uᵀ``) commute exactly
when ``u M⁻¹ wᵀ = 0``, the entry of the Gram matrix ``H M⁻¹ Hᵀ`` between the two contacts:

    G_u G_w = I − 2M⁻¹uᵀu/s_u − 2M⁻¹wᵀw/s_w + 4 (u M⁻¹ wᵀ) M⁻¹uᵀw/(s_u s_w),

and the last term, the only one not symmetric in ``u`` and ``w``, vanishes. (With restitution
the factors 2 become ``1 + e``; the same holds.) Moreover ``w G_u v = w v − 2 (u v)(w M⁻¹ uᵀ)/s_u
= w v``: an impact on ``u`` leaves the relative velocity of contact ``w`` unchanged, so it never
enables or disables ``w``. For a diagonal (or block-diagonal, one block per body) ``M`` this is
the case of contacts that share no body; for a general ``M`` disjoint supports are not enough,
and ``u M⁻¹ wᵀ = 0`` is what is tested (exactly, on the Gram matrix the search already has).
``tests/test_sequential_independence.py`` proves the identity symbolically.

The decomposition
-----------------
Let the contacts split into the connected components ``C_1, …, C_m`` of the graph
``i ~ j ⇔ H_i M⁻¹ H_jᵀ ≠ 0``. By the two facts above, the impacts of different components
commute and never change each other's signs, so from ``v0``

* the orderings of the whole system are exactly the interleavings (shuffles) of one ordering
  of each component, each searched alone from ``v0``;
* the outcome of an interleaving is ``v0 + Σ_c Δ_c``, ``Δ_c`` the change the component's own
  ordering makes; the ``Δ_c`` lie in the mutually M-orthogonal spans of ``M⁻¹H_iᵀ``, ``i ∈ C_c``
  (``⟨M⁻¹H_iᵀ, M⁻¹H_jᵀ⟩_M = H_i M⁻¹ H_jᵀ = 0``), so distinct combinations of component
  outcomes are distinct outcomes;
* the number of orderings of a combination is ``Σ Π_c N_c(L_c) · (L_1 + … + L_m)! / Π_c L_c!``
  over the lengths ``L_c`` (``N_c(L)``: orderings of length ``L`` of component ``c`` giving its
  outcome); the shortest and longest lengths add; the representative ordering (shortest, then
  lexicographically first) is the merge of the components' representatives that always takes
  the smallest surface index next (the merge is monotone in each argument, and over disjoint
  alphabets the greedy merge is the lexicographically first interleaving).

So the search visits ``Σ_c |states_c|`` states instead of up to ``Π_c |states_c|``, and the
ordering counts are computed, not enumerated. Every combined outcome is still replayed along its
representative ordering and verified exactly before it is returned.
"""

from __future__ import annotations

from math import comb

__all__ = ["components", "length_distributions", "combine", "ProductGraph"]


def components(system, active_only: bool = True) -> list:
    """The contacts grouped by the connected components of ``i ~ j ⇔ H_i M⁻¹ H_jᵀ ≠ 0`` (from the
    sparse Gram columns of ``system``), each a sorted tuple, in order of their smallest contact.
    ``active_only``: only the components with a contact approached at ``v0`` (the others never
    act)."""
    k = system.k
    parent = list(range(k))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for i in range(k):
        for j, _ in system.gcols[i]:
            a, b = find(i), find(j)
            if a != b:
                parent[max(a, b)] = min(a, b)
    groups: dict = {}
    for i in range(k):
        groups.setdefault(find(i), []).append(i)
    out = [tuple(g) for _, g in sorted(groups.items())]
    if active_only:
        F = system.F
        out = [c for c in out if any(F.sign(system.w(system.v0, i)) < 0 for i in c)]
    return out


def length_distributions(g, key_of) -> dict:
    """Per outcome of the DAG ``g``: ``{outcome key: {length: number of orderings}}`` (a dynamic
    programme over the DAG in post-order); also sets ``g.terminal_key``."""
    from .search import _postorder

    dist: dict = {}
    for node in _postorder(g):
        kids = g.children[node]
        if not kids:
            key = key_of(g.vel[node])
            g.terminal_key[node] = key
            dist[node] = {key: {0: 1}}
            continue
        acc: dict = {}
        for _, child in kids:
            for key, d in dist[child].items():
                a = acc.setdefault(key, {})
                for length, cnt in d.items():
                    a[length + 1] = a.get(length + 1, 0) + cnt
        dist[node] = acc
    return dist[g.root]


def _merge(reps):
    """The interleaving of the sequences ``reps`` (disjoint alphabets) that always takes the
    smallest next symbol: the lexicographically first one."""
    pos = [0] * len(reps)
    out = []
    while True:
        best = None
        for c, r in enumerate(reps):
            if pos[c] < len(r) and (best is None or r[pos[c]] < reps[best][pos[best]]):
                best = c
        if best is None:
            return tuple(out)
        out.append(reps[best][pos[best]])
        pos[best] += 1


def combine(parts) -> dict:
    """Combine the per-component tables ``parts`` (a list, one ``{key: (length distribution,
    representative)}`` per component) into ``{tuple of keys: [orderings, shortest, longest,
    representative]}``, the table :func:`impactsym.laws.sequential.search._aggregate` gives.

    >>> combine([{"a": ({1: 1}, (0,))}, {"b": ({1: 1}, (1,))}])
    {('a', 'b'): [2, 2, 2, (0, 1)]}
    """
    table = {(): ({0: 1}, ())}
    reps_of = {(): ()}
    for part in parts:
        nxt = {}
        for keys, (dist, _) in table.items():
            for key, (d2, rep2) in part.items():
                out: dict = {}
                for l1, c1 in dist.items():
                    for l2, c2 in d2.items():
                        out[l1 + l2] = out.get(l1 + l2, 0) + c1 * c2 * comb(l1 + l2, l1)
                nk = keys + (key,)
                nxt[nk] = (out, None)
                reps_of[nk] = reps_of[keys] + (rep2,)
        table = nxt
    return {keys: [sum(d.values()), min(d), max(d), _merge(list(reps_of[keys]))]
            for keys, (d, _) in table.items()}


class ProductGraph:
    """The DAGs of independent components, standing for their product (the DAG of the whole
    search, never built): ``vel`` has one entry per state visited (their sum), and
    :meth:`iter_leaves` walks the interleavings depth first, in the order of the full DAG."""

    def __init__(self, graphs):
        self.graphs = graphs
        self.vel = range(sum(len(g.vel) for g in graphs))
        self.outcome_index: dict = {}  # combined key (the tuple of component keys) -> outcome
        self.collapse: dict = {}

    def iter_paths(self):
        """Every ordering of the product, with its combined outcome key, depth first (children by
        surface index, as in the full DAG)."""
        gs = self.graphs
        stack = [(tuple(g.root for g in gs), ())]
        while stack:
            nodes, path = stack.pop()
            kids = sorted((i, c, child) for c, (g, nd) in enumerate(zip(gs, nodes)) for i, child in g.children[nd])
            if not kids:
                yield path, tuple(g.terminal_key[nd] for g, nd in zip(gs, nodes))
                continue
            for i, c, child in reversed(kids):
                nn = list(nodes)
                nn[c] = child
                stack.append((tuple(nn), path + (i,)))
