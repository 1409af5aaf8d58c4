"""All crack segments of a scene as arrays, for the sight tests of the crack rules
(:mod:`efgkit.approx.crack_rules`): segment ends, arc lengths, tips, and runs of segments
with their bounding boxes for the prefilters."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CrackLines"]


@dataclass(frozen=True, eq=False)
class CrackLines:
    """All crack segments of a scene as arrays (segment index = global order).

    Attributes
    ----------
    a, b : ndarray (m, 2)
        Segment ends, in polyline order.
    crack : ndarray (m,) int
        Crack of each segment (cracks in scene order, so ``crack`` is sorted).
    start, length : ndarray (m,)
        Arc length of ``a`` from the crack's first vertex, and segment length.
    ends : ndarray (n_cracks, 2, 2)
        First and last vertex of every crack.
    is_tip : ndarray (n_cracks, 2) bool
        Which of those ends are tips.
    total : ndarray (n_cracks,)
        Crack lengths.
    """

    a: np.ndarray
    b: np.ndarray
    crack: np.ndarray
    start: np.ndarray
    length: np.ndarray
    ends: np.ndarray
    is_tip: np.ndarray
    total: np.ndarray

    @classmethod
    def from_cracks(cls, cracks) -> CrackLines:
        seg = [c.segments for c in cracks]
        ln = [np.linalg.norm(s[:, 1] - s[:, 0], axis=1) for s in seg]
        return cls(np.concatenate([s[:, 0] for s in seg]), np.concatenate([s[:, 1] for s in seg]),
                   np.concatenate([np.full(len(s), k) for k, s in enumerate(seg)]),
                   np.concatenate([np.cumsum(v) - v for v in ln]), np.concatenate(ln),
                   np.array([[c.vertices[0], c.vertices[-1]] for c in cracks]),
                   np.array([c.tips for c in cracks], bool), np.array([v.sum() for v in ln]))

    @property
    def n(self) -> int:
        return len(self.a)

    def chunks(self) -> list[tuple[slice, np.ndarray, np.ndarray]]:
        """About sqrt(m) runs of consecutive segments with their bounding boxes: (segments,
        lower corner (2,), upper corner (2,)) each; the prefilters of the crossing and distance
        tests, so that their cost grows with the segments near a point, not with all m."""
        lo, hi = np.minimum(self.a, self.b), np.maximum(self.a, self.b)
        size = max(1, round(np.sqrt(self.n)))
        return [(slice(k, k + size), lo[k:k + size].min(axis=0), hi[k:k + size].max(axis=0))
                for k in range(0, self.n, size)]

    def distance(self, x: np.ndarray) -> np.ndarray:
        """Distance of points ``x (n, 2)`` to the nearest crack segment, shape (n,).

        A run of segments (:meth:`chunks`) is measured only for the points whose distance to
        its box does not exceed the farthest-corner distance of the nearest box (an upper
        bound of the answer)."""
        x = np.asarray(x, dtype=float).reshape(-1, 2)
        out = np.full(len(x), np.inf)
        runs = self.chunks()
        near = np.stack([np.hypot(*np.maximum(np.maximum(lo - x, x - hi), 0.0).T) for _, lo, hi in runs])
        far = np.stack([np.hypot(*np.maximum(np.abs(x - lo), np.abs(x - hi)).T) for _, lo, hi in runs])
        bound = far.min(axis=0)
        for (segs, _, _), lb in zip(runs, near, strict=True):
            pts = np.flatnonzero(lb <= bound)
            for a, b in zip(self.a[segs], self.b[segs], strict=True):
                ab, xp = b - a, x[pts]
                t = np.clip((xp - a) @ ab / (ab @ ab), 0.0, 1.0)
                out[pts] = np.minimum(out[pts], np.hypot(*(xp - a - t[:, None] * ab).T))
        return out

    def tip_positions(self) -> np.ndarray:
        """Positions of all tips, shape (n_tips, 2)."""
        return self.ends[self.is_tip]
