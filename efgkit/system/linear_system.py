"""The linear system the essential boundary conditions make of ``K c = f``
(:mod:`efgkit.system.constraints`), and a Lagrange saddle point held as its blocks.

The saddle point ``[[K, G^T], [G, 0]]`` of the Lagrange multipliers (seed 003 Eq. 26) is a
copy of K plus the small G blocks. Its iterative solve (the Uzawa steps of
:func:`efgkit.system.linalg.solve`) needs K and G alone, and its residual is a product by
blocks, so :class:`LinearSystem` holds the blocks and forms the matrix only if something asks
for ``A`` (a direct solve, a half model's reduction): at 1e5 nodes of the cracked plate that
copy was 218 MB and 0.13-0.5 s of the constraints stage (docs/performance.md, stage_slopes_notes).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.sparse import bmat, csr_array

__all__ = ["LinearSystem", "saddle_matrix"]


@dataclass(frozen=True, eq=False)
class LinearSystem:
    """``A z = b`` and how to get the MLS coefficients back from ``z``.

    Attributes
    ----------
    matrix : csr_array (n, n) or None
        A as given; None for a saddle point held as its ``blocks``.
    b : (n,)
    spd : bool
        Symmetric positive definite (eligible for AMG + CG).
    n_coeffs : int
        Number of MLS coefficients, n_dofs (2 n_functions and any enrichment unknowns).
    free : (n_free,) int or None
        With elimination, the coefficient indices ``z`` stands for.
    fixed_values : (n_dofs,) or None
        With elimination, the prescribed coefficients.
    support_forces : callable or None
        ``z -> (x (m, 2), force (m, 2))``: the forces the essential conditions apply to
        the body, at the points where they act, from the weak form (docs/theory.md,
        "Reactions"); contracted with a rigid-body motion they balance the load vector.
    blocks : (K (n_coeffs, n_coeffs), G (m, n_coeffs)) or None
        The blocks of the saddle point ``[[K, G^T], [G, 0]]`` (n = n_coeffs + m).

    Examples
    --------
    >>> K, G = csr_array(np.diag([2.0, 4.0])), csr_array(np.array([[1.0, 0.0]]))
    >>> s = LinearSystem(None, np.array([0.0, 4.0, 1.0]), False, 2, blocks=(K, G))
    >>> s.product(np.array([1.0, 1.0, -2.0])).tolist(), s.A.toarray().tolist()
    ([0.0, 4.0, 1.0], [[2.0, 0.0, 1.0], [0.0, 4.0, 0.0], [1.0, 0.0, 0.0]])
    """

    matrix: csr_array | None
    b: np.ndarray
    spd: bool
    n_coeffs: int
    free: np.ndarray | None = None
    fixed_values: np.ndarray | None = None
    support_forces: Callable | None = None
    blocks: tuple[csr_array, csr_array] | None = None

    def __post_init__(self):
        if self.matrix is None and self.blocks is None:
            raise ValueError("LinearSystem needs a matrix or the blocks (K, G) of a saddle point")

    @property
    def size(self) -> int:
        """n, the number of unknowns of ``z``."""
        return len(self.b)

    @cached_property
    def A(self) -> csr_array:
        """The matrix (n, n), formed from ``blocks`` on first use when ``matrix`` is None."""
        return self.matrix if self.matrix is not None else saddle_matrix(*self.blocks)

    def product(self, z: np.ndarray) -> np.ndarray:
        """``A z`` (n,), by blocks for a saddle point held as its blocks."""
        if self.blocks is None:
            return self.matrix @ z
        K, G = self.blocks
        c, lam = z[: self.n_coeffs], z[self.n_coeffs:]
        return np.concatenate([K @ c + G.T @ lam, G @ c])

    def coefficients(self, z: np.ndarray) -> np.ndarray:
        """MLS coefficients ``(n_dofs,)`` from the solution ``z``."""
        if self.free is None:
            return z[: self.n_coeffs]
        c = self.fixed_values.copy()
        c[self.free] = z
        return c


def saddle_matrix(K, G) -> csr_array:
    """``[[K, G^T], [G, 0]]`` (n + m, n + m) of ``K (n, n)`` and ``G (m, n)``: K padded to the
    saddle point's size (sharing its arrays) plus the G blocks, one copy of K (not bmat's COO of
    it: 36 instead of 12 bytes per non-zero at once, 0.7 GB at 1e5 nodes)."""
    m, K = G.shape[0], csr_array(K)
    pad = np.concatenate([K.indptr, np.full(m, K.indptr[-1], K.indptr.dtype)])
    C = csr_array(bmat([[None, G.T], [G, None]], format="csr"))
    if K.nnz + C.nnz < 2**31:  # int32 G blocks: an int64 operand would widen the sum's indices
        C = csr_array((C.data, C.indices.astype(np.int32), C.indptr.astype(np.int32)), shape=C.shape)
    return csr_array(csr_array((K.data, K.indices, pad), shape=(K.shape[0] + m,) * 2) + C)
