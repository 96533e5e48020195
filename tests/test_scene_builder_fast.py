"""The fast line builder (sorted neighbours, sparse H and M, H·v on the nonzeros) against a plain
every-pair reference, and the fast JSON printing of exact matrices against SymPy's own."""

import random

import pytest
import sympy as sp

from impactsym.errors import ImpactInputError
from impactsym.resolution import _float, _text, matrix_json
from impactsym.scenes.builders import balls_on_line


def reference_line(masses, radii, positions, velocities, walls=()):
    """The builder's algorithm before the fast path, for exact rational input: every pair tested,
    dense rows, dense H·v. Returns (M, H, v, contacts, approaching, uninvolved) or raises."""
    S = sp.Rational
    m, r, x, v, w = ([S(t) for t in seq] for seq in (masses, radii, positions, velocities, walls))
    nb = len(m)
    contacts = []
    for i in range(nb):
        for j in range(i + 1, nb):
            lo, hi = (i, j) if x[j] - x[i] >= 0 else (j, i)
            gap = x[hi] - x[lo] - r[lo] - r[hi]
            if gap < 0:
                exc = ImpactInputError("positions", f"balls {i + 1} and {j + 1} overlap (gap {gap} < 0)")
                exc.balls, exc.wall = (i, j), None
                raise exc
            if gap == 0:
                contacts.append((f"{i + 1}-{j + 1}", [(lo, -1), (hi, 1)]))
    for wi, wall in enumerate(w):
        for b in range(nb):
            side = sp.sign(x[b] - wall)
            if side == 0:
                exc = ImpactInputError("positions", f"ball {b + 1} is centred on the wall at {wall}")
                exc.balls, exc.wall = (b,), wi
                raise exc
            gap = (x[b] - r[b] - wall) if side > 0 else (wall - x[b] - r[b])
            if gap < 0:
                exc = ImpactInputError("positions", f"ball {b + 1} and the wall at {wall} overlap (gap {gap} < 0)")
                exc.balls, exc.wall = (b,), wi
                raise exc
            if gap == 0:
                contacts.append((f"wall@{wall}-{b + 1}", [(b, int(side))]))
    seen, unique = set(), []
    for c in contacts:
        if c[0] not in seen:
            seen.add(c[0])
            unique.append(c)
    if not unique:
        raise ImpactInputError("positions", "no contact is closed (every gap is positive): there is no impact")
    involved = sorted({b for _, e in unique for b, _ in e})
    slot = {b: i for i, b in enumerate(involved)}
    rows = []
    for _, e in unique:
        row = [0] * len(involved)
        for b, g in e:
            row[slot[b]] += g
        rows.append(row)
    H = sp.Matrix(rows)
    vv = sp.Matrix([v[b] for b in involved])
    M = sp.diag(*[m[b] for b in involved])
    approaching = [bool(x < 0) for x in H * vv]
    return M, H, vv, [c[0] for c in unique], approaching, [b + 1 for b in range(nb) if b not in slot]


def random_line_scene(rng):
    """A small rational scene on a line: touching runs, zero radii, coincident points, walls and
    (sometimes) overlaps, the balls numbered in a shuffled order."""
    nb = rng.randint(1, 7)
    radii = [rng.choice([0, 0, sp.Rational(1, 2), 1, sp.Rational(3, 4)]) for _ in range(nb)]
    pos, cur = [], sp.Rational(rng.randint(-3, 3), rng.randint(1, 3))
    for b in range(nb):
        if b:
            cur += radii[b - 1] + radii[b] + rng.choice([0, 0, 0, sp.Rational(1, 3), 2, -sp.Rational(1, 4)])
        pos.append(cur)
    perm = list(range(nb))
    rng.shuffle(perm)
    radii, pos = [radii[p] for p in perm], [pos[p] for p in perm]
    masses = [sp.Rational(rng.randint(1, 5), rng.randint(1, 3)) for _ in range(nb)]
    vel = [sp.Rational(rng.randint(-4, 4), rng.randint(1, 3)) for _ in range(nb)]
    walls = []
    for _ in range(rng.choice([0, 0, 1, 2])):
        b = rng.randrange(nb)
        walls.append(pos[b] + rng.choice([-1, 1]) * (radii[b] + rng.choice([0, 0, 1, sp.Rational(-1, 5)])))
    return masses, radii, pos, vel, walls


def test_line_builder_matches_every_pair_reference_on_random_scenes():
    rng = random.Random(20261201)
    seen = {"ok": 0, "error": 0}
    for _ in range(400):
        args = random_line_scene(rng)
        try:
            want = reference_line(*args)
        except ImpactInputError as e:
            with pytest.raises(ImpactInputError) as got:
                balls_on_line(*args[:4], walls=args[4])
            assert str(got.value) == str(e)
            assert getattr(got.value, "balls", None) == getattr(e, "balls", None)
            assert getattr(got.value, "wall", None) == getattr(e, "wall", None)
            seen["error"] += 1
            continue
        sc = balls_on_line(*args[:4], walls=args[4])
        M, H, v, contacts, approaching, uninvolved = want
        assert sc.M == M and sc.H == H and sc.v == v
        assert type(sc.M) is type(M) and type(sc.H) is type(H)
        assert sc.contacts == contacts and sc.approaching == approaching
        assert sc.meta["uninvolved"] == uninvolved
        seen["ok"] += 1
    assert seen["ok"] > 100 and seen["error"] > 50  # both branches were exercised


def test_line_builder_irrational_input_takes_the_certified_path():
    s3 = sp.sqrt(3)
    sc = balls_on_line([1, 2, 1], [s3, 1, 0], [0, 1 + s3, 2 + s3], [1, 0, -1])
    assert sc.contacts == ["1-2", "2-3"] and sc.H == sp.Matrix([[-1, 1, 0], [0, -1, 1]])
    assert sc.approaching == [True, True]
    with pytest.raises(ImpactInputError, match="balls 1 and 2 overlap"):
        balls_on_line([1, 1], [s3, 1], [0, 2], [1, 0])


def test_zero_radius_ball_between_touching_balls_closes_three_contacts():
    sc = balls_on_line([1, 1, 1], [1, 0, 1], [2, 1, 0], [0, 0, 1])
    assert sc.contacts == ["1-2", "1-3", "2-3"]
    M, H, v, contacts, approaching, _ = reference_line([1, 1, 1], [1, 0, 1], [2, 1, 0], [0, 0, 1])
    assert (sc.H, sc.contacts, sc.approaching) == (H, contacts, approaching)


def test_thousand_ball_cradle():
    from impactsym.models.seghete_murphey import cradle

    sc = cradle(1000)
    assert sc.M.shape == (1000, 1000) and sc.H.shape == (999, 1000)
    assert sc.contacts == [f"{i}-{i + 1}" for i in range(1, 1000)]
    assert sc.approaching == [True] + [False] * 998
    assert sc.M == sp.eye(1000) * sc.M[0, 0]
    H = sc.H
    assert all(H[i, i] == -1 and H[i, i + 1] == 1 for i in range(999))
    assert sum(1 for x in H.values() if x != 0) == 2 * 999  # nothing else is nonzero


def test_matrix_json_fast_path_matches_sympy_printing():
    rng = random.Random(7)
    vals = [sp.Rational(rng.randint(-10 ** 6, 10 ** 6), rng.randint(1, 10 ** 6)) for _ in range(60)]
    vals += [sp.Integer(0), sp.Integer(1), sp.Integer(-1), sp.Rational(10 ** 400), sp.Rational(1, 3),
             sp.sqrt(3) / 2, sp.pi]
    A = sp.Matrix(7, 10, vals[:70] + [0] * (70 - len(vals[:70])))
    got = matrix_json("A", A)
    assert got["A"] == [[_text(x, None) for x in r] for r in A.tolist()]
    assert got["A_float"] == [[_float(x) for x in r] for r in A.tolist()]
