"""Essential boundary conditions by collocation: equations replaced by constraint rows.

The modified collocation method of Zhu and Atluri (1998, "A modified collocation method
and a penalty formulation for enforcing the essential boundary conditions in the element
free Galerkin method", Comput. Mech. 21:211-222): the Galerkin equations of the
prescribed components of the nodes on the essential boundary are replaced by the rows
``u^h_a(x_I) = sum_J phi_J(x_I) c_Ja = ubar_a(x_I)``, the actual value of the trial
function at the node (not its coefficient, which plain MLS does not interpolate). The
shape functions stay the plain, continuous MLS ones; the other equations keep the
boundary term ``-int_{Gamma_u} phi_I t(u^h) dGamma`` (built by the caller, e.g.
:func:`efgkit.system.constraints.boundary_traction_term`), so the exact solution satisfies
every equation and the method passes the patch test (docs/theory.md).

:func:`collocation` is the algebra only, ``(K, f) -> LinearSystem``, shared by EFG
(Galerkin rows) and MLPG (local weak-form rows): it knows nothing of the scene. The
system is unsymmetric (``spd=False``): SuperLU, not CG.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array, diags_array, issparse
from scipy.sparse.linalg import splu

from .constraints import check_rigid_modes
from .linear_system import LinearSystem

__all__ = ["SingularRowsError", "collocation", "SINGULAR_PIVOT"]

# Smallest accepted pivot of the Gram matrix R R^T of the unit-normalised constraint rows, relative
# to its largest (1 for unit rows): below it the rows are taken as linearly dependent. A pivot is of
# the order of a squared singular value of R, so 1e-12 refuses rows with a condition number above
# ~1e6. Measured (EFG, linear basis, unit square with all edges prescribed, h = 0.1 and 0.05, regular
# and perturbed by 0.3 h, quartic, Gaussian and cubic weights): smallest pivot 0.11-1.0 at d_max 2,
# 3e-3-0.79 at d_max 3; a node listed twice gives 1e-16 or an exactly zero pivot.
SINGULAR_PIVOT = 1e-12


class SingularRowsError(ValueError):
    """The constraint rows of :func:`collocation` are linearly dependent."""


def _check_input(K, f, rows, values, dofs, node_x):
    """Validated (K csr (n, n), f (n,), rows csr (n_c, n), values (n_c,), dofs (n_c,) int)."""
    if not issparse(K) or K.ndim != 2 or K.shape[0] != K.shape[1]:
        raise TypeError(f"K must be a square scipy.sparse matrix, got {type(K).__name__} "
                        f"of shape {getattr(K, 'shape', None)}")
    n = K.shape[0]
    f = np.asarray(f, dtype=float)
    if f.shape != (n,):
        raise ValueError(f"f must have shape ({n},) like K, got {f.shape}")
    if not issparse(rows) or rows.ndim != 2:
        raise TypeError(f"rows must be a scipy.sparse matrix (n_c, {n}), got {type(rows).__name__}")
    n_c = rows.shape[0]
    if rows.shape[1] != n:
        raise ValueError(f"rows must have {n} columns (one per unknown of K), got shape {rows.shape}")
    values = np.asarray(values, dtype=float)
    if values.shape != (n_c,):
        raise ValueError(f"values must have shape ({n_c},), one per row, got {values.shape}")
    dofs = np.asarray(dofs)
    if dofs.shape != (n_c,) or (n_c and not np.issubdtype(dofs.dtype, np.integer)):
        raise ValueError(f"dofs must be an integer array of shape ({n_c},), one equation per row, "
                         f"got {dofs.dtype} of shape {dofs.shape}")
    if n_c and (dofs.min() < 0 or dofs.max() >= n):
        raise ValueError(f"dofs must lie in [0, {n}), got values from {dofs.min()} to {dofs.max()}")
    uniq, count = np.unique(dofs, return_counts=True)
    if np.any(count > 1):
        raise ValueError(f"dofs must be distinct (each equation replaced once), got dof "
                         f"{int(uniq[count > 1][0])} {int(count.max())} times")
    rows = csr_array(rows, dtype=float)
    for name, arr in (("f", f), ("values", values), ("rows", rows.data), ("K", K.data)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} holds NaN or inf")
    node_x = np.asarray(node_x, dtype=float)
    if node_x.ndim != 2 or node_x.shape[1] != 2 or 2 * len(node_x) > n:
        raise ValueError(f"node_x must have shape (n_nodes, 2) with 2 n_nodes <= {n}, "
                         f"got {node_x.shape}")
    return csr_array(K), f, rows, values, dofs.astype(np.int64)


def _check_independent(rows: csr_array, dofs: np.ndarray) -> None:
    """SingularRowsError unless the rows (n_c, n) are linearly independent.

    The pivots of an LU of the Gram matrix ``R R^T`` of the unit-normalised rows without
    pivoting (symmetric minimum-degree ordering) are positive and bounded by 1 for
    independent rows; a pivot below :data:`SINGULAR_PIVOT` marks a row that depends on
    the ones eliminated before it. Cost: a sparse LU of an (n_c, n_c) matrix with the
    sparsity of the boundary nodes' neighbourhoods, small beside the solve.
    """
    norms = np.sqrt(np.asarray(rows.multiply(rows).sum(axis=1)).ravel())
    if np.any(norms == 0.0):
        k = int(np.flatnonzero(norms == 0.0)[0])
        raise SingularRowsError(
            f"constraint row {k} (replacing equation {dofs[k]}) is zero: no shape function is "
            "non-zero at its point. Check that the point lies inside the body and in some "
            "node's support.")
    R = csr_array(diags_array(1.0 / norms) @ rows)
    # A shift far below SINGULAR_PIVOT keeps exactly dependent rows from stopping the LU, so that
    # their pivot (~1e-15) can name them.
    gram = (R @ R.T + diags_array(np.full(len(dofs), 1e-3 * SINGULAR_PIVOT))).tocsc()
    lu = splu(gram, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
              options={"SymmetricMode": True})
    pivots = np.abs(lu.U.diagonal())
    if pivots.min() < SINGULAR_PIVOT:
        # Pr G Pc = L U with Pc[i, perm_c[i]] = 1: pivot j belongs to the row i with perm_c[i] = j
        k = int(np.flatnonzero(lu.perm_c == np.argmin(pivots))[0])
        raise SingularRowsError(
            f"the {len(dofs)} constraint rows are linearly dependent (smallest pivot of their "
            f"Gram matrix {pivots.min():.1e} < {SINGULAR_PIVOT:g}: row {k}, replacing equation "
            f"{dofs[k]}, depends on the others), so the system would be singular: a node listed "
            "twice, or two nodes at one point? Give each constrained point and component once.")


def collocation(K, f, rows, values, dofs, node_x) -> LinearSystem:
    """Replace equations ``dofs`` of ``K c = f`` by the constraint rows ``rows @ c = values``.

    Zhu and Atluri (1998, Comput. Mech. 21:211-222), the modified collocation method:
    for EFG the rows are the MLS shape functions at the essential-boundary nodes and the
    replaced equations are those of their prescribed components; for MLPG (where every
    node has its own equation) the same. No penalty or multiplier enters the system.

    Parameters
    ----------
    K : sparse (n, n)
        The discrete operator (for EFG: the stiffness minus the Gamma_u boundary term,
        :func:`efgkit.system.constraints.boundary_traction_term`).
    f : (n,)
        Right-hand side.
    rows : csr_array (n_c, n)
        Constraint rows: ``rows[k] @ c`` is the prescribed quantity of constraint k.
    values : (n_c,)
        Prescribed values.
    dofs : (n_c,) int, distinct
        Equation ``dofs[k]`` is replaced by constraint k.
    node_x : (n_nodes, 2)
        Node positions, for the rigid-body check (the first ``2 n_nodes`` unknowns are
        nodal, node-major interleaved).

    Returns
    -------
    LinearSystem
        ``A z = b`` with ``A`` the rows of ``K`` outside ``dofs`` and the constraint rows,
        scaled by ``max|K| / max|rows|`` so that both are of one magnitude (SuperLU's
        threshold pivoting and the residual check weigh them alike); ``spd=False``.

    Raises
    ------
    RigidBodyModeError
        The rows leave a rigid-body motion free (:func:`check_rigid_modes`).
    SingularRowsError
        The rows are linearly dependent (or one is zero).
    ValueError, TypeError
        Shapes, types, repeated or out-of-range ``dofs``, NaN or inf.

    Examples
    --------
    Two nodes at (0, 0) and (1, 0), a spring in x between them; node 0 held and
    u_y of node 1 prescribed, so only equation 2 (u_x of node 1) stays:

    >>> from scipy.sparse import csr_array
    >>> from efgkit.system.linalg import solve
    >>> K = csr_array(np.kron([[1.0, -1.0], [-1.0, 1.0]], np.diag([1.0, 0.0])) + 0.1 * np.eye(4))
    >>> rows = csr_array(np.eye(4)[[0, 1, 3]])
    >>> s = collocation(K, np.ones(4), rows, [0.0, 0.0, 0.5], [0, 1, 3], [[0.0, 0.0], [1.0, 0.0]])
    >>> np.round(s.coefficients(solve(s, "direct")[0]), 6).tolist()
    [0.0, 0.0, 0.909091, 0.5]
    """
    K, f, rows, values, dofs = _check_input(K, f, rows, values, dofs, node_x)
    n = K.shape[0]
    check_rigid_modes(rows, np.asarray(node_x, dtype=float))
    _check_independent(rows, dofs)
    n_c = len(dofs)
    scale = abs(K).max() / abs(rows).max() if K.nnz else 1.0
    keep = np.ones(n)
    keep[dofs] = 0.0
    place = csr_array((np.full(n_c, scale), (dofs, np.arange(n_c))), shape=(n, n_c))
    A = csr_array(diags_array(keep) @ K + place @ rows)
    b = keep * f + place @ values
    return LinearSystem(A, b, spd=False, n_coeffs=n)
