"""Quadrature rules and the point sets they produce.

:class:`Points` holds quadrature or evaluation points of every kind (area
cells, boundary lines, and later the local sub-domains of MLPG); the Gauss rules
on the line and the triangle are the building blocks of every rule in this
package. The argument checks are shared by the rule builders.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.special import roots_jacobi

__all__ = ["Points", "check_count", "check_length", "gauss_legendre", "triangle_rule"]


@dataclass(frozen=True, eq=False)
class Points:
    """Quadrature or evaluation points.

    Attributes
    ----------
    x : ndarray, shape (n, 2)
    w : ndarray, shape (n,)
        Weights: areas for domain rules, lengths for boundary rules.
    owner : ndarray, shape (n,), int, or None
        Cell, triangle, edge or node each point belongs to.
    normal : ndarray, shape (n, 2), or None
        Outward unit normals of boundary points.

    Examples
    --------
    >>> a = Points(np.zeros((2, 2)), np.ones(2), owner=np.array([0, 1]))
    >>> b = a + a
    >>> b.n, b.owner.tolist(), b.normal is None
    (4, [0, 1, 0, 1], True)
    """

    x: np.ndarray
    w: np.ndarray
    owner: np.ndarray | None = None
    normal: np.ndarray | None = None

    def __post_init__(self):
        x = np.asarray(self.x, dtype=float)
        n = len(x) if x.ndim else -1
        for name, shape, kind in [("x", (n, 2), "f"), ("w", (n,), "f"), ("owner", (n,), "i"),
                                  ("normal", (n, 2), "f")]:
            if getattr(self, name) is None:
                continue
            v = np.asarray(getattr(self, name))
            if v.shape != shape or (v.size and v.dtype.kind not in "iu" + "f" * (kind == "f")):
                raise ValueError(f"Points.{name} must be {'integers' if kind == 'i' else 'reals'}"
                                 f" of shape {shape}, got {v.dtype} array of shape {v.shape}")
            # no copy when the dtype is already right (x, w, owner: 93 MB at 2.9M points, mostly page
            # faults of fresh memory: 0.19 s of the quadrature stage's 0.4 s at 97k nodes)
            object.__setattr__(self, name, v.astype(np.int64 if kind == "i" else float, copy=False))

    @property
    def n(self) -> int:
        return len(self.x)

    @classmethod
    def concatenate(cls, *points: Points) -> Points:
        """Join rules; ``owner``/``normal`` are kept (unchanged) only if all parts have them."""
        if not points:
            raise ValueError("Points.concatenate needs at least one Points")

        def join(name):
            parts = [getattr(p, name) for p in points]
            return None if any(v is None for v in parts) else np.concatenate(parts)

        return cls(np.concatenate([p.x for p in points]), np.concatenate([p.w for p in points]),
                   join("owner"), join("normal"))

    def sorted_by(self, key) -> Points:
        """These points in the stable order of ``key(x) (n,)``, every attribute alike.

        Examples
        --------
        >>> Points(np.array([[2., 0], [1, 0], [2, 1]]), np.arange(3.)).sorted_by(lambda x: x[:, 0]).w
        array([1., 0., 2.])
        """
        order = np.argsort(key(self.x), kind="stable")
        return Points(self.x[order], self.w[order], *(None if v is None else v[order]
                                                      for v in (self.owner, self.normal)))

    def __add__(self, other: Points) -> Points:
        if not isinstance(other, Points):
            return NotImplemented
        return Points.concatenate(self, other)


def check_count(name, v, low=1):
    """Raise unless ``v`` is an integer >= ``low`` (TypeError / ValueError naming ``name``)."""
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {v!r}")
    if v < low:
        raise ValueError(f"{name} must be >= {low}, got {v!r}")


def check_length(name, v):
    """Raise unless ``v`` is a finite real > 0 (TypeError / ValueError naming ``name``)."""
    if isinstance(v, bool) or not isinstance(v, (int, float, np.number)):
        raise TypeError(f"{name} must be a real number, got {v!r}")
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be finite and > 0, got {v!r}")


def gauss_legendre(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre rule on [-1, 1], exact for polynomials of degree 2 order - 1.

    Returns
    -------
    xi : ndarray, shape (order,)
    w : ndarray, shape (order,), summing to 2

    Examples
    --------
    >>> xi, w = gauss_legendre(3)
    >>> round(float(w.sum()), 14), round(float(w @ xi**4), 14)  # 2 and 2/5
    (2.0, 0.4)
    """
    check_count("order", order)
    xi, w = _leggauss(int(order))
    return xi.copy(), w.copy()


@functools.lru_cache(maxsize=64)
def _leggauss(order):
    """numpy's Gauss-Legendre rule (an eigenvalue problem), computed once per order: the
    rules of a small run cost more than its MLS kernel (docs/performance.md,
    work_interleaved)."""
    return np.polynomial.legendre.leggauss(order)


def triangle_rule(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Collapsed (Duffy) Gauss rule on the reference triangle (0,0), (1,0), (0,1).

    The square [0, 1]^2 is mapped by ``x = u, y = v (1 - u)``, with Jacobian
    ``1 - u``: ``m = ceil((degree + 1) / 2)`` Gauss-Jacobi (alpha=1, beta=0)
    points in u absorb the Jacobian and m Gauss-Legendre points in v, so the
    rule is exact for total degree ``degree``; all weights are positive and
    all points strictly inside.

    Returns
    -------
    bary : ndarray, shape (m*m, 3)
        Barycentric coordinates ``(1 - x - y, x, y)``.
    w : ndarray, shape (m*m,)
        Weights, summing to 1/2 (the reference area).

    Examples
    --------
    >>> bary, w = triangle_rule(5)
    >>> bary.shape, round(float(w.sum()), 15)
    ((9, 3), 0.5)
    >>> round(float(w @ (bary[:, 1]**2 * bary[:, 2]**3)), 15) == round(2 * 6 / 5040, 15)
    True
    """
    check_count("degree", degree, low=0)
    bary, w = _triangle_rule(max(1, math.ceil((degree + 1) / 2)))
    return bary.copy(), w.copy()


@functools.lru_cache(maxsize=64)
def _triangle_rule(m):
    """:func:`triangle_rule` with ``m`` points per direction, computed once per ``m``."""
    a, wa = roots_jacobi(m, 1.0, 0.0)  # weight (1 - a) on [-1, 1]
    b, wb = _leggauss(m)
    u, v = np.meshgrid((1 + a) / 2, (1 + b) / 2, indexing="ij")
    x, y = u.ravel(), (v * (1 - u)).ravel()
    return np.column_stack([1 - x - y, x, y]), np.outer(wa / 4, wb / 2).ravel()
