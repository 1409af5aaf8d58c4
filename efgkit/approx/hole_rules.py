"""How node supports see holes: see-through (default), visibility or diffraction.

A hole is a nonconvex boundary (seed 003 Sect. 4): with ``visibility`` a pair
(x_I, x) whose segment passes through a hole is cut; with ``diffraction`` its
distance is lengthened around the tangent point x_c of the hole seen from the
node (end of Sect. 4.2, Fig. 11b), ``d = ((s1 + s2) / s0)^lambda s0`` with
``s1 = |x_I - x_c|``, ``s2 = |x - x_c|`` (s2 may cross the hole, as the seed
notes); ``see_through`` ignores holes, which the seed found acceptable for
smooth boundaries (Sects. 4.4, 4.5.1). Circular holes are treated exactly
(segment-disc test, analytic tangent points); other holes through the
vertices of their boundary polyline (silhouette vertices as wrap points).

A node on a circular hole or at a vertex of a polygonal one is its own
tangent point, so diffraction leaves its pairs unmodified (its support spans
the hole as with see-through); a node inside a polygon edge wraps around the
edge's end vertices like any other node.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .crack_rules import wrap_distance

__all__ = ["HOLE_RULES", "Holes", "hole_distances"]

HOLE_RULES = ("see_through", "visibility", "diffraction")


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


@dataclass(frozen=True, eq=False)
class Holes:
    """The holes of a domain: circles (exact) and polygons (boundary polylines).

    Attributes
    ----------
    centres : ndarray (c, 2); radii : ndarray (c,)
        Circular holes.
    polygons : tuple of ndarray (m, 2)
        Other holes, as closed polylines (vertices, not repeated).
    """

    centres: np.ndarray
    radii: np.ndarray
    polygons: tuple

    @classmethod
    def of(cls, domain) -> Holes:
        centres, radii, polys = [], [], []
        for h in domain.holes:
            edges = h.edges()
            if len(edges) == 1 and edges[0].is_arc and abs(abs(edges[0].sweep) - 2 * np.pi) < 1e-12:
                centres.append(edges[0].centre)
                radii.append(float(np.linalg.norm(edges[0].start - edges[0].centre)))
            else:
                polys.append(h.polyline()[0])
        return cls(np.array(centres).reshape(-1, 2), np.array(radii), tuple(polys))

    def distance(self, x: np.ndarray) -> np.ndarray:
        """Distance of points ``x (n, 2)`` to the nearest hole boundary, shape (n,)."""
        out = np.full(len(x), np.inf)
        for c, r in zip(self.centres, self.radii, strict=True):
            out = np.minimum(out, np.abs(np.hypot(*(x - c).T) - r))
        for p in self.polygons:
            a, b = p, np.roll(p, -1, axis=0)
            ab = b - a
            t = np.clip(np.einsum("nkd,kd->nk", x[:, None] - a, ab) / (ab * ab).sum(1), 0, 1)
            out = np.minimum(out, np.hypot(*(x[:, None] - a - t[..., None] * ab).transpose(2, 0, 1))
                             .min(axis=1))
        return out


def _circle(xq, xn, c, r):
    """Pairs whose segment enters the open disc, and the tangent point on the side of x."""
    v = xq - xn
    vv = np.maximum((v * v).sum(1), 1e-300)
    t = np.clip(((c - xn) * v).sum(1) / vv, 0.0, 1.0)
    # the disc is shrunk by 1e-4 r: the quadrature integrates arcs as polylines (sag 1e-5 r),
    # so points between a chord and the arc must not count as inside the hole
    blocked = np.hypot(*(xn + t[:, None] * v - c).T) < r * (1 - 1e-4)
    p = xn - c
    dn = np.maximum(np.hypot(*p.T), r)
    alpha = np.arccos(np.clip(r / dn, -1.0, 1.0))
    u = p / dn[:, None]
    best, xc = np.full(len(xq), np.inf), np.zeros_like(xq)
    for sgn in (1.0, -1.0):
        ca, sa = np.cos(sgn * alpha), np.sin(sgn * alpha)
        tp = c + r * np.column_stack([ca * u[:, 0] - sa * u[:, 1], sa * u[:, 0] + ca * u[:, 1]])
        path = np.hypot(*(xn - tp).T) + np.hypot(*(xq - tp).T)
        take = path < best
        best, xc = np.where(take, path, best), np.where(take[:, None], tp, xc)
    return blocked, xc


def _polygon(xq, xn, poly):
    """Pairs whose segment crosses the polygon, and the silhouette vertex giving the shortest
    path around it."""
    a, b = poly, np.roll(poly, -1, axis=0)
    blocked = np.zeros(len(xq), bool)
    for k in range(len(a)):
        e = b[k] - a[k]
        o1, o2 = _cross(e, xq - a[k]), _cross(e, xn - a[k])
        o3, o4 = _cross(xq - xn, a[k] - xn), _cross(xq - xn, b[k] - xn)
        blocked |= (o1 * o2 < 0) & (o3 * o4 < 0)
    best, xc = np.full(len(xq), np.inf), np.zeros_like(xq)
    prev = np.roll(poly, 1, axis=0)
    for k in range(len(poly)):  # silhouette: both neighbours on one side of the line x_I -> v
        d = poly[k] - xn
        s_prev, s_next = _cross(d, prev[k] - xn), _cross(d, b[k] - xn)
        silhouette = s_prev * s_next >= 0
        path = np.hypot(*d.T) + np.hypot(*(xq - poly[k]).T)
        take = silhouette & (path < best)
        best, xc = np.where(take, path, best), np.where(take[:, None], poly[k], xc)
    return blocked, xc


def hole_distances(xq, xn, cut, d, dd, holes: Holes, rule: str, power: float):
    """Apply a hole rule to pairs with current distances ``d (P,)``, ``dd (P, 2)``.

    Returns cut (P,), d, dd: ``visibility`` cuts the pairs through a hole,
    ``diffraction`` lengthens them around its tangent point (composed with a
    crack rule's change by :func:`~efgkit.approx.crack_rules.wrap_distance`).
    """
    if rule == "see_through":
        return cut, d, dd
    diff = xq - xn
    s0 = np.hypot(*diff.T)
    ds0 = diff / np.where(s0 > 0, s0, 1.0)[:, None]
    tests = [_circle(xq, xn, c, r) for c, r in zip(holes.centres, holes.radii, strict=True)]
    tests += [_polygon(xq, xn, p) for p in holes.polygons]
    for blocked, xc in tests:
        if rule == "visibility":
            cut = cut | blocked
        else:
            d, dd = wrap_distance(d, dd, xq, xn, xc, s0, ds0, power, blocked & ~cut)
    return cut, d, dd
