"""Box grids of the neighbour search: uniform, and nonuniform by seed 000 Sect. 4.1.

Both are stacks of strips of square boxes (the seed's "the uniform box search algorithm
can be viewed as a special case of the nonuniform one"): a uniform grid has one box side
for all strips, a nonuniform one a side per strip set by the supports that reach the
strip. Every node is registered in each box its support disc touches, so a point's
candidates are the members of its own box.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..jit import COMPILED_MIN, resolve_backend
from ..nodes import NodeCloud

__all__ = ["BoxGrid", "KINDS", "SPREAD"]

KINDS = ("auto", "uniform", "nonuniform")
# Largest over median support radius up to which one box side serves all nodes ("auto").
SPREAD = 1.5


@dataclass(frozen=True, eq=False)
class BoxGrid:
    """Nodes registered in the boxes their supports touch.

    Attributes
    ----------
    axis : int
        The strips are stacked along this axis (0: x, 1: y), the longer extent of the
        supports (seed 000 Sect. 4.1 step 1).
    edges : ndarray, shape (n_strips + 1,)
        Strip boundaries along ``axis``; strip ``s`` is ``[edges[s], edges[s + 1])``.
    side : ndarray, shape (n_strips,)
        Box side in each strip (equal to the strip's width).
    offset : ndarray, shape (n_strips + 1,), int
        First box of each strip; ``offset[-1]`` boxes in all.
    lo : float
        Start of the boxes along the other axis.
    start : ndarray, shape (n_boxes + 1,), int
        CSR pointers into ``members``.
    members : ndarray, shape (n_registrations,), int
        Nodes of each box, ascending.
    kind : {"uniform", "nonuniform"}
        The kind built.
    packed : ndarray, shape (n_registrations, 3)
        ``(x_I, y_I, d_mI^2)`` of each entry of ``members``: the query kernels read a
        box's candidates from here in one contiguous run.
    """

    axis: int
    edges: np.ndarray
    side: np.ndarray
    offset: np.ndarray
    lo: float
    start: np.ndarray
    members: np.ndarray
    kind: str = "uniform"
    packed: np.ndarray | None = None

    @classmethod
    def build(cls, nodes: NodeCloud, size: float | None = None, kind: str = "auto",
              factor: float = 1.0, backend: str = "auto") -> BoxGrid:
        """Register ``nodes`` in a uniform or nonuniform box grid.

        Parameters
        ----------
        nodes : NodeCloud
        size : float, optional
            Box side of a uniform grid (default ``factor * max(radius)``, the seed's 2 h_max).
        kind : {"auto", "uniform", "nonuniform"}
            "auto": uniform when the largest radius is at most SPREAD times the median,
            nonuniform otherwise. "nonuniform": strip ``s`` has side ``factor * max{d_mI : the support of I
            reaches strip s}`` (seed 000 Sect. 4.1 steps 2-5 with h-bar = that largest
            smoothing length; the seed's side 2 h-bar is the support radius: factor 1).
        factor : float
            Box side over the largest support radius reaching the box.
        backend : {"auto", "numba", "numpy"}
            Registration by the compiled kernel or in numpy (the same lists;
            :func:`efgkit.jit.resolve_backend` on the number of nodes).

        Examples
        --------
        >>> from efgkit.nodes import NodeCloud
        >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 4.0]])
        >>> g = BoxGrid.build(NodeCloud(x, np.array([0.5, 0.5, 2.0]), np.ones(3, bool)),
        ...                   kind="nonuniform")
        >>> g.axis, bool(g.side.min() < g.side.max())
        (1, True)
        """
        if kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
        if not (np.isfinite(factor) and factor > 0):
            raise ValueError(f"factor must be a positive number, got {factor!r}")
        x = np.ascontiguousarray(nodes.x, dtype=float)
        r = np.ascontiguousarray(nodes.radius, dtype=float)
        if len(x) == 0:
            raise ValueError("nodes is empty: a box grid needs at least one node")
        compiled = resolve_backend(backend, len(x)) == "numba"
        if compiled:  # one compiled pass instead of six numpy reductions (docs/performance.md)
            from .kernels import extent

            low, high, bad_x, bad_r = extent(x, r)
        else:
            bad_x = int((~np.isfinite(x)).any(axis=1).sum())
            bad_r = int((~(r > 0) | ~np.isfinite(r)).sum())
        if bad_x or bad_r:
            raise ValueError("nodes must have finite coordinates and positive finite radii; "
                             f"got {bad_x} non-finite coordinates and {bad_r} bad radii")
        if kind == "auto" and size is not None:
            kind = "uniform"
        if kind == "auto":  # small clouds: uniform, built without compiled kernels
            kind = "uniform" if r.max() <= SPREAD * np.median(r) or \
                resolve_backend("auto", len(x)) == "numpy" else "nonuniform"
        if not compiled:
            low = (x - r[:, None]).min(axis=0)
            high = (x + r[:, None]).max(axis=0)
        axis = 1 if high[1] - low[1] >= high[0] - low[0] else 0
        other = 1 - axis
        a_lo, a_hi = float(low[axis]), float(high[axis])
        if kind == "uniform":
            h = factor * float(r.max()) if size is None else float(size)
            if not (np.isfinite(h) and h > 0):
                raise ValueError(f"size must be a positive number, got {size!r}")
            n = max(1, math.ceil((a_hi - a_lo) / h))
            edges = a_lo + h * np.arange(n + 1)
            if edges[-1] <= a_hi:  # round-off: the last strip must hold a_hi's neighbourhood
                edges = np.append(edges, edges[-1] + h)
        else:
            from .kernels import strip_edges  # compiled: numba only where it is used

            n_bins = int(min(max(64, 8 * math.sqrt(len(x))), 1 << 16))
            edges = strip_edges(x[:, axis], r, a_lo, a_hi, float(factor), n_bins)
        side = np.diff(edges)
        if kind == "uniform":
            side = np.full(len(side), h)
        o_lo, o_hi = float(low[other]), float(high[other])
        per = np.floor((o_hi - o_lo) / side).astype(np.int64) + 1
        offset = np.concatenate([[0], np.cumsum(per)]).astype(np.int64)
        if compiled:
            from .kernels import register

            start, members, packed = register(x, r, axis, edges, side, offset, o_lo)
        else:
            start, members = _register_numpy(x, r, axis, edges, side, offset, o_lo)
            packed = np.column_stack([x, r * r])[members]
        return cls(axis, edges, side, offset, o_lo, start, members, kind, packed)

    @property
    def n_boxes(self) -> int:
        return int(self.offset[-1])

    @property
    def n_strips(self) -> int:
        return len(self.side)

    def box_of(self, x: np.ndarray) -> np.ndarray:
        """Box index of points ``x (n, 2)``, shape (n,); -1 outside the grid. From
        :data:`~efgkit.jit.COMPILED_MIN` points on by the compiled loop of the search
        (:func:`efgkit.search.kernels.box_index`, the same rule and arithmetic: the same
        boxes; the 2.9M points of the cracked plate at 1e5 nodes in 0.05 against 0.16 s,
        medians of 5 in one process)."""
        x = np.asarray(x, dtype=float).reshape(-1, 2)
        if len(x) >= COMPILED_MIN:
            from .kernels import box_index

            return box_index(np.ascontiguousarray(x), self.axis, self.edges, self.side,
                             self.offset, self.lo)
        a, c = x[:, self.axis], x[:, 1 - self.axis]
        s = np.clip(np.searchsorted(self.edges, a, side="right") - 1, 0, self.n_strips - 1)
        j = np.floor((c - self.lo) / self.side[s])
        ok = (a >= self.edges[0]) & (a < self.edges[-1]) & (j >= 0) & \
            (j < self.offset[s + 1] - self.offset[s])
        return np.where(ok, self.offset[s] + np.where(ok, j, 0).astype(np.int64), -1)


def _register_numpy(x, r, axis, edges, side, offset, lo):
    """The registration of :func:`efgkit.search.kernels.register` in numpy (same result)."""
    other = 1 - axis
    a, c, rr = x[:, axis], x[:, other], r * (1.0 + 1e-9)  # grown as in the kernel
    last = np.nextafter(edges[-1], -np.inf)
    s0 = np.searchsorted(edges, np.maximum(a - rr, edges[0]), side="right") - 1
    s1 = np.searchsorted(edges, np.minimum(a + rr, last), side="right") - 1
    node = np.repeat(np.arange(len(x)), s1 - s0 + 1)  # (node, strip) pairs
    strip = np.arange(len(node)) - np.repeat(np.cumsum(s1 - s0 + 1) - (s1 - s0 + 1), s1 - s0 + 1) \
        + s0[node]
    h, per = side[strip], offset[strip + 1] - offset[strip]
    i0 = np.maximum(0, np.floor((c[node] - rr[node] - lo) / h).astype(np.int64))
    i1 = np.minimum(per - 1, np.floor((c[node] + rr[node] - lo) / h).astype(np.int64))
    n = np.maximum(i1 - i0 + 1, 0)
    pair = np.repeat(np.arange(len(node)), n)  # (node, strip, box) triples
    j = np.arange(len(pair)) - np.repeat(np.cumsum(n) - n, n) + i0[pair]
    I, st, hh = node[pair], strip[pair], h[pair]
    ca = np.clip(a[I], edges[st], edges[st + 1])
    cc = np.clip(c[I], lo + j * hh, lo + (j + 1) * hh)
    touch = (ca - a[I]) ** 2 + (cc - c[I]) ** 2 < rr[I] * rr[I]
    box, I = (offset[st] + j)[touch], I[touch]
    order = np.argsort(box, kind="stable")  # nodes ascending within a box
    start = np.zeros(offset[-1] + 1, np.int64)
    np.cumsum(np.bincount(box, minlength=offset[-1]), out=start[1:])
    return start, I[order].astype(np.int64)
