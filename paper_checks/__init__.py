"""paper_checks: the audit of both papers, one claim function per published item.

``paper_checks.seghete_murphey`` and ``paper_checks.acary_taha`` register their claims in
:data:`paper_checks.framework.REGISTRY` at import; :func:`paper_checks.framework.evaluate_all`
runs them; ``impactsym reproduce`` reports them; ``test_claims.py`` makes each one a test that
pins its verdict.
"""

from .framework import REGISTRY, Claim, Finding, claim, evaluate, evaluate_all, load_all  # noqa: F401
