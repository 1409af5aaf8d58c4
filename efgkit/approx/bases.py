"""Polynomial MLS bases in shifted and scaled coordinates.

The basis of a point x is evaluated at ``xi = (x_I - xbar) / scale`` with the
centre ``xbar`` held fixed at the evaluation point and ``scale`` its support
size: the moment matrix then has O(1) entries whatever the units or the
coordinate offset, and shape functions are unchanged (an MLS approximation
does not depend on the basis of the polynomial space it spans).
"""

from __future__ import annotations

import numpy as np

__all__ = ["BASES", "basis", "basis_size", "basis_origin_gradient"]

BASES = {"linear": 3, "quadratic": 6}


def basis_size(name: str) -> int:
    """Number of terms m: 3 (linear, seed 003 Eq. 5c) or 6 (quadratic, Eq. 5d)."""
    try:
        return BASES[name]
    except KeyError:
        raise ValueError(f"basis must be one of {tuple(BASES)}, got {name!r}") from None


def basis(name: str, xi: np.ndarray) -> np.ndarray:
    """p(xi) for ``xi (..., 2)``, shape (..., m).

    Examples
    --------
    >>> basis("quadratic", np.array([[2.0, 3.0]])).tolist()
    [[1.0, 2.0, 3.0, 4.0, 6.0, 9.0]]
    """
    x, y = xi[..., 0], xi[..., 1]
    one = np.ones_like(x)
    if name == "linear":
        return np.stack([one, x, y], axis=-1)
    if name == "quadratic":
        return np.stack([one, x, y, x * x, x * y, y * y], axis=-1)
    raise ValueError(f"basis must be one of {tuple(BASES)}, got {name!r}")


def basis_origin_gradient(name: str) -> np.ndarray:
    """d p / d xi at xi = 0, shape (2, m): rows d/dxi, d/deta (unit vectors e_1, e_2)."""
    g = np.zeros((2, basis_size(name)))
    g[0, 1] = g[1, 2] = 1.0
    return g
