"""Near-tip functions of the enrichments: tip coordinates, branch functions, Williams
modes and ramps, each with its gradient in global coordinates.

Tip coordinates (r, theta) are polar coordinates in the tip frame (x1 ahead of
the tip), theta in [-pi, pi] with the crack faces at +-pi. For a kinked crack
the points behind the kink are mapped first (seed 003 Sect. 5.5, Eqs. 57-59)
so that theta = +-pi follows the preceding segment instead of the straight
line behind the leading one. With alpha the angle of ``x - x_rot`` from the
leading segment and theta_R that of the preceding segment (both in (0, 2 pi)),
the map keeps ``rbar = |x - x_rot|`` and sends alpha to
``alpha* = pi + C (alpha - theta_R)`` with ``C = C_b`` (alpha > theta_R) or
``C_a`` (Eq. 57), so that the preceding segment maps onto the line behind the
tip and the normal to the leading segment through x_rot is fixed. Its
Jacobian is ``J = u* u^T + C v* v^T`` (u, v the radial and tangential unit
vectors at alpha, u*, v* at alpha*), which is Eq. (59) written in vectors.

A point exactly on a crack face is on the polyline's left face (the
convention of :mod:`efgkit.problem.crack`); split nodes carry their own face.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..problem.crack import Crack, Tip

__all__ = ["TipGeometry", "tip_coordinates", "branch_functions", "williams_modes",
           "williams_matrix", "ramp"]


@dataclass(frozen=True, eq=False)
class TipGeometry:
    """A tip with what the enrichment needs of its crack.

    Attributes
    ----------
    tip : Tip
    kink : ndarray (2,) or None
        The kink point x_rot (start of the leading segment) of a polyline
        crack whose preceding segment lies behind the leading one
        (pi/2 < theta_R < 3 pi/2), else None.
    theta_r : float
        theta_R of Eq. (57) in (pi/2, 3 pi/2) (pi for a straight crack).
    upper_is_left : bool
        Whether the polyline's left face is the tip frame's upper face (+x2).
    """

    tip: Tip
    kink: np.ndarray | None
    theta_r: float
    upper_is_left: bool

    @classmethod
    def of(cls, crack: Crack, end: int) -> TipGeometry:
        tip = crack.tip(end)
        v = crack.vertices if end == 1 else crack.vertices[::-1]
        kink, theta_r = None, math.pi
        if len(v) >= 3:
            d = tip.rotation @ (v[-3] - v[-2])  # preceding segment, from the kink, tip frame
            th = math.atan2(d[1], d[0]) % (2 * math.pi)
            if abs(th - math.pi) > 1e-12 and math.pi / 2 < th < 3 * math.pi / 2:
                kink, theta_r = v[-2].copy(), th
        return cls(tip, kink, theta_r, end == 1)


def tip_coordinates(x: np.ndarray, geom: TipGeometry, side: np.ndarray | None = None):
    """Polar tip coordinates and their gradients.

    Parameters
    ----------
    x : ndarray (n, 2)
    geom : TipGeometry
    side : ndarray (n,) int, optional
        +1 / -1: the point is on the polyline's left / right face when it
        lies on the crack line (split nodes); 0 or None: the left face.

    Returns
    -------
    r, theta : ndarray (n,)
    grad_r, grad_theta : ndarray (n, 2)
        Global gradients (grad_theta ~ 1 / r; the caller keeps r > 0).
    """
    Q = geom.tip.rotation
    loc = (np.atleast_2d(x) - geom.tip.x) @ Q.T  # tip frame
    n = len(loc)
    if geom.kink is not None:
        J = np.broadcast_to(np.eye(2), (n, 2, 2)).copy()  # d x*_loc / d x_loc
        k = Q @ (geom.kink - geom.tip.x)
        rel = loc - k
        behind = rel[:, 0] < 0
        if behind.any():
            rb = np.hypot(*rel[behind].T)
            alpha = np.arctan2(rel[behind, 1], rel[behind, 0]) % (2 * np.pi)
            tr = geom.theta_r
            C = np.where(alpha > tr, (np.pi / 2) / (1.5 * np.pi - tr), (np.pi / 2) / (tr - np.pi / 2))
            a_star = np.pi + C * (alpha - tr)
            loc[behind] = k + rb[:, None] * np.column_stack([np.cos(a_star), np.sin(a_star)])
            u = np.column_stack([np.cos(alpha), np.sin(alpha)])
            v = np.column_stack([-np.sin(alpha), np.cos(alpha)])
            us, vs = (np.column_stack([np.cos(a_star), np.sin(a_star)]),
                      np.column_stack([-np.sin(a_star), np.cos(a_star)]))
            J[behind] = us[:, :, None] * u[:, None, :] + C[:, None, None] * vs[:, :, None] * v[:, None, :]
    r = np.hypot(*loc.T)
    theta = np.arctan2(loc[:, 1], loc[:, 0])
    # on the crack line behind the tip: to rounding for points, to the 1e-6 of the node
    # splitting for split nodes (side != 0)
    tol = 1e-12 if side is None else np.where(np.asarray(side) != 0, 1e-6, 1e-12)
    on_face = (loc[:, 0] < 0) & (np.abs(loc[:, 1]) <= tol * r)
    if on_face.any():
        left = np.ones(n) if side is None else np.where(np.asarray(side) < 0, -1.0, 1.0)
        upper = left > 0 if geom.upper_is_left else left < 0
        theta = np.where(on_face, np.where(upper, np.pi, -np.pi), theta)
    safe = np.where(r > 0, r, 1.0)
    dr_loc = np.column_stack([np.cos(theta), np.sin(theta)])
    dt_loc = np.column_stack([-np.sin(theta), np.cos(theta)]) / safe[:, None]
    # chain rule: d/dx_loc = J^T d/dx*, then back to global: d/dx = Q^T d/dx_loc
    if geom.kink is None:  # J = I
        return r, theta, dr_loc @ Q, dt_loc @ Q
    grad_r = np.einsum("nji,nj->ni", J, dr_loc) @ Q
    grad_t = np.einsum("nji,nj->ni", J, dt_loc) @ Q
    return r, theta, grad_r, grad_t


def branch_functions(r, theta, grad_r, grad_theta, kind: str):
    """Near-tip basis functions and their gradients.

    ``kind="radial"``: [sqrt(r)] (seed 003 Eq. 52); ``"full"``:
    [sqrt(r) cos(t/2), sqrt(r) sin(t/2), sqrt(r) sin(t/2) sin(t), sqrt(r) cos(t/2) sin(t)]
    (the near-tip terms of Eq. 50). Returns F (n, m) and dF (n, 2, m).
    """
    sr = np.sqrt(r)
    isr = np.where(r > 0, 0.5 / np.where(r > 0, sr, 1.0), 0.0)  # d sqrt(r) / dr
    if kind == "radial":
        F = sr[:, None]
        dF = (isr[:, None] * grad_r)[:, :, None]
        return F, dF
    if kind != "full":
        raise ValueError(f"kind must be 'radial' or 'full', got {kind!r}")
    c, s = np.cos(theta / 2), np.sin(theta / 2)
    st, ct = np.sin(theta), np.cos(theta)
    ang = np.stack([c, s, s * st, c * st], axis=1)  # angular parts
    dang = np.stack([-s / 2, c / 2, c / 2 * st + s * ct, -s / 2 * st + c * ct], axis=1)
    F = sr[:, None] * ang
    dF = (isr[:, None, None] * grad_r[:, :, None] * ang[:, None, :]
          + sr[:, None, None] * grad_theta[:, :, None] * dang[:, None, :])
    return F, dF


def williams_modes(F, dF, geom: TipGeometry, mu: float, kappa: float):
    """Williams displacement of unit K_I and unit K_II (seed 003 Eq. 38) in global components.

    With c = 1 / (2 mu sqrt(2 pi)) and F the four "full" branch functions,
    mode I: (u1, u2) = c ((kappa - 1) F1 + F3, (kappa + 1) F2 - F4), mode II:
    (u1, u2) = c ((kappa + 1) F2 + F4, -(kappa - 1) F1 + F3) in the tip frame
    (the trigonometric identities 2 sin^2(t/2) cos(t/2) = sin(t) sin(t/2) and
    2 cos^2(t/2) sin(t/2) = sin(t) cos(t/2) turn Eq. 38 into these).

    Returns
    -------
    Q : ndarray (n, 2, 2)
        ``Q[:, mode, comp]`` global displacement components.
    dQ : ndarray (n, 2, 2, 2)
        ``dQ[:, mode, comp, dir]`` = d Q_comp / d x_dir.
    """
    Mg = williams_matrix(geom, mu, kappa).reshape(4, 4)  # (mode comp, function)
    n = len(F)  # products with the 4 x 4 matrix (the three-operand einsums loop 5x slower)
    Q = (F @ Mg.T).reshape(n, 2, 2)
    dQ = (dF @ Mg.T).reshape(n, 2, 2, 2).transpose(0, 2, 3, 1)  # (n, dir, mode, comp) -> ...
    return Q, dQ


def williams_matrix(geom: TipGeometry, mu: float, kappa: float) -> np.ndarray:
    """The coefficients of :func:`williams_modes`: ``Q[mode, comp] = Mg[mode, comp] . F``
    in global components, shape (2, 2, 4) (mode, comp, branch function)."""
    c = 1.0 / (2.0 * mu * math.sqrt(2.0 * math.pi))
    M = c * np.array([[[kappa - 1, 0, 1, 0], [0, kappa + 1, 0, -1]],
                      [[0, kappa + 1, 0, 1], [-(kappa - 1), 0, 1, 0]]])  # (mode, comp_loc, 4)
    R = geom.tip.rotation  # rows e1, e2: global = R^T local
    return np.einsum("lc,mlf->mcf", R, M)  # (mode, comp_global, 4)


def ramp(r, grad_r, r1: float, r2: float, kind: str = "quintic"):
    """Ramp R of seed 003 Eq. (54): 1 for r <= r1, 0 for r >= r2, and its gradient.

    ``xi = (r - r1) / (r2 - r1)``; linear ``1 - xi``, quintic
    ``1 - 10 xi^3 + 15 xi^4 - 6 xi^5``. Returns R (n,) and dR (n, 2).
    """
    xi = np.clip((r - r1) / (r2 - r1), 0.0, 1.0)
    inside = (r > r1) & (r < r2)
    if kind == "linear":
        R, dRdxi = 1.0 - xi, -np.ones_like(xi)
    elif kind == "quintic":
        R = 1.0 - xi**3 * (10.0 - 15.0 * xi + 6.0 * xi**2)
        dRdxi = -30.0 * xi**2 * (1.0 - xi) ** 2
    else:
        raise ValueError(f"ramp must be 'linear' or 'quintic', got {kind!r}")
    dR = np.where(inside[:, None], (dRdxi / (r2 - r1))[:, None] * grad_r, 0.0)
    return R, dR
