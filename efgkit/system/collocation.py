"""Collocation of essential conditions: equations replaced by constraint rows.

``collocation(K, f, rows, values, dofs)`` replaces the equations ``dofs`` of ``K c = f``
by the constraint rows ``rows @ c = values`` (e.g. u^h_c(x_I) = ubar_c(x_I) at the
essential-boundary nodes I, for MLPG the rows of the nodes' own local weak forms). The
shape functions stay the plain (continuous) MLS ones, so the method passes the patch test
wherever the weak form does.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array, diags_array

from .constraints import LinearSystem

__all__ = ["collocation"]


def collocation(K, f, rows, values, dofs) -> LinearSystem:
    """Replace equations ``dofs (k,)`` of ``K c = f`` by ``rows (k, n) @ c = values (k,)``.

    The constraint rows are scaled to the size of K's entries (as the multiplier rows of
    :func:`~efgkit.system.constraints.lagrange`), so that the residual check weighs them
    like the other equations. The result is unsymmetric (``spd=False``).

    Examples
    --------
    >>> K = csr_array(np.array([[2.0, -1.0], [-1.0, 2.0]]))
    >>> sys = collocation(K, np.array([0.0, 1.0]), csr_array(np.array([[1.0, 0.0]])), [0.5], [0])
    >>> np.linalg.solve(sys.A.toarray(), sys.b).tolist()
    [0.5, 0.75]
    """
    K = csr_array(K)
    n = K.shape[0]
    f = np.asarray(f, dtype=float)
    rows = csr_array(rows)
    values = np.asarray(values, dtype=float).reshape(-1)
    dofs = np.asarray(dofs, dtype=np.int64).reshape(-1)
    if K.shape != (n, n) or f.shape != (n,):
        raise ValueError(f"K must be square and f match it, got {K.shape} and {f.shape}")
    if rows.shape != (len(dofs), n) or values.shape != (len(dofs),):
        raise ValueError(f"rows must have shape (len(dofs), n) = ({len(dofs)}, {n}) and values "
                         f"({len(dofs)},), got {rows.shape} and {values.shape}")
    if len(np.unique(dofs)) != len(dofs) or (len(dofs) and (dofs.min() < 0 or dofs.max() >= n)):
        raise ValueError(f"dofs must be distinct equation numbers in [0, {n}), got {dofs.tolist()[:10]}")
    scale = abs(K).max() / max(abs(rows).max(), np.finfo(float).tiny) if len(dofs) else 1.0
    keep = np.ones(n)
    keep[dofs] = 0.0
    sel = csr_array((np.ones(len(dofs)), (dofs, np.arange(len(dofs)))), shape=(n, len(dofs)))
    A = csr_array(diags_array(keep) @ K + sel @ (scale * rows))
    b = keep * f
    b[dofs] = scale * values
    A.eliminate_zeros()
    return LinearSystem(A, b, spd=False, n_coeffs=n)
