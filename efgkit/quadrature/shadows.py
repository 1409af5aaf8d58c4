"""Gauss rules on the shadow rays of MLPG sub-domains that hold a crack tip.

A disc clipped to the part its node can see (:mod:`efgkit.quadrature.discs`) is bounded
behind a tip by the ray from the node through the tip: an interior line of the body on
which the local weak form needs the traction term (:mod:`efgkit.methods.local`).
"""

from __future__ import annotations

import numpy as np

from .discs import visible
from .rules import Points, gauss_legendre

__all__ = ["shadow_pieces"]


def shadow_pieces(scene, nodes, r_s: np.ndarray, cseg: np.ndarray, order: int) -> Points:
    """Gauss points (x, w, owner node, outward normal) on the shadow rays inside the discs.

    A disc that holds a crack tip is clipped to the part visible from its node, so its
    boundary holds the segment of the ray from x_I through the tip to the circle: an
    interior line of the body, on which the traction sigma(u) n is not zero. The local
    weak form (seed 002 Eq. 21, integrated by parts over the visible part) needs
    -int v_I sigma(u) n there; without it a disc next to a tip misses a term of order
    sigma h and the uniaxial patch test of a cracked plate fails (issue 14). The points
    are moved 1e-7 r_sI into the visible side (on the ray itself the visibility of x_I's
    own trial function is a ray-casting tie). A node split on a crack face looks from
    1e-6 r_sI off the crack into its face's material: its ray through the tip runs along
    the crack line and hides the far side of that line beyond the tip.
    """
    tips = np.array([t.x for t in scene.tips]).reshape(-1, 2)
    empty = Points(np.zeros((0, 2)), np.zeros(0), np.zeros(0, int), np.zeros((0, 2)))
    if not len(tips) or not len(cseg):
        return empty
    d = np.hypot(nodes.x[:, None, 0] - tips[None, :, 0], nodes.x[:, None, 1] - tips[None, :, 1])
    node, tip = np.nonzero((d < r_s[:, None]) & (d > 1e-9 * r_s[:, None]))
    if not len(node):
        return empty
    e = (tips[tip] - nodes.x[node]) / d[node, tip][:, None]
    perp = np.column_stack([-e[:, 1], e[:, 0]])
    length = r_s[node] - d[node, tip]
    probe = tips[tip] + 0.5 * length[:, None] * e
    eps = 1e-3 * r_s[node][:, None]
    origin = _face_origins(nodes, cseg, 1e-6 * r_s)[node]
    vis = np.column_stack([visible(origin, probe + s * eps * perp, cseg, 1e-9) for s in (1.0, -1.0)])
    one = vis[:, 0] != vis[:, 1]  # exactly one side hidden: the ray bounds the visible part
    hidden = np.where(vis[:, 0], -1.0, 1.0)[:, None] * perp  # outward normal of Omega_s
    g, gw = gauss_legendre(order)
    t = 0.5 * (g + 1.0)
    k = np.repeat(np.flatnonzero(one), order)
    tt = np.tile(t, one.sum())
    x = (tips[tip[k]] + (tt * length[k])[:, None] * e[k] - 1e-7 * r_s[node[k]][:, None] * hidden[k])
    w = np.tile(0.5 * gw, one.sum()) * length[k]
    inside = np.asarray(scene.domain.contains(x), bool)
    return Points(x[inside], w[inside], node[k][inside], hidden[k][inside])


def _face_origins(nodes, cseg: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """Node positions (n, 2), those split on a crack moved ``offset (n,)`` into their face."""
    x = nodes.x.copy()
    if nodes.face is None or not np.any(nodes.face):
        return x
    k = np.flatnonzero(nodes.face != 0)
    e = cseg[nodes.face_segment[k], 1] - cseg[nodes.face_segment[k], 0]
    left = np.column_stack([-e[:, 1], e[:, 0]]) / np.hypot(*e.T)[:, None]
    x[k] += (offset[k] * nodes.face[k])[:, None] * left
    return x
