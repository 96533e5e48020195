"""The example systems of Seghete & Murphey (sec. II-C, III-B), built with the scene builders.

Every scene is described by its bodies (masses, radii, positions, velocities, walls) and reduced
by :func:`impactsym.scenes.balls_on_line` to the contacts closed at the impact instant, so the
gradient rows are the paper's covectors because the geometry says so, not because they were
typed in. The same functions feed the tests, the paper checks, the benchmarks and the CLI
(``impactsym resolve --law sequential --scene NAME``, see :data:`SCENES`).

two_balls_wall     sec. II-C.1 / III-B.1 and III-B.3: wall at 0, two balls touching it in a row;
                   ``u = [1, 0]`` (wall–ball 1), ``v = [−1, 1]`` (ball 1–ball 2)
three_ball_cradle  sec. II-C.2 / III-B.2: ``u = [−1, 1, 0]``, ``v = [0, −1, 1]``
cradle             an n-ball cradle whose first k balls (the strikers) arrive together
balls_against_wall n balls in a row against a wall

Examples
--------
>>> sc = two_balls_wall(masses=("11/10", 1))
>>> sc.M, sc.H
(Matrix([
[11/10, 0],
[    0, 1]]), Matrix([
[ 1, 0],
[-1, 1]]))
>>> cradle(5, strikers=2).v.T
Matrix([[1, 1, 0, 0, 0]])
"""

from __future__ import annotations

from fractions import Fraction

from ..arithmetic import LazyModule, sympy_instance
from ..errors import ImpactInputError
from ..scenes import Scene, balls_on_line

# SymPy is imported on first use: ``rational=True`` builds a scene in Fractions without it (issue 15)
sp = LazyModule("sympy", globals(), "sp")

__all__ = ["two_balls_wall", "three_ball_cradle", "cradle", "balls_against_wall", "SCENES"]


def _positive_int(value, argument, minimum):
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ImpactInputError(argument, f"must be an integer >= {minimum}, got {value!r}")
    return value


def _ball_count(value):
    """``n_balls``: an integer >= 1 and at most the sequential law's ``MAX_COORDINATES`` (one
    coordinate per ball; refused here, before the O(n²) symbolic scene is built)."""
    from ..laws.sequential import MAX_COORDINATES

    n = _positive_int(value, "n_balls", 1)
    if n > MAX_COORDINATES:
        raise ImpactInputError("n_balls", f"must be at most {MAX_COORDINATES} (the sequential law's limit "
                                          f"MAX_COORDINATES, one coordinate per ball), got {n}")
    return n


def _row_positions(n, radius, start, rational=False):
    r = Fraction(radius) if rational else sp.sympify(radius)
    return [start + r + 2 * r * i for i in range(n)]


def two_balls_wall(masses=(1, 1), velocities=(-1, -2), radius=1, *, rational=False) -> Scene:
    """Two balls in a row against a wall (fig. 3): wall at 0, balls at ``r`` and ``3r``.

    ``φ_u = x₁ − r`` and ``φ_v = x₂ − x₁ − 2r``: ``u = [1, 0]``, ``v = [−1, 1]`` (sec. II-C.1).
    The default ``v0 = (−1, −2)`` approaches both contacts (``u v0 = −1``, ``v v0 = −1``).
    ``masses=("11/10", 1)`` is sec. III-B.3's ``M = diag(1.1, 1)``.

    Every builder here takes ``rational=True``: its numbers ``int`` or ``Fraction``, and the
    scene's ``M``, ``H``, ``v`` :class:`~impactsym.resolution.RationalMatrix`, built without SymPy
    (:func:`impactsym.scenes.balls_on_line`).

    >>> two_balls_wall().contacts
    ['wall@0-1', '1-2']
    """
    if len(masses) != 2 or len(velocities) != 2:
        raise ImpactInputError("masses/velocities", "two_balls_wall needs exactly two of each")
    sc = balls_on_line(list(masses), [radius, radius], _row_positions(2, radius, 0, rational), list(velocities), [0],
                       rational=rational)
    # the paper's order of the surfaces: u (wall) first, then v (ball-ball)
    order = [sc.contacts.index("wall@0-1"), sc.contacts.index("1-2")]
    return _reorder(sc, order, {"paper": "seghete-murphey", "ref": "sec. II-C.1, III-B.1, III-B.3",
                                "scene": "two-balls-wall"})


def _reorder(sc: Scene, order, meta) -> Scene:
    from ..resolution import RationalMatrix

    if isinstance(sc.H, RationalMatrix):
        rows = sc.H.tolist()
        H = RationalMatrix([rows[i] for i in order])
    else:
        H = sc.H.extract(order, list(range(sc.H.shape[1]))) if sympy_instance(sc.H, "MatrixBase") else sc.H[order]
    sc.meta.update(meta)
    return Scene(sc.M, H, sc.v, sc.coordinates, [sc.contacts[i] for i in order],
                 [sc.approaching[i] for i in order], sc.meta)


def three_ball_cradle(velocities=(1, 0, 0), masses=(1, 1, 1), radius=1, *, rational=False) -> Scene:
    """Newton's cradle with three balls (fig. 5, sec. III-B.2): ``u = [−1, 1, 0]``, ``v = [0, −1, 1]``.

    >>> three_ball_cradle().H
    Matrix([
    [-1,  1, 0],
    [ 0, -1, 1]])
    """
    if len(masses) != 3 or len(velocities) != 3:
        raise ImpactInputError("masses/velocities", "three_ball_cradle needs exactly three of each")
    sc = balls_on_line(list(masses), [radius] * 3, _row_positions(3, radius, 0, rational), list(velocities),
                       rational=rational)
    sc.meta.update({"paper": "seghete-murphey", "ref": "sec. II-C.2, III-B.2, eq. 4", "scene": "three-ball-cradle"})
    return sc


def cradle(n_balls=3, strikers=1, masses=None, speed=1, radius=1, *, rational=False) -> Scene:
    """An ``n``-ball cradle: balls touching in a row, the first ``strikers`` moving at ``speed``.

    Contacts ``1-2, …, (n−1)-n`` with rows ``[…, −1, 1, …]``; only contact ``k–(k+1)`` approaches
    (the strikers move together, their mutual contacts graze).

    Parameters
    ----------
    n_balls : int ≥ 2
    strikers : int, 1 ≤ strikers < n_balls
    masses : sequence of n masses (default: all 1)
    speed : the strikers' common velocity (> 0 approaches)

    >>> sc = cradle(4, 1)
    >>> sc.contacts, sc.approaching
    (['1-2', '2-3', '3-4'], [True, False, False])
    """
    n = _positive_int(_ball_count(n_balls), "n_balls", 2)
    k = _positive_int(strikers, "strikers", 1)
    if k >= n:
        raise ImpactInputError("strikers", f"must be smaller than n_balls={n}, got {k}")
    masses = [1] * n if masses is None else list(masses)
    if len(masses) != n:
        raise ImpactInputError("masses", f"has {len(masses)} entries, expected n_balls={n}")
    sc = balls_on_line(masses, [radius] * n, _row_positions(n, radius, 0, rational), [speed] * k + [0] * (n - k),
                       rational=rational)
    sc.meta.update({"paper": "seghete-murphey", "ref": "sec. III-B.2 (generalized)", "scene": "cradle",
                    "n_balls": n, "strikers": k})
    return sc


def balls_against_wall(n_balls=2, masses=None, velocities=None, radius=1, *, rational=False) -> Scene:
    """``n`` balls in a row, the first touching a wall at 0 (fig. 3 for ``n = 2``).

    Default velocities: the last ball strikes (``v = −1``), the others rest.

    >>> balls_against_wall(3).contacts
    ['1-2', '2-3', 'wall@0-1']
    """
    n = _ball_count(n_balls)
    masses = [1] * n if masses is None else list(masses)
    velocities = [0] * (n - 1) + [-1] if velocities is None else list(velocities)
    if len(masses) != n or len(velocities) != n:
        raise ImpactInputError("masses/velocities", f"need n_balls={n} entries each")
    sc = balls_on_line(masses, [radius] * n, _row_positions(n, radius, 0, rational), velocities, [0],
                       rational=rational)
    sc.meta.update({"paper": "seghete-murphey", "ref": "sec. II-C.1 (generalized)", "scene": "balls-against-wall",
                    "n_balls": n})
    return sc


#: CLI scene name -> builder (``impactsym resolve --law sequential --scene NAME``)
SCENES = {
    "two-balls-wall": two_balls_wall,
    "three-ball-cradle": three_ball_cradle,
    "cradle": cradle,
    "balls-against-wall": balls_against_wall,
}
