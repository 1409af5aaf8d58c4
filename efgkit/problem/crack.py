"""Crack polylines, their tips and tip frames.

A crack is a polyline ``vertices (n >= 2, 2)``. Each of its two ends is either
a *tip* (a free end inside the body) or a *mouth* (an end on the domain
boundary: an edge crack, or a crack starting at a hole). The tip frame has
``x1`` along the last segment, pointing ahead of the tip (out of the crack),
and ``x2`` turned counter-clockwise from it; angles are in radians
(seed 003 Fig. 31).

Sides: the *left* face of a crack segment ``a -> b`` is where
``cross(b - a, x - a) > 0``. A point exactly on the crack line is on the left
face (a documented convention that makes every side test deterministic).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .geometry import check_coordinates

__all__ = ["FACE_OFFSET", "Crack", "Tip"]

# Points on a crack face sit this many local spacings off the crack line, on their face, so
# that fields discontinuous across the crack are those of that face (face loads, crack-face
# terms of J, crack-opening samples).
FACE_OFFSET = 1e-7


@dataclass(frozen=True)
class Tip:
    """A crack tip and its frame.

    Attributes
    ----------
    x : ndarray (2,)
        Position.
    angle : float
        Direction of the tip frame's x1 axis (pointing ahead of the tip), radians.
    crack : str
        Name of the crack.
    end : int
        0 if the tip is the crack's first vertex, 1 if its last.
    """

    x: np.ndarray
    angle: float
    crack: str
    end: int

    @property
    def id(self) -> str:
        """``"<crack name>:<end>"``, unique within a scene."""
        return f"{self.crack}:{self.end}"

    @property
    def rotation(self) -> np.ndarray:
        """Rows are the frame axes e1, e2 in global coordinates, shape (2, 2):
        ``x_local = rotation @ (x - tip.x)``."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        return np.array([[c, s], [-s, c]])


def _first_crossing(v: np.ndarray, i: int, scale: float) -> int | None:
    """The first segment j >= i + 2 of the polyline ``v (n + 1, 2)`` that shares a point with
    segment i (touching counts), or None.

    The orientations are formed in coordinates scaled by a power of two (exact, so the tests
    are those of the unscaled values), which keeps their products finite up to the coordinate
    limit; ``scale`` is the crack length (the tolerance ``(1e-12 scale)^2``).
    """
    k = min(0, -int(np.frexp(np.abs(v).max())[1]))  # shrink only
    w = np.ldexp(v, k)
    eps_on = (1e-12 * scale * 2.0**k) ** 2  # compares orientations (scaled by 2^2k)
    eps_cross = (1e-12 * scale * 2.0 ** (2 * k)) ** 2  # compares their products (by 2^4k)
    a, b, c, d = w[i], w[i + 1], w[i + 2:-1], w[i + 3:]

    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (
            r[..., 0] - p[..., 0])

    def on(p, q, r, o):  # the bounding-box tests in the given coordinates
        return (np.abs(o) <= eps_on) & np.all(np.minimum(p, q) - 1e-12 <= r, axis=-1) & np.all(
            r <= np.maximum(p, q) + 1e-12, axis=-1)

    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    va, vb, vc, vd = v[i], v[i + 1], v[i + 2:-1], v[i + 3:]
    hit = ((o1 * o2 < -eps_cross) & (o3 * o4 < -eps_cross)) | on(va, vb, vc, o1) | on(
        va, vb, vd, o2) | on(vc, vd, va, o3) | on(vc, vd, vb, o4)
    return i + 2 + int(np.argmax(hit)) if hit.any() else None


@dataclass(frozen=True)
class Crack:
    """A crack as a polyline of ``vertices (n >= 2, 2)``.

    Parameters
    ----------
    vertices : array_like (n, 2)
    tips : (bool, bool)
        Which of the two ends (first vertex, last vertex) are tips; an end
        that is not a tip must lie on the domain boundary or on another crack's
        face (a junction, :mod:`efgkit.problem.junctions`; checked by
        :class:`~efgkit.problem.scene.Scene`). ``(False, True)``: an edge crack
        growing from its last vertex; ``(False, False)``: a crack run through
        (from a hole to another hole, say) with no tip left.
    name : str
        Unique within a scene; names the crack in errors and results.
    pressure : float
        Uniform pressure on both faces (stress unit; > 0 pushes them apart).

    Raises
    ------
    ValueError
        Zero-length segments (duplicate consecutive vertices), a polyline that
        crosses or touches itself (including a segment that doubles back),
        non-finite vertices, coordinates beyond
        :data:`~efgkit.problem.geometry.COORDINATE_LIMIT` (1e150) or spanning less
        than its inverse (their squares overflow or underflow).

    Examples
    --------
    >>> c = Crack([[0.0, 0.0], [1.0, 0.0]], tips=(False, True), name="a")
    >>> [(t.id, t.x.tolist(), t.angle) for t in c.tip_list]
    [('a:1', [1.0, 0.0], 0.0)]
    >>> c2 = c.extended(0.5, math.pi / 2)
    >>> np.round(c2.vertices, 12).tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5]]
    """

    vertices: np.ndarray
    tips: tuple[bool, bool] = (True, True)
    name: str = "crack"
    pressure: float = 0.0

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 2:
            raise ValueError(f"crack {self.name!r}: vertices must have shape (n >= 2, 2), got {v.shape}")
        if not np.all(np.isfinite(v)):
            k = int(np.argmax(~np.isfinite(v).all(axis=1)))
            raise ValueError(f"crack {self.name!r}: vertex {k} is not finite ({v[k].tolist()})")
        check_coordinates(f"crack {self.name!r}: vertices", v)
        seg = np.linalg.norm(np.diff(v, axis=0), axis=1)
        scale = float(seg.sum())
        if np.any(seg <= 1e-12 * max(scale, 1e-300)):
            k = int(np.argmin(seg))
            raise ValueError(
                f"crack {self.name!r}: zero-length segment between vertices {k} and {k + 1} "
                f"(duplicate vertex {v[k].tolist()}); remove it"
            )
        tips = tuple(bool(t) for t in self.tips)
        if len(tips) != 2:
            raise ValueError(f"crack {self.name!r}: tips must be two booleans, got {self.tips!r}")
        if isinstance(self.pressure, bool) or not isinstance(self.pressure, (int, float, np.number)) \
                or not math.isfinite(self.pressure):
            raise ValueError(f"crack {self.name!r}: pressure must be a finite number, got "
                             f"{self.pressure!r}")
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "tips", tips)
        object.__setattr__(self, "pressure", float(self.pressure))
        self._check_simple(v, scale)

    def _check_simple(self, v, scale):
        n = len(v) - 1
        for i in range(n - 1):  # adjacent segments: doubling back (angle of 180 degrees)
            d0, d1 = v[i + 1] - v[i], v[i + 2] - v[i + 1]
            cross = d0[0] * d1[1] - d0[1] * d1[0]
            if abs(cross) <= 1e-12 * np.linalg.norm(d0) * np.linalg.norm(d1) and d0 @ d1 < 0:
                raise ValueError(f"crack {self.name!r} doubles back on itself at vertex {i + 1} "
                                 f"{v[i + 1].tolist()}: self-intersecting")
        for i in range(n - 2):  # vectorised over the later segments
            j = _first_crossing(v, i, scale)
            if j is not None:
                raise ValueError(
                    f"crack {self.name!r} intersects itself: segments {i} and {j} "
                    f"(vertices {i}-{i + 1} and {j}-{j + 1}) meet")

    @property
    def segments(self) -> np.ndarray:
        """Segments, shape (n - 1, 2, 2): ``[:, 0]`` start, ``[:, 1]`` end."""
        return np.stack([self.vertices[:-1], self.vertices[1:]], axis=1)

    @property
    def length(self) -> float:
        return float(np.linalg.norm(np.diff(self.vertices, axis=0), axis=1).sum())

    def tip(self, end: int) -> Tip:
        """The tip at ``end`` (0: first vertex, 1: last vertex)."""
        if end not in (0, 1) or not self.tips[end]:
            have = [e for e in (0, 1) if self.tips[e]]
            raise ValueError(f"crack {self.name!r} has no tip at end {end!r}; its tip ends are {have}")
        v = self.vertices
        a, b = (v[1], v[0]) if end == 0 else (v[-2], v[-1])
        d = b - a
        return Tip(b.copy(), math.atan2(d[1], d[0]), self.name, end)

    @property
    def tip_list(self) -> tuple[Tip, ...]:
        """The crack's tips, first end first."""
        return tuple(self.tip(e) for e in (0, 1) if self.tips[e])

    def extended(self, da: float, angle: float = 0.0, end: int | None = None) -> Crack:
        """A new crack with a segment of length ``da`` added at a tip.

        ``angle`` is the kink angle measured from the tip's x1 axis
        (counter-clockwise positive, radians); ``end`` selects the tip
        (needed only when both ends are tips).
        """
        if not (isinstance(da, (int, float)) and math.isfinite(da) and da > 0):
            raise ValueError(f"crack {self.name!r}: extension da must be finite and > 0, got {da!r}")
        if not (isinstance(angle, (int, float)) and math.isfinite(angle) and abs(angle) < math.pi):
            raise ValueError(f"crack {self.name!r}: kink angle must lie in (-pi, pi), got {angle!r}")
        if end is None:
            ends = [e for e in (0, 1) if self.tips[e]]
            if len(ends) > 1:
                raise ValueError(f"crack {self.name!r} has two tips: give end=0 or end=1")
            end = ends[0]
        t = self.tip(end)
        new = t.x + da * np.array([math.cos(t.angle + angle), math.sin(t.angle + angle)])
        v = np.vstack([self.vertices, new]) if end == 1 else np.vstack([new, self.vertices])
        return replace(self, vertices=v)

    def points_along(self, arc: np.ndarray, end: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Points at arc lengths ``arc (m,)`` from vertex ``end`` (0: first, 1: last), and the
        unit left normal of the segment each lies on (left of the polyline's direction)."""
        v = self.vertices if end == 0 else self.vertices[::-1]
        ln = np.linalg.norm(np.diff(v, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(ln)])
        arc = np.clip(np.asarray(arc, dtype=float), 0.0, cum[-1])
        k = np.clip(np.searchsorted(cum, arc, side="right") - 1, 0, len(ln) - 1)
        d = (v[k + 1] - v[k]) / ln[k, None]
        x = v[k] + (arc - cum[k])[:, None] * d
        left = np.column_stack([-d[:, 1], d[:, 0]])
        return x, (left if end == 0 else -left)

    def side(self, x: np.ndarray, segment: int) -> np.ndarray:
        """+1 on the left face of segment ``segment`` (or on its line), -1 on the right; (n,)."""
        a, b = self.segments[segment]
        x = np.atleast_2d(np.asarray(x, dtype=float))
        c = (b[0] - a[0]) * (x[:, 1] - a[1]) - (b[1] - a[1]) * (x[:, 0] - a[0])
        return np.where(c >= 0, 1, -1)

    def project(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Nearest points of the polyline to ``x (n, 2)``: segment index (n,), parameter
        t in [0, 1] along it (n,) and distance (n,)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        s = self.segments
        a, ab = s[None, :, 0], s[None, :, 1] - s[None, :, 0]
        t = np.clip(np.sum((x[:, None] - a) * ab, -1) / np.sum(ab * ab, -1), 0.0, 1.0)
        d = np.linalg.norm(x[:, None] - a - t[..., None] * ab, axis=-1)
        k = np.argmin(d, axis=1)
        rows = np.arange(len(x))
        return k, t[rows, k], d[rows, k]

    def distance(self, x: np.ndarray) -> np.ndarray:
        """Distance of points ``x (n, 2)`` to the crack polyline, shape (n,)."""
        return self.project(x)[2]
