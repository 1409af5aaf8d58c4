"""MLPG1 test functions: the quartic spline of seed 002 Eq. (8) on every node's disc.

The test function of node I is v_I(x) = w(|x - x_I| / r_sI) with the quartic spline
w(s) = 1 - 6 s^2 + 8 s^3 - 3 s^4 (s <= 1), which vanishes with zero slope on the disc
circle L_s (seed 002 Eqs. 8, 20-21). At the quadrature points of node I's disc only v_I
is used (each point belongs to one node's local weak form), so the test operator has one
non-zero per point: its owner.
"""

from __future__ import annotations

import numpy as np

from ..search import Neighbours
from .shape import Shape
from .weights import quartic

__all__ = ["disc_test_functions"]


def disc_test_functions(x: np.ndarray, owner: np.ndarray, centres: np.ndarray,
                        radii: np.ndarray, derivatives: bool = True) -> Shape:
    """Test functions v_owner at points ``x (n, 2)``, as a :class:`Shape` with one column each.

    Parameters
    ----------
    x : ndarray (n, 2)
    owner : ndarray (n,) int
        The node whose local weak form each point integrates.
    centres : ndarray (n_nodes, 2); radii : ndarray (n_nodes,)
        Disc centres (the nodes) and test radii r_sI.
    derivatives : bool
        Also dv/dx = w'(s) (x - x_I) / (s r_sI^2) = g(s) (x - x_I) / r_sI^2.

    Examples
    --------
    >>> v = disc_test_functions(np.array([[0.5, 0.0]]), np.array([0]), np.zeros((1, 2)), np.ones(1))
    >>> float(v.values[0, 0]), float(v.ddx[0, 0])   # w(1/2) = 5/16, w'(1/2) = -3/2
    (0.3125, -1.5)
    """
    x = np.asarray(x, dtype=float)
    owner = np.asarray(owner, dtype=np.int64)
    if x.ndim != 2 or x.shape[1] != 2 or owner.shape != (len(x),):
        raise ValueError(f"x must have shape (n, 2) and owner (n,), got {x.shape} and {owner.shape}")
    d = x - centres[owner]
    r = radii[owner]
    w, g = quartic(np.hypot(*d.T) / r)
    nb = Neighbours(owner[:, None], np.ones((len(x), 1), bool))
    if not derivatives:
        return Shape(nb, w[:, None], None, None, len(centres))
    grad = (g / r**2)[:, None] * d
    return Shape(nb, w[:, None], grad[:, :1].copy(), grad[:, 1:].copy(), len(centres))
