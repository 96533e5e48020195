"""What a scene reduces to, as ``impactsym scene show`` reports it: the relative normal velocities
``w = H v`` and the state of each closed contact (approaching ``w_i < 0``, grazing, leaving; decided
exactly), and the kinetic angles between contacts,
``cos θ_ij = H_i M⁻¹ H_jᵀ / √(H_i M⁻¹ H_iᵀ · H_j M⁻¹ H_jᵀ)`` (``CONVENTIONS.md``; Acary & Taha eq. 40),
from the Delassus matrix ``W = H M⁻¹ Hᵀ`` computed exactly (python-flint for rational data, SymPy
otherwise; float input at its exact binary value).

Examples
--------
>>> from impactsym.models.acary_taha import chain3
>>> d = describe_scene(chain3())
>>> d["contact_states"], d["approaching_contacts"]
(['approaching', 'grazing'], ['1-2'])
>>> [(a["contacts"], a["cos"], a["angle"]) for a in d["kinetic_angles"]]
[(['1-2', '2-3'], '-1/2', '2*pi/3')]
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .scene import Scene

__all__ = ["describe_scene", "kinetic_angles", "contact_states"]


def _exact_data(scene: Scene):
    """``(W, w)`` exact: ``W = H M⁻¹ Hᵀ`` and ``w = H v`` as SymPy matrices (float input at its exact
    binary value)."""
    from ..arithmetic import rational_matrix, to_sympy_matrix, tidy

    M, H, v = scene.M, scene.H, scene.v
    if not scene.exact:
        M, H = np.asarray(M, dtype=float), np.atleast_2d(np.asarray(H, dtype=float))
        v = np.asarray(v, dtype=float).reshape(-1, 1)
    Mq, Hq, vq = rational_matrix(M), rational_matrix(H), rational_matrix(v)
    if Mq is not None and Hq is not None and vq is not None:
        W = Hq * Mq.solve(Hq.transpose())
        return to_sympy_matrix(W), to_sympy_matrix(Hq * vq)
    M, H, v = sp.Matrix(M), sp.Matrix(H), sp.Matrix(v)
    W = (H * M.LUsolve(H.T)).applyfunc(lambda x: tidy(sp.radsimp(x)))
    return W, (H * v).applyfunc(lambda x: tidy(sp.radsimp(x)))


def contact_states(scene: Scene, _data=None) -> list[str]:
    """``"approaching"`` (``H_i v < 0``), ``"grazing"`` (``= 0``) or ``"leaving"`` (``> 0``) for each
    closed contact, decided exactly.

    >>> from impactsym.models.seghete_murphey import cradle
    >>> contact_states(cradle(3, strikers=2))
    ['grazing', 'approaching']
    """
    from ..exact import certified_sign

    _, w = _data or _exact_data(scene)
    return [("approaching", "grazing", "leaving")[certified_sign(x) + 1] for x in w]


def kinetic_angles(scene: Scene, _data=None) -> tuple[list[dict], int]:
    """The kinetic angles of the pairs of closed contacts that are not orthogonal (``W_ij ≠ 0``).

    Returns
    -------
    (angles, orthogonal)
        ``angles``: one dict per pair ``i < j`` with ``W_ij ≠ 0``: ``contacts`` (the two names),
        ``cos`` and ``angle`` (exact text for exact input, floats otherwise) with ``cos_float`` and
        ``angle_float`` (radians), and ``coupled`` (``cos θ_ij < 0``, Acary & Taha eq. 43, decided
        exactly). ``orthogonal``: how many other pairs there are (``cos θ_ij = 0``, ``θ = π/2``).

    Examples
    --------
    >>> import sympy as sp
    >>> from impactsym.models.acary_taha import pool
    >>> angles, orthogonal = kinetic_angles(pool(sp.pi / 4))
    >>> angles[0]["cos"], angles[0]["coupled"], orthogonal
    ('-sqrt(2)/4', True, 0)
    >>> kinetic_angles(pool(sp.pi / 2))[0], kinetic_angles(pool(sp.pi / 2))[1]
    ([], 1)
    """
    from ..arithmetic import tidy
    from ..exact import certified_sign
    from ..numbers import exact_str

    W, _ = _data or _exact_data(scene)
    k = W.shape[0]
    names = list(scene.contacts) if len(scene.contacts) == k else [str(i + 1) for i in range(k)]
    out, orthogonal = [], 0
    for i in range(k):
        for j in range(i + 1, k):
            s = certified_sign(W[i, j])
            if s == 0:
                orthogonal += 1
                continue
            c = tidy(sp.radsimp(W[i, j] / sp.sqrt(W[i, i] * W[j, j])))
            angle = sp.acos(c)
            entry = {"contacts": [names[i], names[j]]}
            if scene.exact:
                entry.update({"cos": exact_str(c), "cos_float": float(sp.N(c, 17)),
                              "angle": exact_str(angle), "angle_float": float(sp.N(angle, 17))})
            else:
                entry.update({"cos": float(sp.N(c, 17)), "cos_float": float(sp.N(c, 17)),
                              "angle": float(sp.N(angle, 17)), "angle_float": float(sp.N(angle, 17))})
            entry["coupled"] = s < 0
            out.append(entry)
    return out, orthogonal


def describe_scene(scene: Scene) -> dict:
    """What the scene reduces to, beyond ``M``, ``H``, ``v`` (``impactsym scene show``'s
    ``reduced`` object).

    Returns
    -------
    dict
        ``exact``, ``n`` (coordinates), ``k`` (closed contacts), ``relative_velocity`` ``w = H v``
        (+ ``_float``), ``contact_states``, ``approaching`` (booleans), ``approaching_contacts``
        (names), ``kinetic_energy`` ``T = ½ vᵀ M v`` (+ ``_float``), ``kinetic_angles`` and
        ``orthogonal_pairs`` (:func:`kinetic_angles`), ``uninvolved_bodies`` (balls numbered from
        1 that touch nothing and stay out of ``M``; when the scene was built from bodies).

    Examples
    --------
    >>> from impactsym.models.seghete_murphey import two_balls_wall
    >>> d = describe_scene(two_balls_wall())
    >>> d["relative_velocity"], d["approaching"], d["kinetic_energy"]
    (['-1', '-1'], [True, True], '5/2')
    """
    from ..numbers import exact_str

    data = _exact_data(scene)
    states = contact_states(scene, data)
    k = len(states)
    names = list(scene.contacts) if len(scene.contacts) == k else [str(i + 1) for i in range(k)]
    if scene.exact:
        T = sp.Rational(1, 2) * (scene.v.T * scene.M * scene.v)[0, 0]
        T = sp.radsimp(T) if not T.is_Rational else T
        energy = {"kinetic_energy": exact_str(T), "kinetic_energy_float": float(sp.N(T, 17))}
        w = data[1]
        wj = {"relative_velocity": [exact_str(x) for x in w], "relative_velocity_float": [float(sp.N(x, 17)) for x in w]}
    else:
        vf = np.asarray(scene.v, dtype=float).reshape(-1)
        T = 0.5 * float(vf @ np.asarray(scene.M, dtype=float) @ vf)
        wf = (np.atleast_2d(np.asarray(scene.H, dtype=float)) @ vf).tolist()
        energy = {"kinetic_energy": T, "kinetic_energy_float": T}
        wj = {"relative_velocity": wf, "relative_velocity_float": wf}
    angles, orthogonal = kinetic_angles(scene, data)
    out = {"exact": scene.exact, "n": scene.n, "k": k, **wj, "contact_states": states,
           "approaching": [s == "approaching" for s in states],
           "approaching_contacts": [c for c, s in zip(names, states) if s == "approaching"],
           **energy, "kinetic_angles": angles, "orthogonal_pairs": orthogonal}
    if "uninvolved" in scene.meta:
        out["uninvolved_bodies"] = list(scene.meta["uninvolved"])
    return out
