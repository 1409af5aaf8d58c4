"""Shape functions at many points, formed a chunk of points at a time and never all held.

A :class:`PointShapes` stands for the shape functions (and the enrichment operators) at the
domain quadrature points of a large solve without holding them: :meth:`PointShapes.chunk`
forms those of one chunk of points (neighbour search, crack rules, MLS, enrichment), and the
fields (:meth:`~PointShapes.displacement`, :meth:`~PointShapes.gradient`,
:meth:`~PointShapes.strain`) are evaluated chunk by chunk, at all points or at the rows asked
for. The stiffness is assembled from the chunks the same way
(:func:`efgkit.system.streamed.streamed_stiffness`). The shape functions of a point depend on
that point alone (its neighbours, its crack rule, its enrichment), so a chunk's rows are the
rows of the shape functions formed at all points at once.

Memory: a chunk of ``c`` points with ``k`` neighbours holds the padded values, d/dx, d/dy
(float64), the int32 indices and the mask (29 bytes per slot) and the enrichment operators;
at 2**18 points and k = 23 about 0.2 GB with the MLS temporaries, whatever the size of the
problem.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..jit import COMPILED_MIN
from ..problem.material import strain_from_gradient
from ..search import find_neighbours
from .approximation import Approximation
from .shape import Shape

__all__ = ["CHUNK_POINTS", "PointShapes"]

# Points per chunk: large enough that every chunk takes the compiled kernels
# (efgkit.jit.COMPILED_MIN = 5e4) and that the per-chunk costs that scale with the node count
# (the assembly's row arrays) stay small; small enough that a chunk's arrays (~0.2 GB) are a
# fraction of the stiffness.
CHUNK_POINTS = 2**18


@dataclass(frozen=True, eq=False)
class PointShapes:
    """The shape functions of ``approx`` at the points ``x``, formed on demand in chunks.

    Attributes
    ----------
    approx : Approximation
        The trial functions (nodes, search structure, crack rule, enrichment).
    x : ndarray, shape (n_points, 2)
        The points (the domain quadrature points, sorted by box: chunks are compact).
    chunk_points : int, optional
        Points per chunk (default :data:`CHUNK_POINTS`, read when the object is made).

    Examples
    --------
    >>> from efgkit import EFG, Domain
    >>> from efgkit.nodes import generate_nodes
    >>> from efgkit.search import BoxGrid
    >>> nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    >>> approx = Approximation(nodes, BoxGrid.build(nodes))
    >>> x = np.random.default_rng(0).random((50, 2))
    >>> ps = PointShapes(approx, x, chunk_points=16)
    >>> c = np.tile([1.0, -2.0], nodes.n)         # u = (1, -2) everywhere
    >>> bool(np.allclose(ps.displacement(c), [1.0, -2.0])), ps.n_chunks
    (True, 4)
    """

    approx: Approximation
    x: np.ndarray
    chunk_points: int | None = None

    def __post_init__(self):
        if self.chunk_points is None:
            object.__setattr__(self, "chunk_points", CHUNK_POINTS)
        if not isinstance(self.chunk_points, (int, np.integer)) or self.chunk_points < 1:
            raise ValueError(f"chunk_points must be a positive integer, got {self.chunk_points!r}")

    @property
    def n_points(self) -> int:
        return len(self.x)

    @property
    def n_functions(self) -> int:
        """Number of nodal shape functions."""
        return self.approx.nodes.n

    @property
    def n_dofs(self) -> int:
        """Length of a coefficient vector: 2 per node plus the enrichment unknowns."""
        return self.approx.n_dofs

    @property
    def shape(self) -> tuple[int, int]:
        return (self.n_points, self.n_functions)

    @property
    def n_chunks(self) -> int:
        return -(-self.n_points // self.chunk_points)

    def bounds(self, n: int | None = None) -> list[tuple[int, int]]:
        """``(start, stop)`` of the chunks of ``n`` rows (default: all points): as few as
        hold at most ``chunk_points`` each, of equal sizes (no small last chunk, which would
        take other kernels than the rest)."""
        n = self.n_points if n is None else n
        edges = np.linspace(0, n, -(-n // self.chunk_points) + 1).round().astype(np.int64)
        return [(int(s), int(e)) for s, e in zip(edges[:-1], edges[1:], strict=True)]

    def chunk(self, start: int, stop: int, derivatives: bool = True, clock=None,
              rows: np.ndarray | None = None) -> Shape:
        """The shape functions (and enrichment operators) at the points ``start:stop``
        (of ``x[rows]`` when ``rows`` is given), a :class:`Shape` of ``stop - start`` rows.
        ``clock`` (a :class:`~efgkit.timing.Stopwatch`) gets the laps "search" and "shape"."""
        x = self.x[start:stop] if rows is None else self.x[rows[start:stop]]
        boxes = self.approx.boxes  # the search of all points at once (not a chunk's own choice)
        method = boxes.kind if self.n_points >= COMPILED_MIN else "auto"
        nb = find_neighbours(x, self.approx.nodes, boxes, method=method)
        if clock is not None:
            clock.lap("search")
        sh = self.approx.shape(x, derivatives=derivatives, neighbours=nb)
        if clock is not None:
            clock.lap("shape")
        return sh

    def _rows(self, rows) -> tuple[np.ndarray | None, int]:
        if rows is None:
            return None, self.n_points
        rows = np.asarray(rows)
        if rows.dtype == bool:
            if rows.shape != (self.n_points,):
                raise ValueError(f"rows as a mask must have shape ({self.n_points},), got {rows.shape}")
            rows = np.flatnonzero(rows)
        elif rows.ndim != 1 or not np.issubdtype(rows.dtype, np.integer):
            raise ValueError(f"rows must be point indices (m,) or a mask, got {rows.dtype} {rows.shape}")
        elif len(rows) and (rows.min() < -self.n_points or rows.max() >= self.n_points):
            raise ValueError(f"rows must lie in [0, {self.n_points}), got {rows.min()} to {rows.max()}")
        return rows, len(rows)

    def _check(self, coeffs) -> np.ndarray:
        c = np.asarray(coeffs, dtype=float)
        if c.shape != (self.n_dofs,):
            raise ValueError(f"coeffs must have shape ({self.n_dofs},), got {c.shape}")
        return c

    def displacement(self, coeffs, rows=None) -> np.ndarray:
        """u at the points (or at ``rows``: indices or a mask) for ``coeffs (n_dofs,)``,
        shape (m, 2); chunk by chunk (values only)."""
        c, (rows, n) = self._check(coeffs), self._rows(rows)
        out = np.empty((n, 2))
        for s, e in self.bounds(n):
            out[s:e] = self.chunk(s, e, derivatives=False, rows=rows).displacement(c)
        return out

    def gradient(self, coeffs, rows=None) -> np.ndarray:
        """du_i/dx_j at the points (or at ``rows``), shape (m, 2, 2); chunk by chunk."""
        c, (rows, n) = self._check(coeffs), self._rows(rows)
        out = np.empty((n, 2, 2))
        for s, e in self.bounds(n):
            out[s:e] = self.chunk(s, e, rows=rows).gradient(c)
        return out

    def strain(self, coeffs, rows=None) -> np.ndarray:
        """Strain (xx, yy, xy engineering) at the points (or at ``rows``), shape (m, 3)."""
        return strain_from_gradient(self.gradient(coeffs, rows))
