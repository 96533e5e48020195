"""The two-surface law restates the derivation's exit closed forms for certified arithmetic (fmpz/fmpq
integer powers in Q(√−Δ) and Arb balls of the angle form); here both restatements are evaluated
against :mod:`derivations.two_surface` (``exact_exit_relative_velocity`` and the trigonometric
``exit_relative_velocity``) at random rationals. The trigonometric forms are evaluated in Arb (ball
arithmetic at 256 bits, :func:`_arb_value`), so the 40-digit agreement is certain."""

import random
from fractions import Fraction

import sympy as sp
from flint import arb, ctx, fmpq

from derivations import two_surface as ts
from impactsym.laws.two_surface import _Data, _field_power_exit, _w_after


def _random_data(rng):
    while True:
        sa, sb = (Fraction(rng.randint(1, 30), rng.randint(1, 9)) for _ in range(2))
        g = Fraction(rng.randint(-30, 30), rng.randint(1, 9))
        if sa * sb - g * g > 0:
            ca, cb = (Fraction(rng.randint(-20, 20), rng.randint(1, 7)) for _ in range(2))
            return sa, sb, g, ca, cb


def _q(x):
    return fmpq(x.numerator, x.denominator)


def _arb_value(expr, env):
    """``expr`` (the derivation's trigonometric exit: sums, products, integer and half powers, ``sin``
    of its symbols and rationals) as an Arb ball at the current precision, ``env`` the symbols' balls;
    any other node raises."""
    if expr.is_Symbol:
        return env[expr]
    if expr.is_Rational:
        return arb(fmpq(int(expr.p), int(expr.q)))
    args = [_arb_value(a, env) for a in expr.args] if not expr.is_Pow else None
    if expr.is_Add:
        return sum(args[1:], args[0])
    if expr.is_Mul:
        out = args[0]
        for a in args[1:]:
            out = out * a
        return out
    if expr.is_Pow:
        base, e = _arb_value(expr.base, env), expr.exp
        if e == sp.S.Half:
            return base.sqrt()
        if e == -sp.S.Half:
            return 1 / base.sqrt()
        if e.is_Integer:
            return base ** int(e)
    if isinstance(expr, sp.sin):
        return args[0].sin()
    raise TypeError(f"_arb_value: no rule for {type(expr).__name__}")


def test_exit_restatements_equal_the_derivation_at_random_rationals():
    rng = random.Random(30112026)
    trig = {m: ts.exit_relative_velocity(m) for m in range(1, 9)}
    for _ in range(15):
        sa, sb, g, ca, cb = _random_data(rng)
        d = _Data(*(_q(x) for x in (sa, sb, g, ca, cb)))
        for m in range(1, 9):
            want = ts.exact_exit_relative_velocity(sa, sb, g, ca, cb, m)
            got = _field_power_exit(d, m)
            assert tuple(Fraction(int(x.p), int(x.q)) for x in got) == want
            prec = 256
            with ctx.workprec(prec):
                balls = _w_after(d.balls(prec), m)
                for ball, exact in zip(balls, want):
                    assert ball.contains(arb(exact.numerator) / exact.denominator)
                mids = [arb(ball.mid()) for ball in balls]  # (exact midpoints)
                S = {ts.s_A: arb(_q(sa)), ts.s_B: arb(_q(sb)), ts.g: arb(_q(g)), ts.c_A: arb(_q(ca)), ts.c_B: arb(_q(cb))}
                S[ts.Delta] = arb(_q(sa * sb - g * g))
                S[ts.psi] = arb.atan2(-S[ts.c_A] * S[ts.Delta].sqrt(), S[ts.s_A] * S[ts.c_B] - S[ts.g] * S[ts.c_A])
                S[ts.beta] = arb.atan2(S[ts.Delta].sqrt(), -S[ts.g])
                for expr, mid in zip(trig[m], mids):
                    val = _arb_value(expr, S)  # certain: every point of the ball passes
                    assert (abs(val - mid) - arb(10) ** -40 * (1 + abs(val))).upper() <= 0
