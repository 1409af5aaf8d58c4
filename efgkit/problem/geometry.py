"""The 2D body: a closed outer loop with holes, edges straight or circular arcs, named.

A :class:`Loop` is a closed chain of edges; edge ``k`` runs from ``vertices[k]``
to ``vertices[k + 1]`` (cyclically). It is straight when ``sweeps[k] == 0`` and
otherwise a circular arc about ``centres[k]`` through the signed angle
``sweeps[k]`` (counter-clockwise positive). A full circle is one vertex and
one edge of sweep ``+-2 pi``.

:class:`Domain` orients the outer loop counter-clockwise and the holes
clockwise, so that for every edge the outward normal (out of the material) is
the travel direction turned clockwise: ``n = (t_y, -t_x)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .edge import Edge

__all__ = ["COORDINATE_LIMIT", "Domain", "Loop", "Edge", "check_coordinates", "segments_intersect"]

# Coordinates are squared (lengths, areas, weights, energies): beyond 1e150 a square overflows
COORDINATE_LIMIT = 1e150  # float64 (max 1.8e308), and a body smaller than 1e-150 squares to zero


def check_coordinates(what: str, x) -> None:
    """A ValueError (naming ``what``, the value, the limit and the remedy) for finite points
    ``x (n, 2)`` with a coordinate beyond :data:`COORDINATE_LIMIT` in magnitude, or spanning
    less than its inverse (but more than 0): their squares overflow or underflow."""
    x = np.asarray(x, dtype=float).reshape(-1, 2)
    big = np.abs(x).max(axis=1) > COORDINATE_LIMIT
    if big.any():
        k = int(np.argmax(big))
        raise ValueError(
            f"{what}: coordinate {k} {x[k].tolist()} is too large to square without overflow "
            f"(|x| <= {COORDINATE_LIMIT:g}: lengths, areas and energies are computed from squares, "
            "and float64 ends at 1.8e308); rescale the units (e.g. m instead of nm)")
    span = float(np.ptp(x, axis=0).max()) if len(x) else 0.0
    if 0 < span < 1.0 / COORDINATE_LIMIT:
        raise ValueError(f"{what} span {span:.3g}, too small to square without underflow (span >= "
                         f"{1 / COORDINATE_LIMIT:g}); rescale the units (e.g. nm instead of m)")


@dataclass(frozen=True)
class Loop:
    """Closed chain of named straight or arc edges.

    Parameters
    ----------
    vertices : array_like, shape (n, 2)
    names : sequence of str, length n
        Name of edge k (vertices[k] -> vertices[k+1]); several edges may share a name.
    centres : array_like, shape (n, 2), optional
        Arc centres; NaN rows (the default) are straight edges.
    sweeps : array_like, shape (n,), optional
        Signed arc angles in radians; 0 (the default) for straight edges.

    Examples
    --------
    >>> sq = Loop.polygon([[0, 0], [1, 0], [1, 1], [0, 1]], ["b", "r", "t", "l"])
    >>> round(sq.area, 12)
    1.0
    >>> round(Loop.circle([0, 0], 1.0, "hole").area, 4)
    3.1416
    """

    vertices: np.ndarray
    names: tuple[str, ...]
    centres: np.ndarray = field(default=None)
    sweeps: np.ndarray = field(default=None)

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) == 0:
            raise ValueError(f"vertices must have shape (n, 2) with n >= 1, got {v.shape}")
        n = len(v)
        c = np.full((n, 2), np.nan) if self.centres is None else np.asarray(self.centres, float)
        s = np.zeros(n) if self.sweeps is None else np.asarray(self.sweeps, float).reshape(-1)
        names = tuple(self.names)
        if len(names) != n or c.shape != (n, 2) or s.shape != (n,):
            raise ValueError(
                f"a loop of {n} vertices needs {n} edge names, centres (n, 2) and sweeps (n,); "
                f"got {len(names)} names, centres {c.shape}, sweeps {s.shape}"
            )
        if not np.all(np.isfinite(v)) or not np.all(np.isfinite(s)):
            raise ValueError("loop vertices and sweeps must be finite (no NaN or inf)")
        check_coordinates("loop vertices (and arc centres)", np.vstack([v, c[np.isfinite(c).all(axis=1)]]))
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "names", names)
        object.__setattr__(self, "centres", c)
        object.__setattr__(self, "sweeps", s)
        for k, e in enumerate(self.edges()):
            if e.is_arc:
                if not np.all(np.isfinite(e.centre)):
                    raise ValueError(f"arc edge {k} ({e.name!r}) needs a finite centre")
                r0, r1 = np.linalg.norm(e.start - e.centre), np.linalg.norm(e.end - e.centre)
                end, _ = e.at(np.array([1.0]))
                if r0 == 0 or abs(r0 - r1) > 1e-9 * r0 or np.linalg.norm(end[0] - e.end) > 1e-7 * r0:
                    raise ValueError(
                        f"arc edge {k} ({e.name!r}): start, end, centre and sweep disagree"
                    )
            elif e.length == 0.0:
                raise ValueError(
                    f"edge {k} ({e.name!r}) has zero length: vertices {k} and {(k + 1) % n} "
                    "coincide; remove the duplicate vertex"
                )

    @classmethod
    def polygon(cls, vertices, names=None) -> Loop:
        """Straight-edged loop; edge names default to ``edge0, edge1, ...``."""
        v = np.asarray(vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
            raise ValueError(f"a polygon needs vertices of shape (n >= 3, 2), got {v.shape}")
        names = tuple(names) if names is not None else tuple(f"edge{k}" for k in range(len(v)))
        return cls(v, names)

    @classmethod
    def circle(cls, centre, radius: float, name: str = "hole") -> Loop:
        """Full circle of ``radius`` about ``centre`` (one arc edge, counter-clockwise)."""
        if not (math.isfinite(radius) and radius > 0):
            raise ValueError(f"circle radius must be finite and > 0, got {radius!r}")
        c = np.asarray(centre, dtype=float).reshape(2)
        return cls(c[None] + [[radius, 0.0]], (name,), c[None], np.array([2 * math.pi]))

    def edges(self) -> list[Edge]:
        n = len(self.vertices)
        return [
            Edge(self.names[k], self.vertices[k], self.vertices[(k + 1) % n], self.centres[k],
                 float(self.sweeps[k]))
            for k in range(n)
        ]

    def polyline(self) -> tuple[np.ndarray, np.ndarray]:
        """Closed polyline: points ``(m, 2)`` (last not repeated) and owning edge ``(m,)``."""
        pts, owner = [], []
        for k, e in enumerate(self.edges()):
            p = e.polyline()[:-1]
            pts.append(p)
            owner.append(np.full(len(p), k))
        return np.concatenate(pts), np.concatenate(owner)

    @property
    def signed_area(self) -> float:
        """Area by the shoelace formula on the polyline (> 0 counter-clockwise)."""
        p, _ = self.polyline()
        q = np.roll(p, -1, axis=0)
        return 0.5 * float(np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]))

    @property
    def area(self) -> float:
        return abs(self.signed_area)

    def reversed(self) -> Loop:
        """The same loop traversed the other way (edge names and arcs kept)."""
        n = len(self.vertices)
        order = [(-k) % n for k in range(n)]  # new vertex k is old vertex -k
        edge = [(-k - 1) % n for k in range(n)]  # new edge k is old edge -k-1
        return Loop(self.vertices[order], tuple(self.names[e] for e in edge),
                    self.centres[edge], -self.sweeps[edge])

    def self_intersections(self) -> np.ndarray:
        """Pairs of non-adjacent polyline segments that intersect, shape (k, 2)."""
        p, _ = self.polyline()
        a, b = p, np.roll(p, -1, axis=0)
        m = len(p)
        i, j = np.triu_indices(m, k=2)
        keep = ~((i == 0) & (j == m - 1))  # first and last segments are adjacent
        i, j = i[keep], j[keep]
        hit = segments_intersect(a[i], b[i], a[j], b[j])
        return np.column_stack([i[hit], j[hit]])


def segments_intersect(a, b, c, d) -> np.ndarray:
    """Whether segments ab and cd intersect (touching counts), vectorised.

    Parameters are arrays of shape (n, 2); returns a bool array (n,).
    """

    def orient(p, q, r):
        return (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])

    # orientations (squares) and their products (fourth powers) in coordinates scaled by a
    # power of two per row: exact, the same comparisons, and no overflow up to COORDINATE_LIMIT
    e = -np.frexp(np.abs(np.stack(np.broadcast_arrays(a, b, c, d), 1)).max(axis=(1, 2)))[1][:, None]
    sa, sb, sc, sd = (np.ldexp(z, e) for z in (a, b, c, d))
    scale = np.maximum(np.abs(sb - sa).max(axis=1), np.abs(sd - sc).max(axis=1)) ** 2
    eps = 1e-12 * scale
    o1, o2 = orient(sa, sb, sc), orient(sa, sb, sd)
    o3, o4 = orient(sc, sd, sa), orient(sc, sd, sb)
    proper = (o1 * o2 < -eps**2) & (o3 * o4 < -eps**2)

    def on(p, q, r, o):  # r on segment pq, given orient(p, q, r) = o
        return (np.abs(o) <= eps) & (np.minimum(p, q) - 1e-12 <= r).all(1) & (
            r <= np.maximum(p, q) + 1e-12).all(1)

    return proper | on(a, b, c, o1) | on(a, b, d, o2) | on(c, d, a, o3) | on(c, d, b, o4)


@dataclass(frozen=True)
class Domain:
    """Outer loop minus holes, with named edges.

    The outer loop is stored counter-clockwise and holes clockwise.
    Validation rejects degenerate or self-intersecting loops and holes not
    strictly inside the outer loop or overlapping each other.

    Examples
    --------
    >>> dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)])
    >>> sorted(dom.edge_names)
    ['bottom', 'hole', 'left', 'right', 'top']
    >>> dom.contains([[0.1, 0.1], [1.0, 0.5], [3.0, 0.0]]).tolist()
    [True, False, False]
    """

    outer: Loop
    holes: tuple[Loop, ...] = ()

    def __post_init__(self):
        holes = tuple(self.holes)
        outer = self.outer
        for name, loop in [("outer", outer)] + [(f"hole {k}", h) for k, h in enumerate(holes)]:
            if not isinstance(loop, Loop):
                raise TypeError(f"{name} must be a Loop, got {type(loop).__name__}")
            p, _ = loop.polyline()
            scale = float(np.ptp(p, axis=0).max()) if len(p) else 0.0
            bad = loop.self_intersections() if len(p) >= 3 else []
            if len(bad):
                raise ValueError(
                    f"{name} loop is self-intersecting (near {p[bad[0, 0]].tolist()}); "
                    "give vertices in boundary order without crossings"
                )
            if len(p) < 3 or loop.area <= 1e-12 * max(scale, 1e-300) ** 2:
                raise ValueError(f"{name} loop is empty or degenerate (zero area)")
        if outer.signed_area < 0:
            outer = outer.reversed()
        holes = tuple(h.reversed() if h.signed_area > 0 else h for h in holes)
        object.__setattr__(self, "outer", outer)
        object.__setattr__(self, "holes", holes)
        from matplotlib.path import Path  # here, not at import: `import efgkit` stays light

        outer_path = Path(outer.polyline()[0])
        for k, h in enumerate(holes):
            hp = h.polyline()[0]
            if not outer_path.contains_points(hp).all():
                raise ValueError(
                    f"hole {k} is not strictly inside the outer boundary (e.g. point "
                    f"{hp[~outer_path.contains_points(hp)][0].round(6).tolist()}); move or shrink it"
                )
            for j in range(k):
                if Path(holes[j].polyline()[0]).contains_points(hp).any() or Path(
                        hp).contains_points(holes[j].polyline()[0]).any():
                    raise ValueError(f"holes {j} and {k} overlap; merge them into one loop")

    @classmethod
    def rectangle(cls, x0, y0, x1, y1, names=("bottom", "right", "top", "left"), holes=()):
        """Axis-aligned rectangle [x0, x1] x [y0, y1] with named sides."""
        if not (x1 > x0 and y1 > y0):
            raise ValueError(f"rectangle needs x1 > x0 and y1 > y0, got {(x0, y0, x1, y1)}")
        v = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
        return cls(Loop.polygon(v, names), tuple(holes))

    @property
    def loops(self) -> tuple[Loop, ...]:
        return (self.outer, *self.holes)

    def edges(self, name: str | None = None) -> list[Edge]:
        """All edges, or those called ``name`` (KeyError naming the valid ones if none)."""
        es = [e for loop in self.loops for e in loop.edges()]
        if name is None:
            return es
        sel = [e for e in es if e.name == name]
        if not sel:
            raise KeyError(f"no edge named {name!r}; the domain's edges are {sorted(self.edge_names)}")
        return sel

    @property
    def edge_names(self) -> set[str]:
        return {n for loop in self.loops for n in loop.names}

    @property
    def area(self) -> float:
        return self.outer.area - sum(h.area for h in self.holes)

    @property
    def bbox(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of the outer loop."""
        p = self.outer.polyline()[0]
        return (*p.min(axis=0), *p.max(axis=0))

    @property
    def size(self) -> float:
        """Diagonal of the bounding box: the length scale of tolerances."""
        x0, y0, x1, y1 = self.bbox
        return math.hypot(x1 - x0, y1 - y0)

    def boundary_segments(self) -> np.ndarray:
        """Polyline segments of all loops, shape (m, 2, 2): ``[:, 0]`` start, ``[:, 1]`` end."""
        segs = []
        for loop in self.loops:
            p, _ = loop.polyline()
            segs.append(np.stack([p, np.roll(p, -1, axis=0)], axis=1))
        return np.concatenate(segs)

    def distance_to_boundary(self, x) -> np.ndarray:
        """Distance of points ``x (n, 2)`` to the boundary polyline, shape (n,)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        s = self.boundary_segments()
        out = np.full(len(x), np.inf)
        chunk = max(1, 2_000_000 // len(s))
        for i in range(0, len(x), chunk):
            p = x[i:i + chunk, None, :]
            a, ab = s[None, :, 0], s[None, :, 1] - s[None, :, 0]
            t = np.clip(np.sum((p - a) * ab, -1) / np.sum(ab * ab, -1), 0.0, 1.0)
            d = np.linalg.norm(p - a - t[..., None] * ab, axis=-1)
            out[i:i + chunk] = d.min(axis=1)
        return out

    def contains(self, x, tol: float = 0.0) -> np.ndarray:
        """Points inside the material, shape (n,) bool.

        Points within ``tol`` of the boundary count as inside (use a small
        positive ``tol`` to keep nodes placed on the boundary).
        """
        from matplotlib.path import Path

        x = np.atleast_2d(np.asarray(x, dtype=float))
        inside = Path(self.outer.polyline()[0]).contains_points(x)
        for h in self.holes:
            inside &= ~Path(h.polyline()[0]).contains_points(x)
        if tol > 0:
            inside |= self.distance_to_boundary(x) <= tol
        return inside

    def field_points(self, x) -> np.ndarray:
        """``x`` as finite points (n, 2) of the material (within 1e-9 of the domain size of it),
        where solution fields are evaluated; a ValueError names the first one outside."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        if x.ndim != 2 or x.shape[1] != 2 or not np.all(np.isfinite(x)):
            raise ValueError(f"x must be finite points of shape (n, 2), got shape {x.shape}")
        outside = ~self.contains(x, tol=1e-9 * self.size)
        if outside.any():
            k = int(np.argmax(outside))
            raise ValueError(f"{int(outside.sum())} point(s) lie outside the body, e.g. x[{k}] = "
                             f"{x[k].tolist()}: fields are defined only in the material (an "
                             "approximation there would be an extrapolation)")
        return x
