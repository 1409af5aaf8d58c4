"""Geometry of crack paths for the growth verification scripts: distances between
polylines, headings, crossings and the turn of a path (``verification/two_holes.py``).

Paths are polylines ``(n, 2)`` of vertices (mm), a crack's initial segment first.
"""

from __future__ import annotations

import math

import numpy as np


def _segments(v):
    v = np.asarray(v)
    return v[:-1], v[1:]


def min_distance(a, b) -> float:
    """Smallest distance between two polylines ``(n, 2)``, ``(m, 2)`` (0 if they cross)."""
    (a0, a1), (b0, b1) = _segments(a), _segments(b)

    def point_seg(p, s0, s1):  # p (k, 2) against segments (m, 2): (k, m)
        d = s1 - s0
        t = np.clip(np.einsum("kmi,mi->km", p[:, None] - s0, d) / np.einsum("mi,mi->m", d, d), 0, 1)
        return np.linalg.norm(p[:, None] - (s0 + t[..., None] * d), axis=-1)

    gap = min(point_seg(np.vstack([a0, a1[-1:]]), b0, b1).min(),
              point_seg(np.vstack([b0, b1[-1:]]), a0, a1).min())
    o = lambda p, q, r: np.sign((q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1])  # noqa: E731
                                 - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0]))
    A0_, A1_, B0_, B1_ = a0[:, None], a1[:, None], b0[None], b1[None]
    cross = (o(A0_, A1_, B0_) * o(A0_, A1_, B1_) < 0) & (o(B0_, B1_, A0_) * o(B0_, B1_, A1_) < 0)
    return 0.0 if cross.any() else float(gap)


def headings(v) -> np.ndarray:
    """Direction (degrees) of each segment of a path ``(n, 2)``."""
    d = np.diff(np.asarray(v), axis=0)
    return np.degrees(np.arctan2(d[:, 1], d[:, 0]))


def y_at_centre(v) -> float | None:
    """Height where the path first crosses x = 0 (interpolated), None if it does not."""
    v = np.asarray(v)
    k = np.nonzero(np.diff(np.sign(v[:, 0])) != 0)[0]
    if not len(k):
        return None
    p, q = v[k[0]], v[k[0] + 1]
    return float(p[1] + (q[1] - p[1]) * (0 - p[0]) / (q[0] - p[0]))


def _point_polyline(p, v) -> float:
    """Distance of the point ``p (2,)`` to the polyline ``v (n, 2)``."""
    a, b = np.asarray(v[:-1], float), np.asarray(v[1:], float)
    d = b - a
    t = np.clip(np.einsum("mi,mi->m", p - a, d) / np.einsum("mi,mi->m", d, d), 0, 1)
    return float(np.linalg.norm(p - (a + t[:, None] * d), axis=1).min())


def approach_to_face(v, other) -> float:
    """Closest approach of the grown part of path ``v (n, 2)`` (its vertices after the
    initial crack) to the initial crack of ``other`` (its first two vertices: the face
    behind the other tip once the paths have passed), mm; 0 for a tip that joins it."""
    return min(_point_polyline(p, np.asarray(other)[:2]) for p in np.asarray(v)[2:])


def turn_towards(v, sign: float) -> float:
    """How far a path turns back towards the line of holes after crossing x = 0: for the
    left crack (``sign = 1``, above the line, running to +x) its height at x = 0 less its
    lowest point beyond; for the right one (``sign = -1``) its highest point beyond
    x = 0 less its height there (mm). None if the path does not cross x = 0."""
    v = np.asarray(v)
    y0 = y_at_centre(v)
    if y0 is None:
        return None
    beyond = v[sign * v[:, 0] > 0, 1]
    return float(y0 - beyond.min()) if sign > 0 else float(beyond.max() - y0)


def path_difference(a, b) -> float:
    """Largest height difference |y_a(x) - y_b(x)| of the grown parts of two paths of one
    crack (vertices after the initial crack, ``(n, 2)``) over their common x-range, mm
    (the grown parts are single-valued in x here); nan if one is not."""
    ga, gb = np.asarray(a)[1:], np.asarray(b)[1:]
    out = []
    for g in (ga, gb):
        g = g[np.argsort(g[:, 0])]
        if np.any(np.diff(g[:, 0]) <= 0):
            return math.nan
        out.append(g)
    lo, hi = max(out[0][0, 0], out[1][0, 0]), min(out[0][-1, 0], out[1][-1, 0])
    x = np.linspace(lo, hi, 201)
    return float(np.max(np.abs(np.interp(x, *out[0].T) - np.interp(x, *out[1].T))))
