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

Without enrichment (seed 002's plain variant) the trial functions are smooth functions
that jump (visibility) or kink (diffraction, transparency) across the shadow rays from
the tip, and the k = 1 Gaussian weight kinks at r_I (slope -0.149), so every shape
function derivative jumps on every support circle. Both lines cross the discs near the
tip at radii a node-centred rule does not see, and there the rows of the plain SENT moved
by ~1e-3 from one rule to the next, J by ~1 % (docs/theory.md, MLPG1, "The plain SENT
and the J domain"). The discs crossed by a shadow ray (:func:`split_tip_discs`) are
integrated with every ray split at the shadow rays and the support circles
(:mod:`efgkit.quadrature.ray_splits`), ``split_radial`` Gauss points per radial piece
and ``split_angular`` per angular piece (and on full discs).
"""

from __future__ import annotations

import numpy as np

from ..quadrature.discs import disc_points
from ..quadrature.ray_splits import split_disc_points
from ..quadrature.rules import Points

__all__ = ["near_tip_discs", "refine_tip_discs", "split_tip_discs", "tip_disc_rule"]


def tip_disc_rule(points: Points, scene, method, nodes, r_s: np.ndarray, segments: np.ndarray,
                  theta_a: np.ndarray, span: np.ndarray) -> Points:
    """The disc ``points`` of an MLPG discretisation (``method``, ``scene``, ``nodes``) with
    the discs near its crack tips integrated as their integrands need: with an enrichment
    (r^(-1/2) derivatives) by a finer rule (:func:`refine_tip_discs`, ``method.tip_radial``
    x ``method.tip_angular``); without one, under the Gauss rule, with their rays split at
    the shadow rays and support circles (:func:`split_tip_discs`, ``method.split_radial``
    x ``method.split_angular``). Unchanged without tips and for the seed's midpoint rule."""
    if not scene.tips:
        return points
    if method.enrichment != "none":
        return refine_tip_discs(points, nodes.x, r_s, r_s / method.test_radius, segments,
                                theta_a, span, np.array([t.x for t in scene.tips]),
                                method.quadrature, method.tip_radial, method.tip_angular)
    if method.quadrature != "gauss":
        return points
    return split_tip_discs(points, scene, nodes, r_s, segments, theta_a, span,
                           method.split_radial, method.split_angular)


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



def split_tip_discs(points: Points, scene, nodes, r_s: np.ndarray, segments: np.ndarray,
                    theta_a: np.ndarray, span: np.ndarray, radial: int, angular: int) -> Points:
    """``points`` with the discs that shadow rays cross integrated by
    :func:`~efgkit.quadrature.ray_splits.split_disc_points` (``radial`` points per radial
    piece, ``angular`` per angular piece and on full discs), each ray split at the shadow
    rays and at the support circles of the nodes whose supports reach the disc.

    The shadow ray of a node I whose support holds a tip starts at the tip, points along
    tip - x_I and ends where it leaves the support (length r_I - d_I, d_I = |tip - x_I|);
    a disc is crossed when its centre lies within r_sI + max(r_I - d_I) of the tip. The
    discs are split tip by tip (each with its nearest tip that crosses it; the rays of every
    tip apply), so that the support circles tested are those near one tip. Other discs are
    unchanged; points stay sorted by owner.

    Examples
    --------
    >>> from efgkit import Crack, Domain, Elastic, MLPG, Scene
    >>> from efgkit.methods.local import discretize_local
    >>> sc = Scene(Domain.rectangle(0, 0, 2, 2), Elastic(1.0, 0.3),
    ...            cracks=(Crack([[0, 1], [1, 1]], (False, True)),))
    >>> def areas(**kw):
    ...     p = discretize_local(sc, MLPG(spacing=0.25, **kw)).points
    ...     return p.n, np.bincount(p.owner, p.w)
    >>> (n, a), (n_fine, a_fine) = areas(split_angular=8), areas(split_angular=128)
    >>> n < n_fine, float(np.abs(a - a_fine).max()) < 1e-8   # the visible parts of the discs
    (True, True)
    """
    tips = np.array([t.x for t in scene.tips]).reshape(-1, 2)
    dist = np.hypot(nodes.x[:, None, 0] - tips[None, :, 0], nodes.x[:, None, 1] - tips[None, :, 1])
    holds = (dist < nodes.radius[:, None]) & (dist > 1e-9 * nodes.radius[:, None])  # (n, t)
    node, tip = np.nonzero(holds)
    if not len(node):
        return points
    length = nodes.radius[node] - dist[node, tip]
    directions = (tips[tip] - nodes.x[node]) / dist[node, tip, None]
    reach = np.zeros(len(tips))
    np.maximum.at(reach, tip, length)
    crossed = dist < r_s[:, None] + reach[None]  # (n, t)
    near = np.flatnonzero(crossed.any(axis=1))
    group = np.where(crossed, dist, np.inf)[near].argmin(axis=1)  # each disc with its nearest tip
    parts = []
    for t in np.unique(group):  # few tips; the support circles that reach the group's discs
        k = near[group == t]
        lo = (nodes.x[k] - r_s[k, None]).min(axis=0)
        hi = (nodes.x[k] + r_s[k, None]).max(axis=0)
        cand = np.flatnonzero(np.all((nodes.x + nodes.radius[:, None] > lo) &
                                     (nodes.x - nodes.radius[:, None] < hi), axis=1))
        gap = np.hypot(*(nodes.x[cand, None] - nodes.x[k][None]).transpose(2, 0, 1))
        circ = cand[(gap < nodes.radius[cand, None] + r_s[k][None]).any(axis=1)]
        pts = split_disc_points(nodes.x[k], r_s[k], segments, theta_a[k], span[k], radial, angular,
                                tips[tip], directions, length, piece_angular=angular,
                                circles=(nodes.x[circ], nodes.radius[circ]))
        parts.append(Points(pts.x, pts.w, k[pts.owner]))
    split = Points.concatenate(*parts)
    keep = ~np.isin(points.owner, near)
    owner = np.concatenate([points.owner[keep], split.owner])
    order = np.argsort(owner, kind="stable")
    return Points(np.concatenate([points.x[keep], split.x])[order],
                  np.concatenate([points.w[keep], split.w])[order], owner[order])
