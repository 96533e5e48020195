"""The two-surface law restates the derivation's exit closed forms for certified arithmetic (fmpz/fmpq
integer powers in Q(√−Δ) and Arb balls of the angle form); here both restatements are evaluated
against :mod:`derivations.two_surface` (``exact_exit_relative_velocity`` and the trigonometric
``exit_relative_velocity``) at random rationals."""

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
                mids = [sp.Float(ball.mid().str(60, radius=False), 60) for ball in balls]
            S = {ts.s_A: sp.Rational(sa.numerator, sa.denominator), ts.s_B: sp.Rational(sb.numerator, sb.denominator),
                 ts.g: sp.Rational(g.numerator, g.denominator), ts.c_A: sp.Rational(ca.numerator, ca.denominator),
                 ts.c_B: sp.Rational(cb.numerator, cb.denominator)}
            D = S[ts.s_A] * S[ts.s_B] - S[ts.g] ** 2
            S[ts.Delta] = D
            S[ts.psi] = sp.atan2(-S[ts.c_A] * sp.sqrt(D), S[ts.s_A] * S[ts.c_B] - S[ts.g] * S[ts.c_A])
            S[ts.beta] = sp.atan2(sp.sqrt(D), -S[ts.g])
            for expr, mid in zip(trig[m], mids):
                val = sp.N(expr.subs(S), 50)
                assert abs(val - mid) <= sp.Float("1e-40") * (1 + abs(val))
