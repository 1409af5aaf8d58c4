"""A background-cell rule held per cell; its points written once, in the order asked for.

Most points of :func:`efgkit.quadrature.cells.cell_points` lie in whole cells: a corner
plus the offsets of the cell's tensor Gauss rule. :class:`CellRule` keeps them so (a corner
and an owner per cell, the offsets and weights once per rule) beside the points listed one
by one (cut-cell triangles, tip fans): 3.5 MB for the 2.9M points of the cracked plate at
97k nodes. :meth:`CellRule.sorted_by` writes the points in the stable order of a key of
their positions, the box order of the search, without first writing all of them in cell
order and then gathering them (93 MB written twice at 97k nodes, most of it the page faults
of fresh memory: docs/performance.md, stage_slopes_notes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..jit import COMPILED_MIN
from ..memory import fresh_array
from .rules import Points

__all__ = ["CellRule"]

# points per block when the keys are taken a block at a time (at least COMPILED_MIN, so the
# key functions run their compiled loops on all blocks but the last)
KEY_BLOCK = 2**17


@dataclass(frozen=True, eq=False)
class CellRule:
    """Points of whole cells as corner + offset, the rest listed, numbered segment by segment.

    Attributes
    ----------
    start : ndarray, shape (s + 1,), int
        First point of each segment; ``start[-1]`` is the number of points ``n``.
    first : ndarray, shape (s,), int
        First cell (whole segments) or listed row (listed segments) of each segment.
    rule : ndarray, shape (s,), int
        Tensor rule of each whole segment; -1 for listed segments.
    q : ndarray, shape (r,), int
        Points per cell of each rule.
    corner : ndarray, shape (f, 2)
        Lower-left corners of the whole cells.
    cell : ndarray, shape (f,), int
        Owner of the points of each whole cell.
    offsets : ndarray, shape (r, max q, 2)
        Points of each rule relative to the corner (rows past ``q[r]`` unused).
    weights : ndarray, shape (r, max q)
    listed : Points
        The other points, with their owners.

    Examples
    --------
    >>> from efgkit.quadrature.cells import cell_rule
    >>> from efgkit.problem.geometry import Domain, Loop
    >>> dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)])
    >>> rule = cell_rule(dom, 0.1, 3)
    >>> pts = rule.sorted_by(lambda x: np.floor(4 * x[:, 0]))  # by vertical bands
    >>> bool(np.all(np.diff(np.floor(4 * pts.x[:, 0])) >= 0)), pts.n == rule.n
    (True, True)
    """

    start: np.ndarray
    first: np.ndarray
    rule: np.ndarray
    q: np.ndarray
    corner: np.ndarray
    cell: np.ndarray
    offsets: np.ndarray
    weights: np.ndarray
    listed: Points

    @classmethod
    def from_parts(cls, parts, n_cells: int) -> CellRule:
        """The rule of ``parts`` in order: whole cells ``(corners (f, 2), offsets (q, 2),
        weights (q,), owner (f,))`` or listed points ``(x, w, owner)``, owners in
        ``0 .. n_cells - 1``, renumbered over the cells that hold points."""
        whole, listed, segments, offsets, weights = [], [], [], [], []
        n_whole = n_listed = n = 0
        for part in parts:
            if len(part) == 4:
                corners, off, wt, ids = part
                m = len(corners) * len(off)
                if m:
                    segments.append((n, n_whole, len(offsets)))
                    whole.append((corners, ids))
                    offsets.append(off)
                    weights.append(wt)
                    n_whole += len(corners)
            else:
                m = len(part[0])
                if m:
                    segments.append((n, n_listed, -1))
                    listed.append(part)
                    n_listed += m
            n += m
        q = np.array([len(o) for o in offsets], np.int64)
        off_table = np.zeros((len(q), max(q, default=0), 2))
        w_table = np.zeros((len(q), max(q, default=0)))
        for r, (o, wt) in enumerate(zip(offsets, weights, strict=True)):
            off_table[r, : q[r]], w_table[r, : q[r]] = o, wt
        corner = np.concatenate([c for c, _ in whole]) if whole else np.zeros((0, 2))
        cell = np.concatenate([i for _, i in whole]) if whole else np.zeros(0, np.int64)
        lx, lw, lo = ((np.concatenate([p[k] for p in listed]) for k in range(3)) if listed else
                      (np.zeros((0, 2)), np.zeros(0), np.zeros(0, np.int64)))
        used = np.zeros(n_cells, bool)  # cells numbered over those with points
        used[cell], used[lo] = True, True
        number = np.cumsum(used) - 1
        seg = np.array(segments, np.int64).reshape(-1, 3)
        return cls(np.append(seg[:, 0], n), seg[:, 1], seg[:, 2], q, corner, number[cell],
                   off_table, w_table, Points(lx, lw, number[lo]))

    @property
    def n(self) -> int:
        return int(self.start[-1])

    def points(self) -> Points:
        """All points in their own order: segment by segment, cell by cell."""
        return Points(*self._write(None, 0, self.n)) if self.n >= COMPILED_MIN else self._points_numpy()

    def sorted_by(self, key) -> Points:
        """The points in the stable order of ``key(x (m, 2)) -> (m,)``, a key of each point's
        position alone, as ``points().sorted_by(key)`` gives them, but each written once
        (large rules: the keys taken a block of :data:`KEY_BLOCK` points at a time)."""
        if self.n < COMPILED_MIN:
            return self.points().sorted_by(key)
        keys = np.concatenate([key(self._write(None, s, min(s + KEY_BLOCK, self.n), x_only=True)[0])
                               for s in range(0, self.n, KEY_BLOCK)])
        return Points(*self._write(np.argsort(keys, kind="stable"), 0, self.n))

    def _write(self, order, base: int, end: int, x_only: bool = False):
        """``x, w, owner`` of the points ``order`` (or ``base .. end - 1``), each written once
        into fresh arrays by the compiled loop (``w, owner`` None with ``x_only``)."""
        from .cell_kernels import write_points

        m = end - base if order is None else len(order)
        x = fresh_array((m, 2), float)
        w = None if x_only else fresh_array(m, float)
        owner = None if x_only else fresh_array(m, np.int64)
        unused = np.zeros(0, np.int64)
        write_points(unused if order is None else order, base, self.start, self.first, self.rule,
                     self.q, self.corner, self.cell, self.offsets, self.weights, self.listed.x,
                     self.listed.w, self.listed.owner, x, np.zeros(0) if x_only else w,
                     unused if x_only else owner, x_only)
        return x, w, owner

    def _points_numpy(self) -> Points:
        """:meth:`points` in numpy (small rules: no compilation), segment by segment."""
        x, w, owner = np.empty((self.n, 2)), np.empty(self.n), np.empty(self.n, np.int64)
        for k in range(len(self.first)):
            out, r, f = slice(self.start[k], self.start[k + 1]), self.rule[k], self.first[k]
            if r < 0:
                rows = slice(f, f + out.stop - out.start)
                x[out], w[out], owner[out] = self.listed.x[rows], self.listed.w[rows], self.listed.owner[rows]
                continue
            q = self.q[r]
            cells = slice(f, f + (out.stop - out.start) // q)
            np.add(self.corner[cells, None, :], self.offsets[r, :q], out=x[out].reshape(-1, q, 2))
            w[out].reshape(-1, q)[:] = self.weights[r, :q]
            owner[out].reshape(-1, q)[:] = self.cell[cells, None]
        return Points(x, w, owner)
