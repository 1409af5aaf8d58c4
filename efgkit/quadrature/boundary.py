"""Gauss rules on boundary lines: tractions, essential-BC terms and multiplier knots.

Edges are integrated piecewise on equal-parameter segments of about the nodal
spacing (arcs on the exact circle), and split at crack mouths, where the trial
functions jump (seed 003 Sect. 2.2: the faces carry separate nodes).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..problem.geometry import Domain
from .rules import Points, check_count, check_length, gauss_legendre

__all__ = ["boundary_points", "edge_rule"]


def break_parameters(edge, breaks: np.ndarray | None) -> np.ndarray:
    """Edge parameters (0 < s < 1) of the points ``breaks (b, 2)`` that lie on ``edge``
    (within 1e-9 of its length): crack mouths, where pieces and multiplier knots split."""
    if breaks is None or len(breaks) == 0:
        return np.zeros(0)
    b = np.asarray(breaks, dtype=float).reshape(-1, 2)
    s = edge.parameter(b)
    on_edge = np.hypot(*(edge.at(s)[0] - b).T) <= 1e-9 * max(edge.length, 1e-300)
    return s[on_edge & (s > 1e-9) & (s < 1 - 1e-9)]


def merge_knots(knots: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The increasing knots ``0 .. 1`` with the parameters ``s`` added (closer than 1e-9 merged)."""
    if len(s) == 0:
        return knots
    knots = np.unique(np.concatenate([knots, s]))
    knots = knots[np.append(True, np.diff(knots) > 1e-9)]
    knots[-1] = 1.0
    return knots


def edge_rule(edge, n_segments, order: int, breaks: np.ndarray | None = None):
    """Gauss rule on ``n_segments`` equal-parameter pieces of ``edge`` (or on the pieces
    between the parameters ``n_segments``, an increasing array from 0 to 1), further
    split at the points of ``breaks (b, 2)`` that lie on the edge (crack mouths).

    Returns x (m, 2), w (m,), outward normal (m, 2) and the edge parameter
    s (m,) in [0, 1] of each point.

    Examples
    --------
    >>> from efgkit.problem.geometry import Domain
    >>> e = Domain.rectangle(0, 0, 1, 1).edges("left")[0]
    >>> x, w, n, s = edge_rule(e, 2, 2, breaks=np.array([[0.0, 0.3]]))
    >>> round(float(w.sum()), 14), len(x)   # 3 pieces: cut at y = 0.3 (the left edge runs down)
    (1.0, 6)
    """
    knots = (np.linspace(0.0, 1.0, n_segments + 1) if np.ndim(n_segments) == 0
             else np.asarray(n_segments, dtype=float))
    knots = merge_knots(knots, break_parameters(edge, breaks))
    xi, gw = gauss_legendre(order)
    lo, hi = knots[:-1], knots[1:]
    seg = np.repeat(np.arange(len(lo)), order)
    t = np.tile((xi + 1) / 2, len(lo))
    x, tangent = edge.at(lo[seg] + t * (hi - lo)[seg])
    w = np.tile(gw / 2, len(lo)) * edge.length * (hi - lo)[seg]
    normal = np.column_stack([tangent[:, 1], -tangent[:, 0]])
    return x, w, normal, lo[seg] + t * (hi - lo)[seg]


def boundary_points(domain: Domain, where: str | Callable | None, order: int,
                    h: float, breaks: np.ndarray | None = None) -> Points:
    """Gauss-Legendre points along boundary edges.

    Each selected edge is split into ``ceil(length / h)`` segments of equal
    parameter with ``order`` points each; on arcs ``ds = R |sweep| ds_param``,
    so the rule is on the exact circle, not a polyline.

    Parameters
    ----------
    domain : Domain
    where : str, callable or None
        An edge name (the KeyError of :meth:`Domain.edges` for an unknown
        one), a mask ``x (n, 2) -> bool (n,)`` applied to the points of all
        edges, or None for all edges.
    order : int
        Gauss points per segment.
    h : float
        Segment length (the nodal spacing).
    breaks : ndarray (b, 2), optional
        Points where the rule must not straddle (crack mouths, where the
        trial functions jump): an edge through one is split there.

    Returns
    -------
    Points
        ``x (n, 2)``, ``w (n,)`` line weights summing to the edge lengths,
        ``normal (n, 2)`` outward unit normals, ``owner (n,)``: the index of
        the edge in ``domain.edges()``.

    Examples
    --------
    >>> from efgkit.problem.geometry import Domain, Loop
    >>> dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)])
    >>> pts = boundary_points(dom, "hole", 4, 0.1)
    >>> bool(abs(pts.w.sum() - 0.5 * np.pi) < 1e-14)  # 2 pi R
    True
    >>> bool(np.allclose(pts.normal, -(pts.x - [1, 0.5]) / 0.25))  # out of the material
    True
    """
    check_count("order", order)
    check_length("h", h)
    edges = domain.edges()
    mask = None
    if isinstance(where, str):
        domain.edges(where)  # KeyError naming the valid edges
        sel = [k for k, e in enumerate(edges) if e.name == where]
    elif where is None or callable(where):
        sel, mask = range(len(edges)), where
    else:
        raise TypeError(f"where must be an edge name, a callable x -> mask or None, got {where!r}")
    parts = []
    for k in sel:
        e = edges[k]
        x, w, normal, _ = edge_rule(e, max(1, math.ceil(e.length / h - 1e-9)), order, breaks)
        parts.append(Points(x, w, np.full(len(x), k), normal))
    pts = Points.concatenate(*parts)
    if mask is None:
        return pts
    keep = np.asarray(mask(pts.x))
    if keep.shape != (pts.n,) or keep.dtype != bool:
        raise ValueError(f"where(x) must return a bool mask of shape ({pts.n},), "
                         f"got {keep.dtype} {keep.shape}")
    return Points(pts.x[keep], pts.w[keep], pts.owner[keep], pts.normal[keep])
