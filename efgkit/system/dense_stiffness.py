"""The stiffness of small systems in dense arrays: the nodal block of few functions and the
enrichment blocks of few enrichment unknowns.

At a few hundred unknowns the scipy.sparse products of the reference
(:func:`efgkit.system.assemble.stiffness`, numpy path) cost far more than their arithmetic
(each product or sum of small sparse matrices takes 20-200 microseconds). Here the same sums
run on dense arrays, seed 003 Eq. (22a):

* nodal block, when ``n_points n_test n_trial <= DENSE_WORK``: with the derivative operators
  as dense ``(n_points, n)`` arrays, ``P_de = T_d^T W Phi_e`` (d, e in {x, y}, ``W = diag(w)``)
  and ``K_ab = sum_de D[v(a, d), v(b, e)] P_de`` on the rows 2 I + a and columns 2 J + b
  (v the Voigt row: xx 0, yy 1, xy and yx 2), as the sparse reference combines them;
* enrichment blocks, when ``n_extra <= DENSE_EXTRA`` (two unknowns per tip for the extrinsic
  MLS of seed 003 Eq. 44b): the enrichment's gradient operators as dense
  ``(n_points, n_extra)`` arrays ``E_ab = d u_a / d x_b`` and

      S_i = W sum_j D_ij eps_j(E),           eps(E) = (E_xx, E_yy, E_xy + E_yx),
      K_ne[2 I]     = (dx^T S_xx + dy^T S_xy)_I,
      K_ne[2 I + 1] = (dy^T S_yy + dx^T S_xy)_I,
      K_ee = sum_i eps_i^T S_i,

  ``K_en = K_ne^T`` for a symmetric D (the rows of the unknowns' own stresses, D^T, else).

Both are used on the numpy path only (fewer than :data:`efgkit.jit.COMPILED_MIN` points);
they give the reference's matrices to rounding (sums in another order), without the entries
that are exactly zero (as the sparse products drop them).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array

from ..approx.shape import Shape

__all__ = ["DENSE_EXTRA", "DENSE_WORK", "dense_enrichment_blocks", "dense_nodal_stiffness"]

DENSE_EXTRA = 16  # at most this many enrichment unknowns take the dense blocks (8 tips)
DENSE_WORK = 1_000_000  # n_points n_test n_trial up to which the nodal block is dense

_VOIGT = {(0, 0): 0, (1, 1): 1, (0, 1): 2, (1, 0): 2}  # (component, derivative) -> Voigt row


def dense_nodal_stiffness(test: Shape, trial: Shape, w: np.ndarray, D: np.ndarray) -> csr_array:
    """The nodal stiffness, csr_array (2 n_test, 2 n_trial), from dense derivative arrays
    (module docstring); ``test``, ``trial`` without enrichment, sharing the points.

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic
    >>> from efgkit.nodes import generate_nodes
    >>> from efgkit.approx.mls import mls_shape
    >>> from efgkit.system.assemble import stiffness
    >>> cloud = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    >>> sh = mls_shape(np.random.default_rng(0).random((200, 2)), cloud)
    >>> K = dense_nodal_stiffness(sh, sh, np.full(200, 1 / 200), Elastic(1.0, 0.3).D)
    >>> ref = stiffness(sh, np.full(200, 1 / 200), Elastic(1.0, 0.3).D, backend="numba")
    >>> bool(abs(K - ref).max() < 1e-14 * abs(ref).max())
    True
    """
    T = [test.dx.toarray(), test.dy.toarray()]
    Phi = [w[:, None] * op.toarray() for op in (trial.dx, trial.dy)]
    P = {(d, e): T[d].T @ Phi[e] for d in (0, 1) for e in (0, 1)}
    K = np.zeros((2 * test.n_functions, 2 * trial.n_functions))
    for a in (0, 1):
        for b in (0, 1):
            terms = [D[_VOIGT[a, d], _VOIGT[b, e]] * p for (d, e), p in P.items()
                     if D[_VOIGT[a, d], _VOIGT[b, e]] != 0]
            if terms:
                K[a::2, b::2] = sum(terms[1:], terms[0])
    return csr_array(K)


def dense_enrichment_blocks(shape: Shape, w: np.ndarray, D: np.ndarray):
    """``(K_ne, K_en, K_ee)`` as csr_array (2 n_functions, n_extra), (n_extra, 2 n_functions)
    and (n_extra, n_extra) for the shape functions ``shape`` (with derivatives and an
    :class:`~efgkit.approx.shape.Extra`) at points of weights ``w (n_points,)``, elasticity
    ``D (3, 3)``. Entries that are exactly zero are not stored (as in the sparse products).

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic
    >>> from efgkit.approx.shape import Extra
    >>> from efgkit.nodes import generate_nodes
    >>> from efgkit.approx.mls import mls_shape
    >>> cloud = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.5))
    >>> x = np.random.default_rng(0).random((50, 2))
    >>> s = mls_shape(x, cloud)
    >>> g = csr_array(np.column_stack([x[:, 0], 0 * x[:, 0]]))  # one unknown: u = (x^2 / 2, 0)
    >>> z = csr_array((50, 2))
    >>> sh = Shape(s.neighbours, s.values, s.ddx, s.ddy, s.n_functions, Extra(z, z, g, z, z, z))
    >>> K_ne, K_en, K_ee = dense_enrichment_blocks(sh, np.full(50, 1 / 50), Elastic(1.0, 0.0).D)
    >>> K_ne.shape, K_ee.shape, bool(abs(K_ee[0, 0] - (x[:, 0] ** 2).mean()) < 1e-12)
    ((18, 2), (2, 2), True)
    """
    e = shape.extra
    gxx, gxy, gyx, gyy = (op.toarray() for op in (e.gxx, e.gxy, e.gyx, e.gyy))
    eps = (gxx, gyy, gxy + gyx)  # strain of each unknown, (n_points, n_extra)
    dxT, dyT = shape.dx.T, shape.dy.T  # (n_functions, n_points), sparse

    def stresses(C):  # W C eps of every unknown: three (n_points, n_extra)
        return [w[:, None] * sum(C[i, j] * eps[j] for j in range(3) if C[i, j] != 0)
                for i in range(3)]

    def nodal_rows(sig):  # sum_q B_I^T sig, rows 2 I + c: (2 n_functions, n_extra)
        K = np.empty((2 * shape.n_functions, sig[0].shape[1]))
        K[0::2] = dxT @ sig[0] + dyT @ sig[2]
        K[1::2] = dyT @ sig[1] + dxT @ sig[2]
        return K

    sig = stresses(D)
    K_ne = nodal_rows(sig)
    K_en = K_ne.T if np.array_equal(D, D.T) else nodal_rows(stresses(D.T)).T  # E^T D B
    K_ee = sum(eps[i].T @ sig[i] for i in range(3))
    return csr_array(K_ne), csr_array(K_en), csr_array(K_ee)
