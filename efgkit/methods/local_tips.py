"""Finer disc rules for the MLPG1 sub-domains next to a crack tip (issue 14).

With a crack-tip enrichment the trial functions carry the near-tip field, whose
derivatives grow like r^(-1/2) at the tip (r the distance to the tip). The disc rule of
:func:`~efgkit.quadrature.discs.disc_points` is centred on the node, not on the tip: on a
disc that holds the tip, or passes close to it, the integrand eps(v_I)^T D eps(u^h) of the
row of seed 002 Eq. (23) is singular or nearly so, and 5 x 8 Gauss points (16 per angular
piece) integrate it with an error that does not fall with h. These rows are the local
equilibrium of the tip region; their error acts as a spurious force there. Measured on
``gallery.shear_edge_crack()`` (d_max 3, diffraction, extrinsic MLS; statics: every
horizontal cut carries 7 / 0): the cut y = 4 below the crack carried 6.80, 7.83, 7.55, 7.42,
7.81, 6.86 at h = 0.5, 0.45, 0.4, 0.35, 0.3, 0.25 (0.63 vertical at h = 0.35), erratic
also under a finer rule on every disc (h = 0.35: 7.11 / 0.05 with 10 x 16 / 32, 6.92 / 2.44
with 16 x 32 / 64); with ``tip_radial`` x ``tip_angular`` = 20 x 64 on the discs near the
tip only, 7.08, 7.11, 7.05, 7.14, 7.22, 7.05 (docs/theory.md, MLPG1, "Statics of the
shear edge crack").

A disc is *near* a tip when its centre lies within r_sI + c_I of it (c_I = r_sI /
test_radius, the node's spacing measure): it holds the tip or passes within one spacing of
it. Its points are replaced by those of the same rule (sectors, angular pieces between the
kinks of r_max(theta)) with ``tip_radial`` Gauss points in r, ``tip_angular`` per angular
piece (and on full discs).
"""

from __future__ import annotations

import numpy as np

from ..quadrature.discs import disc_points
from ..quadrature.rules import Points

__all__ = ["near_tip_discs", "refine_tip_discs", "tip_disc_rule"]


def tip_disc_rule(points: Points, scene, method, x: np.ndarray, r_s: np.ndarray,
                  segments: np.ndarray, theta_a: np.ndarray, span: np.ndarray) -> Points:
    """The disc ``points`` of an MLPG discretisation (``method``, ``scene``) with the discs near
    its crack tips refined (:func:`refine_tip_discs`, ``method.tip_radial`` x
    ``method.tip_angular``) when an enrichment makes the integrands singular there; unchanged
    without tips or without enrichment (the plain trial functions are not singular)."""
    if method.enrichment == "none" or not scene.tips:
        return points
    return refine_tip_discs(points, x, r_s, r_s / method.test_radius, segments, theta_a, span,
                            np.array([t.x for t in scene.tips]), method.quadrature,
                            method.tip_radial, method.tip_angular)


def near_tip_discs(x: np.ndarray, r_s: np.ndarray, c: np.ndarray, tips: np.ndarray) -> np.ndarray:
    """Indices of the discs (centres ``x (n, 2)``, radii ``r_s (n,)``, spacings ``c (n,)``)
    whose centre lies within r_s + c of one of the ``tips (t, 2)``.

    Examples
    --------
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]])
    >>> near_tip_discs(x, np.full(3, 0.6), np.full(3, 0.7), np.array([[1.2, 0.0]])).tolist()
    [0, 1]
    """
    tips = np.asarray(tips, float).reshape(-1, 2)
    if len(tips) == 0:
        return np.zeros(0, np.int64)
    d = np.hypot(*(x[:, None, :] - tips[None]).transpose(2, 0, 1)).min(axis=1)  # (n,), few tips
    return np.flatnonzero(d < r_s + c)


def refine_tip_discs(points: Points, x: np.ndarray, r_s: np.ndarray, c: np.ndarray,
                     segments: np.ndarray, theta_a: np.ndarray, span: np.ndarray,
                     tips: np.ndarray, rule: str, radial: int, angular: int) -> Points:
    """``points`` of :func:`~efgkit.quadrature.discs.disc_points` with the discs near the
    ``tips (t, 2)`` (:func:`near_tip_discs`) integrated by ``radial`` x ``angular`` points
    (``angular`` per angular piece of a cut disc) instead; other discs unchanged. Points
    stay sorted by owner.

    Examples
    --------
    >>> x, r = np.array([[0.0, 0.0], [3.0, 0.0]]), np.ones(2)
    >>> seg = np.zeros((0, 2, 2))
    >>> th, sp = np.zeros(2), np.full(2, 2 * np.pi)
    >>> base = disc_points(x, r, seg, th, sp, "gauss", 5, 8)
    >>> fine = refine_tip_discs(base, x, r, r, seg, th, sp, np.array([[0.5, 0.0]]), "gauss", 10, 32)
    >>> np.bincount(fine.owner).tolist(), round(float(fine.w[fine.owner == 0].sum() - np.pi), 12)
    ([320, 40], 0.0)
    """
    near = near_tip_discs(x, r_s, c, tips)
    if len(near) == 0:
        return points
    fine = disc_points(x[near], r_s[near], segments, theta_a[near], span[near], rule, radial,
                       angular, piece_angular=angular)
    keep = ~np.isin(points.owner, near)
    owner = np.concatenate([points.owner[keep], near[fine.owner]])
    order = np.argsort(owner, kind="stable")
    return Points(np.concatenate([points.x[keep], fine.x])[order],
                  np.concatenate([points.w[keep], fine.w])[order], owner[order])
