"""GMRES with a multigrid (auxiliary-space) preconditioner for the unsymmetric MLPG1 system.

The MLPG1 stiffness ``A`` (seed 002 Eqs. 20-24) tests the elasticity operator with a bump
``v_I`` of radius r_s ~ 1.1 h around each node, so away from the boundary its row I behaves
like the row of a nodal stiffness applied to the trial field near x_I; with the nodal-value
matrix ``Phi_JI = phi_I(x_J)`` (coefficients -> values at the nodes) and ``P`` the P1
elasticity stiffness on a Delaunay triangulation of the nodes
(:func:`~efgkit.system.auxiliary.p1_stiffness`),

    ``A ~ P Phi``,   so   ``M = Phi^-1 P^-1``

is a right preconditioner (``A M`` close to the identity on most modes). It is applied
with the scalable pieces of :mod:`efgkit.system.auxiliary`: a fixed Chebyshev polynomial
in ``Phi`` for ``Phi^-1`` and one V-cycle of smoothed aggregation (rigid-body modes) on
``P`` for ``P^-1``. The rows that do not follow ``A ~ P Phi`` -- the penalty rows of the
nodes on Gamma_u (1e3 E/h), collocation rows, enrichment unknowns -- form a layer ``L``
solved by sparse LU after the interior ``I``: ``z_I = M_I r_I``, ``z_L = A_LL^-1 (r_L -
A_LI z_I)`` (block Gauss-Seidel). GMRES on ``A M`` (right preconditioning: its residual is
the true one) runs in cycles of :data:`CYCLE` iterations.

The approximation ``A ~ P Phi`` holds only while ``Phi`` is positive on every mode. Its
symbol at the checkerboard (the highest grid frequency) is measured on a unit plate, h =
1/30 (``Phi`` row of the centre node applied to ``(-1)^(i+j)``): Gaussian weight, k = 2,
c = 0.5 r_I, quadratic basis, d_max = 2.5 (the MLPG defaults of this writing) -0.067;
with d_max = 3: -0.36; linear basis -0.20; quartic -0.007; cubic spline +0.089;
Gaussian c = 0.365 r_I (seed 002) +0.95; Gaussian k = 1, c = 0.5 r_I (MLPG's default since
issue 14) +0.0024, too close to zero (:data:`CHECKERBOARD_MIN`). Where it is negative, ``Phi`` and therefore
``A`` have near-zero eigenvalues on a ring of high-frequency modes (``A``'s symbol crosses
zero there: -277 at the checkerboard against 4633 at its maximum, in units of E), which
no smooth SPD surrogate (``P``, ``Phi^T P Phi``, EFG's Galerkin stiffness on the same
cloud) can represent, and GMRES stagnates. A cycle that reduces the residual by less than
:data:`STAGNATION` therefore stops the solve, and the caller falls back (reported).
"""

from __future__ import annotations

import time
import warnings

import numpy as np
from scipy.sparse import coo_array, csc_array, csr_array
from scipy.sparse.linalg import LinearOperator, splu

from .auxiliary import (
    AMG_OPTIONS,
    AuxiliarySpace,
    chebyshev_inverse,
    coarse_solver,
    p1_stiffness,
    smoothed_aggregation,
    vcycle,
)
from .constraints import rigid_body_modes
from .linalg import SolverError
from .linear_system import LinearSystem

__all__ = ["CHECKERBOARD_MIN", "CYCLE", "MAX_ITERATIONS", "STAGNATION", "amg_gmres", "checkerboard_quotient",
           "surrogate_preconditioner"]

CYCLE = 40  # GMRES restart length (inner iterations per cycle)
# The answer is accepted only from a fast solve: with the default Gaussian weight (Phi not
# positive), h = 1/16 converged slowly (172 iterations) to a relative residual of 4.7e-9 with
# coefficients 7.6e-7 off the direct solve (error_estimate 2.9e-10, 2600x too small); with the
# cubic weight 20-23 iterations, error_estimate 2.3e-10 against a true 2.8e-10.
MAX_ITERATIONS = 120
# A cycle must reduce the residual by at least this factor, or the solve stops as stagnant.
# Cubic-spline weight, unit plate: 22-23 iterations to 1e-9 at 3.4k and 13k unknowns (about
# 1e-4 per 40 iterations at worst); Gaussian k = 2 default, h = 1/24: 1.1e-3 after 80 iterations,
# less than 10x below the first cycle's.
STAGNATION = 0.1
# The quotient must clear zero by a margin: MLPG's default Gaussian k = 1, c = 0.5 r_I (0.0024
# at h = 0.1) converged at 1k nodes (84 iterations, coefficients 2.3e-8 off SuperLU's with an
# error_estimate of 5.5e-10) but stagnated at 20k nodes (plate: residual 1.3e-3 after 80
# iterations; clamped SENT 8.2e-8); the cubic spline (0.089) converges at every size measured.
CHECKERBOARD_MIN = 0.02
# After the residual meets rtol, cycles continue (tighter) until error_estimate <= ESTIMATE_FACTOR
# * rtol: on the clamped SENT (cubic weight, 0.9k-2.5k unknowns) a residual of 2e-9 left the
# coefficients 0.7-2e-5 off the direct solve (error_estimate 0.45-1.4e-5).
ESTIMATE_FACTOR = 100.0


def _layer_split(n, n_nodes, free, layer):
    """Unknown indices of the interior nodes' coefficients (isys), their position in the
    node-major interior coefficient vector (mask), the interior nodes and the layer unknowns."""
    free = np.arange(n) if free is None else np.asarray(free)
    layer_node = np.zeros(n_nodes, bool)
    lay = np.asarray(layer, dtype=np.int64)
    layer_node[lay[lay < 2 * n_nodes] // 2] = True
    pos = -np.ones(max(int(free.max(initial=0)) + 1, 2 * n_nodes), dtype=np.int64)
    pos[free] = np.arange(n)
    inner = np.flatnonzero(~layer_node)
    idof = (2 * inner[:, None] + np.arange(2)).ravel()
    mask = pos[idof] >= 0
    isys = pos[idof[mask]]
    lsys = np.setdiff1d(np.arange(n), isys)
    return isys, mask, inner, idof, lsys


def surrogate_preconditioner(A, space: AuxiliarySpace, layer, free=None):
    """The right preconditioner ``M ~ A^-1`` of the module docstring.

    Parameters
    ----------
    A : sparse (n, n)
        The MLPG1 system matrix (unsymmetric).
    space : AuxiliarySpace
        Node positions, nodal shape-function values ``phi (n_nodes, >= n_nodes)``,
        elasticity matrix, domain and crack segments.
    layer : ndarray of int
        Coefficient indices (``2 I + c``) whose rows are boundary rows (penalty,
        collocation); their nodes go to the LU-solved layer, as do all unknowns beyond
        the ``2 n_nodes`` nodal coefficients (enrichment).
    free : ndarray (n,) of int, optional
        Coefficient index of each unknown (systems with eliminated coefficients).

    Returns
    -------
    M : LinearOperator (n, n)
    info : dict with ``layer``, ``interior``, ``levels`` and setup seconds ``t_*``.
    """
    t = [time.perf_counter()]
    A = csr_array(A)
    n, nn = A.shape[0], len(space.x)
    isys, mask, inner, idof, lsys = _layer_split(n, nn, free, layer)
    P = p1_stiffness(space.x, space.D, space.domain, space.cuts)
    Pi = csr_array(P[idof[mask]][:, idof[mask]])
    diag = Pi.diagonal()
    if np.any(diag <= 0):  # nodes left without triangles: A's diagonal there
        lone = np.flatnonzero(diag <= 0)
        Pi = csr_array(Pi + coo_array((np.abs(A.diagonal()[isys[lone]]), (lone, lone)), shape=Pi.shape))
    t.append(time.perf_counter())
    ml = smoothed_aggregation(Pi, rigid_body_modes(space.x)[idof[mask]], **AMG_OPTIONS)
    coarse = coarse_solver(ml.levels[-1].A)
    F = csr_array(space.phi[inner][:, inner])
    F.sort_indices()
    t.append(time.perf_counter())
    lu = None
    if len(lsys):
        try:
            lu = splu(csc_array(A[lsys][:, lsys]), permc_spec="COLAMD")
        except RuntimeError as err:
            raise SolverError(f"the boundary-layer block of the MLPG system ({len(lsys)} unknowns) "
                              f"is singular ({err}): check the essential boundary conditions") from None
    A_li = csr_array(A[lsys][:, isys])
    t.append(time.perf_counter())
    ni = len(inner)

    def apply(r):
        r = np.asarray(r).ravel()
        z = np.zeros(n)
        e = np.zeros(2 * ni)
        e[mask] = vcycle(ml.levels, coarse, r[isys])
        z[isys] = chebyshev_inverse(F, e.reshape(ni, 2)).ravel()[mask]
        if lu is not None:
            z[lsys] = lu.solve(r[lsys] - A_li @ z[isys])
        return z

    info = {"layer": len(lsys), "interior": len(isys), "levels": len(ml.levels),
            "t_p1": t[1] - t[0], "t_amg": t[2] - t[1], "t_layer_lu": t[3] - t[2]}
    return LinearOperator((n, n), matvec=apply, dtype=float), info


def checkerboard_quotient(space: AuxiliarySpace) -> float:
    """Rayleigh quotient ``c^T Phi c / c^T c`` of the nodal-value matrix for the checkerboard
    ``c_I = (-1)^(i + j)``, (i, j) the node's position in units of the median nearest-neighbour
    distance (the highest grid frequency), over the rows of the nodes with full supports (at
    least 0.9 times the 95th percentile of the row counts; boundary rows are larger: with them
    the Gaussian default gave +0.077 on an 11 x 11 plate). Negative:
    ``Phi`` is not positive and :func:`surrogate_preconditioner` cannot converge (module
    docstring); on a regular grid it is the checkerboard symbol (-0.067 for the Gaussian
    default, +0.089 for the cubic spline, unit plate, h = 1/30).

    Examples
    --------
    >>> from efgkit.system.auxiliary import AuxiliarySpace
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> checkerboard_quotient(AuxiliarySpace(x, csr_array(np.eye(4)), np.eye(3)))
    1.0
    """
    from scipy.spatial import cKDTree

    x = np.asarray(space.x, dtype=float)
    if len(x) < 2:
        return 1.0
    h = float(np.median(cKDTree(x).query(x, k=2)[0][:, 1]))
    ij = np.rint((x - x.min(axis=0)) / h).astype(np.int64)
    c = np.where((ij[:, 0] + ij[:, 1]) % 2 == 0, 1.0, -1.0)
    F = csr_array(space.phi[:, : len(x)])
    nnz = np.diff(F.indptr)
    deep = nnz >= 0.9 * np.percentile(nnz, 95)  # full supports: the boundary rows would hide it
    return float(np.sum((c * (F @ c))[deep]) / np.count_nonzero(deep))


def amg_gmres(system: LinearSystem, space: AuxiliarySpace, layer, rtol: float = 1e-8):
    """Right-preconditioned GMRES(:data:`CYCLE`) with :func:`surrogate_preconditioner`.

    Returns (z (n,), info) with ``iterations``, ``converged``, ``stagnated`` (a cycle
    reduced the residual by less than :data:`STAGNATION`; or, without an iteration,
    :func:`checkerboard_quotient` ``checkerboard`` < :data:`CHECKERBOARD_MIN`), ``residual`` (relative, true),
    ``error_estimate`` ``||M r|| / ||z||`` (the error of z if ``M`` were ``A^-1``; not a
    bound), ``setup_time``, ``krylov_time`` and the preconditioner's setup parts. The
    caller decides what a miss means (:func:`efgkit.system.krylov.solve_unsymmetric`).

    Examples
    --------
    Two layer nodes: with one, the P1 block of the other three keeps a rotation about it and
    is singular (its pseudo-inverse makes ``M`` singular).

    >>> from efgkit.system.auxiliary import AuxiliarySpace
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> A = csr_array(np.eye(8) * 2.0)
    >>> z, info = amg_gmres(LinearSystem(A, np.ones(8), False, 8),  # layer: nodes 0 and 1
    ...                     AuxiliarySpace(x, csr_array(np.eye(4)), np.eye(3)), [0, 1, 2, 3])
    >>> bool(np.allclose(z, 0.5)), info["converged"]
    (True, True)
    """
    from pyamg.krylov import fgmres

    A, b = csr_array(system.A), np.asarray(system.b, dtype=float)
    bnorm = float(np.linalg.norm(b))
    t0 = time.perf_counter()
    q = checkerboard_quotient(space)
    if q < CHECKERBOARD_MIN:  # Phi not (clearly) positive: GMRES stagnates (module docstring)
        return np.zeros(len(b)), {"solver": "gmres", "preconditioner": "auxiliary", "iterations": 0,
                                  "converged": False, "stagnated": True, "residual": 1.0,
                                  "checkerboard": q, "setup_time": time.perf_counter() - t0}
    M, info = surrogate_preconditioner(A, space, layer, system.free)
    t1 = time.perf_counter()
    z = np.zeros(len(b))
    its, res, stagnated, target, est = 0, 1.0, False, 0.5 * rtol, np.inf
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # fgmres' small least-squares solves near convergence
        while its < MAX_ITERATIONS:
            hist = []
            z, _ = fgmres(A, b, x0=z, tol=target, restart=CYCLE, maxiter=1, M=M, residuals=hist)
            its += len(hist) - 1
            if not np.all(np.isfinite(z)):
                res = np.inf
                break
            new = float(np.linalg.norm(b - A @ z)) / bnorm if bnorm > 0 else 0.0
            if new <= target or (new <= rtol and len(hist) <= 1):
                res, est = new, _estimate(A, b, z, M)
                if est <= ESTIMATE_FACTOR * rtol or len(hist) <= 1:
                    break
                target = min(target, new) * max(ESTIMATE_FACTOR * rtol / est, 1e-3)
                continue
            stagnated = new > STAGNATION * res
            res = new
            if stagnated:
                break
    est = _estimate(A, b, z, M) if not np.isfinite(est) else est
    info.update(solver="gmres", preconditioner="auxiliary", iterations=its, checkerboard=q,
                converged=bool(res <= rtol), stagnated=stagnated, residual=res,
                error_estimate=est, setup_time=t1 - t0, krylov_time=time.perf_counter() - t1)
    return z, info


def _estimate(A, b, z, M) -> float:
    """``||M (b - A z)|| / ||z||``: the relative error of z (n,) if M were A^-1."""
    zn = float(np.linalg.norm(z))
    return float(np.linalg.norm(M.matvec(b - A @ z))) / zn if zn > 0 else 0.0
