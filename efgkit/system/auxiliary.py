"""Auxiliary-space preconditioner for large EFG systems.

Smoothed aggregation on the EFG matrix itself converges slowly: MLS supports
overlap widely (~88 nonzeros per row), so the strength graph is dense, and
MLS smoothing makes oscillatory coefficient vectors low-energy modes that no
rigid-body coarse space contains. This module instead relates the EFG
stiffness to a P1 finite-element stiffness ``P`` on a Delaunay triangulation
of the same nodes. The link is the nodal-value matrix ``Phi_JI = phi_I(x_J)``
(coefficients -> values at the nodes): with it ``K ~ Phi^T P Phi`` holds to a
spectral factor of about 0.25-2.5, whereas ``K`` and ``P`` alone differ by a
factor of ~3000 on oscillatory modes (``Phi`` has eigenvalues down to ~0.02).

The preconditioner works on two blocks of the unknowns:

* the boundary layer ``L``: rows that the essential-BC terms touch
  (``A - K != 0``: penalty, Nitsche) and anything beyond the nodal
  coefficients (enrichment), solved exactly by sparse LU, so that even a
  penalty of 1e8 E/h is resolved;
* the interior ``I``: ``Y V Y^T``, with ``V`` one V-cycle of pyamg smoothed
  aggregation (rigid-body modes) on ``P`` restricted to the interior nodes
  and ``Y ~ Phi_II^-1`` a fixed Chebyshev polynomial in ``Phi_II`` (degree
  :data:`AUXILIARY_DEGREE`), between two damped Jacobi steps on ``A_II``
  itself, ``W = omega D_II^-1``: ``z = W t; z += Y V Y^T (t - A_II z); z +=
  W (t - A_II z)``, whose error propagation is ``I - B_I A_II = (I - W A_II)
  (I - Y V Y^T A_II) (I - W A_II)`` (the auxiliary-space method with a
  smoother on the original space: J. Xu, Computing 56, 1996, 215-235).
  ``omega = SMOOTHER_DAMPING / lambda_max(D_II^-1 A_II)``
  (:func:`jacobi_spectral_radius`); the Jacobi steps remove the oscillatory
  coefficient modes that the P1 space represents poorly.

The blocks are combined multiplicatively, layer - interior - layer (symmetric
block Gauss-Seidel): ``z_L = A_LL^-1 r_L``, ``z_I = B_I (r_I - A_IL z_L)``,
``z_L = A_LL^-1 (r_L - A_LI z_I)``. ``B`` is symmetric by construction and
positive definite: with ``X = I - W A_II`` (A-norm at most 1 for ``omega
lambda_max <= 2``) and ``Y V Y^T`` SPD, ``v^T A (I - B_I A) v = (X v)^T A (I -
Y V Y^T A) (X v) < v^T A v`` for ``v != 0``, and the exact layer solves are
A-orthogonal projections; so it drives CG on the EFG system. On the cracked
plate of 97k nodes (Lagrange, 2 Uzawa steps) this takes 97-100 CG iterations
against 173-176 of the additive form without the Jacobi steps (degree 8), for
about 1.2 times the work per iteration (107 against 90 ms): the solve stage in
0.6-0.8 of the time (docs/performance.md, solve_stage). From
:data:`~efgkit.system.compiled_operators.COMPILED_MIN_UNKNOWNS` unknowns on, the
polynomials, the V-cycle and the products with ``A`` run on compiled kernels
(:mod:`efgkit.system.compiled_operators`): the same operator, 60 against 107 ms per
iteration at 97k nodes (docs/performance.md, solve_stage_notes).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_array, csc_array, csr_array
from scipy.sparse.linalg import LinearOperator, MatrixRankWarning, splu

from .auxiliary_p1 import p1_stiffness

__all__ = ["AuxiliarySpace", "auxiliary_preconditioner", "chebyshev_inverse", "coarse_solver",
           "jacobi_spectral_radius", "p1_stiffness", "smoothed_aggregation", "vcycle"]

CHEBYSHEV_DEGREE = 8
# The EFG preconditioner's polynomial degree and Jacobi damping (omega lambda_max); CG iterations
# on the cracked plate, 1e5 nodes, Lagrange (2 Uzawa steps): degree 5 / 6 / 8 at damping 1.6:
# 143 / 99 / 105; damping 1.3 / 1.6 / 1.8 / 1.98 at degree 6: 105 / 99 / 95 / 93 (2 is the
# bound for a positive definite preconditioner; 1.6 leaves 20 % for the estimate's error).
AUXILIARY_DEGREE = 6
SMOOTHER_DAMPING = 1.6
# Damped Jacobi steps on each side of Y V Y^T. At 97k nodes (compiled operators, CPU of CG,
# load 2.5-3.4): 1 step 87 iterations, 4.9-5.1 s; 2: 71-72, 5.1-5.3 s; 3: 63, 5.3-5.5 s.
JACOBI_STEPS = 1
SMOOTHER = True  # False: the additive form without Jacobi steps (before; for comparisons)
LANCZOS_STEPS = 12
CHEBYSHEV_INTERVAL = (0.03, 1.05)  # eigenvalues of Phi: <= 1 (partition of unity), >= ~0.02
AMG_OPTIONS = dict(symmetry="symmetric", max_coarse=500, improve_candidates=None,
                   presmoother=("gauss_seidel", {"sweep": "symmetric"}),
                   postsmoother=("gauss_seidel", {"sweep": "symmetric"}))
# The EFG preconditioner's V-cycle: symmetric Gauss-Seidel, except one forward sweep down and
# one backward sweep up on level 1 (still a symmetric cycle). At 97k nodes level 1 (44k unknowns,
# 2.4M non-zeros) cost as much as level 0; one sweep on each side there: 87 CG iterations as
# with symmetric sweeps, CG 4.9-5.1 against 5.4 s CPU (load 2.7-3.4); on level 1 and below:
# 102-103 iterations; on every level: 100 (docs/performance.md, solve_stage_notes).
_GS = "gauss_seidel"
VCYCLE_SMOOTHERS = dict(
    presmoother=[(_GS, {"sweep": "symmetric"}), (_GS, {"sweep": "forward"}), (_GS, {"sweep": "symmetric"})],
    postsmoother=[(_GS, {"sweep": "symmetric"}), (_GS, {"sweep": "backward"}), (_GS, {"sweep": "symmetric"})])


@dataclass(frozen=True, eq=False)
class AuxiliarySpace:
    """What the auxiliary-space preconditioner needs of a discretisation.

    Attributes
    ----------
    x : ndarray (n_nodes, 2)
        Node positions (split nodes nudged off the crack onto their face).
    phi : csr_array (n_nodes, n_nodes)
        Shape functions at the nodes, ``phi[J, I] = phi_I(x_J)``.
    D : ndarray (3, 3)
        Elasticity matrix (Voigt, engineering shear).
    domain : Domain or None
        Triangles outside it are dropped from the P1 stiffness.
    cuts : ndarray (n_segments, 2, 2) or None
        Crack segments: triangles that straddle them are dropped.
    """

    x: np.ndarray
    phi: csr_array
    D: np.ndarray
    domain: object = None
    cuts: np.ndarray | None = None


def chebyshev_inverse(F: csr_array, r: np.ndarray, degree: int | None = None,
                      interval=None) -> np.ndarray:
    """``p(F) r ~ F^-1 r`` by ``degree`` Chebyshev steps from zero (Saad, Alg. 12.1).

    ``F`` (m, m) has eigenvalues in (or near) the real ``interval``; ``p`` is
    a fixed polynomial, so ``r -> p(F) r`` is linear and ``p(F)^T = p(F^T)``.
    ``r`` is (m,) or (m, k). Defaults: :data:`CHEBYSHEV_DEGREE`,
    :data:`CHEBYSHEV_INTERVAL`.

    Examples
    --------
    >>> from scipy.sparse import csr_array
    >>> F = csr_array(np.diag([0.1, 0.5, 1.0]))
    >>> np.round(chebyshev_inverse(F, np.ones(3), 20, (0.1, 1.0)), 3).tolist()
    [10.0, 2.0, 1.0]
    """
    degree = CHEBYSHEV_DEGREE if degree is None else degree
    a, b = CHEBYSHEV_INTERVAL if interval is None else interval
    theta, delta = (b + a) / 2, (b - a) / 2
    sigma = theta / delta
    rho = 1 / sigma
    x = np.zeros_like(r, dtype=float)
    res = np.array(r, dtype=float)
    d = res / theta
    for _ in range(degree):
        x += d
        res -= F @ d
        rho_new = 1 / (2 * sigma - rho)
        d *= rho_new * rho
        d += (2 * rho_new / delta) * res
        rho = rho_new
    return x


def vcycle(levels, coarse, b: np.ndarray, i: int = 0) -> np.ndarray:
    """One V-cycle of a pyamg hierarchy from a zero guess (no residual norms)."""
    lv = levels[i]
    if i == len(levels) - 1:
        return coarse.solve(b)
    x = np.zeros_like(b)
    lv.presmoother(lv.A, x, b)
    x += lv.P @ vcycle(levels, coarse, lv.R @ (b - lv.A @ x), i + 1)
    lv.postsmoother(lv.A, x, b)
    return x


class _PseudoInverse:
    def __init__(self, A):
        self.pinv = np.linalg.pinv(A.toarray(), hermitian=True)  # pyamg levels are sparse

    def solve(self, b):
        return self.pinv @ b


def smoothed_aggregation(A, B, **options):
    """pyamg's smoothed-aggregation hierarchy of ``A`` with near-nullspace ``B``, built from a
    fixed random state: pyamg estimates the spectral radius of each level (the prolongation
    smoother's weight) by Lanczos from ``np.random.rand``, which changed the preconditioner by
    up to 1e-5 and CG by 86-90 iterations between set-ups of the same system. The caller's
    legacy global state is restored afterwards."""
    import pyamg

    state = np.random.get_state()  # noqa: NPY002 - pyamg draws from the legacy global state
    np.random.seed(0)  # noqa: NPY002
    try:
        return pyamg.smoothed_aggregation_solver(A, B=B, **options)
    finally:
        np.random.set_state(state)  # noqa: NPY002


def coarse_solver(A):
    """LU of the coarsest multigrid level; a pseudo-inverse when that level is singular (an
    aggregate of one node cannot carry three rigid-body candidates, and the tentative
    prolongator then has dependent columns), which is exact on the range of ``A``."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", MatrixRankWarning)
            return splu(csc_array(A))
    except (RuntimeError, MatrixRankWarning):
        return _PseudoInverse(A)


def jacobi_spectral_radius(A, rows: np.ndarray, steps: int = LANCZOS_STEPS) -> float:
    """Largest eigenvalue of ``D^-1 A_rr`` (``D`` the diagonal of ``A``, ``r`` the index
    array ``rows``), estimated by ``steps`` Lanczos steps on ``D^-1/2 A_rr D^-1/2`` from a
    random start (seed 0; Saad, Iterative Methods for Sparse Linear Systems, 2003, Alg. 6.15):
    the largest Ritz value, which lies below the eigenvalue and converges to it quickly (1e5
    nodes of the cracked plate: 3.95 after 12 steps against 3.97 after 40). Products with the
    whole ``A`` on vectors that vanish outside ``rows`` (no copy of ``A_rr``).

    Examples
    --------
    >>> from scipy.sparse import csr_array
    >>> A = csr_array(np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]]))
    >>> round(jacobi_spectral_radius(A, np.arange(3)), 6)   # 1 + cos(pi / 4)
    1.707107
    """
    from scipy.linalg import eigvalsh_tridiagonal

    n = A.shape[0]
    s = np.zeros(n)
    s[rows] = 1.0 / np.sqrt(A.diagonal()[rows])
    q = np.zeros(n)
    q[rows] = np.random.default_rng(0).uniform(-1.0, 1.0, len(rows))
    q /= np.linalg.norm(q)
    q_old, alpha, beta = np.zeros(n), [], [0.0]
    for _ in range(min(steps, len(rows))):
        w = s * (A @ (s * q))
        alpha.append(float(np.dot(q, w)))
        w -= alpha[-1] * q + beta[-1] * q_old
        beta.append(float(np.linalg.norm(w)))
        if beta[-1] <= 1e-12 * abs(alpha[-1]):  # an invariant subspace: the Ritz values are exact
            break
        q_old, q = q, w / beta[-1]
    d, e = np.array(alpha), np.array(beta[1:len(alpha)])
    return float(eigvalsh_tridiagonal(d, e)[-1]) if len(d) > 1 else float(d[0])


def auxiliary_preconditioner(A: csr_array, K: csr_array, x: np.ndarray, phi: csr_array,
                             D: np.ndarray, free: np.ndarray | None = None, domain=None,
                             cuts=None, *, product=None, bc_terms=None) -> tuple[LinearOperator, dict]:
    """The auxiliary-space preconditioner of ``A`` (module docstring).

    Parameters
    ----------
    A : csr_array (n, n)
        SPD system matrix (stiffness plus penalty/Nitsche terms, or the free
        block of an eliminated system).
    K : csr_array (n_coeffs, n_coeffs)
        The stiffness without essential-BC terms (all coefficients).
    x : (n_nodes, 2)
        Node coordinates; coefficient ``2 i + c`` belongs to node ``i``.
    phi : csr_array (n_nodes, >= n_nodes)
        Shape functions at the nodes, ``phi[J, I] = phi_I(x_J)``.
    D : (3, 3)
        Elasticity matrix (Voigt, engineering shear).
    free : (n,) int, optional
        Coefficient index of each unknown (eliminated systems).
    domain, cuts
        Passed to :func:`p1_stiffness`.
    product : operator, optional
        ``x -> A x`` with a ``diagonal()`` (e.g.
        :class:`~efgkit.system.compiled_operators.SymmetricOperator`); ``A`` itself by default.
    bc_terms : sparse (n, n), optional
        ``A - K`` on the unknowns when the caller has it (the augmentation of the Uzawa
        steps): its non-zero rows are the boundary layer (else found from ``A - K``).

    Returns
    -------
    M : LinearOperator (n, n)
        Approximates ``A^-1``. From
        :data:`~efgkit.system.compiled_operators.COMPILED_MIN_UNKNOWNS` unknowns on, its
        Chebyshev polynomials and V-cycle are the compiled ones
        (:mod:`efgkit.system.compiled_operators`), the same operator to round-off.
    info : dict
        Setup seconds per part (``t_*``) and the block sizes.
    """
    from .compiled_operators import use_compiled

    t = {"start": time.perf_counter()}
    n, nn = A.shape[0], len(x)
    product = A if product is None else product
    diag = product.diagonal()
    free = np.arange(K.shape[0]) if free is None else np.asarray(free)
    P = p1_stiffness(x, D, domain, cuts)
    t["p1"] = time.perf_counter()
    # Boundary layer: unknowns whose rows the BC terms change, grown to whole nodes.
    if bc_terms is None:
        Ksys = K if len(free) == K.shape[0] and np.array_equal(free, np.arange(K.shape[0])) \
            else csr_array(K[free][:, free])
        bc_terms = A - Ksys
    Bc = csr_array(bc_terms)
    Bc.eliminate_zeros()
    touched = free[np.diff(Bc.indptr) > 0]
    layer_node = np.zeros(nn, bool)
    layer_node[touched[touched < 2 * nn] // 2] = True
    pos = -np.ones(max(K.shape[0], 2 * nn), dtype=np.int64)
    pos[free] = np.arange(n)
    inner = np.flatnonzero(~layer_node)
    idof = (2 * inner[:, None] + np.arange(2)).ravel()
    mask = pos[idof] >= 0  # interior coefficients that are unknowns (not eliminated)
    isys = pos[idof[mask]]
    lsys = np.setdiff1d(np.arange(n), isys)
    t["layer"] = time.perf_counter()
    Pi = csr_array(P[idof[mask]][:, idof[mask]])
    lone = np.flatnonzero(Pi.diagonal() <= 0)
    if len(lone):  # nodes left without triangles: fall back to A's diagonal
        Pi = csr_array(Pi + coo_array((diag[isys[lone]], (lone, lone)), shape=Pi.shape))
    from .constraints import rigid_body_modes

    smoothers = VCYCLE_SMOOTHERS if SMOOTHER else {}
    ml = smoothed_aggregation(Pi, rigid_body_modes(x)[idof[mask]], **(AMG_OPTIONS | smoothers))
    coarse = coarse_solver(ml.levels[-1].A)
    t["amg"] = time.perf_counter()
    F = csr_array(phi[inner][:, inner])
    F.sort_indices()
    Ft = csr_array(F.T)
    lu = splu(csc_array(A[lsys][:, lsys])) if len(lsys) else None
    t["layer_lu"] = time.perf_counter()
    ni = len(inner)
    degree = AUXILIARY_DEGREE if SMOOTHER else CHEBYSHEV_DEGREE
    if use_compiled(n):
        from .compiled_operators import CompiledChebyshev, CompiledVcycle, sweeps_of

        Y, Yt = (CompiledChebyshev(M, degree, CHEBYSHEV_INTERVAL) for M in (F, Ft))
        options = AMG_OPTIONS | smoothers
        V = CompiledVcycle(ml.levels, coarse, sweeps_of(options["presmoother"], options["postsmoother"]))
    else:
        def Y(r):
            return chebyshev_inverse(F, r, degree)

        def Yt(r):
            return chebyshev_inverse(Ft, r, degree)

        def V(b):
            return vcycle(ml.levels, coarse, b)

    every = bool(mask.all())  # no interior coefficient eliminated: no scatter needed

    def aux(r):  # Y V Y^T on the interior unknowns of r (n,), zero elsewhere
        if every:
            ri = r[isys]
        else:
            ri = np.zeros(2 * ni)
            ri[mask] = r[isys]
        s = Yt(ri.reshape(ni, 2)).ravel()
        if every:
            e = V(s)
        else:
            e = np.zeros(2 * ni)
            e[mask] = V(s[mask])
        z = np.zeros(n)
        y = Y(e.reshape(ni, 2)).ravel()
        z[isys] = y if every else y[mask]
        return z

    if not SMOOTHER:  # the additive form (before)
        def apply(r):
            r = np.asarray(r).ravel()
            z = aux(r)
            if lu is not None:
                z[lsys] = lu.solve(r[lsys])
            return z
        info = _info(t)
        info.update(layer=len(lsys), interior=len(isys), levels=len(ml.levels))
        return LinearOperator((n, n), matvec=apply, dtype=float), info
    lam = jacobi_spectral_radius(product, isys)
    w = np.zeros(n)  # omega D^-1 on the interior, 0 on the layer
    w[isys] = SMOOTHER_DAMPING / lam / diag[isys]
    AL = csr_array(A[lsys]) if lu is not None else None  # (n_layer, n): A_LL, A_LI; A_IL = A_LI^T
    ALt = csr_array(AL.T) if lu is not None else None
    t["smoother"] = time.perf_counter()

    def apply_block_gs(r):
        r = np.asarray(r).ravel()
        if lu is not None:  # layer, then the interior against its residual, then the layer again
            zl = lu.solve(r[lsys])
            rt = r - ALt @ zl  # its interior part r_I - A_IL z_L (the layer part unused)
        else:
            rt = r
        z = w * rt
        for _ in range(JACOBI_STEPS - 1):
            z += w * (rt - product @ z)
        z += aux(rt - product @ z)
        for _ in range(JACOBI_STEPS):
            z += w * (rt - product @ z)
        if lu is not None:
            z[lsys] = lu.solve(r[lsys] - AL @ z)
        return z

    info = _info(t)
    info.update(layer=len(lsys), interior=len(isys), levels=len(ml.levels), jacobi_lambda_max=lam)
    return LinearOperator((n, n), matvec=apply_block_gs, dtype=float), info


def _info(t: dict) -> dict:
    """Seconds between the consecutive marks of ``t`` as ``t_<mark>``."""
    keys = list(t)
    return {f"t_{k}": t[k] - t[p] for p, k in zip(keys[:-1], keys[1:], strict=True)}
