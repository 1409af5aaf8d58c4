"""Which points the crack tests need to look at: a bounding-box prefilter.

A crack rule can change the weight of a pair (x, x_I) only when the support of I, of
radius d_mI <= max d_mI, reaches a crack. The points farther than max d_mI from the
bounding box of every run of crack segments (:meth:`CrackLines.chunks`) are left out of
the distance and crossing tests, which then cost in proportion to the points near a
crack, not to all points.
"""

from __future__ import annotations

import numpy as np

from .crack_rules import CrackLines

__all__ = ["points_near"]


def points_near(lines: CrackLines, x: np.ndarray, radius: float) -> np.ndarray:
    """Indices of the points of ``x (n, 2)`` closer than ``radius`` to the bounding box of
    some run of crack segments, shape (m,) ascending: a superset of the points closer than
    ``radius`` to a crack.

    Examples
    --------
    >>> from efgkit import Crack
    >>> lines = CrackLines.from_cracks((Crack([[0.0, 0.0], [1.0, 0.0]]),))
    >>> points_near(lines, np.array([[0.5, 0.1], [0.5, 0.5], [1.05, 0.0]]), 0.2).tolist()
    [0, 2]
    """
    x = np.asarray(x, dtype=float).reshape(-1, 2)
    runs = lines.chunks()
    lo = np.min([b[1] for b in runs], axis=0) - radius  # all runs first: one cheap test
    hi = np.max([b[2] for b in runs], axis=0) + radius
    # column by column: numpy's reductions along the short axis of (n, 2) are 10x slower
    x0, x1 = x[:, 0], x[:, 1]
    if len(x) == 0 or x0.min() >= hi[0] or x0.max() <= lo[0] or x1.min() >= hi[1] \
            or x1.max() <= lo[1]:
        return np.zeros(0, np.int64)  # a chunk of points away from every crack
    pts = np.flatnonzero((x0 > lo[0]) & (x0 < hi[0]) & (x1 > lo[1]) & (x1 < hi[1]))
    near = np.zeros(len(pts), bool)
    for _, a, b in runs:  # about sqrt(segments) runs
        gap = np.maximum(np.maximum(a - x[pts], x[pts] - b), 0.0)
        near |= np.hypot(*gap.T) < radius
    return pts[near]
