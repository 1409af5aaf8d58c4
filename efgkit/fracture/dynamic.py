"""The dynamic J' of Nishioka and Atluri and the interaction integral with inertia, in domain form.

Seed 002 Eq. 31 (Nishioka and Atluri, Eng. Fract. Mech. 18, 1983) defines, for a tip
moving or not,

.. math::

    J'_k = \\lim_{\\varepsilon\\to 0}\\Big\\{\\int_{\\Gamma_p + \\Gamma_c}
        [(W + T) n_k - t_i u_{i,k}]\\,dS
      + \\int_{V_p - V_\\varepsilon} [(\\rho \\ddot u_i - b_i) u_{i,k}
        - \\rho \\dot u_i \\dot u_{i,k}]\\,dV\\Big\\},

``W = sigma_ij u_i,j / 2`` (strain energy density), ``T = rho u'_i u'_i / 2`` (kinetic
energy density; the seed's ``K``), ``u'`` velocity, ``u''`` acceleration, ``b`` body force.
It equals the near-tip contour integral ``lim int_{Gamma_eps} [(W + T) n_k - t_i u_i,k] ds``.
With ``q`` (:class:`~efgkit.fracture.qfunctions.QFunction`, 1 at the tip, 0 on
``Gamma_p``), the divergence theorem on the ring between ``Gamma_eps`` and ``Gamma_p``
(with ``sigma_ij,j = rho u''_i - b_i``, ``W_,k = sigma_ij u_i,jk`` and a homogeneous
``rho``) gives the domain form used here, in the tip frame (``k = 1, 2``; seed 002 Eq. 32):

.. math::

    J'_k = \\int_A \\big[\\sigma_{ij} u_{i,k} - (W + T)\\delta_{kj}\\big] q_{,j}\\,dA
         + \\int_A \\big[(\\rho \\ddot u_i - b_i) u_{i,k} - \\rho \\dot u_i \\dot u_{i,k}\\big] q\\,dA
         + \\int_{C_+ \\cup C_-} \\big[(W + T) m_k - t_i u_{i,k}\\big] q\\,ds,

``m`` the body's outward normal on the faces (``m = -e_2`` on the upper face, ``+e_2`` on
the lower one), ``t`` the traction applied there. For ``k = 1`` the face term is the
static one, ``-t_i u_i,1 q``; for ``k = 2`` it holds ``(W + T)`` on both faces (it cancels
for the pure singular fields, not in general). This form needs the velocity gradient
``u'_i,k``. Behind a moving tip ``u' ~ r^{-1/2}``: the ``q``-term then has the integrable
pointwise cancellation ``u''_i u_i,1 - u'_i u'_i,1 = 0`` of steady motion, and ``T`` has a
finite flux into the tip, so this is the form for ``V > 0``.

For a stationary crack (``V = 0``) ``u'`` is bounded at the tip and
``-int rho u'_i u'_i,k q = -int T_,k q = int T q_,k - int_{C+-} T m_k q`` (by parts; the
``Gamma_eps`` term vanishes), so every kinetic term cancels and the velocity is not needed:

.. math::

    J'_k = \\int_A \\big[\\sigma_{ij} u_{i,k} - W\\delta_{kj}\\big] q_{,j}\\,dA
         + \\int_A (\\rho \\ddot u_i - b_i) u_{i,k}\\, q\\,dA
         + \\int_{C_+ \\cup C_-} \\big[W m_k - t_i u_{i,k}\\big] q\\,ds

(used when no velocity gradient is given: the static integrand plus the inertia of the
acceleration). With ``u' = u'' = b = 0`` both are the static
J of :mod:`efgkit.fracture.integrals` (``k = 1``).

*Interaction integral.* With a static auxiliary field ``u^a`` (Williams, unit ``K_I`` or
``K_II``; no velocity, ``sigma^a_ij,j = 0``), the cross terms of ``J'_1(u + u^a)`` are
the static interaction integrand plus ``int_A (rho u''_i - b_i) u^a_i,1 q dA``; for a
stationary crack ``K = E' I / 2`` as in the static case. A moving tip would need the
moving-crack auxiliary fields: for ``V > 0`` only the ``J'`` estimate is given.

Inputs are arrays at points (Gauss points, nodes with volumes), as in
:func:`~efgkit.fracture.integrals.domain_integrals`; one pass over the points of the
largest disc serves every domain (:func:`dynamic_integrands`, then
:func:`contract_dynamic` per ``q``), and
:func:`~efgkit.fracture.dynamic_tip.dynamic_tip_result` averages several.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..problem.crack import Tip
from ..problem.frames import rotate_gradient, rotate_vectors, rotate_voigt
from ..problem.material import Elastic, strain_from_gradient, voigt_tensor
from .auxiliary_fields import auxiliary_fields
from .integrals import FaceLoad, Integrands, contract, domain_integrands, real_array
from .qfunctions import QFunction

__all__ = ["DynamicIntegrands", "DynamicSIF", "contract_dynamic", "dynamic_integrands"]

_AT_TIP = 1e-10  # points closer than this times r_max are left out (the static rule keeps them all)


def _density(rho, material: Elastic) -> float:
    """The homogeneous density of the domain form: ``rho`` (a number > 0), or ``material.rho``
    when ``rho`` is None. An array is refused: a varying density adds ``rho_,k`` terms."""
    if rho is None:
        rho = material.rho
        if rho is None:
            raise ValueError("rho is None and the material has no density: give rho or "
                             "Elastic(..., rho=...)")
    if isinstance(rho, bool) or not isinstance(rho, (int, float, np.integer, np.floating)):
        raise TypeError(f"rho must be one number (the domain form of J' assumes a homogeneous "
                        f"density), got {type(rho).__name__}")
    if not (math.isfinite(rho) and rho > 0):
        raise ValueError(f"rho must be finite and > 0, got {rho!r}")
    return float(rho)


@dataclass(frozen=True)
class DynamicSIF:
    """Dynamic J' and interaction integrals of one tip over one domain.

    Attributes
    ----------
    J1, J2 : float
        ``J'_1``, ``J'_2`` in the tip frame (seed 002 Eqs. 31-32).
    KI, KII : float
        From the interaction integrals with the inertia term (stationary crack).
    n_points : int
        Points in the disc ``r < radius``.
    radius : float
    mismatch : float
        As :attr:`~efgkit.fracture.integrals.SIF.mismatch` (stress against ``grad_u``).
    """

    J1: float
    J2: float
    KI: float
    KII: float
    n_points: int
    radius: float
    mismatch: float = 0.0


@dataclass(frozen=True, eq=False)
class DynamicIntegrands:
    """The integrands of one tip's dynamic domain integrals at the points of a disc.

    Attributes
    ----------
    static : Integrands
        The static integrands at the same points (:func:`~efgkit.fracture.integrals.domain_integrands`).
    rho : float
    c : ndarray (2, m, 2)
        ``w [sigma_ij u_i,k - (W + T) delta_kj]``, ``k = 1, 2`` (coefficients of ``q_,j``),
        tip frame; without the velocity gradient ``T`` is left out (module docstring).
    e : ndarray (4, m)
        Coefficients of ``q``: ``w [(rho u''_i - b_i) u_i,k - rho u'_i u'_i,k]`` for
        ``k = 1, 2`` (the last term only with the velocity gradient) and
        ``w (rho u''_i - b_i) u^a_i,1`` for the mode I and mode II auxiliary fields.
    kinetic : {"W+T", "W"}
        Which form (module docstring).
    """

    static: Integrands
    rho: float
    c: np.ndarray
    e: np.ndarray
    kinetic: str


def dynamic_integrands(x, w, stress, grad_u, velocity, acceleration, rho, tip: Tip,
                       material: Elastic, r_max: float, grad_v=None,
                       body_force=None) -> DynamicIntegrands:
    """The :class:`DynamicIntegrands` of ``tip`` at the points within ``r_max``.

    Parameters
    ----------
    x : ndarray (n, 2)
        Points (global).
    w : ndarray (n,)
        Weights (areas).
    stress : ndarray (n, 3)
        Voigt (xx, yy, xy), global.
    grad_u : ndarray (n, 2, 2)
        ``grad_u[:, i, j] = du_i/dx_j``, global.
    velocity, acceleration : ndarray (n, 2)
        ``u'``, ``u''``, global (the velocity enters only with ``grad_v``).
    rho : float or None
        Homogeneous density (None: ``material.rho``).
    tip : Tip
    material : Elastic
    r_max : float
        Radius of the largest domain.
    grad_v : ndarray (n, 2, 2), optional
        Velocity gradient ``du'_i/dx_j``; selects the ``W + T`` form (needed when the
        tip moves), else the ``W`` form without kinetic terms (stationary crack).
    body_force : ndarray (n, 2), optional
        ``b`` (global), if the scene has one.

    Raises
    ------
    ValueError
        Shapes, non-finite values in the disc (names the array and the point), an empty disc.
    """
    if not isinstance(tip, Tip):
        raise TypeError(f"tip must be an efgkit.problem.crack.Tip, got {type(tip).__name__}")
    if not isinstance(material, Elastic):
        raise TypeError(f"material must be an Elastic, got {type(material).__name__}")
    rho = _density(rho, material)
    x = real_array("x", x, (-1, 2))
    n = len(x)
    arrays = {"x": x, "w": real_array("w", w, (n,)), "stress": real_array("stress", stress, (n, 3)),
              "grad_u": real_array("grad_u", grad_u, (n, 2, 2)),
              "velocity": real_array("velocity", velocity, (n, 2)),
              "acceleration": real_array("acceleration", acceleration, (n, 2))}
    if grad_v is not None:
        arrays["grad_v"] = real_array("grad_v", grad_v, (n, 2, 2))
    if body_force is not None:
        arrays["body_force"] = real_array("body_force", body_force, (n, 2))
    d = (x - tip.x) @ tip.rotation.T
    r = np.hypot(d[:, 0], d[:, 1])
    sel = np.flatnonzero((r < r_max) & (r > _AT_TIP * r_max))
    if len(sel) == 0:
        near = float(r[r > _AT_TIP * r_max].min(initial=math.inf))
        raise ValueError(f"tip {tip.id} at {tip.x.tolist()}: the J' domain of radius {r_max:.6g} "
                         f"holds no points (nearest point at r = {near:.6g}); enlarge the radius "
                         "or give points near the tip")
    for name, a in arrays.items():
        bad = ~np.isfinite(a[sel].reshape(len(sel), -1)).all(axis=1)
        if np.any(bad):
            i = int(sel[np.argmax(bad)])
            raise ValueError(f"{name} at point {i} {x[i].tolist()} (r = {r[i]:.3g} from tip {tip.id}) "
                             "is not finite; evaluate fields away from singular points")
    a = {k: v[sel] for k, v in arrays.items()}
    static = domain_integrands(a["x"], a["w"], a["stress"], a["grad_u"], tip, material, r_max)
    if len(static.x) != len(sel):  # the static rule keeps every point of this selection
        raise RuntimeError("static and dynamic integrands selected different points")
    ang = -tip.angle
    s = voigt_tensor(rotate_voigt(a["stress"], ang))
    g = rotate_gradient(a["grad_u"], ang)
    v = rotate_vectors(a["velocity"], ang)
    f = rho * rotate_vectors(a["acceleration"], ang)  # rho u'' - b
    if body_force is not None:
        f -= rotate_vectors(a["body_force"], ang)
    W = 0.5 * np.einsum("mij,mij->m", s, g)
    if grad_v is not None:
        W = W + 0.5 * rho * np.einsum("mi,mi->m", v, v)  # W + T
    c = np.einsum("mij,mik->kmj", s, g)  # sigma_ij u_i,k, (2, m, 2)
    c[0, :, 0] -= W
    c[1, :, 1] -= W
    e = np.empty((4, len(sel)))
    e[:2] = np.einsum("mi,mik->km", f, g)
    if grad_v is not None:
        e[:2] -= rho * np.einsum("mi,mik->km", v, rotate_gradient(a["grad_v"], ang))
    # auxiliary fields at the same angles as the static integrands (crack line: left face)
    on_line = 0.0 if tip.end == 1 else -0.0
    dl = d[sel]
    x2 = np.where(np.abs(dl[:, 1]) <= 1e-12 * r_max, on_line, dl[:, 1])
    _, ga = auxiliary_fields(r[sel], np.arctan2(x2, dl[:, 0]), material)
    e[2:] = np.einsum("mi,kmi->km", f, ga[:2, :, :, 0])
    ws = a["w"]
    return DynamicIntegrands(static, rho, c * ws[:, None], e * ws,
                             "W+T" if grad_v is not None else "W")


def _face_terms(faces: FaceLoad, face_velocity, it: DynamicIntegrands, q: QFunction) -> np.ndarray:
    """The face terms ``int [(W (+ T)) m_k - t_i u_i,k] q ds`` of J'_1, J'_2, ndarray (2,);
    ``W`` from ``faces.energy`` where it is given (:mod:`efgkit.fracture.face_fit`)."""
    tip, material = it.static.tip, it.static.material
    d = (faces.x - tip.x) @ tip.rotation.T
    inside = np.hypot(d[:, 0], d[:, 1]) < q.r_out
    if not np.any(inside):
        return np.zeros(2)
    ang = -tip.angle
    t = rotate_vectors(faces.traction[inside], ang)
    g = rotate_gradient(faces.grad_u[inside], ang)
    eps = strain_from_gradient(g)
    W = 0.5 * np.einsum("mi,mi->m", eps @ material.D.T, eps)
    if faces.energy is not None:  # the near-tip W of efgkit.fracture.face_fit where given
        e = faces.energy[inside]
        W = np.where(np.isnan(e), W, e)
    if it.kinetic == "W+T":
        if face_velocity is None:
            raise ValueError("the W + T form (velocity gradient given) with loaded or sampled faces "
                             "needs face_velocity (m, 2), the velocity at the face points")
        fv = real_array("face_velocity", face_velocity, (len(faces.x), 2))
        if not np.all(np.isfinite(fv)):
            raise ValueError("face_velocity must be finite")
        v = rotate_vectors(fv[inside], ang)
        W = W + 0.5 * it.rho * np.einsum("mi,mi->m", v, v)
    m2 = -faces.side[inside]  # outward normal of the body: -e2 on the upper face
    wq = faces.w[inside] * q.value(faces.x[inside], tip)
    out = -np.einsum("m,mi,mik->k", wq, t, g)
    out[1] += np.sum(wq * W * m2)
    return out


def contract_dynamic(integrands: DynamicIntegrands, q: QFunction, faces: FaceLoad | None = None,
                     face_velocity=None) -> DynamicSIF:
    """``J'_1``, ``J'_2`` and the interaction ``K_I``, ``K_II`` over the disc of ``q``.

    ``q.r_out <= integrands.static.r_max``. ``faces`` (:class:`~efgkit.fracture.integrals.FaceLoad`,
    tractions possibly zero) adds the crack-face terms (module docstring); ``face_velocity``
    ``(m, 2)``, global, at ``faces.x``, is needed by the ``W + T`` form. Without ``faces``
    the ``J'_2`` face term (``W`` on the faces) is left out: exact only when the faces carry
    equal ``W`` (the pure singular fields, mode I symmetry).
    """
    if not isinstance(integrands, DynamicIntegrands):
        raise TypeError(f"integrands must be DynamicIntegrands, got {type(integrands).__name__}")
    base = contract(integrands.static, q, faces)  # validates q, faces; static K with face terms
    it, tip = integrands.static, integrands.static.tip
    inside = it.r < q.r_out
    qv, dq = q.value_and_gradient(it.x[inside], tip)
    dq = dq @ tip.rotation.T
    J = np.einsum("kmj,mj->k", integrands.c[:, inside], dq) + integrands.e[:2, inside] @ qv
    if faces is not None:
        J = J + _face_terms(faces, face_velocity, integrands, q)
    I = integrands.e[2:, inside] @ qv
    Ep = it.material.E_prime
    return DynamicSIF(J1=float(J[0]), J2=float(J[1]), KI=base.KI + float(Ep * I[0] / 2),
                      KII=base.KII + float(Ep * I[1] / 2), n_points=base.n_points,
                      radius=q.r_out, mismatch=base.mismatch)
