"""Termination of compliant impacts: the separating-direction certificate and the checks a run passes.

The theorem (proved in ``docs/compliant_termination.md``). For the compliant model of
:mod:`impactsym.compliant` (``M q̈ = Hᵀ f``, unilateral power-law contacts, elastic or damped):

* If some ``u`` has ``H u > 0`` on every row (a *separating direction*), every impulse stays
  bounded for all time, ``Σ_i (Hu)_i P_i(t) ≤ 2 ‖u‖_M √(2 T⁻)`` (and, when ``H`` has full row
  rank, ``P_i(t) ≤ 2 √(2 T⁻ (W⁻¹)_ii)`` with ``W = H M⁻¹ Hᵀ``); the velocity converges and the
  limit leaves or grazes every contact. *Elastic* contacts then reach the stopping condition of
  :func:`impactsym.compliant.compliant_impact` (every contact open, none approaching) in finite
  time; damped ones converge to it (finite time not proved in general).
* Otherwise (Gordan's alternative) some ``λ ≥ 0``, ``λ ≠ 0`` has ``Hᵀλ = 0``: the contacts in
  its support can never all leave, ``H v ≥ 0`` forces ``(H v)_i = 0`` there, and the theorem
  gives nothing; a ball between two walls rings for ever when elastic.

:func:`separating_direction` decides which case holds and returns an exact certificate for it
(verified exactly before it is returned: rational rows in python-flint ``fmpq``, without SymPy,
algebraic rows in SymPy with certified signs); :func:`impulse_bounds` turns a certificate into the bounds; and
:func:`check_run` is the a-posteriori check every compliant run passes before it is returned
(momentum balance, energy, impulse bound), raising :class:`~impactsym.errors.VerificationError`
when the integration broke a proved fact.

Examples
--------
A chain of three balls: ``u = (−2, −1, 0)`` spreads them apart (so does any ``u`` with
increasing entries).

>>> c = separating_direction([[-1, 1, 0], [0, -1, 1]])
>>> c.separating, c.vector, c.products
(True, (-2, -1, 0), (1, 1))

A ball between two walls: no separating direction, the certificate is ``λ = (1, 1)``.

>>> c = separating_direction([[1], [-1]])
>>> c.separating, c.vector, c.products, c.support
(False, (1, 1), (0,), (0, 1))

Exact algebraic rows (a point in a corner of a floor and a 60° wall) are decided exactly:

>>> import sympy as sp
>>> c = separating_direction(sp.Matrix([[0, 1], [sp.sqrt(3) / 2, sp.Rational(1, 2)]]))
>>> c.separating, c.field, c.products
(True, 'algebraic', (1, 1/2 + sqrt(3)/2))
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from .arithmetic import LazyModule, sympy_instance
from .errors import ImpactInputError, UndecidableSign, VerificationError

#: SymPy, imported on first use: rational rows are decided and certified in python-flint alone
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["SeparationCertificate", "separating_direction", "verify_certificate", "impulse_bounds",
           "energy_tolerance", "check_run", "MOMENTUM_TOL", "DOC"]

#: where the theorem and its proof are written
DOC = "docs/compliant_termination.md"
#: the momentum balance ``‖(v⁺ − v⁻) − M⁻¹HᵀP‖_M ≤ MOMENTUM_TOL · ‖v⁻‖_M`` of a run (the integrators
#: carry ``v`` and ``P`` as separate states; a Runge–Kutta method keeps the linear invariant
#: ``v − M⁻¹HᵀP`` to rounding: measured ≤ 4.4e-14 relative on chains of up to 100 balls)
MOMENTUM_TOL = 1e-9


# --------------------------------------------------------------------------------- exact data
def _exact(F, x):
    """A field element as the certificate keeps it: ``fmpq`` for rational rows, SymPy otherwise."""
    return x if F.name == "rational" else F.to_sympy(x)


def _float20(x) -> float:
    """``float(N(x, 20))``: bit for bit SymPy's, for an ``fmpq`` without SymPy."""
    from flint import fmpq

    if isinstance(x, fmpq):
        from .arithmetic.literals import json_float

        return json_float(int(x.p), int(x.q), 20)
    return float(sp.N(x, 20))


def _exact_rows(H):
    """``H`` as exact rows in one field: ``(F, rows, k, n)``; floats at their binary value,
    SymPy ``Float`` likewise, integers/rationals/strings/SymPy expressions as they are."""
    from .arithmetic.fields import AlgebraicField, RationalField
    from .arithmetic.rational import as_fmpq, float_to_rational

    if sympy_instance(H, "MatrixBase"):
        k, n = H.shape
        entries = list(H)
    else:
        arr = np.asarray(H, dtype=object)
        if arr.ndim == 1:
            arr = arr.reshape(1, -1)
        if arr.ndim != 2:
            raise ImpactInputError("H", f"must be a matrix (k x n), got {arr.ndim} dimensions")
        k, n = arr.shape
        entries = list(arr.ravel())
    if k == 0 or n == 0:
        raise ImpactInputError("H", f"must have at least one row and one column, got shape ({k}, {n})")
    fixed = []
    for x in entries:
        if isinstance(x, str):
            x = sp.sympify(x)
        if sympy_instance(x, "Float"):
            x = float_to_rational(float(x))
        fixed.append(x)
    q = [as_fmpq(x) for x in fixed]
    if all(x is not None for x in q):
        return RationalField, [q[i * n:(i + 1) * n] for i in range(k)], k, n
    expr = []
    for x in fixed:
        e = float_to_rational(x) if isinstance(x, (float, np.floating)) else sp.sympify(x)
        if e.free_symbols or not e.is_real:
            raise ImpactInputError("H", f"entries must be real numbers without symbols, got {e}")
        expr.append(e)
    return AlgebraicField, [expr[i * n:(i + 1) * n] for i in range(k)], k, n


def _to_float(F, x) -> float:
    # a rational: the nearest float (as float of SymPy's Rational, which rounds to nearest)
    return int(x.p) / int(x.q) if F.name == "rational" else float(sp.N(x, 20))


def _rationals(xs, F, denominators=(1, 1000, 10**6)):
    """Candidate exact vectors near the float vector ``xs``: small denominators first, then the
    floats' exact binary values."""
    for d in denominators:
        yield [F.num(Fraction(float(x)).limit_denominator(d)) if F.name == "rational"
               else sp.Rational(Fraction(float(x)).limit_denominator(d)) for x in xs]
    yield [F.num(float(x)) if F.name == "rational" else sp.Rational(Fraction(float(x))) for x in xs]


# ------------------------------------------------------------------------------- certificate
@dataclass(frozen=True)
class SeparationCertificate:
    """An exact certificate of one side of Gordan's alternative for the rows ``H``.

    Attributes
    ----------
    separating : True: ``vector`` is ``u`` (n entries) with ``H u > 0``; False: ``vector`` is
        ``λ`` (k entries), ``λ ≥ 0``, ``λ ≠ 0``, ``Hᵀλ = 0``
    vector : exact numbers: python-flint ``fmpq`` for rational rows, SymPy numbers for algebraic
        ones (both print as SymPy does: ``"-1/3"``)
    products : ``H u`` (k entries, all > 0) or ``Hᵀλ`` (n entries, all 0), exact
    field : ``"rational"`` (flint ``fmpq``) or ``"algebraic"`` (SymPy, certified signs)
    """

    separating: bool
    vector: tuple
    products: tuple
    field: str

    @property
    def support(self) -> tuple:
        """The contacts (0-based) with ``λ_i > 0``: they can never all leave; empty if separating."""
        if self.separating:
            return ()
        return tuple(i for i, x in enumerate(self.vector) if x != 0)

    @property
    def vector_float(self) -> np.ndarray:
        return np.array([_float20(x) for x in self.vector], dtype=float)

    @property
    def products_float(self) -> np.ndarray:
        return np.array([_float20(x) for x in self.products], dtype=float)

    def statement(self) -> str:
        """The certified fact in words (for refusals and ``details``)."""
        if self.separating:
            return (f"u = ({', '.join(map(str, self.vector))}) has H u = ({', '.join(map(str, self.products))}) > 0: "
                    "a separating direction")
        return (f"lambda = ({', '.join(map(str, self.vector))}) >= 0 has H^T lambda = 0 (checked exactly), so by "
                "Gordan's alternative no u has H u > 0")

    def as_json(self) -> dict:
        return {"separating": self.separating, "kind": "u" if self.separating else "lambda",
                "vector": [str(x) for x in self.vector], "vector_float": self.vector_float.tolist(),
                "products": [str(x) for x in self.products], "field": self.field,
                "support": list(self.support)}


def verify_certificate(H, certificate: SeparationCertificate) -> SeparationCertificate:
    """Check ``certificate`` against ``H`` in exact arithmetic; return it, or raise.

    ``u``: every ``(H u)_i > 0`` (exact rational comparison, or a certified sign for algebraic
    rows). ``λ``: every ``λ_i ≥ 0``, some ``λ_i > 0``, every ``(Hᵀλ)_j = 0`` (exactly; for algebraic
    rows a zero is proved by :func:`~impactsym.arithmetic.closed_form.certified_sign`, which
    raises rather than guess). The ``products`` stored in the certificate are recomputed, not
    trusted.

    Raises
    ------
    VerificationError
        The certificate does not certify what it claims (a bug, or a tampered certificate).

    Examples
    --------
    >>> bad = SeparationCertificate(True, (1, 0), (1, 1), "rational")
    >>> verify_certificate([[1, 0], [0, 1]], bad)
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: separating_direction: verification of the outcome failed: (H u)_2 = 0 is not > 0 (a bug in impactsym; the outcome was not returned)
    """
    from .arithmetic.linalg import dot

    F, rows, k, n = _exact_rows(H)
    name = "separating_direction"
    vec = [F.num(x) if F.name == "rational" else sp.sympify(x) for x in certificate.vector]
    if certificate.separating:
        if len(vec) != n:
            raise VerificationError(name, f"u has {len(vec)} entries, H has {n} columns")
        prods = [dot(r, vec, F) for r in rows]
        for i, s in enumerate(prods):
            if F.sign(s) <= 0:
                raise VerificationError(name, f"(H u)_{i + 1} = {F.to_sympy(s)} is not > 0")
    else:
        if len(vec) != k:
            raise VerificationError(name, f"lambda has {len(vec)} entries, H has {k} rows")
        signs = [F.sign(x) for x in vec]
        if any(s < 0 for s in signs) or not any(s > 0 for s in signs):
            raise VerificationError(name, "lambda must be >= 0 and not 0")
        prods = [dot([rows[i][j] for i in range(k)], vec, F) for j in range(n)]
        for j, s in enumerate(prods):
            if F.sign(s) != 0:
                raise VerificationError(name, f"(H^T lambda)_{j + 1} = {F.to_sympy(s)} is not 0")
    if len(certificate.products) != len(prods):
        raise VerificationError(name, f"{len(certificate.products)} stored products, {len(prods)} recomputed")
    if F.name == "rational":
        from .arithmetic.rational import as_fmpq

        same = all(as_fmpq(a) == b for a, b in zip(certificate.products, prods))
    else:
        exact = tuple(F.to_sympy(x) for x in prods)
        same = tuple(sp.sympify(x) for x in certificate.products) == exact or all(
            sp.simplify(sp.sympify(a) - b) == 0 for a, b in zip(certificate.products, exact))
    if not same:
        raise VerificationError(name, f"the stored products {certificate.products} are not the recomputed "
                                      f"{tuple(F.to_sympy(x) for x in prods)}")
    return certificate


def _lp_u(Hf):
    from scipy.optimize import linprog

    k, n = Hf.shape
    res = linprog(np.zeros(n), A_ub=-Hf, b_ub=-np.ones(k), bounds=[(None, None)] * n, method="highs")
    return res.x if res.status == 0 else None


def _lp_lambda(Hf):
    """The float ``y ≥ 0`` of largest support with ``Hᵀy = 0``, ``y_i ≥ 1`` on it (or None)."""
    from scipy.optimize import linprog

    k, n = Hf.shape
    c = np.concatenate([np.zeros(k), -np.ones(k)])
    A_eq = np.hstack([Hf.T, np.zeros((n, k))])
    A_ub = np.hstack([-np.eye(k), np.eye(k)])  # t_i - y_i <= 0
    res = linprog(c, A_ub=A_ub, b_ub=np.zeros(k), A_eq=A_eq, b_eq=np.zeros(n),
                  bounds=[(0, None)] * k + [(0, 1)] * k, method="highs")
    if res.status != 0:  # pragma: no cover - always feasible (0) and bounded
        return None
    y = res.x[:k]
    S = [i for i in range(k) if res.x[k + i] > 0.5]
    return (y, S) if S else None


def _try_u(F, rows, k, n, u_float):
    from .arithmetic.linalg import dot

    for u in _rationals(u_float, F):
        if all(F.sign(dot(r, u, F)) > 0 for r in rows):
            return SeparationCertificate(True, tuple(_exact(F, x) for x in u),
                                         tuple(_exact(F, dot(r, u, F)) for r in rows), F.name)
    return None


def _try_lambda(F, rows, k, n, y, S):
    """An exact ``λ`` supported on ``S`` near the float ``y``: from the exact null space of ``H_Sᵀ``."""
    from .arithmetic.linalg import nullspace

    colsT = [[rows[i][j] for i in S] for j in range(n)]  # H_S^T, n rows of |S| entries
    basis = nullspace(colsT, len(S), F)
    if not basis:
        return None
    N = np.array([[_to_float(F, x) for x in b] for b in basis]).T  # |S| x m
    coef, *_ = np.linalg.lstsq(N, y[S], rcond=None)
    for c in _rationals(coef, F):
        lam_S = [F.norm(sum((ci * b[s] for ci, b in zip(c, basis)), F.zero)) for s in range(len(S))]
        if all(F.sign(x) > 0 for x in lam_S):
            lam = [F.zero] * k
            for s, i in enumerate(S):
                lam[i] = lam_S[s]
            if F.name == "algebraic":
                lam = [sp.radsimp(x) for x in lam]
            cert = SeparationCertificate(False, tuple(_exact(F, x) for x in lam), (0,) * n, F.name)
            try:
                return verify_certificate_rows(F, rows, k, n, cert)
            except VerificationError:  # pragma: no cover - the null space is exact
                continue
    return None


def verify_certificate_rows(F, rows, k, n, cert):
    """:func:`verify_certificate` on rows already made exact (internal): rational rows as lists of
    ``fmpq`` (no SymPy), algebraic ones as a SymPy matrix."""
    if F.name == "rational":
        return verify_certificate([list(r) for r in rows], cert)
    return verify_certificate(sp.Matrix(k, n, [F.to_sympy(x) for r in rows for x in r]), cert)


def _exact_lp(F, rows, k, n):
    """Gordan's alternative decided by SymPy's exact simplex (rational rows only)."""
    from sympy.solvers.simplex import linprog

    Hx = sp.Matrix(k, n, [F.to_sympy(x) for r in rows for x in r])
    # maximize t subject to H u >= t 1, 0 <= u+, u-, t <= 1 (u = u+ - u-; t >= 0 loses nothing since
    # u = 0, t = 0 is feasible). The box is written as constraints: SymPy 1.14's ``bounds`` argument
    # returned an infeasible point here (t = 1 with H u = -1/2 on a row), so it is not used
    m = 2 * n + 1
    A = sp.Matrix.hstack(-Hx, Hx, sp.ones(k, 1)).col_join(sp.eye(m))
    opt, x = linprog(sp.Matrix([0] * (2 * n) + [-1]), A, sp.zeros(k, 1).col_join(sp.ones(m, 1)))
    if -opt > 0:
        u = [x[j] - x[n + j] for j in range(n)]
        return SeparationCertificate(True, tuple(u), tuple(Hx * sp.Matrix(u)), F.name)
    # maximize sum t_i subject to H^T y = 0, 0 <= t_i <= min(y_i, 1)
    c = sp.Matrix([0] * k + [-1] * k)
    A = sp.Matrix.hstack(-sp.eye(k), sp.eye(k)).col_join(sp.Matrix.hstack(sp.zeros(k, k), sp.eye(k)))
    b = sp.Matrix([0] * k + [1] * k)
    _, x = linprog(c, A, b, sp.Matrix.hstack(Hx.T, sp.zeros(n, k)), sp.zeros(n, 1))
    lam = tuple(x[:k])
    return SeparationCertificate(False, lam, (0,) * n, F.name)


def separating_direction(H) -> SeparationCertificate:
    """Decide Gordan's alternative for the contact rows ``H``, with an exact certificate.

    Exactly one holds: some ``u`` has ``H u > 0`` (every contact can be made to leave at once),
    or some ``λ ≥ 0``, ``λ ≠ 0`` has ``Hᵀλ = 0`` (never both: ``λᵀ H u`` would be both ``> 0`` and
    ``0``). A float linear program (``scipy.optimize.linprog``, HiGHS) finds a candidate;
    the verdict rests on the exact check (:func:`verify_certificate`). ``u`` is rounded to
    rationals (small denominators first); ``λ`` is taken in the exact null space of ``H_Sᵀ`` on
    the program's support ``S``. When neither candidate verifies, rational rows are decided by
    SymPy's exact simplex; algebraic rows raise.

    Parameters
    ----------
    H : (k, n) contact rows: a SymPy matrix (rational or algebraic entries such as ``sqrt(3)/2``),
        nested lists, or a float array (floats taken at their exact binary value)

    Returns
    -------
    SeparationCertificate
        verified exactly before it is returned

    Raises
    ------
    ImpactInputError
        ``H`` is not a real matrix.
    UndecidableSign
        Algebraic rows for which neither candidate could be verified (never guessed).

    Examples
    --------
    A chain between two walls is confined; a point in a triangle too:

    >>> separating_direction([[1, 0, 0], [-1, 1, 0], [0, -1, 1], [0, 0, -1]]).vector
    (1, 1, 1, 1)
    >>> separating_direction([[1, 0], [0, 1], [-1, -1]]).support
    (0, 1, 2)
    """
    key = _certificate_key(H)
    if key is not None:
        try:
            _CERTIFICATES.move_to_end(key)
            return _CERTIFICATES[key]
        except KeyError:  # not remembered (or dropped meanwhile by another thread)
            pass
    cert = _separating_direction(H)
    if key is not None:
        _CERTIFICATES[key] = cert
        while len(_CERTIFICATES) > _CERTIFICATES_MAX:
            try:
                _CERTIFICATES.popitem(last=False)
            except KeyError:  # pragma: no cover - emptied by another thread
                break
    return cert


#: verified certificates by the rows' exact key (:func:`_certificate_key`), most recent last: the
#: compliant laws of one system (hertz, linear, power, hunt-crossley, the refusal checks, the
#: a-posteriori bound) ask for the same rows' certificate several times, each an LP and an exact check
_CERTIFICATES: OrderedDict = OrderedDict()
_CERTIFICATES_MAX = 256


def _certificate_key(H):
    """A hashable key that determines the exact rows of ``H`` (float64 arrays by their bytes, SymPy
    matrices by their entries), or None for other input (not remembered). The certificate is a
    frozen dataclass of exact numbers (fmpq or SymPy): the one returned again is the one verified before."""
    if isinstance(H, np.ndarray) and H.dtype == np.float64 and H.ndim == 2:
        return ("float64", H.shape, H.tobytes())
    from .resolution import RationalMatrix

    if isinstance(H, RationalMatrix):  # the command line's exact rows without SymPy (Fractions)
        return ("fractions", H.shape, tuple(map(tuple, H.tolist())))
    if sympy_instance(H, "MatrixBase"):
        try:
            return ("sympy", H.shape, tuple(H))
        except TypeError:  # pragma: no cover - an unhashable entry
            return None
    return None


def _separating_direction(H) -> SeparationCertificate:
    F, rows, k, n = _exact_rows(H)
    Hf = np.array([[_to_float(F, x) for x in r] for r in rows], dtype=float)
    if not np.all(np.isfinite(Hf)):
        raise ImpactInputError("H", "contains NaN or inf")
    u = _lp_u(Hf)
    if u is not None:
        cert = _try_u(F, rows, k, n, u)
        if cert is not None:
            return verify_certificate_rows(F, rows, k, n, cert)
    ys = _lp_lambda(Hf)
    if ys is not None:
        cert = _try_lambda(F, rows, k, n, *ys)
        if cert is not None:
            return cert
    if F.name == "rational":
        return verify_certificate_rows(F, rows, k, n, _exact_lp(F, rows, k, n))
    raise UndecidableSign("separating_direction: neither a separating direction u (H u > 0) nor a confinement "
                          "lambda >= 0 (H^T lambda = 0) could be verified exactly for these algebraic rows")


# ------------------------------------------------------------------------------- a posteriori
def energy_tolerance(rtol: float) -> float:
    """The stated tolerance on ``|T⁺/T⁻ − 1|`` of an elastic run at the integrator tolerance
    ``rtol``: ``min(1e5 rtol, 10 √rtol)``.

    Not a proof: DOP853's ``rtol`` bounds the local error of a step, not the global error. The
    constant is measured (``docs/compliant_termination.md``: worst ``|T⁺/T⁻ − 1|`` over chains,
    cradles, walls, the planar scenes and random mass ratios, exponents 1, 3/2, 5/2, was
    ``3.3e3 rtol`` at ``rtol = 1e-11`` and below ``5.2e2 rtol`` elsewhere).

    >>> energy_tolerance(1e-11), round(energy_tolerance(1e-3), 3)
    (1e-06, 0.316)
    """
    return float(min(1e5 * rtol, 10 * np.sqrt(rtol)))


def impulse_bounds(M, H, v, certificate: SeparationCertificate | None = None, *, verify: bool = True) -> np.ndarray:
    """Proved per-contact bounds on the impulses ``P_i(t)`` of a compliant impact, for all ``t``.

    With ``E⁻ = T⁻ = ½ v⁻ᵀ M v⁻`` (every gap starts open or touching, so no elastic energy):

    * from a separating direction ``u`` (``H u > 0``):
      ``P_i ≤ 2 ‖u‖_M √(2 T⁻) / (H u)_i`` (since ``Σ_j (Hu)_j P_j ≤ 2 ‖u‖_M √(2T⁻)``);
    * when ``W = H M⁻¹ Hᵀ`` is non-singular (``H`` of full row rank):
      ``P_i ≤ 2 √(2 T⁻ (W⁻¹)_ii)`` (the direction ``u = M⁻¹HᵀW⁻¹e_i``, ``H u = e_i``).

    The smaller of the two is returned (floats; ``inf`` for a contact neither bounds, i.e. when
    there is no separating direction). A given ``certificate`` is verified against ``H`` first
    (:func:`verify_certificate`; ``verify=False`` only for one :func:`separating_direction` has
    just returned): a bound from a wrong ``u`` would not be a bound. The proof is step 2 of ``docs/compliant_termination.md``;
    it needs only ``f ≥ 0`` and an energy that does not grow, so it holds for the damped laws too.

    Examples
    --------
    One ball on a wall, ``μ = 2``, ``w = −1``: the elastic impulse ``2 μ |w| = 4`` meets the bound.

    >>> impulse_bounds([[2.0]], [[-1.0]], [1.0]).tolist()
    [4.0]
    """
    Mf = np.asarray(M, dtype=float)
    Hf = np.atleast_2d(np.asarray(H, dtype=float))
    v = np.asarray(v, dtype=float).reshape(-1)
    T0 = 0.5 * float(v @ Mf @ v)
    if certificate is None:
        certificate = separating_direction(Hf)
    elif verify:
        verify_certificate(Hf, certificate)
    k = Hf.shape[0]
    bound = np.full(k, np.inf)
    if certificate.separating:
        u, Hu = certificate.vector_float, certificate.products_float
        bound = np.minimum(bound, 2 * np.sqrt(max(float(u @ Mf @ u), 0.0)) * np.sqrt(2 * T0) / Hu)
    W = Hf @ np.linalg.solve(Mf, Hf.T)
    if np.linalg.matrix_rank(W) == k:
        d = np.maximum(np.diag(np.linalg.inv(W)), 0.0)
        with np.errstate(over="ignore", under="ignore"):
            q = 2 * T0 * d
        # √(2T⁻ d) as one root while 2T⁻d is a normal float; as a product of roots where it would
        # underflow (bodies of 1e-85 kg at 1e-85 m/s: 2T⁻d ~ 1e-340, a bound of 0 refused the run)
        # or overflow (1e100: a bound of inf checked nothing)
        normal = (q >= np.finfo(float).tiny) & np.isfinite(q)
        bound = np.minimum(bound, 2 * np.where(normal, np.sqrt(q), np.sqrt(2 * T0) * np.sqrt(d)))
    return bound


def check_run(M, H, v_minus, v_plus, impulses, *, elastic: bool, rtol: float, certificate=None,
              law: str = "compliant_impact", bounds=None) -> dict:
    """The a-posteriori checks of a compliant (or LZB) run; raise if a proved fact is broken.

    1. Momentum balance ``M (v⁺ − v⁻) = Hᵀ P``: ``‖(v⁺ − v⁻) − M⁻¹HᵀP‖_M ≤ MOMENTUM_TOL ‖v⁻‖_M``.
    2. Energy: elastic ``|T⁺/T⁻ − 1| ≤ energy_tolerance(rtol)``; damped ``T⁺/T⁻ ≤ 1 + that``.
    3. Impulses ``0 ≤ P_i ≤ bound_i (1 + energy_tolerance(rtol))`` with the proved
       :func:`impulse_bounds` (only a contact that some certificate bounds).

    A violation means the integration failed (these are consequences of the model, not
    properties of the input): :class:`~impactsym.errors.VerificationError`, never a returned result.

    Returns
    -------
    dict : the measured residuals and the tolerances used

    Examples
    --------
    >>> r = check_run([[2.0]], [[-1.0]], [1.0], [-1.0], [4.0], elastic=True, rtol=1e-11)
    >>> r["momentum_residual"], r["energy_error"], r["impulse_margin"]
    (0.0, 0.0, 0.0)
    >>> check_run([[2.0]], [[-1.0]], [1.0], [-1.0], [4.5], elastic=True, rtol=1e-11)
    Traceback (most recent call last):
    ...
    impactsym.errors.VerificationError: compliant_impact: verification of the outcome failed: the momentum balance M(v+ - v-) = H^T P is off by 0.25 (relative, kinetic metric) > 1e-09 (a bug in impactsym; the outcome was not returned)
    """
    Mf = np.asarray(M, dtype=float)
    Hf = np.atleast_2d(np.asarray(H, dtype=float))
    vm = np.asarray(v_minus, dtype=float).reshape(-1)
    vp = np.asarray(v_plus, dtype=float).reshape(-1)
    P = np.asarray(impulses, dtype=float).reshape(-1)
    norm_m = float(np.sqrt(vm @ Mf @ vm))
    r = (vp - vm) - np.linalg.solve(Mf, Hf.T @ P)
    mom = float(np.sqrt(max(float(r @ Mf @ r), 0.0))) / norm_m
    if not mom <= MOMENTUM_TOL:
        raise VerificationError(law, f"the momentum balance M(v+ - v-) = H^T P is off by {mom:.3g} (relative, "
                                     f"kinetic metric) > {MOMENTUM_TOL:g}")
    tol = energy_tolerance(rtol)
    ratio = float(vp @ Mf @ vp) / float(vm @ Mf @ vm)
    err = abs(ratio - 1) if elastic else max(ratio - 1, 0.0)
    if not err <= tol:
        what = "|T+/T- - 1|" if elastic else "T+/T- - 1 (a damped run gained energy)"
        raise VerificationError(law, f"{what} = {err:.3g} > {tol:.3g} (the stated energy tolerance at rtol {rtol:g})")
    if np.any(P < -tol * np.max(np.abs(P), initial=0.0)):
        raise VerificationError(law, f"a negative impulse {P.min():.3g}: contact forces never pull")
    if bounds is None:
        bounds = impulse_bounds(Mf, Hf, vm, certificate)
    finite = np.isfinite(bounds)
    margin = float(np.max((P[finite] - bounds[finite]) / bounds[finite], initial=-np.inf)) if np.any(finite) else None
    if margin is not None and margin > tol:
        i = int(np.argmax(np.where(finite, (P - bounds) / np.where(finite, bounds, 1.0), -np.inf)))
        raise VerificationError(law, f"the impulse P_{i + 1} = {P[i]:.12g} exceeds its proved bound {bounds[i]:.12g} "
                                     f"(step 2 of {DOC}) by more than {tol:.3g} relative: the integration failed")
    return {"momentum_residual": mom, "momentum_tol": MOMENTUM_TOL, "energy_error": err, "energy_tol": tol,
            "impulse_margin": None if margin is None else max(margin, 0.0),
            "impulse_bounds": [float(b) if np.isfinite(b) else None for b in bounds]}
