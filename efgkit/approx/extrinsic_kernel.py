"""Compiled (numba) kernel of the extrinsic MLS enrichment columns, one pass per point.

The enrichment unknowns K_I, K_II of a tip multiply ``psi_m = Q_m(x) - sum_I phi_I(x)
Q_m(x_I)`` (seed 003 Eq. 44b) with Q the Williams fields of unit K_I and K_II (Eq. 38),
optionally ramped (Eq. 54). :func:`efgkit.approx.enrichment.extra_columns` forms them in
numpy from :func:`~efgkit.approx.tip_functions.tip_coordinates`,
:func:`~efgkit.approx.tip_functions.branch_functions`,
:func:`~efgkit.approx.tip_functions.williams_modes`, :func:`~efgkit.approx.tip_functions.ramp`
and :func:`~efgkit.approx.enrichment.interpolant`, with arrays of (n, 2, 2) per step; this
kernel computes the same formulas point by point in one loop (tip frame and kinked-crack map,
Eqs. 57-59; the four branch functions; the modes; the ramp; minus the MLS interpolant of
the nodal Q over the point's neighbours), so that nothing but the outputs is allocated (the
tests compare it with the numpy path to 1e-13). At 2.9M points of the cracked plate the
enrichment columns took 7.7 s in numpy and take 0.7 s with it (kernel 0.55 s, the CSR the rest;
docs/performance.md, "Shape stage of the cracked solve").
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..timing import watch_compiles

__all__ = ["extrinsic_fields", "tip_radii"]

watch_compiles()  # before anything here compiles

RAMP_IDS = {"linear": 0, "quintic": 1}


@njit(cache=True, inline="always")
def _polar(x0, x1, tip, rot, kink, has_kink, theta_r, upper):
    """Tip coordinates of one point as :func:`~efgkit.approx.tip_functions.tip_coordinates`
    (``side`` None): r, theta, d r / dx, d r / dy, d theta / dx, d theta / dy."""
    d0 = x0 - tip[0]
    d1 = x1 - tip[1]
    l0 = d0 * rot[0, 0] + d1 * rot[0, 1]  # tip frame: loc = Q (x - x_tip)
    l1 = d0 * rot[1, 0] + d1 * rot[1, 1]
    j00 = 1.0
    j01 = 0.0
    j10 = 0.0
    j11 = 1.0
    if has_kink:
        r0 = l0 - kink[0]
        r1 = l1 - kink[1]
        if r0 < 0.0:  # behind the kink: Eq. 57 maps the angle, keeps the distance
            rb = math.hypot(r0, r1)
            alpha = math.atan2(r1, r0) % (2.0 * math.pi)
            if alpha > theta_r:
                c = (math.pi / 2) / (1.5 * math.pi - theta_r)
            else:
                c = (math.pi / 2) / (theta_r - math.pi / 2)
            a_star = math.pi + c * (alpha - theta_r)
            ca, sa = math.cos(alpha), math.sin(alpha)
            cs, ss = math.cos(a_star), math.sin(a_star)
            l0 = kink[0] + rb * cs
            l1 = kink[1] + rb * ss
            # J = u* u^T + C v* v^T (Eq. 59 in vectors)
            j00 = cs * ca + c * ss * sa
            j01 = cs * sa - c * ss * ca
            j10 = ss * ca - c * cs * sa
            j11 = ss * sa + c * cs * ca
    r = math.hypot(l0, l1)
    theta = math.atan2(l1, l0)
    if l0 < 0.0 and abs(l1) <= 1e-12 * r:  # on the crack line behind the tip: the left face
        theta = math.pi if upper else -math.pi
    safe = r if r > 0.0 else 1.0
    ct, st = math.cos(theta), math.sin(theta)
    # d/dx_loc = J^T d/dx*, then d/dx = Q^T d/dx_loc
    gr0 = j00 * ct + j10 * st
    gr1 = j01 * ct + j11 * st
    gt0 = (-j00 * st + j10 * ct) / safe
    gt1 = (-j01 * st + j11 * ct) / safe
    return (r, theta, gr0 * rot[0, 0] + gr1 * rot[1, 0], gr0 * rot[0, 1] + gr1 * rot[1, 1],
            gt0 * rot[0, 0] + gt1 * rot[1, 0], gt0 * rot[0, 1] + gt1 * rot[1, 1])


@njit(cache=True, parallel=True)
def tip_radii(x, tip, rot, kink, has_kink, theta_r, upper):
    """r of the tip coordinates (kink-mapped) of the points ``x (n, 2)``, shape (n,)."""
    n = len(x)
    out = np.empty(n)
    for q in prange(n):
        out[q] = _polar(x[q, 0], x[q, 1], tip, rot, kink, has_kink, theta_r, upper)[0]
    return out


@njit(cache=True, parallel=True)
def extrinsic_fields(x, rows, tip, rot, kink, has_kink, theta_r, upper, Mg, ramped, r1, r2,
                     ramp_id, idx, mask, values, ddx, ddy, qn, derivatives):
    """psi and its gradient for the two modes of one tip at the points ``x[rows]``.

    Parameters
    ----------
    x : ndarray (n, 2)
    rows : ndarray (m,) int
        The points to form.
    tip, rot, kink : ndarray (2,), (2, 2), (2,)
        Tip position, rotation (rows e1, e2 of the tip frame), kink in the tip frame.
    has_kink : bool; theta_r : float; upper : bool
        The kinked-crack map (Eq. 57) and which face theta = +pi is.
    Mg : ndarray (2, 2, 4)
        Williams modes in global components: ``Q[mode, comp] = Mg[mode, comp] . F``.
    ramped : bool; r1, r2 : float; ramp_id : int
        The ramp of Eq. 54 (0 linear, 1 quintic).
    idx, mask : ndarray (n, k)
        The points' neighbours (after the crack rule).
    values, ddx, ddy : ndarray (n, k)
        The nodal shape functions and derivatives (``ddx``, ``ddy`` unread without
        ``derivatives``).
    qn : ndarray (n_nodes, 4)
        The (ramped) Q at the nodes, ``qn[I, 2 mode + comp]``.
    derivatives : bool

    Returns
    -------
    out : tuple of 6 ndarray (m, 2)
        ``out[key][row, mode]`` for the keys ux, uy, gxx, gxy, gyx, gyy (separate arrays:
        each becomes an operator's data; without ``derivatives`` the last four are (0, 2)).
    r : ndarray (m,)
        The tip distance of the rows (the caller's at-the-tip check).
    """
    m = len(rows)
    k = idx.shape[1]
    ux = np.empty((m, 2))
    uy = np.empty((m, 2))
    md = m if derivatives else 0
    gxx = np.empty((md, 2))
    gxy = np.empty((md, 2))
    gyx = np.empty((md, 2))
    gyy = np.empty((md, 2))
    rr = np.empty(m)
    for j in prange(m):
        q = rows[j]
        r, th, gr0, gr1, gt0, gt1 = _polar(x[q, 0], x[q, 1], tip, rot, kink, has_kink,
                                           theta_r, upper)
        rr[j] = r
        sr = math.sqrt(r)
        isr = 0.5 / sr if r > 0.0 else 0.0
        c, s = math.cos(th / 2), math.sin(th / 2)
        st, ct = math.sin(th), math.cos(th)
        a0, a1, a2, a3 = c, s, s * st, c * st  # angular parts of the branch functions
        b0, b1 = -s / 2, c / 2
        b2, b3 = c / 2 * st + s * ct, -s / 2 * st + c * ct
        F0, F1, F2, F3 = sr * a0, sr * a1, sr * a2, sr * a3
        # dF[d, f] = isr grad_r[d] ang[f] + sr grad_theta[d] dang[f]
        fx0 = isr * gr0 * a0 + sr * gt0 * b0
        fx1 = isr * gr0 * a1 + sr * gt0 * b1
        fx2 = isr * gr0 * a2 + sr * gt0 * b2
        fx3 = isr * gr0 * a3 + sr * gt0 * b3
        fy0 = isr * gr1 * a0 + sr * gt1 * b0
        fy1 = isr * gr1 * a1 + sr * gt1 * b1
        fy2 = isr * gr1 * a2 + sr * gt1 * b2
        fy3 = isr * gr1 * a3 + sr * gt1 * b3
        R = 1.0
        dR0 = 0.0
        dR1 = 0.0
        if ramped:
            xi = min(max((r - r1) / (r2 - r1), 0.0), 1.0)
            if ramp_id == 0:
                R, dRdxi = 1.0 - xi, -1.0
            else:
                R = 1.0 - xi**3 * (10.0 - 15.0 * xi + 6.0 * xi**2)
                dRdxi = -30.0 * xi**2 * (1.0 - xi) ** 2
            if r1 < r < r2:
                dR0 = dRdxi / (r2 - r1) * gr0
                dR1 = dRdxi / (r2 - r1) * gr1
        # the MLS interpolant of the nodal Q (Eq. 44b), its four columns in one pass
        v0 = v1 = v2 = v3 = 0.0
        x0 = x1 = x2 = x3 = 0.0
        y0 = y1 = y2 = y3 = 0.0
        for a in range(k):
            if not mask[q, a]:
                continue
            I = idx[q, a]
            p = values[q, a]
            v0 += p * qn[I, 0]
            v1 += p * qn[I, 1]
            v2 += p * qn[I, 2]
            v3 += p * qn[I, 3]
            if derivatives:
                px = ddx[q, a]
                py = ddy[q, a]
                x0 += px * qn[I, 0]
                x1 += px * qn[I, 1]
                x2 += px * qn[I, 2]
                x3 += px * qn[I, 3]
                y0 += py * qn[I, 0]
                y1 += py * qn[I, 1]
                y2 += py * qn[I, 2]
                y3 += py * qn[I, 3]
        for mode in range(2):
            for comp in range(2):
                g = Mg[mode, comp]
                Q = g[0] * F0 + g[1] * F1 + g[2] * F2 + g[3] * F3
                Qx = g[0] * fx0 + g[1] * fx1 + g[2] * fx2 + g[3] * fx3
                Qy = g[0] * fy0 + g[1] * fy1 + g[2] * fy2 + g[3] * fy3
                if ramped:
                    Qx = R * Qx + Q * dR0
                    Qy = R * Qy + Q * dR1
                    Q = R * Q
                col = 2 * mode + comp
                if col == 0:
                    v, vx, vy = v0, x0, y0
                elif col == 1:
                    v, vx, vy = v1, x1, y1
                elif col == 2:
                    v, vx, vy = v2, x2, y2
                else:
                    v, vx, vy = v3, x3, y3
                if comp == 0:
                    ux[j, mode] = Q - v
                    if derivatives:
                        gxx[j, mode] = Qx - vx
                        gxy[j, mode] = Qy - vy
                else:
                    uy[j, mode] = Q - v
                    if derivatives:
                        gyx[j, mode] = Qx - vx
                        gyy[j, mode] = Qy - vy
    return (ux, uy, gxx, gxy, gyx, gyy), rr
