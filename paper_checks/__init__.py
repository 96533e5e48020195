"""paper_checks: the audit of both papers, one claim function per published item.

``paper_checks.seghete_murphey`` and ``paper_checks.acary_taha`` register their claims in
:data:`paper_checks.framework.REGISTRY` at import; :func:`paper_checks.framework.evaluate_all`
runs them; :func:`paper_checks.audit.run_audit` runs the whole audit (claims, the ``G_u``
derivation, the cross-check) and is what ``impactsym reproduce`` calls and renders;
``test_claims.py`` makes each claim a test that pins its verdict.
"""

from .audit import AuditResult, run_audit  # noqa: F401
from .framework import REGISTRY, Claim, Finding, claim, evaluate, evaluate_all, load_all  # noqa: F401
