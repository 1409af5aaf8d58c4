"""K_I and K_II from the dynamic J'_1 of the symmetric and antisymmetric parts of the field.

The mixed-mode split of seed 002 Eqs. 37-38 rests on ``J'_2``, whose crack-face term
holds the strain energy density ``W`` on both faces close to the tip, where a discrete field
without enrichment is poorest. The decomposition method (Ishikawa, Kitagawa and Okamura,
ICM 3, 1979; Rigby and Aliabadi, Int. J. Solids Struct. 35, 1998), applied here to the
dynamic ``J'`` of seed 002 Eq. 31, avoids ``J'_2``: with the reflection
``P' = (x'_1, -x'_2)`` of a point ``P`` across the crack line (tip frame ``x'``) and
``S = diag(1, -1)``,

.. math::

    u^I(P) = \\tfrac12 [u(P) + S u(P')],\\qquad u^{II}(P) = \\tfrac12 [u(P) - S u(P')],

    \\nabla u^{I,II}(P) = \\tfrac12 [\\nabla u(P) \\pm S\\, \\nabla u(P')\\, S],

the same for the acceleration, body force and face traction. ``u^I`` is symmetric about the
crack line (pure mode I), ``u^II`` antisymmetric (pure mode II), both satisfy the equations
of motion, and on a disc symmetric about the crack line the cross terms of ``J'_1`` cancel:
``J'_1 = J'_1(u^I) + J'_1(u^II)``. At ``V = 0`` (seed 002 Eq. 33 with ``A_I = A_II =
(kappa + 1) / 4``)

.. math::

    K_I = \\pm\\sqrt{E' J'_1(u^I)},\\qquad K_{II} = \\pm\\sqrt{E' J'_1(u^{II})},

negative ``J'_1`` taken as 0 (Macaulay), signs those of the interaction integrals of the
same parts (:mod:`efgkit.fracture.dynamic`). Only ``J'_1`` is used: its face term is
``-t_i u_i,1`` on loaded faces, with no ``W``. The mirrored points must lie in the body and
see the same crack: a straight crack and discs clear of the boundary and of other cracks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial import cKDTree

from ..problem.crack import Tip
from ..problem.frames import rotate_gradient, rotate_vectors
from ..problem.material import Elastic, strain_from_gradient
from .dynamic import contract_dynamic, dynamic_integrands
from .integrals import FaceLoad, real_array
from .qfunctions import QFunction

__all__ = ["DecomposedSIF", "decomposed_tip_result", "mirror_points", "split_gradients",
           "split_vectors"]

_S = np.array([1.0, -1.0])


def mirror_points(x, tip: Tip) -> np.ndarray:
    """Reflections of ``x (n, 2)`` across the crack line of ``tip`` (global), ndarray (n, 2).

    Examples
    --------
    >>> t = Tip(np.array([1.0, 1.0]), np.pi / 4, "c", 1)
    >>> mirror_points(np.array([[1.0, 2.0]]), t).round(12).tolist()
    [[2.0, 1.0]]
    """
    x = real_array("x", x, (-1, 2))
    d = (x - tip.x) @ tip.rotation.T
    return tip.x + (d * _S) @ tip.rotation


def split_vectors(tip: Tip, v, v_mirror) -> tuple[np.ndarray, np.ndarray]:
    """Symmetric and antisymmetric parts ``(v (P) +- S v(P')) / 2`` (tip frame), global, (n, 2) each."""
    a = rotate_vectors(v, -tip.angle)
    b = rotate_vectors(v_mirror, -tip.angle) * _S
    return (rotate_vectors(0.5 * (a + b), tip.angle), rotate_vectors(0.5 * (a - b), tip.angle))


def split_gradients(tip: Tip, g, g_mirror) -> tuple[np.ndarray, np.ndarray]:
    """Symmetric and antisymmetric parts ``(grad u(P) +- S grad u(P') S) / 2`` (tip frame),
    global, (n, 2, 2) each."""
    a = rotate_gradient(g, -tip.angle)
    b = rotate_gradient(g_mirror, -tip.angle) * np.outer(_S, _S)
    return (rotate_gradient(0.5 * (a + b), tip.angle), rotate_gradient(0.5 * (a - b), tip.angle))


def _split_faces(faces: FaceLoad, tip: Tip, r_max: float) -> tuple[FaceLoad, FaceLoad]:
    """The face points' parts: every point paired with its mirror among the face points."""
    xm = mirror_points(faces.x, tip)
    j = np.zeros(len(xm), int)
    dist = np.full(len(xm), np.inf)
    for side in (1.0, -1.0):  # each point's mirror among the other face's points
        mine, other = np.flatnonzero(faces.side == side), np.flatnonzero(faces.side == -side)
        if len(mine) and len(other):
            dist[mine], k = cKDTree(faces.x[other]).query(xm[mine])
            j[mine] = other[k]
    if np.any(dist > 1e-9 * r_max):
        i = int(np.argmax(dist))
        raise ValueError(f"faces: the point {faces.x[i].tolist()} has no mirror on the other face "
                         f"(nearest at {dist[i]:.3g}); sample both faces at the same distances")
    g = split_gradients(tip, faces.grad_u, faces.grad_u[j])
    t = split_vectors(tip, faces.traction, faces.traction[j])
    return tuple(replace(faces, traction=t[k], grad_u=g[k]) for k in (0, 1))


@dataclass(frozen=True)
class DecomposedSIF:
    """K_I, K_II of one tip from ``J'_1`` of the symmetric and antisymmetric parts.

    Attributes
    ----------
    KI, KII : float
        ``sign sqrt(E' <J'_1(u^I)>)``, ``sign sqrt(E' <J'_1(u^II)>)`` (means over the domains).
    J1_I, J1_II : ndarray (n_radii,)
        ``J'_1`` of each part per domain, by increasing radius.
    radii : ndarray (n_radii,)
    spread : float
        ``max(ptp K_I, ptp K_II) / |K|`` over the domains (K per domain from its own J'_1).
    """

    KI: float
    KII: float
    J1_I: np.ndarray
    J1_II: np.ndarray
    radii: np.ndarray
    spread: float


def decomposed_tip_result(tip: Tip, x, w, grad_u, grad_u_mirror, acceleration,
                          acceleration_mirror, radii, material: Elastic, rho=None,
                          q="wendland_c2", faces: FaceLoad | None = None, body_force=None,
                          body_force_mirror=None) -> DecomposedSIF:
    """K_I, K_II of a stationary tip by the decomposition method (module docstring).

    Parameters
    ----------
    tip : Tip
    x : ndarray (n, 2)
        Points (global) with weights ``w (n,)``; the largest disc should hold them all.
    grad_u, grad_u_mirror : ndarray (n, 2, 2)
        Displacement gradient (global) at ``x`` and at ``mirror_points(x, tip)``.
    acceleration, acceleration_mirror : ndarray (n, 2)
        ``u''`` (global) at ``x`` and at the mirrored points (zeros for a static field).
    radii : sequence of float
        Domain radii (at least three).
    material : Elastic
    rho : float, optional
        Density (None: ``material.rho``).
    q : str or callable
        q-function name or ``radius -> QFunction``.
    faces : FaceLoad, optional
        Face points with tractions and gradients; every point needs its mirror on the other face.
    body_force, body_force_mirror : ndarray (n, 2), optional
        ``b`` (global) at ``x`` and at the mirrored points.

    Raises
    ------
    ValueError
        Fewer than three radii, unpaired face points, and as
        :func:`~efgkit.fracture.dynamic.dynamic_integrands`.
    """
    rs = np.sort(np.asarray(radii, float).reshape(-1))
    if len(rs) < 3 or not np.all(np.isfinite(rs) & (rs > 0)):
        raise ValueError(f"radii must be at least three finite radii > 0, got {rs.tolist()}; "
                         "domain independence needs three")
    if rho is None and material.rho is None:
        rho = 1.0  # the density only multiplies the acceleration
        if np.any(np.asarray(acceleration) != 0) or np.any(np.asarray(acceleration_mirror) != 0):
            raise ValueError("rho is None and the material has no density: give rho")
    n = len(real_array("x", x, (-1, 2)))
    gm = real_array("grad_u_mirror", grad_u_mirror, (n, 2, 2))
    am = real_array("acceleration_mirror", acceleration_mirror, (n, 2))
    G = split_gradients(tip, real_array("grad_u", grad_u, (n, 2, 2)), gm)
    A = split_vectors(tip, real_array("acceleration", acceleration, (n, 2)), am)
    B = (None, None)
    if body_force is not None:
        B = split_vectors(tip, real_array("body_force", body_force, (n, 2)),
                          real_array("body_force_mirror", body_force_mirror, (n, 2)))
    F = (None, None) if faces is None else _split_faces(faces, tip, rs[-1])
    qs = [q(r) if callable(q) else QFunction(q, r, n=2.0 if q == "power" else None) for r in rs]
    J = np.empty((2, len(rs)))
    sign = np.empty((2, len(rs)))
    for k in (0, 1):  # the two parts
        it = dynamic_integrands(x, w, strain_from_gradient(G[k]) @ material.D.T, G[k],
                                np.zeros((n, 2)), A[k], rho, tip, material, rs[-1],
                                body_force=B[k])
        for i, qf in enumerate(qs):
            res = contract_dynamic(it, qf, F[k])
            J[k, i] = res.J1
            sign[k, i] = res.KI if k == 0 else res.KII
    Ep = material.E_prime
    Kd = np.sqrt(Ep * np.clip(J, 0.0, None)) * np.where(sign < 0, -1.0, 1.0)
    K = np.sqrt(Ep * np.clip(J.mean(axis=1), 0.0, None)) * np.where(sign.mean(axis=1) < 0, -1.0, 1.0)
    norm = math.hypot(*K) or float(np.max(np.hypot(*Kd)))
    spread = float(np.ptp(Kd, axis=1).max() / norm) if norm > 0 else 0.0
    return DecomposedSIF(float(K[0]), float(K[1]), J[0], J[1], rs, spread)
