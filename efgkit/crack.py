"""Crack polylines (the scene schema; crack rules and enrichment build on it)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Crack"]


@dataclass(frozen=True)
class Crack:
    """A crack as a polyline of ``vertices (n >= 2, 2)``.

    Each end not lying on the domain boundary is a tip; ``tips`` says which of
    the two ends are tips (``(False, True)``: an edge crack growing from the
    first vertex).
    """

    vertices: np.ndarray
    tips: tuple[bool, bool] = (True, True)
    name: str = "crack"

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 2:
            raise ValueError(f"crack {self.name!r}: vertices must have shape (n >= 2, 2), got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError(f"crack {self.name!r}: vertices must be finite (no NaN or inf)")
        seg = np.linalg.norm(np.diff(v, axis=0), axis=1)
        if np.any(seg == 0):
            k = int(np.argmin(seg))
            raise ValueError(
                f"crack {self.name!r}: zero-length segment between vertices {k} and {k + 1} "
                "(duplicate vertex); remove it"
            )
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "tips", tuple(bool(t) for t in self.tips))

    @property
    def segments(self) -> np.ndarray:
        """Segments, shape (n - 1, 2, 2)."""
        return np.stack([self.vertices[:-1], self.vertices[1:]], axis=1)
