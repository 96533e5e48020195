"""SymPy derivations: each module derives one family of formulas from the papers' first
principles, proves what can be proved, and writes generated code (``generate()``).

Rewrite every committed generated file with ``python -m derivations``; the test
``tests/test_codegen_sync.py`` regenerates them into a temporary folder and fails with a
unified diff when they differ.

Modules
-------
algebra     verified rewriting in the non-commutative algebra of w, u, M (general-n proofs)
codegen     the one writer of generated files (header, deterministic formatting)
chain3      closed forms of the 3-ball chain (Acary & Taha eqs. 13-19)
domains     validity domains of the impulse-ratio law (Acary & Taha eqs. 19, 28-32)
pool        closed forms of the pool and Bernoulli's problem (Acary & Taha eqs. 25-37)
reflection  the single-impact map G_u and the Newton-restitution map G_u(e) (Seghete & Murphey eq. 1)
impulse_ratio_root  the physical root of the impulse-ratio quadratic, stable and naive forms
two_surface the two-surface problem: plane reduction, exact reflection count, the paper's bound (sec. III-C)
"""

#: derivation modules that write generated code, in generation order
FAMILIES = ["reflection", "impulse_ratio_root", "two_surface", "chain3", "pool", "domains"]
