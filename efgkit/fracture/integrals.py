"""Stress intensity factors, J and T from domain integrals of fields at points.

Every integral here is a weighted sum over points: ``x (n, 2)`` with weights
``w (n,)`` (Gauss points of background cells, of MLPG discs or of finite
elements, or nodes with their volumes for the point-wise evaluation of seed 001
Eq. 8), the stress ``(n, 3)`` and the displacement gradient ``(n, 2, 2)`` of
the computed solution there. No discretisation is assumed.

In the tip frame (``x1`` ahead of the tip, :class:`~efgkit.problem.crack.Tip`), with
``q`` a :class:`~efgkit.fracture.qfunctions.QFunction`, the domain form of J
(seed 001 Eq. 7; Moran and Shih 1987, seed 003 Sect. 5.6) with the crack-face
term (derived from seed 001 Eq. 6 by the divergence theorem) is

.. math::

    J = \\int_A \\left(\\sigma_{ij} u_{i,1} - W\\delta_{1j}\\right) q_{,j}\\,dA
        - \\int_{C_+ \\cup C_-} t_i u_{i,1}\\, q\\,ds,\\qquad W = \\tfrac12\\sigma_{ij}u_{i,j},

where ``t`` is the traction applied to the body on the faces. The interaction
integral of the actual field with an auxiliary field (superscript a) is

.. math::

    I = \\int_A \\left(\\sigma_{ij} u^a_{i,1} + \\sigma^a_{ij} u_{i,1}
        - \\sigma_{ik}\\varepsilon^a_{ik}\\delta_{1j}\\right) q_{,j}\\,dA
        - \\int_{C_+ \\cup C_-} t_i u^a_{i,1}\\, q\\,ds

(the auxiliary fields here carry no face traction). With the Williams fields
of unit ``K_I`` and of unit ``K_II`` (:mod:`efgkit.problem.exact.williams`),
``I = 2 K / E'`` (mixed-mode J of seed 003 Sect. 5.6.2), so
``K_I = E' I_I / 2`` and ``K_II = E' I_II / 2``, ``E' = E`` in plane stress and
``E / (1 - nu^2)`` in plane strain. With the field of a unit point force along
``x1`` at the tip, ``T = E' I / f`` on traction-free faces (Kim and Paulino,
CMAME 192, 2003; Nakamura and Parks, IJSS 29, 1992). When the faces
at the tip carry a pressure ``p``, the uniform (``r^0``) part of the stress
has ``sigma_22^0 = -p`` besides ``sigma_11^0 = T``, and ``E' I / f =
sigma_11^0 - sigma_22^0`` (verified to rounding for uniform fields with
their face tractions in ``tests/test_integrals.py``), so ``T = E' I / f + sigma_22^0`` with
``sigma_22^0`` taken from the face traction nearest the tip. Shear tractions on
the faces at the tip make the T integral diverge (``u^a_{1,1} ~ 1/r`` there).

Sign convention: ``K_II > 0`` when the upper face (``theta = +pi``, on the
left of the crack seen from behind the tip) slides in ``+x1`` relative to the
lower face, as in :func:`~efgkit.problem.exact.williams.williams_displacement`
(``u_1(+pi) - u_1(-pi) = (kappa + 1) K_II sqrt(r / 2 pi) / mu``). Mirroring a
field about the crack line flips ``K_II`` and keeps ``K_I``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..problem.crack import Tip
from ..problem.frames import rotate_gradient, rotate_voigt
from ..problem.material import Elastic, strain_from_gradient, voigt_tensor
from .auxiliary_fields import auxiliary_fields
from .faces import AT_TIP, FaceLoad, face_terms, real_array
from .qfunctions import QFunction

__all__ = ["SIF", "FaceLoad", "Integrands", "contract", "domain_integrals", "domain_integrands",
           "k_from_j", "real_array"]


@dataclass(frozen=True)
class SIF:
    """Results of the domain integrals of one tip over one domain.

    Attributes
    ----------
    J : float
        J integral (energy release rate).
    KI, KII : float
        Stress intensity factors from the interaction integrals.
    T : float
        T-stress from the point-force interaction integral.
    KJ : float
        ``sqrt(E' J)`` (the ``K`` of a pure mode; 0 when ``J <= 0``).
    n_points : int
        Points inside the domain disc ``r < radius``.
    radius : float
        Outer radius of the domain (``q.r_out``).
    mismatch : float
        ``sum w |grad q| |sigma - D eps(grad_u)| / sum w |grad q| |sigma|``: 0 for
        a stress computed from ``grad_u`` with the same material; large values
        flag a wrong plane or inconsistent inputs.
    """

    J: float
    KI: float
    KII: float
    T: float
    KJ: float
    n_points: int
    radius: float
    mismatch: float = 0.0


def k_from_j(J: float, material: Elastic) -> float:
    """``K = sqrt(E' J)`` for a single mode (seed 000 Eq. 5.7, ``2 mu / (1 - nu) = E'`` in
    plane strain; ``E' = E`` in plane stress).

    Examples
    --------
    >>> m = Elastic(E=2.0, nu=0.0, plane="stress")
    >>> k_from_j(0.5, m)
    1.0
    """
    if not isinstance(material, Elastic):
        raise TypeError(f"material must be an Elastic, got {type(material).__name__}")
    if not (math.isfinite(J) and J >= 0):
        raise ValueError(f"J must be finite and >= 0 to give K = sqrt(E' J), got {J!r}")
    return math.sqrt(material.E_prime * J)


def domain_integrals(x, w, stress, grad_u, tip: Tip, material: Elastic, q: QFunction,
                     faces: FaceLoad | None = None) -> SIF:
    """J, K_I, K_II and T of one tip from fields at points, over the disc of ``q``.

    Formulas and sign convention: module docstring (seed 001 Eq. 7, seed 003
    Sect. 5.6). The point-wise evaluation of seed 001 Eq. 8 is this function
    with ``x`` the nodes and ``w`` their volumes (:func:`~efgkit.fracture.volumes.nodal_volumes`);
    Eq. 8 as printed has ``u_{i,j}`` and ``delta_ij`` where Eq. 7 (and Moran
    and Shih) have ``u_{i,1}`` and ``delta_1j``: the latter is implemented.
    Points at the tip itself (``r <= 1e-12 r_out``) are left out (every
    :class:`QFunction` has ``grad q = 0`` there, and the fields may be
    infinite); points on the crack line behind the tip count as on the
    polyline's left face, like :meth:`Crack.side` and the crack rules: the
    upper face (``theta = +pi``) of a tip at the crack's last vertex, the
    lower one (``theta = -pi``) of a tip at its first vertex.

    Parameters
    ----------
    x : ndarray (n, 2)
        Points (global coordinates). Only those with ``r < q.r_out`` are used.
    w : ndarray (n,)
        Weights (areas).
    stress : ndarray (n, 3)
        Stress at ``x``, Voigt (xx, yy, xy), global.
    grad_u : ndarray (n, 2, 2)
        ``grad_u[:, i, j] = du_i/dx_j`` at ``x``, global.
    tip : Tip
    material : Elastic
        Gives ``E'``, ``mu``, ``kappa`` and the auxiliary fields' plane.
    q : QFunction
        Weight function; ``q.r_out`` is the domain radius.
    faces : FaceLoad, optional
        Loaded crack-face points; omit for traction-free faces.

    Returns
    -------
    SIF

    Raises
    ------
    ValueError
        No point in the disc (names the tip and radius), arrays of
        inconsistent shape, non-finite values in the disc, face points off
        the crack line.
    TypeError
        ``tip``, ``material`` or ``q`` of the wrong type.

    Examples
    --------
    Exact mode I field on a polar Gauss rule around a tip at the origin:

    >>> from efgkit.problem.exact.williams import williams_gradient, williams_stress
    >>> m = Elastic(1.0, 0.25, "stress")
    >>> tr, tw = np.polynomial.legendre.leggauss(16)
    >>> s = (tr + 1) / 2; r = s**2; th = np.pi * tr          # r = s^2 smooths the r^1/2
    >>> R, TH = [a.ravel() for a in np.meshgrid(r, th, indexing="ij")]
    >>> W = np.outer(s**3 * tw, np.pi * tw).ravel()         # dA = r dr dth = 2 s^3 ds dth
    >>> x = np.column_stack([R * np.cos(TH), R * np.sin(TH)])
    >>> tip = Tip(np.zeros(2), 0.0, "c", 1)
    >>> res = domain_integrals(x, W, williams_stress(R, TH, 2.0, 0.0),
    ...                        williams_gradient(R, TH, 2.0, 0.0, m.mu, m.kappa), tip, m,
    ...                        QFunction("wendland_c2", 1.0))
    >>> round(res.KI, 9), round(res.J, 9), abs(res.KII) < 1e-12   # J = K_I^2 / E'
    (2.0, 4.0, True)
    """
    if not isinstance(q, QFunction):
        raise TypeError(f"q must be a QFunction, got {type(q).__name__}")
    return contract(domain_integrands(x, w, stress, grad_u, tip, material, q.r_out), q, faces)


@dataclass(frozen=True, eq=False)
class Integrands:
    """The integrands of one tip's domain integrals at the points of a disc, before ``grad q``.

    Every integral of the module docstring is ``sum_m c_m . grad q(x_m)`` over the
    points ``r_m < R`` of the disc of ``q``, so one pass over the points of the
    largest disc serves every q-function and radius (:func:`contract`).

    Attributes
    ----------
    tip : Tip
    material : Elastic
    r_max : float
        Radius of the disc the points were taken from.
    x : ndarray (m, 2)
        Global points with ``1e-12 r_max < r < r_max``.
    r : ndarray (m,)
        Their distances from the tip.
    c : ndarray (4, m, 2)
        ``w (sigma_ij u_i,1 - W delta_1j)`` (J) and the three interaction
        integrands (Williams mode I, mode II, point force), tip frame.
    norms : ndarray (2, m)
        ``|w| |sigma|`` and ``|w| |sigma - D eps(grad_u)|`` (:attr:`SIF.mismatch`).
    """

    tip: Tip
    material: Elastic
    r_max: float
    x: np.ndarray
    r: np.ndarray
    c: np.ndarray
    norms: np.ndarray


def domain_integrands(x, w, stress, grad_u, tip: Tip, material: Elastic, r_max: float) -> Integrands:
    """The :class:`Integrands` of ``tip`` at the points within ``r_max`` (arguments as in
    :func:`domain_integrals`); raises when the disc holds no points or non-finite values."""
    if not isinstance(tip, Tip):
        raise TypeError(f"tip must be an efgkit.problem.crack.Tip, got {type(tip).__name__}; take it from "
                        "scene.tips or crack.tip(end)")
    if not isinstance(material, Elastic):
        raise TypeError(f"material must be an Elastic, got {type(material).__name__}")
    x = real_array("x", x, (-1, 2))
    n = len(x)
    w = real_array("w", w, (n,))
    stress = real_array("stress", stress, (n, 3))
    grad_u = real_array("grad_u", grad_u, (n, 2, 2))
    d = (x - tip.x) @ tip.rotation.T  # tip-frame coordinates
    r = np.hypot(d[:, 0], d[:, 1])
    sel = np.flatnonzero((r < r_max) & (r > AT_TIP * r_max))
    if len(sel) == 0:
        _no_points(tip, r_max, r[r > AT_TIP * r_max])
    for name, a in (("x", x), ("w", w), ("stress", stress), ("grad_u", grad_u)):
        bad = ~np.isfinite(a[sel].reshape(len(sel), -1)).all(axis=1)
        if np.any(bad):
            i = int(sel[np.argmax(bad)])
            raise ValueError(f"{name} at point {i} {x[i].tolist()} (r = {r[i]:.3g} from tip {tip.id}) "
                             "is not finite; evaluate fields away from singular points")
    sv = rotate_voigt(stress[sel], -tip.angle)
    s = voigt_tensor(sv)
    g = rotate_gradient(grad_u[sel], -tip.angle)
    ws = w[sel]
    c = np.empty((4, len(sel), 2))
    # J (seed 001 Eq. 7): (sigma_ij u_i,1 - W delta_1j) q,j
    c[0] = np.einsum("mij,mi->mj", s, g[:, :, 0])
    c[0, :, 0] -= 0.5 * np.einsum("mij,mij->m", s, g)
    # interaction integrals with the three auxiliary fields; a point on the crack line
    # behind the tip is on the polyline's left face, as in Crack.side: upper (+0.0 gives
    # theta = +pi) for a tip at the last vertex, lower (-0.0: -pi) at the first
    on_line = 0.0 if tip.end == 1 else -0.0
    x2 = np.where(np.abs(d[sel, 1]) <= 1e-12 * r_max, on_line, d[sel, 1])
    sa, ga = auxiliary_fields(r[sel], np.arctan2(x2, d[sel, 0]), material)
    c[1:] = np.einsum("mij,kmi->kmj", s, ga[:, :, :, 0]) + np.einsum("kmij,mi->kmj", sa, g[:, :, 0])
    c[1:, :, 0] -= np.einsum("mij,kmij->km", s, ga)
    c *= ws[:, None]
    # consistency of stress and grad_u through the material, weighted like the integrand
    norms = np.abs(ws) * np.stack([np.linalg.norm(sv, axis=1),
                                   np.linalg.norm(sv - strain_from_gradient(g) @ material.D.T,
                                                  axis=1)])
    return Integrands(tip, material, float(r_max), x[sel], r[sel], c, norms)


def _no_points(tip: Tip, radius: float, r_beyond: np.ndarray):
    near = float(r_beyond.min(initial=math.inf))
    raise ValueError(f"tip {tip.id} at {tip.x.tolist()}: the J domain of radius {radius:.6g} "
                     f"holds no points (nearest point at r = {near:.6g}); enlarge the radius "
                     "or give points near the tip")


def contract(integrands: Integrands, q: QFunction, faces: FaceLoad | None = None) -> SIF:
    """J, K_I, K_II and T over the disc of ``q`` (``q.r_out <= integrands.r_max``) from
    :class:`Integrands`, with the crack-face terms of ``faces``: a sum of
    ``c . grad q`` over the points (as :func:`domain_integrals`)."""
    if not isinstance(q, QFunction):
        raise TypeError(f"q must be a QFunction, got {type(q).__name__}")
    if faces is not None and not isinstance(faces, FaceLoad):
        raise TypeError(f"faces must be a FaceLoad or None, got {type(faces).__name__}")
    it, tip = integrands, integrands.tip
    if q.r_out > it.r_max * (1 + 1e-12):
        raise ValueError(f"q.r_out = {q.r_out:.6g} exceeds the radius {it.r_max:.6g} the "
                         "integrands were taken from; take them for the largest domain")
    inside = it.r < q.r_out
    if not np.any(inside):
        _no_points(tip, q.r_out, it.r)
    dq = q.gradient(it.x[inside], tip) @ tip.rotation.T
    c = it.c[:, inside]
    J = float(np.sum(c[0] * dq))
    I = np.einsum("kmj,mj->k", c[1:], dq)
    s22 = 0.0
    if faces is not None:
        Jf, If, s22 = face_terms(faces, tip, it.material, q)
        J, I = J + Jf, I + If
    Ep = it.material.E_prime
    gq = np.hypot(dq[:, 0], dq[:, 1])
    den = float(gq @ it.norms[0, inside])
    mis = float(gq @ it.norms[1, inside]) / den if den > 0 else 0.0
    return SIF(J=J, KI=float(Ep * I[0] / 2), KII=float(Ep * I[1] / 2),
               T=float(Ep * I[2] + s22), KJ=math.sqrt(Ep * max(J, 0.0)),
               n_points=int(np.count_nonzero(inside)), radius=q.r_out, mismatch=mis)
