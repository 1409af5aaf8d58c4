"""One boundary edge of a :class:`~efgkit.problem.geometry.Loop`: a straight segment or a
circular arc, with points and tangents at a parameter ``s`` in [0, 1], the inverse, and
its polyline. Re-exported by :mod:`efgkit.problem.geometry`."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Edge"]

_ARC_STEP = 2 * math.pi / 720  # polyline resolution of arcs: sag 1e-5 R


@dataclass(frozen=True)
class Edge:
    """One boundary edge: straight (``sweep == 0``) or a circular arc.

    Attributes
    ----------
    name : str
    start, end : ndarray, shape (2,)
    centre : ndarray, shape (2,) (NaN for straight edges)
    sweep : float, signed angle of the arc in radians (0 for straight edges)
    """

    name: str
    start: np.ndarray
    end: np.ndarray
    centre: np.ndarray
    sweep: float

    @property
    def is_arc(self) -> bool:
        return self.sweep != 0.0

    @property
    def length(self) -> float:
        if self.is_arc:
            return abs(self.sweep) * float(np.linalg.norm(self.start - self.centre))
        return float(np.linalg.norm(self.end - self.start))

    def at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points and unit tangents at parameters ``s`` in [0, 1].

        Returns ``x (n, 2)`` and ``t (n, 2)``; ``|dx/ds| = length``.
        """
        s = np.asarray(s, dtype=float)
        if not self.is_arc:
            x = self.start + s[:, None] * (self.end - self.start)
            t = np.broadcast_to((self.end - self.start) / self.length, x.shape)
            return x, np.array(t)
        d = self.start - self.centre
        R = math.hypot(*d)
        ang = math.atan2(d[1], d[0]) + s * self.sweep
        x = self.centre + R * np.column_stack([np.cos(ang), np.sin(ang)])
        sgn = math.copysign(1.0, self.sweep)
        t = sgn * np.column_stack([-np.sin(ang), np.cos(ang)])
        return x, t

    def parameter(self, x: np.ndarray) -> np.ndarray:
        """Parameter s in [0, 1] of points ``x (n, 2)`` on or near the edge, shape (n,): the
        projection, clipped to the ends (on an arc, by angle: a point outside the swept
        angle may clip to either end; callers check the distance)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        if not self.is_arc:
            d = self.end - self.start
            return np.clip((x - self.start) @ d / (d @ d), 0.0, 1.0)
        a0 = math.atan2(*(self.start - self.centre)[::-1])
        ang = np.arctan2(x[:, 1] - self.centre[1], x[:, 0] - self.centre[0]) - a0
        turn = math.copysign(2 * math.pi, self.sweep)
        return np.clip(np.mod(ang, turn) / self.sweep, 0.0, 1.0)

    def polyline(self) -> np.ndarray:
        """Vertices of the edge as a polyline, shape (m + 1, 2), start and end included."""
        if not self.is_arc:
            return np.array([self.start, self.end])
        m = max(2, math.ceil(abs(self.sweep) / _ARC_STEP))
        x, _ = self.at(np.linspace(0.0, 1.0, m + 1))
        x[0], x[-1] = self.start, self.end  # exact end points
        return x
