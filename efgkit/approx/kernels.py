"""Compiled (numba) kernels for the hot loops: the MLS shape functions per point.

Each kernel computes exactly what its plain-numpy reference in
:mod:`efgkit.approx.mls` computes (the tests compare them to 1e-12); it exists
only because a per-point loop over tiny m x m systems is where numpy spends
its time on temporaries. Pass ``backend="numpy"`` to :func:`mls_shape` to use
the reference.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..timing import watch_compiles

__all__ = ["mls_padded", "mls_linear", "WEIGHT_IDS", "BASIS_IDS", "weight_id"]

watch_compiles()  # before anything here compiles

WEIGHT_IDS = {"quartic": 0, "cubic": 1, "gaussian": 2}
BASIS_IDS = {"linear": 0, "quadratic": 1}


@njit(cache=True, inline="always")
def _weight(wid, s, beta):
    """(w, w'/s) of seed 003 Eq. (1a-b), the cubic spline and the Gaussian of exponent k
    (id 10 + k, seed 002 Eq. 7); 0 outside s < 1."""
    if s >= 1.0:
        return 0.0, 0.0
    if wid == 0:
        return 1.0 + s * s * (-6.0 + s * (8.0 - 3.0 * s)), -12.0 + s * (24.0 - 12.0 * s)
    if wid == 1:
        if s <= 0.5:
            return 2.0 / 3.0 - 4.0 * s * s + 4.0 * s**3, -8.0 + 12.0 * s
        return 4.0 / 3.0 * (1.0 - s) ** 3, -4.0 * (1.0 - s) ** 2 / s
    if wid >= 10:  # Gaussian of exponent k = wid - 10 (seed 002 Eq. 7)
        k = wid - 10
        b2k = beta ** (2 * k)
        e = np.exp(-b2k * s ** (2 * k))
        eb = np.exp(-b2k)
        return (e - eb) / (1.0 - eb), -2.0 * k * b2k * s ** (2 * k - 2) * e / (1.0 - eb)
    e = np.exp(-((beta * s) ** 2))
    eb = np.exp(-(beta**2))
    return (e - eb) / (1.0 - eb), -2.0 * beta**2 * e / (1.0 - eb)


def weight_id(name: str, k: int = 1) -> int:
    """The kernels' id of weight ``name`` (the Gaussian of exponent k > 1: 10 + k)."""
    return 10 + k if name == "gaussian" and k != 1 else WEIGHT_IDS[name]


@njit(cache=True, inline="always")
def _basis(bid, xi, eta, p):
    p[0] = 1.0
    p[1] = xi
    p[2] = eta
    if bid == 1:
        p[3] = xi * xi
        p[4] = xi * eta
        p[5] = eta * eta


@njit(cache=True)
def _invert(A, inv, m):
    """Gauss-Jordan inverse with partial pivoting; returns rcond (1-norm), 0 if singular.

    For m > 3 the rcond is that of the Jacobi-scaled ``S A S``, ``S = diag(A)^-1/2``, as
    :func:`efgkit.approx.mls._inv_rcond` computes it (0 if a diagonal entry is not positive).
    """
    work = A.copy()
    for i in range(m):
        for j in range(m):
            inv[i, j] = 1.0 if i == j else 0.0
    for c in range(m):
        piv = c
        for r in range(c + 1, m):
            if abs(work[r, c]) > abs(work[piv, c]):
                piv = r
        if work[piv, c] == 0.0:
            return 0.0
        if piv != c:
            for j in range(m):
                work[c, j], work[piv, j] = work[piv, j], work[c, j]
                inv[c, j], inv[piv, j] = inv[piv, j], inv[c, j]
        d = 1.0 / work[c, c]
        for j in range(m):
            work[c, j] *= d
            inv[c, j] *= d
        for r in range(m):
            if r != c:
                f = work[r, c]
                if f != 0.0:
                    for j in range(m):
                        work[r, j] -= f * work[c, j]
                        inv[r, j] -= f * inv[c, j]
    scale = np.ones(m)
    if m > 3:
        for i in range(m):
            if not A[i, i] > 0.0:
                return 0.0
            scale[i] = 1.0 / np.sqrt(A[i, i])
    na = 0.0
    ni = 0.0
    for j in range(m):
        sa = 0.0
        si = 0.0
        for i in range(m):
            sa += abs(A[i, j]) * scale[i] * scale[j]
            si += abs(inv[i, j]) / (scale[i] * scale[j])
        na = max(na, sa)
        ni = max(ni, si)
    return 1.0 / (na * ni)


@njit(cache=True, inline="always")
def _pair_weight(q, a, dx, dy, r, wid, beta, wg, wgx, wgy):
    """(w, dw/dx, dw/dy) of pair (q, a): computed from the distance, or given (crack rules)."""
    if wg.shape[0] > 0:
        return wg[q, a], wgx[q, a], wgy[q, a]
    wa, ga = _weight(wid, np.sqrt(dx * dx + dy * dy) / r, beta)
    f = -ga / (r * r)
    return wa, f * dx, f * dy


@njit(cache=True, parallel=True)
def mls_padded(x, nx, radius, idx, mask, wid, beta, bid, derivatives, wg, wgx, wgy):
    """MLS on padded neighbour arrays (see :func:`efgkit.approx.mls.mls_shape`).

    Parameters
    ----------
    x : (n, 2) points; nx : (n_nodes, 2) nodes; radius : (n_nodes,)
    idx, mask : (n, k) padded neighbours
    wid, bid : weight and basis ids; beta : Gaussian d_max / alpha
    derivatives : bool
    wg, wgx, wgy : (n, k) given weights and derivatives (crack rules), or (0, 0) arrays

    Returns
    -------
    phi, dphidx, dphidy : (n, k); rcond : (n,)
    """
    n, k = idx.shape
    m = 3 if bid == 0 else 6
    phi = np.zeros((n, k))
    gx = np.zeros((n, k))
    gy = np.zeros((n, k))
    rcond = np.zeros(n)
    for q in prange(n):
        P = np.empty((k, m))
        w = np.zeros(k)
        dwx = np.zeros(k)
        dwy = np.zeros(k)
        A = np.zeros((m, m))
        Ax = np.zeros((m, m))
        Ay = np.zeros((m, m))
        inv = np.empty((m, m))
        scale = 0.0
        for a in range(k):
            if mask[q, a]:
                scale = max(scale, radius[idx[q, a]])
        for a in range(k):
            if not mask[q, a]:
                for i in range(m):
                    P[a, i] = 0.0
                continue
            I = idx[q, a]
            X = nx[I, 0] - x[q, 0]
            Y = nx[I, 1] - x[q, 1]
            w[a], dwx[a], dwy[a] = _pair_weight(q, a, X, Y, radius[I], wid, beta, wg, wgx, wgy)
            wa = w[a]
            _basis(bid, X / scale, Y / scale, P[a])
            for i in range(m):
                for j in range(m):
                    pp = P[a, i] * P[a, j]
                    A[i, j] += wa * pp
                    Ax[i, j] += dwx[a] * pp
                    Ay[i, j] += dwy[a] * pp
        rc = _invert(A, inv, m)
        rcond[q] = rc
        if rc == 0.0:
            continue
        gam = np.empty(m)
        for i in range(m):
            gam[i] = inv[i, 0]
        gamx = np.zeros(m)
        gamy = np.zeros(m)
        if derivatives:
            rx = np.zeros(m)
            ry = np.zeros(m)
            rx[1] = 1.0 / scale
            ry[2] = 1.0 / scale
            for i in range(m):
                for j in range(m):
                    rx[i] -= Ax[i, j] * gam[j]
                    ry[i] -= Ay[i, j] * gam[j]
            for i in range(m):
                for j in range(m):
                    gamx[i] += inv[i, j] * rx[j]
                    gamy[i] += inv[i, j] * ry[j]
        for a in range(k):
            if not mask[q, a]:
                continue
            pg = 0.0
            pgx = 0.0
            pgy = 0.0
            for i in range(m):
                pg += P[a, i] * gam[i]
                pgx += P[a, i] * gamx[i]
                pgy += P[a, i] * gamy[i]
            phi[q, a] = w[a] * pg
            if derivatives:
                gx[q, a] = dwx[a] * pg + w[a] * pgx
                gy[q, a] = dwy[a] * pg + w[a] * pgy
    return phi, gx, gy, rcond


@njit(cache=True, parallel=True)
def mls_linear(x, nx, radius, idx, mask, wid, beta, derivatives, wg, wgx, wgy):
    """:func:`mls_padded` for the linear basis, written out for speed.

    The moment matrices are symmetric 3 x 3, so only their six distinct sums
    are accumulated (for A, A_,x and A_,y), they are inverted by the adjugate,
    and the pair weights of the first pass are kept in the output arrays until the
    output pass overwrites them (no allocation per point, no second weight evaluation), and
    the support scale is found in the moment pass (the sums are scaled after it): together
    15-30 % less time than two weight evaluations and a scale pass (2.4e5 points of the
    cracked plate, 2 and 1 threads on a shared machine, docs/performance.md).
    """
    n, k = idx.shape
    phi = np.zeros((n, k))
    gx = np.zeros((n, k))
    gy = np.zeros((n, k))
    rcond = np.zeros(n)
    for q in prange(n):
        xq = x[q, 0]
        yq = x[q, 1]
        scale = 0.0  # the largest support radius of the neighbours, found in the same pass
        # Sums of w p p^T with p = (1, X, Y), X = dx / scale: s0, sx, sy, sxx, sxy, syy (and for
        # dw/dx, dw/dy), accumulated in dx, dy and scaled once the pass has found the scale.
        a0 = a1 = a2 = a11 = a12 = a22 = 0.0
        b0 = b1 = b2 = b11 = b12 = b22 = 0.0
        c0 = c1 = c2 = c11 = c12 = c22 = 0.0
        for a in range(k):
            if not mask[q, a]:
                continue
            I = idx[q, a]
            dx = nx[I, 0] - xq
            dy = nx[I, 1] - yq
            wa, wx, wy = _pair_weight(q, a, dx, dy, radius[I], wid, beta, wg, wgx, wgy)
            phi[q, a] = wa  # the outputs hold the weights until the output pass
            gx[q, a] = wx
            gy[q, a] = wy
            scale = max(scale, radius[I])
            X = dx  # unscaled here
            Y = dy
            a0 += wa
            a1 += wa * X
            a2 += wa * Y
            a11 += wa * X * X
            a12 += wa * X * Y
            a22 += wa * Y * Y
            if derivatives:
                b0 += wx
                b1 += wx * X
                b2 += wx * Y
                b11 += wx * X * X
                b12 += wx * X * Y
                b22 += wx * Y * Y
                c0 += wy
                c1 += wy * X
                c2 += wy * Y
                c11 += wy * X * X
                c12 += wy * X * Y
                c22 += wy * Y * Y
        inv_s = 1.0 / scale
        s2 = inv_s * inv_s
        a1 *= inv_s
        a2 *= inv_s
        a11 *= s2
        a12 *= s2
        a22 *= s2
        b1 *= inv_s
        b2 *= inv_s
        b11 *= s2
        b12 *= s2
        b22 *= s2
        c1 *= inv_s
        c2 *= inv_s
        c11 *= s2
        c12 *= s2
        c22 *= s2
        # Adjugate of the symmetric A = [[a0, a1, a2], [a1, a11, a12], [a2, a12, a22]].
        i00 = a11 * a22 - a12 * a12
        i01 = a2 * a12 - a1 * a22
        i02 = a1 * a12 - a2 * a11
        i11 = a0 * a22 - a2 * a2
        i12 = a1 * a2 - a0 * a12
        i22 = a0 * a11 - a1 * a1
        det = a0 * i00 + a1 * i01 + a2 * i02
        if det == 0.0 or not np.isfinite(det):
            for a in range(k):  # singular (rcond 0): zeros, not the weights
                phi[q, a] = 0.0
                gx[q, a] = 0.0
                gy[q, a] = 0.0
            continue
        d = 1.0 / det
        i00 *= d
        i01 *= d
        i02 *= d
        i11 *= d
        i12 *= d
        i22 *= d
        na = max(abs(a0) + abs(a1) + abs(a2), abs(a1) + abs(a11) + abs(a12),
                 abs(a2) + abs(a12) + abs(a22))
        ni = max(abs(i00) + abs(i01) + abs(i02), abs(i01) + abs(i11) + abs(i12),
                 abs(i02) + abs(i12) + abs(i22))
        rcond[q] = 1.0 / (na * ni)
        g0 = i00  # gamma = A^-1 e_1
        g1 = i01
        g2 = i02
        hx0 = hx1 = hx2 = hy0 = hy1 = hy2 = 0.0
        if derivatives:
            # gamma_,x = A^-1 (p_,x - A_,x gamma), p_,x = (0, 1/s, 0); likewise y.
            rx0 = -(b0 * g0 + b1 * g1 + b2 * g2)
            rx1 = inv_s - (b1 * g0 + b11 * g1 + b12 * g2)
            rx2 = -(b2 * g0 + b12 * g1 + b22 * g2)
            ry0 = -(c0 * g0 + c1 * g1 + c2 * g2)
            ry1 = -(c1 * g0 + c11 * g1 + c12 * g2)
            ry2 = inv_s - (c2 * g0 + c12 * g1 + c22 * g2)
            hx0 = i00 * rx0 + i01 * rx1 + i02 * rx2
            hx1 = i01 * rx0 + i11 * rx1 + i12 * rx2
            hx2 = i02 * rx0 + i12 * rx1 + i22 * rx2
            hy0 = i00 * ry0 + i01 * ry1 + i02 * ry2
            hy1 = i01 * ry0 + i11 * ry1 + i12 * ry2
            hy2 = i02 * ry0 + i12 * ry1 + i22 * ry2
        for a in range(k):
            if not mask[q, a]:
                continue
            I = idx[q, a]
            dx = nx[I, 0] - xq
            dy = nx[I, 1] - yq
            wa = phi[q, a]  # the weights of the first pass
            wx = gx[q, a]
            wy = gy[q, a]
            X = dx * inv_s
            Y = dy * inv_s
            pg = g0 + g1 * X + g2 * Y
            phi[q, a] = wa * pg
            if derivatives:
                gx[q, a] = wx * pg + wa * (hx0 + hx1 * X + hx2 * Y)
                gy[q, a] = wy * pg + wa * (hy0 + hy1 * X + hy2 * Y)
    return phi, gx, gy, rcond
