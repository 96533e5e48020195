"""Termination of the compliant impact (docs/compliant_termination.md): the exact Gordan
certificate both ways, its rejection when wrong, the proved impulse bound, the checks a run
passes before it is returned, and the elastic laws' refusal without a separating direction."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from impactsym import termination
from impactsym.compliant import chain_impact, chain_matrices, compliant_impact
from impactsym.errors import ImpactInputError, NonTermination, UndecidableSign, VerificationError
from impactsym.lawbook import resolve
from impactsym.models import acary_taha, seghete_murphey
from impactsym.resolution import System
from impactsym.termination import (SeparationCertificate, check_run, energy_tolerance, impulse_bounds,
                                   separating_direction, verify_certificate)

S3 = sp.sqrt(3)


def exact_H(H):
    # floats at their exact binary value (sp.Rational of a float is exact)
    return sp.Matrix(H) if isinstance(H, sp.MatrixBase) else sp.Matrix(
        [[sp.Rational(x) if isinstance(x, float) else sp.sympify(x) for x in r] for r in np.asarray(H, dtype=object)])


def independently_certified(H, c):
    """The certificate's claim re-checked here with SymPy, exactly (not with the module's code)."""
    Hx = exact_H(H)
    x = sp.Matrix(c.vector)
    if c.separating:
        return all(sp.simplify(y).is_positive for y in Hx * x)
    return (all(sp.simplify(y) == 0 for y in Hx.T * x) and all(sp.simplify(y).is_nonnegative for y in x)
            and any(sp.simplify(y).is_positive for y in x))


SEPARATING = {
    "chain 3": chain_matrices([1, 1, 1])[1],
    "chain 10, right wall": chain_matrices([1] * 10, ("right",))[1],
    "cradle 5, 2 strikers": seghete_murphey.cradle(5, 2).H,
    "balls against a wall": seghete_murphey.balls_against_wall(3).H,
    "pool pi/3, pi/12": acary_taha.pool(sp.pi / 3, sp.pi / 12).H,
    "bernoulli": acary_taha.bernoulli().H,
    "V-groove (sqrt 3)": sp.Matrix([[S3 / 2, sp.Rational(1, 2)], [-S3 / 2, sp.Rational(1, 2)]]),
    "dependent rows, same side": [[1, 1], [2, 2]],
}
CONFINED = {
    "ball between two walls": ([[1], [-1]], (0, 1)),
    "ball between two walls, in the plane": ([[1, 0], [-1, 0]], (0, 1)),
    "chain of 3 between two walls": (chain_matrices([1, 1, 1], ("left", "right"))[1], (0, 1, 2, 3)),
    "point in a triangle": ([[1, 0], [0, 1], [-1, -1]], (0, 1, 2)),
    "balls 1-2 between walls, ball 3 free": ([[1, 0, 0], [-1, 1, 0], [0, -1, 0], [0, 0, 1]], (0, 1, 2)),
    "antiparallel sqrt(3) rows": (sp.Matrix([[S3, 1], [-1, -1 / S3]]), (0, 1)),
}


@pytest.mark.parametrize("name", SEPARATING)
def test_separating_direction_is_certified_exactly(name):
    H = SEPARATING[name]
    c = separating_direction(H)
    assert c.separating and c.support == () and independently_certified(H, c)
    assert c.field == ("algebraic" if name in ("pool pi/3, pi/12", "bernoulli", "V-groove (sqrt 3)") else "rational")


@pytest.mark.parametrize("name", CONFINED)
def test_confinement_is_certified_exactly(name):
    H, support = CONFINED[name]
    c = separating_direction(H)
    assert not c.separating and c.support == support and independently_certified(H, c)
    assert all(x == 0 for x in c.products)


def test_the_ball_between_two_walls_certificate_is_lambda_one_one():
    c = separating_direction([[1], [-1]])
    assert c.vector == (1, 1) and "Gordan" in c.statement()


def test_gordan_alternative_on_random_integer_rows_agrees_with_the_exact_simplex():
    # sampling: 40 random 2-4 x 1-3 integer matrices; the float-LP path and SymPy's exact simplex
    # must give the same side, and each certificate is re-checked here exactly
    rng = np.random.default_rng(13)
    sides = set()
    for _ in range(40):
        k, n = rng.integers(2, 5), rng.integers(1, 4)
        H = rng.integers(-2, 3, size=(k, n))
        H[np.all(H == 0, axis=1), 0] = 1
        c = separating_direction(H.tolist())
        F, rows, kk, nn = termination._exact_rows(H.tolist())
        e = termination._exact_lp(F, rows, kk, nn)
        assert c.separating == e.separating and independently_certified(H.tolist(), c)
        sides.add(c.separating)
    assert sides == {True, False}  # both sides met


def test_the_exact_fallback_decides_when_the_float_candidates_are_wrong(monkeypatch):
    # float LPs that return garbage: rational rows are still decided, exactly; algebraic rows raise
    # (with no certificate remembered from an earlier test, so the fallback itself is what answers)
    monkeypatch.setattr(termination, "_CERTIFICATES", type(termination._CERTIFICATES)())
    monkeypatch.setattr(termination, "_lp_u", lambda Hf: np.full(Hf.shape[1], -1.0))
    monkeypatch.setattr(termination, "_lp_lambda", lambda Hf: (np.full(Hf.shape[0], 1.0), [0]))
    c = separating_direction(chain_matrices([1, 1, 1])[1].tolist())
    assert c.separating and independently_certified(chain_matrices([1, 1, 1])[1], c)
    c = separating_direction([[1], [-1]])
    assert not c.separating and c.support == (0, 1)
    with pytest.raises(UndecidableSign, match="neither a separating direction"):
        separating_direction(sp.Matrix([[S3, 1], [-1, -1 / S3]]))



def test_a_remembered_certificate_is_the_one_of_the_same_exact_rows():
    # one certificate per exact row set: equal float arrays share it; rows whose exact values
    # differ (the binary 0.1 against 1/10; a sign) never do
    Hf = np.array([[-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])
    c = separating_direction(Hf)
    assert separating_direction(Hf.copy()) is c and separating_direction(np.asfortranarray(Hf)) is c
    assert separating_direction(-Hf).vector != c.vector
    assert independently_certified(-Hf, separating_direction(-Hf))
    # rows (a, -1), (-1, 10): confined exactly at a = 1/10 (lambda = (10, 1)), separated in a sliver at
    # the binary 0.1 (a hair above 1/10); each answer is right for its own rows whichever comes first
    binary = sp.Matrix([[sp.Float(0.1), -1], [-1, 10]])
    tenth = sp.Matrix([[sp.Rational(1, 10), -1], [-1, 10]])
    exact = {id(binary): [[0.1, -1], [-1, 10]], id(tenth): tenth}  # the float at its binary value, for the check
    for first, second in ((binary, tenth), (tenth, binary)):
        termination._CERTIFICATES.clear()
        a, b = separating_direction(first), separating_direction(second)
        assert a.separating != b.separating
        assert independently_certified(exact[id(first)], a) and independently_certified(exact[id(second)], b)
    assert separating_direction(np.array([[0.1, -1.0], [-1.0, 10.0]])).separating
    assert not separating_direction(tenth).separating


# ----------------------------------------------------------------- mutations: wrong certificates
@pytest.mark.parametrize("H, cert, words", [
    ([[1, 0], [0, 1]], SeparationCertificate(True, (1, 0), (1, 0), "rational"), "(H u)_2 = 0 is not > 0"),
    ([[-1, 1, 0], [0, -1, 1]], SeparationCertificate(True, (0, 2, 1), (2, -1), "rational"), "(H u)_2 = -1"),
    ([[1], [-1]], SeparationCertificate(False, (1, 2), (0,), "rational"), "(H^T lambda)_1 = -1 is not 0"),
    ([[1], [-1]], SeparationCertificate(False, (-1, -1), (0,), "rational"), "lambda must be >= 0"),
    ([[1], [-1]], SeparationCertificate(False, (0, 0), (0,), "rational"), "not 0"),
    ([[1], [-1]], SeparationCertificate(False, (1, 1), (5,), "rational"), "stored products"),
    # algebraic: lambda = (1, 1) misses H^T lambda = 0 by an irrational amount
    (sp.Matrix([[S3, 1], [-1, -1 / S3]]), SeparationCertificate(False, (1, 1), (0, 0), "algebraic"),
     "(H^T lambda)_1 = -1 + sqrt(3) is not 0"),
    # algebraic: u = (1, -1) gives H u = (sqrt(3)/2 - 1/2, -sqrt(3)/2 - 1/2), the second < 0
    (sp.Matrix([[S3 / 2, sp.Rational(1, 2)], [-S3 / 2, sp.Rational(1, 2)]]),
     SeparationCertificate(True, (1, -1), (0, 0), "algebraic"), "(H u)_2"),
])
def test_a_wrong_certificate_is_rejected_by_the_exact_check(H, cert, words):
    with pytest.raises(VerificationError) as info:
        verify_certificate(H, cert)
    assert words in str(info.value)


def test_a_wrong_certificate_gives_no_bound():
    with pytest.raises(VerificationError, match="is not > 0"):
        impulse_bounds(np.eye(3), chain_matrices([1, 1, 1])[1], [1, 0, 0],
                       SeparationCertificate(True, (0, 0, 1), (0, 1), "rational"))


# -------------------------------------------------------------------------------- the bounds
def test_the_bound_is_attained_by_one_elastic_contact():
    # ball of mass 2 on a wall at speed 1: P = 2 mu |w| = 4 = 2 sqrt(2 T- mu)
    r = compliant_impact([[2.0]], [[-1.0]], [1.0], 3.0)
    b = impulse_bounds([[2.0]], [[-1.0]], [1.0])
    assert b.tolist() == [4.0] and abs(r.impulses[0] / b[0] - 1) < 1e-9


def test_both_proved_bounds_on_a_chain():
    # certificate bound P_i <= 2 |u|_M sqrt(2T-) / (Hu)_i and the W bound 2 sqrt(2 T- (W^-1)_ii)
    M, H, _ = chain_matrices([1, 2, 3])
    v = np.array([1.0, 0, -0.5])
    c = separating_direction(H)
    T0 = 0.5 * v @ M @ v
    u, Hu = c.vector_float, c.products_float
    by_u = 2 * np.sqrt(u @ M @ u) * np.sqrt(2 * T0) / Hu
    W = H @ np.linalg.solve(M, H.T)
    by_w = 2 * np.sqrt(2 * T0 * np.diag(np.linalg.inv(W)))
    assert np.array_equal(impulse_bounds(M, H, v, c), np.minimum(by_u, by_w))
    r = chain_impact([1, 2, 3], v, [1, 2])
    assert np.all(r.impulses <= np.minimum(by_u, by_w))


def random_chains(seed, count):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        n = int(rng.integers(2, 6))
        masses = 10 ** rng.uniform(-1, 1, n)
        v = np.zeros(n)
        v[: int(rng.integers(1, n))] = rng.uniform(0.5, 2)
        walls = ("right",) if rng.random() < 0.4 else ()
        k = n - 1 + len(walls)
        yield masses, v, walls, 10 ** rng.uniform(-1, 1, k), rng.choice([1.0, 1.5, 2.0], k)


def test_the_impulse_bound_holds_on_random_chains():
    # sampling (8 chains: 2-5 balls, masses and stiffnesses over two decades, 1..n-1 strikers,
    # sometimes a wall, exponents 1, 3/2, 2): not a proof, the proof is step 2 of the document
    for masses, v, walls, K, p in random_chains(7, 8):
        r = chain_impact(masses, v, K, exponent=p, walls=walls)
        M, H, _ = chain_matrices(masses, walls)
        b = impulse_bounds(M, H, v)
        assert r.outcome == "separated" and r.certificate.separating
        assert np.all(r.impulses >= 0) and np.all(r.impulses <= b), (masses, v, walls, K, p)
        assert np.all(H @ r.velocity >= -1e-12 * np.max(-(H @ v)))  # the stopping condition


# ------------------------------------------------------------------ checks of a run (tampering)
def chain_run():
    M, H, _ = chain_matrices([1, 1, 1])
    v = np.array([1.0, 0, 0])
    return M, H, v, chain_impact([1, 1, 1], v, 1.0)


def test_a_run_carries_its_certificate_and_checks():
    M, H, v, r = chain_run()
    assert r.certificate.separating and r.checks["momentum_residual"] < 1e-12
    assert r.checks["energy_error"] < r.checks["energy_tol"] == energy_tolerance(1e-11) == 1e-6


def test_a_tampered_impulse_breaks_the_momentum_balance():
    M, H, v, r = chain_run()
    with pytest.raises(VerificationError, match="momentum balance"):
        check_run(M, H, v, r.velocity, r.impulses * 1.01, elastic=True, rtol=1e-11)


def test_a_tampered_velocity_breaks_the_energy():
    M, H, v, r = chain_run()
    P = r.impulses * 1.1  # consistent momentum, too much energy
    vp = v + np.linalg.solve(M, H.T @ P)
    with pytest.raises(VerificationError, match=r"\|T\+/T- - 1\|"):
        check_run(M, H, v, vp, P, elastic=True, rtol=1e-11)
    with pytest.raises(VerificationError, match="gained energy"):
        check_run(M, H, v, vp, P, elastic=False, rtol=1e-11)


def test_an_impulse_above_its_bound_raises():
    M, H, v, r = chain_run()
    b = impulse_bounds(M, H, v)
    check_run(M, H, v, r.velocity, r.impulses, elastic=True, rtol=1e-11, bounds=b)
    with pytest.raises(VerificationError, match="exceeds its proved bound"):
        check_run(M, H, v, r.velocity, r.impulses, elastic=True, rtol=1e-11, bounds=r.impulses / 1.01)


def test_an_integration_that_breaks_the_bound_raises_instead_of_returning(monkeypatch):
    # mutation: a bound half as large as the proved one; the run must stop with an error mid-way
    real = termination.impulse_bounds
    monkeypatch.setattr(termination, "impulse_bounds", lambda *a, **k: real(*a, **k) / 2)
    with pytest.raises(VerificationError, match="exceeds its proved"):
        chain_impact([1, 1, 1], [1, 0, 0], 1.0)


# ------------------------------------------------------------------------- confined systems
def test_an_elastic_ball_between_two_walls_never_separates():
    # proved in the document (a 1-D conservative oscillator); the engine stops at its cap and says why
    with pytest.raises(NonTermination, match=r"t_max = 20 .*no separating direction \(lambda = \(1, 1\)"):
        compliant_impact([[1.0]], [[1.0], [-1.0]], [-1.0], 1.0, t_max=20.0)


def test_a_confined_system_can_still_end():
    # walls on both sides of ball 1 in x (confined, lambda = (1, 1, 0)), ball 2 falls on it in y: the
    # walls never act, the impact ends. So the laws' refusal is "not proved to end", not "never ends"
    H = np.array([[1.0, 0, 0, 0], [-1, 0, 0, 0], [0, -1, 0, 1]])
    r = compliant_impact(np.eye(4), H, [0, 0, 0, -1.0], 1.0, max_events=50)
    assert r.outcome == "separated" and not r.certificate.separating and r.certificate.support == (0, 1)
    assert abs(r.velocity[1] + 1) < 1e-9 and abs(r.velocity[3]) < 1e-9


@pytest.mark.parametrize("law", ["hertz", "linear", "power", "lzb"])
@pytest.mark.parametrize("H, lam", [("1;-1", "lambda = (1, 1)"),
                                    ("1,0,0;-1,1,0;0,-1,1;0,0,-1", "lambda = (1, 1, 1, 1)")])
def test_the_elastic_laws_refuse_a_jammed_scene_naming_lambda(law, H, lam):
    n = len(H.split(";")[0].split(","))
    s = System.from_matrices(sp.eye(n), H, sp.Matrix([-1] + [0] * (n - 1)))
    with pytest.raises(ImpactInputError) as info:
        resolve(law, s, **({"exponent": 2} if law == "power" else {}))
    msg = str(info.value)
    assert lam in msg and "Gordan's alternative no u has H u > 0" in msg and "confine" in msg


def test_the_refusal_is_exact_for_algebraic_rows():
    s = System.from_matrices(sp.eye(2), sp.Matrix([[S3, 1], [-1, -1 / S3]]), sp.Matrix([-1, 0]))
    with pytest.raises(ImpactInputError, match=r"lambda = \(2\*sqrt\(3\)/3, 2\)"):
        resolve("hertz", s)


def test_damped_laws_without_a_separating_direction():
    s = System.from_matrices("1", "1;-1", "-1", sp.Rational(1, 2))
    with pytest.raises(ImpactInputError, match="rest tolerance"):
        resolve("hunt-crossley", s)
    # the engine: damped, it ends only at rest_tol (outcome "rest")
    r = chain_impact([1], [1], 1.0, [0.3, 0.3], walls=("left", "right"), model="linear", rest_tol=1e-3)
    assert r.outcome == "rest" and r.energy_ratio <= 1e-3 and not r.certificate.separating


def test_laws_report_the_certificate_and_checks():
    res = resolve("hertz", System.from_scene(acary_taha.pool(sp.pi / 3, sp.pi / 12)))
    t = res.details["termination"]
    assert t["certificate"]["separating"] and t["checks"]["energy_error"] < t["checks"]["energy_tol"]
    assert t["document"] == "docs/compliant_termination.md"
    lz = resolve("lzb", System.from_scene(acary_taha.chain3([1, 1, 1], [1, 0, 0])))
    assert lz.details["termination"]["checks"]["momentum_residual"] < 1e-12
