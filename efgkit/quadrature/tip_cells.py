"""Quadrature of the background cells that hold a crack tip.

Near a tip the integrands are singular (enriched strains ~ r^-1/2, their
products ~ 1/r) and the crack rules put kinks on rays through the tip (the
shadow lines of the nodes whose supports hold it). A cell holding a tip is
therefore integrated as a fan of triangles with the tip as common apex, split
at the crack leaving the cell and at the shadow rays, and each triangle gets a
Gauss rule collapsed at the tip (Duffy):

    x(u, v) = x_tip + u (a - x_tip) + u v (b - a),   dA = 2 |T| u du dv,

so the factor u cancels a 1/r singularity and the integrand is smooth in
(u, v) on every fan triangle. The tip may lie inside the cell, on an edge or
at a corner (zero-area fan triangles are dropped); moving it slightly moves
the rule continuously.
"""

from __future__ import annotations

import numpy as np

from .rules import gauss_legendre

__all__ = ["collapsed_rule", "tip_cell_rule", "tip_cells"]


def collapsed_rule(apex: np.ndarray, a: np.ndarray, b: np.ndarray, order: int):
    """Gauss rule on triangles (apex, a, b), collapsed at the apex.

    Parameters
    ----------
    apex, a, b : ndarray (t, 2)
    order : int
        Gauss-Legendre points in u (from the apex) and in v (along a -> b).

    Returns
    -------
    x : ndarray (t * order^2, 2); w : ndarray (t * order^2,)

    Examples
    --------
    >>> x, w = collapsed_rule(np.zeros((1, 2)), np.array([[1.0, 0.0]]), np.array([[0.0, 1.0]]), 8)
    >>> round(float(w.sum()), 14), round(float(w @ (1 / np.hypot(*x.T))), 6)  # sqrt(2) asinh(1)
    (0.5, 1.24645)
    """
    g, gw = gauss_legendre(order)
    g, gw = (g + 1) / 2, gw / 2
    u, v = np.meshgrid(g, g, indexing="ij")
    wu = np.outer(gw, gw) * u
    u, v, wu = u.ravel(), v.ravel(), wu.ravel()
    e_a, e_ab = a - apex, b - a
    area2 = np.abs(e_a[:, 0] * e_ab[:, 1] - e_a[:, 1] * e_ab[:, 0])  # 2 |T|
    x = apex[:, None, :] + u[None, :, None] * (e_a[:, None, :] + v[None, :, None] * e_ab[:, None, :])
    return x.reshape(-1, 2), (area2[:, None] * wu[None, :]).ravel()


def _perimeter_param(p: np.ndarray, corner: np.ndarray, size: float) -> np.ndarray:
    """Counter-clockwise perimeter coordinate in [0, 4) of points on the square's boundary."""
    u = (p - corner) / size
    s = np.where(np.isclose(u[:, 1], 0.0, rtol=0.0, atol=1e-12), u[:, 0],
                 np.where(np.isclose(u[:, 0], 1.0, rtol=0.0, atol=1e-12), 1.0 + u[:, 1],
                          np.where(np.isclose(u[:, 1], 1.0, rtol=0.0, atol=1e-12), 3.0 - u[:, 0],
                                   4.0 - u[:, 1])))
    return np.mod(s, 4.0)


def _ray_exit(tip: np.ndarray, d: np.ndarray, corner: np.ndarray, size: float) -> np.ndarray:
    """Where rays from ``tip`` (inside or on the closed square) along ``d (k, 2)`` leave it."""
    lo, hi = corner, corner + size
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(d > 0, (hi - tip) / d, np.where(d < 0, (lo - tip) / d, np.inf))
    # a tip on the cell's edge (to rounding) may sit a hair outside: never step backwards
    return tip + np.maximum(np.min(t, axis=1), 0.0)[:, None] * d


def tip_cell_rule(corner: np.ndarray, size: float, tip: np.ndarray, directions: np.ndarray,
                  order: int):
    """Fan rule of one square cell holding a tip.

    Parameters
    ----------
    corner : ndarray (2,)
        Lower-left corner of the cell.
    size : float
        Its side.
    tip : ndarray (2,)
        The tip, inside the closed square.
    directions : ndarray (k, 2)
        Rays from the tip to split the fan at: the crack leaving the tip and
        the shadow rays.
    order : int
        Points per direction of each collapsed Gauss rule.

    Returns
    -------
    x : ndarray (m, 2); w : ndarray (m,)
        Weights summing to size^2.

    Examples
    --------
    >>> x, w = tip_cell_rule(np.zeros(2), 1.0, np.array([0.5, 0.5]), np.array([[-1.0, 0.0]]), 4)
    >>> round(float(w.sum()), 14), len(x) == 5 * 16
    (1.0, True)
    """
    sq = corner + size * np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    d = np.asarray(directions, dtype=float).reshape(-1, 2)
    d = d[np.hypot(*d.T) > 0]
    exits = _ray_exit(tip, d, corner, size) if len(d) else np.zeros((0, 2))
    pts = np.vstack([sq, exits])
    s = _perimeter_param(pts, corner, size)
    o = np.argsort(s, kind="stable")
    pts, s = pts[o], s[o]
    keep = np.append(np.diff(s) > 1e-12, True)
    pts = pts[keep]
    a, b = pts, np.roll(pts, -1, axis=0)
    area2 = np.abs((a[:, 0] - tip[0]) * (b[:, 1] - tip[1]) - (a[:, 1] - tip[1]) * (b[:, 0] - tip[0]))
    ok = area2 > 1e-12 * size**2
    apex = np.broadcast_to(tip, (int(ok.sum()), 2))
    return collapsed_rule(apex, a[ok], b[ok], order)


def tip_cells(sel, origin, size, tips, cracks, tip_rays, order, boundary):
    """Remove the cells of ``sel (c, 2)`` whose closed square holds a tip; return the
    remaining cells and the fan rules (x, w) of the removed ones.

    The fan covers the whole square and splits it only along the tip's own crack
    segment, so a cell that the body's ``boundary (m, 2, 2)`` or any other crack
    segment (a kink, another crack) enters is left to the clipped rule of
    the cut-cell rule of :func:`efgkit.quadrature.cells.cell_points` instead: correct area,
    without the collapsed rule at the tip.
    """
    fans, drop = [], np.zeros(len(sel), bool)
    by_name = {c.name: c for c in cracks}
    for t, tip in enumerate(tips):
        u = (tip.x - origin) / size
        hold = np.all((sel >= np.floor(u - 1e-9) - 1) & (sel <= np.floor(u + 1e-9)), axis=1)
        hold &= np.all((sel <= u + 1e-9) & (u - 1e-9 <= sel + 1), axis=1)
        crack = by_name[tip.crack]
        v = crack.vertices if tip.end == 0 else crack.vertices[::-1]
        others = [c.segments for c in cracks if c is not crack]
        others.append(np.stack([v[1:-1], v[2:]], axis=1))  # the tip's crack beyond segment 0
        blocking = np.concatenate([boundary, *others])
        rays = [v[1] - v[0]]
        if tip_rays is not None:
            rays.append(np.asarray(tip_rays[t], dtype=float).reshape(-1, 2))
        rays = np.vstack(rays)
        for i in np.flatnonzero(hold & ~drop):
            corner = origin + size * sel[i]
            if _enters_square(blocking, corner, size):
                continue
            fans.append(tip_cell_rule(corner, size, tip.x, rays, order))
            drop[i] = True
    return sel[~drop], fans


def _enters_square(seg: np.ndarray, corner: np.ndarray, size: float) -> bool:
    """Whether any segment of ``seg (m, 2, 2)`` passes through the open square
    ``corner + [0, size]^2`` (shrunk by 1e-9 size: lying along its sides does not count)."""
    lo, hi = corner + 1e-9 * size, corner + (1 - 1e-9) * size
    a, d = seg[:, 0], seg[:, 1] - seg[:, 0]
    t0, t1 = np.zeros(len(seg)), np.ones(len(seg))
    for k in range(2):  # Liang-Barsky clipping against the two slabs
        with np.errstate(divide="ignore", invalid="ignore"):
            ta, tb = (lo[k] - a[:, k]) / d[:, k], (hi[k] - a[:, k]) / d[:, k]
        flat = d[:, k] == 0
        inside = (a[:, k] > lo[k]) & (a[:, k] < hi[k])
        t0 = np.where(flat, np.where(inside, t0, np.inf), np.maximum(t0, np.minimum(ta, tb)))
        t1 = np.where(flat, t1, np.minimum(t1, np.maximum(ta, tb)))
    return bool(np.any(t0 < t1))
