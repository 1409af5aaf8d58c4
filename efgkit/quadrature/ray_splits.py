"""MLPG disc rules split where the rays of a disc cross the shadow rays of a crack tip.

Under the visibility rule the trial function of every node I whose support holds a tip
jumps across the shadow ray from the tip in the direction e_I = (tip - x_I) / |tip - x_I|,
up to where that ray leaves the node's support, at length r_I - |tip - x_I| (seed 001
Sect. 4.1; EFG splits its tip cells there, :mod:`efgkit.quadrature.tip_cells`). A disc
rule centred on its node (:func:`~efgkit.quadrature.discs.disc_points`) meets these jumps
at arbitrary radii on its rays, and its error does not fall as the rule is refined (the
plain SENT's J moved by ~1 % from one disc rule to the next; docs/theory.md, MLPG1).

Here every ray theta of the disc of x_J is split at its crossings with the shadow rays,

    x_J + rho (cos theta, sin theta) = x_tip + s e_I,   0 < rho < r_max(theta),
    0 <= s <= r_I - |x_tip - x_I|,

and each radial piece gets its own Gauss rule (Gauss-Jacobi with weight rho on the first
piece [0, rho_1], Gauss-Legendre times rho on the others), so that along every ray the
integrand is smooth on each piece. The angular rule is that of the unsplit disc: as a
function of theta the ray integrals are smooth except where a ray passes through the tip
(an angular break of every disc cut by the crack) or an end of a shadow ray. A ray that
crosses no shadow ray gets exactly the points of the unsplit rule; splitting a radial
interval keeps the rule exact for polynomials (the patch tests).
"""

from __future__ import annotations

import numpy as np
from scipy.special import roots_jacobi

from .discs import disc_rays, polar_points, sorted_points
from .rules import Points, check_count, gauss_legendre

__all__ = ["circle_crossings", "ray_crossings", "split_disc_points"]


def ray_crossings(x: np.ndarray, theta: np.ndarray, r_max: np.ndarray, origins: np.ndarray,
                  directions: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Radii where the rays ``theta (m, a)`` from ``x (m, 2)`` cross the segments
    ``origins + s directions``, 0 <= s <= ``lengths`` (``(k, 2)``, unit ``directions``,
    ``(k,)``), sorted along the last axis; ``r_max (m, a)`` where a ray crosses fewer.
    Shape (m, a, k).

    Examples
    --------
    >>> c = ray_crossings(np.zeros((1, 2)), np.array([[0.0, np.pi / 2]]), np.ones((1, 2)),
    ...                   np.array([[0.5, -1.0]]), np.array([[0.0, 1.0]]), np.array([2.0]))
    >>> c.ravel().tolist()   # the ray along x meets the line x = 0.5 at 0.5; the other never
    [0.5, 1.0]
    """
    u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)[:, :, None, :]  # (m, a, 1, 2)
    e = directions[None, None]  # (1, 1, k, 2)
    p = (origins[None] - x[:, None])[:, None]  # (m, 1, k, 2): x_tip - x_J
    den = u[..., 0] * e[..., 1] - u[..., 1] * e[..., 0]  # u x e
    ok = np.abs(den) > 1e-12
    safe = np.where(ok, den, 1.0)
    rho = (p[..., 0] * e[..., 1] - p[..., 1] * e[..., 0]) / safe
    s = (p[..., 0] * u[..., 1] - p[..., 1] * u[..., 0]) / safe
    rm = r_max[:, :, None]
    hit = ok & (rho > 0) & (rho < rm) & (s >= 0) & (s <= lengths[None, None])
    return np.sort(np.where(hit, rho, rm), axis=-1)


def circle_crossings(x: np.ndarray, theta: np.ndarray, r_max: np.ndarray, centres: np.ndarray,
                     radii: np.ndarray) -> np.ndarray:
    """Radii where the rays ``theta (m, a)`` from ``x (m, 2)`` cross the circles
    ``centres (c, 2)``, ``radii (c,)``; ``r_max (m, a)`` for crossings beyond it or none.
    Shape (m, a, 2 c), unsorted.

    Examples
    --------
    >>> circle_crossings(np.zeros((1, 2)), np.zeros((1, 1)), np.full((1, 1), 5.0),
    ...                  np.array([[2.0, 0.0]]), np.ones(1)).ravel().tolist()
    [1.0, 3.0]
    """
    u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)[:, :, None, :]  # (m, a, 1, 2)
    p = (x[:, None] - centres[None])[:, None]  # (m, 1, c, 2)
    b = (u * p).sum(axis=-1)  # (m, a, c)
    q = (p * p).sum(axis=-1) - radii ** 2
    disc = b * b - q
    root = np.sqrt(np.maximum(disc, 0.0))
    rho = np.concatenate([-b - root, -b + root], axis=-1)
    rm = r_max[:, :, None]
    hit = (np.concatenate([disc, disc], axis=-1) > 0) & (rho > 0) & (rho < rm)
    return np.where(hit, rho, rm)


def split_disc_points(x: np.ndarray, r: np.ndarray, segments: np.ndarray, theta_a: np.ndarray,
                      span: np.ndarray, radial: int, angular: int, origins: np.ndarray,
                      directions: np.ndarray, lengths: np.ndarray, tol: float = 1e-6,
                      piece_angular: int | None = None, circles=None) -> Points:
    """The Gauss disc rule of :func:`~efgkit.quadrature.discs.disc_points` (``rule="gauss"``)
    with every ray split at its crossings (:func:`ray_crossings`) with the segments
    ``origins (k, 2) + s directions (k, 2)``, 0 <= s <= ``lengths (k,)``; ``radial``
    points per piece. Returns Points sorted by owner (the disc's index).

    Examples
    --------
    >>> x, r, seg = np.zeros((1, 2)), np.ones(1), np.zeros((0, 2, 2))
    >>> full = (np.zeros(1), np.full(1, 2 * np.pi))
    >>> p = split_disc_points(x, r, seg, *full, 5, 8, np.array([[0.5, -1.0]]),
    ...                       np.array([[0.0, 1.0]]), np.array([2.0]))
    >>> round(float(p.w.sum() / np.pi), 13), round(float(p.w @ p.x[:, 0] ** 2 / (np.pi / 4)), 13)
    (1.0, 1.0)
    """
    check_count("radial", radial)
    a, gj = roots_jacobi(radial, 0.0, 1.0)  # weight (1 + a) on [-1, 1]
    fr_j, wr_j = (a + 1) / 2, gj / 4
    g, gw = gauss_legendre(radial)
    fr_l, wr_l = (g + 1) / 2, gw / 2
    out = []
    for k, theta, dth, rm in disc_rays(x, r, segments, theta_a, span, "gauss", angular, tol,
                                       piece_angular):
        c = ray_crossings(x[k], theta, rm, origins, directions, lengths)  # (m, a, n_c)
        if circles is not None:
            c = np.sort(np.concatenate([c, circle_crossings(x[k], theta, rm, *circles)], axis=-1),
                        axis=-1)
        lo = np.concatenate([np.zeros(rm.shape + (1,)), c], axis=-1)  # piece starts
        hi = np.concatenate([c, rm[..., None]], axis=-1)
        first = np.zeros(lo.shape, bool)
        first[..., 0] = True
        span_r = np.maximum(hi - lo, 0.0)[..., None]  # (m, a, P, 1)
        rad = np.where(first[..., None], hi[..., None] * fr_j, lo[..., None] + span_r * fr_l)
        w = np.where(first[..., None], hi[..., None] ** 2 * wr_j, span_r * wr_l * rad)
        w = w * dth[:, :, None, None]
        m, na = theta.shape
        out.append(polar_points(x[k], k, theta, rad.reshape(m, na, -1), w.reshape(m, na, -1)))
    return sorted_points(out)
