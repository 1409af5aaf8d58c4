"""Linear solvers: SuperLU for small and medium systems, pyamg smoothed
aggregation with rigid-body modes + CG for large SPD ones. Every solve checks
its residual and raises :class:`SolverError` rather than return a wrong answer.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.sparse import csc_array
from scipy.sparse.linalg import MatrixRankWarning, splu

from .constraints import LinearSystem

__all__ = ["solve", "SolverError", "AUTO_AMG_THRESHOLD"]

AUTO_AMG_THRESHOLD = 150_000  # unknowns above which "auto" uses AMG for SPD systems


class SolverError(RuntimeError):
    """A linear solve failed or its residual is too large."""


def _direct(A, b):
    A = csc_array(A)
    with warnings.catch_warnings():
        warnings.simplefilter("error", MatrixRankWarning)
        try:
            lu = splu(A, permc_spec="MMD_AT_PLUS_A")
        except (RuntimeError, MatrixRankWarning) as err:
            raise SolverError(
                f"the system matrix ({A.shape[0]} unknowns) is singular: {err}. Check the "
                "essential boundary conditions and that every node's support holds quadrature points."
            ) from None
    return lu.solve(b)


def _amg(A, b, near_nullspace, tol):
    import pyamg

    B = None if near_nullspace is None else np.asarray(near_nullspace, dtype=float)
    ml = pyamg.smoothed_aggregation_solver(A.tocsr(), B=B, symmetry="symmetric",
                                           strength=("symmetric", {"theta": 0.0}), max_coarse=500)
    residuals = []
    x = ml.solve(b, tol=tol, accel="cg", maxiter=500, residuals=residuals)
    return x, len(residuals)


def solve(system: LinearSystem, solver: str = "auto", near_nullspace=None,
          rtol: float = 1e-8) -> tuple[np.ndarray, dict]:
    """Solve ``system`` and return (solution z, info).

    Parameters
    ----------
    system : LinearSystem
    solver : {"auto", "direct", "amg"}
        "auto" takes AMG for SPD systems above :data:`AUTO_AMG_THRESHOLD`
        unknowns and SuperLU otherwise.
    near_nullspace : ndarray (n, k), optional
        Rigid-body modes for smoothed aggregation.
    rtol : float
        Largest accepted relative residual ||A z - b|| / ||b||.

    Returns
    -------
    z : ndarray (n,)
    info : dict with ``solver``, ``residual`` and (AMG) ``iterations``.

    Examples
    --------
    >>> from scipy.sparse import csr_array
    >>> from efgkit.constraints import LinearSystem
    >>> z, info = solve(LinearSystem(csr_array(np.diag([2.0, 4.0])), np.ones(2), True, 2))
    >>> z.tolist(), info["solver"]
    ([0.5, 0.25], 'direct')
    """
    A, b = system.A, system.b
    n = A.shape[0]
    if solver not in ("auto", "direct", "amg"):
        raise ValueError(f"solver must be 'auto', 'direct' or 'amg', got {solver!r}")
    if solver == "amg" and not system.spd:
        raise ValueError("solver='amg' needs an SPD system; the Lagrange-multiplier system is "
                         "a saddle point: use solver='direct' or another bc method")
    use_amg = solver == "amg" or (solver == "auto" and system.spd and n > AUTO_AMG_THRESHOLD)
    info = {"solver": "amg" if use_amg else "direct"}
    bnorm = float(np.linalg.norm(b))
    if bnorm == 0.0:
        info["residual"] = 0.0
        return np.zeros(n), info
    if use_amg:
        ns = None
        if near_nullspace is not None and system.free is not None:
            ns = near_nullspace[system.free]
        elif near_nullspace is not None and near_nullspace.shape[0] == n:
            ns = near_nullspace
        z, its = _amg(A, b, ns, tol=min(rtol, 1e-10) * 1e-2)
        info["iterations"] = its
    else:
        z = _direct(A, b)
    if not np.all(np.isfinite(z)):
        raise SolverError("the solve produced NaN or inf: the system is singular or overflowed")
    res = float(np.linalg.norm(A @ z - b)) / bnorm
    info["residual"] = res
    if res > rtol:
        raise SolverError(
            f"relative residual {res:.2e} exceeds {rtol:.0e} ({info['solver']} solver, {n} "
            "unknowns): the system is near-singular (check supports and the penalty factor)"
        )
    return z, info
