"""Unsymmetric solves (MLPG): SuperLU, or GMRES / BiCGSTAB with an incomplete-LU
preconditioner, every answer checked against its residual.

The MLPG1 stiffness is not symmetric (test != trial functions), so CG and the SPD
multigrid of :mod:`efgkit.system.linalg` do not apply. ``"auto"`` takes SuperLU up to
:data:`AUTO_KRYLOV_THRESHOLD` unknowns and GMRES above: first with the multigrid
(auxiliary-space) preconditioner of :mod:`efgkit.system.krylov_mlpg` when the caller gives
the nodal data, then, if that stagnates, with ILU, then SuperLU; each fallback is reported.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.sparse import csc_array, csr_array, diags_array
from scipy.sparse.linalg import LinearOperator, bicgstab, gmres, spilu

from .linalg import SolverError
from .linalg import solve as linalg_solve
from .linear_system import LinearSystem

__all__ = ["solve_unsymmetric", "AUTO_KRYLOV_THRESHOLD", "KRYLOV_SOLVERS"]

AUTO_KRYLOV_THRESHOLD = 60_000  # unknowns above which "auto" takes GMRES
KRYLOV_SOLVERS = ("auto", "direct", "gmres", "bicgstab", "amg")
MAX_ITERATIONS = 2000


def solve_unsymmetric(system: LinearSystem, solver: str = "auto", rtol: float = 1e-8,
                      drop_tol: float = 1e-5, fill_factor: float = 20.0,
                      auxiliary=None) -> tuple[np.ndarray, dict]:
    """Solve the unsymmetric ``system``; returns (z, info).

    Parameters
    ----------
    solver : {"auto", "direct", "gmres", "bicgstab", "amg"}
        SuperLU (column ordering COLAMD, partial pivoting), or a Krylov method
        (restarted GMRES(50), BiCGSTAB) preconditioned by ILU (``spilu`` with
        ``drop_tol``, ``fill_factor``, the minimum-degree ordering of A + A^T and diagonal
        pivots), after a row scaling to unit maxima. Measured on MLPG1 plates (square,
        quadratic basis): 7.4k unknowns 12 GMRES iterations, 20k unknowns 15; with the
        default COLAMD ordering and partial pivoting, or ``drop_tol=1e-3, fill_factor=5``,
        GMRES stalled at 20k unknowns (residual 4e2 to 6e2 after 2000 iterations). With
        ``drop_tol=1e-4, fill_factor=10`` (the former defaults) GMRES failed at 81k unknowns
        (residual 2.9e2 after 451 iterations) and at 201k (1.1 after 1952); with the defaults
        ``drop_tol=1e-5, fill_factor=20`` (MLPG1 unit plate, ``benchmarks/mlpg_solve.py``,
        restart 50): 20k unknowns 6 iterations (ILU setup 5 s, nnz(L + U) 8.7 nnz(K)); 81k
        unknowns 12 iterations (setup 47 s, 12.5 nnz(K)); 201k unknowns (100k nodes) 13
        iterations, residual 2.6e-10 (setup 209 s, GMRES 13 s, nnz(L + U) = 229 M, 15.5
        nnz(K), about 2.7 GB).
        ``"amg"``: GMRES with the multigrid preconditioner of :mod:`efgkit.system.krylov_mlpg`
        (needs ``auxiliary``); SolverError if it stagnates or misses ``rtol``. ``"auto"``
        above the threshold tries that first (given ``auxiliary``), then ILU-GMRES, then
        SuperLU, and says why in ``info["fallback"]``.
    rtol : float
        Required relative residual ||A z - b|| / ||b||.
    auxiliary : callable ``() -> (AuxiliarySpace, layer)``, optional
        The nodal data and the boundary-row coefficients of
        :func:`~efgkit.system.krylov_mlpg.surrogate_preconditioner`; called only when the
        multigrid preconditioner is tried.

    Returns
    -------
    z : ndarray (n,)
    info : dict with ``solver``, ``residual`` and (Krylov) ``iterations``,
        ``preconditioner``, ``setup_time``, ``krylov_time``.

    Raises
    ------
    SolverError
        Singular system, NaN, or a residual above ``rtol``.

    Examples
    --------
    >>> A = csr_array(np.array([[4.0, 1.0], [-1.0, 3.0]]))
    >>> z, info = solve_unsymmetric(LinearSystem(A, np.array([1.0, 2.0]), False, 2), "gmres")
    >>> bool(np.allclose(A @ z, [1.0, 2.0])), info["solver"]
    (True, 'gmres')
    """
    if solver not in KRYLOV_SOLVERS:
        raise ValueError(f"solver must be one of {KRYLOV_SOLVERS}, got {solver!r}")
    if solver == "amg" and auxiliary is None:
        raise ValueError("solver='amg' needs auxiliary (the nodal data of the multigrid "
                         "preconditioner, given by efgkit.static.solve_mlpg): use solver='gmres'")
    A, b = csr_array(system.A), system.b
    n = A.shape[0]
    if solver == "direct" or (solver == "auto" and n <= AUTO_KRYLOV_THRESHOLD):
        return linalg_solve(LinearSystem(A, b, False, system.n_coeffs, system.free,
                                         system.fixed_values), "direct", rtol=rtol)
    first = None
    if solver == "amg" or (solver == "auto" and auxiliary is not None):
        z, first = _amg(system, auxiliary, rtol, solver)
        if z is not None:
            return z, first
    bnorm = float(np.linalg.norm(b))
    kind = "gmres" if solver == "auto" else solver
    if bnorm == 0.0:
        return np.zeros(n), {"solver": kind, "residual": 0.0, "iterations": 0}
    t0 = time.perf_counter()
    d = np.asarray(abs(A).max(axis=1).todense()).ravel()
    if np.any(d == 0):
        raise SolverError(f"row {int(np.argmin(d))} of the system matrix is zero: an equation "
                          "without test-function support (a node whose sub-domain holds no "
                          "quadrature point)")
    S = csr_array(diags_array(1.0 / d) @ A)
    bs = b / d
    try:
        ilu = spilu(csc_array(S), drop_tol=drop_tol, fill_factor=fill_factor,
                    permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0)
    except RuntimeError as err:
        raise SolverError(f"the incomplete LU factorisation failed ({err}): the system is "
                          "singular; check the essential boundary conditions") from None
    M = LinearOperator(S.shape, matvec=ilu.solve, dtype=float)
    setup = time.perf_counter() - t0
    count = [0]

    def step(_):
        count[0] += 1

    t0 = time.perf_counter()
    tol, z, flag = 0.1 * rtol, None, 0  # on the scaled system; tightened until A's residual meets rtol
    for _ in range(4):
        if kind == "gmres":
            z, flag = gmres(S, bs, x0=z, rtol=tol, atol=0.0, restart=50,
                            maxiter=MAX_ITERATIONS // 50 + 1, M=M, callback=step,
                            callback_type="pr_norm")
        else:
            z, flag = bicgstab(S, bs, x0=z, rtol=tol, atol=0.0, maxiter=MAX_ITERATIONS, M=M,
                               callback=step)
        if not np.all(np.isfinite(z)) or flag != 0 or np.linalg.norm(A @ z - b) <= rtol * bnorm:
            break
        tol *= 0.01
    info = {"solver": kind, "iterations": count[0], "preconditioner": "ilu",
            "setup_time": setup, "krylov_time": time.perf_counter() - t0}
    if first is not None:
        info.update(first)
    if not np.all(np.isfinite(z)):
        raise SolverError(f"{kind} produced NaN or inf: the system is singular or overflowed")
    res = float(np.linalg.norm(A @ z - b)) / bnorm
    info["residual"] = res
    if not res <= rtol and solver == "auto":
        z, direct = linalg_solve(LinearSystem(A, b, False, system.n_coeffs), "direct", rtol=rtol)
        why = f"{kind} reached {res:.1e} in {count[0]} iterations"
        return z, {**info, **direct, "fallback": f"{info['fallback']}; {why}" if first else why}
    if not res <= rtol:
        raise SolverError(
            f"relative residual {res:.2e} exceeds {rtol:.0e} after {count[0]} {kind} iterations "
            f"({n} unknowns, flag {flag}). Remedy: solver='direct', or the other Krylov solver")
    return z, info


def _amg(system, auxiliary, rtol, solver):
    """GMRES with the multigrid preconditioner (:func:`~efgkit.system.krylov_mlpg.amg_gmres`):
    (z, info) when it met ``rtol``; else SolverError for solver="amg", or (None, info with
    the reason in ``fallback``) for "auto"."""
    from .krylov_mlpg import CHECKERBOARD_MIN, amg_gmres

    space, layer = auxiliary()
    z, info = amg_gmres(system, space, layer, rtol)
    if info["converged"]:
        return z, info
    why = (f"multigrid-preconditioned GMRES {'stagnated at' if info['stagnated'] else 'reached'} "
           f"relative residual {info['residual']:.1e} after {info['iterations']} iterations")
    if info["iterations"] == 0:
        why = ("multigrid-preconditioned GMRES not tried: the MLS nodal matrix is not clearly positive "
               f"on the checkerboard (Rayleigh quotient {info['checkerboard']:.2g} < "
               f"{CHECKERBOARD_MIN})")
    if solver == "amg":
        raise SolverError(f"solver='amg': {why} ({system.A.shape[0]} unknowns). The MLS nodal "
                          "matrix is probably not positive on high-frequency modes (module "
                          "efgkit.system.krylov_mlpg). Remedy: solver='gmres' (ILU) or 'direct', or an MLS "
                          "weight whose nodal matrix is positive (weight='cubic')")
    return None, {"amg_iterations": info["iterations"], "amg_residual": info["residual"], "fallback": why}
