"""Linear solvers: SuperLU for small and medium systems, preconditioned CG for
large SPD ones, and for large Lagrange-multiplier saddle points Uzawa steps on
the augmented Lagrangian with the same CG. Every solve checks its residual and
raises :class:`SolverError` rather than return a wrong answer.

The CG preconditioner is the auxiliary-space one of :mod:`efgkit.system.auxiliary`
(P1 stiffness on a Delaunay triangulation of the nodes, linked to the MLS
coefficients by the nodal values of the shape functions) when the solve is
given the discretisation and the bare stiffness; otherwise pyamg smoothed
aggregation with rigid-body modes on the system matrix itself, which is
several times slower on EFG matrices (dense strength graph, oscillatory
low-energy modes).

A small residual does not certify CG's answer on an ill-conditioned system (penalty 1e10 E/h:
relative residual 1.7e-10, coefficients 37 % off), so a bound on its energy error
(:func:`~efgkit.system.conjugate_gradient.energy_error_bound`, from the Ritz values of the
CG run: :mod:`efgkit.system.conjugate_gradient`) must also stay below ``ERROR_FACTOR * rtol``.
"""

from __future__ import annotations

import contextlib
import time
import warnings

import numpy as np
from scipy.sparse import csc_array, csr_array, diags_array
from scipy.sparse.linalg import LinearOperator, MatrixRankWarning, splu

from .blas_threads import one_blas_thread, single_blas_thread
from .conjugate_gradient import energy_error_bound, preconditioned_cg, ritz_range
from .linear_system import LinearSystem

__all__ = ["solve", "SolverError", "AUTO_AMG_THRESHOLD", "ERROR_FACTOR"]

AUTO_AMG_THRESHOLD = 20_000  # unknowns above which "auto" uses CG for SPD systems
# What the EFG driver passes as ``dense`` (efgkit.static.solve): its small systems have full
# enrichment columns (two per tip for the extrinsic MLS), which fill SuperLU's factor; the
# SENT's 314 unknowns: dense Cholesky 0.7 ms against 2.4 ms, K the same to 3e-14
# (docs/performance.md, work_interleaved)
DENSE_SOLVE = 400
# Augmented-Lagrangian weight: its largest diagonal entry over K's. The Uzawa steps shrink a
# multiplier mode by 1 / (1 + rho mu); at 1e3 the Kirsch plate (symmetry supports, one component
# per edge) has a mode with rho mu ~ 0.01: 20 steps left the gap at 5e-8 > rtol and 'auto' fell
# back to SuperLU (87 % of the example's time). The auxiliary preconditioner factors the
# boundary rows, so a larger weight costs no CG iterations (condition estimate 864 at 1e3-1e7);
# steps / CG iterations at 1e3, 1e5, 1e6, 1e7: Kirsch 8.2k nodes 20+ / 340 (failed), 7 / 217,
# 2 / 142, 2 / 116; cracked plate 7.8k nodes 3 / 179, 2 / 136, 2 / 130. 1e6 keeps the round-off
# of K + rho P (~1e-10 relative) well below rtol.
AUGMENTATION = 1e6
MAX_UZAWA_STEPS = 20
# The first Uzawa step's CG stops at UZAWA_FIRST_STEP times the final tolerance: its answer is
# off by the multiplier error anyway (the gap G c - q after it is ~6e-6 of ||b|| on the cracked
# plate), which the next step removes, warm-started. The later steps and the answer's checks
# keep rtol. CG iterations (first + second step) at 97k nodes: 1 (the exact first step) 86 + 14,
# 40: 69 + 18, 120: 65 + 20, 400: 61 + 25; at 19.6k nodes 82 + 10 against 66 + 19 at 120
# (docs/performance.md, solve_stage_notes).
UZAWA_FIRST_STEP = 100.0
# An iterative answer is accepted if the bound on its relative energy error (energy_error_bound) is at most
# ERROR_FACTOR * rtol (1e-3 at the default rtol): the bound over the residual measures how far the
# conditioning amplifies a residual. Measured bounds, CG to rtol 1e-8 (true errors about half):
# cantilever 48 x 12, 1.3k-29k unknowns, default penalty 6e-7 to 2.6e-6, Nitsche 2e-7; Uzawa steps 5e-8;
# cracked square with Williams displacements on all edges, 7.5k and 29k unknowns, default penalty 1.1e-4
# (the largest seen at default settings). Refused: penalty 1e8 / 1e10 E/h on the cantilever, 3.5e-2 /
# 0.22-0.50 (the coefficients 0.1-37 % off); 1e4 E/h on the cracked square, 3.7e-3.
ERROR_FACTOR = 1e5


class SolverError(RuntimeError):
    """A linear solve failed or its residual is too large."""


def _direct(A, b, spd, dense: int = 0):
    """SuperLU. SPD systems keep the diagonal pivots of the symmetric minimum-degree
    ordering of A + A^T (10-40x faster on irregular clouds than threshold pivoting);
    saddle-point (Lagrange) systems need pivoting, and there the column ordering COLAMD
    fills 40% less and runs 3x faster (Kirsch plate, 16.6k unknowns: 4.5 s against
    13.2 s; with PU enrichment 6x). SPD systems of at most ``dense`` unknowns: dense
    Cholesky (LAPACK), SuperLU if it fails."""
    if spd and A.shape[0] <= dense:  # one BLAS thread: a second one stalls on busy cores
        from scipy.linalg import cho_factor, cho_solve

        with contextlib.suppress(np.linalg.LinAlgError), one_blas_thread():
            return cho_solve(cho_factor(A.toarray()), b)
    A = csc_array(A)
    opts = dict(permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                options={"SymmetricMode": True}) if spd else dict(permc_spec="COLAMD")
    with warnings.catch_warnings():
        warnings.simplefilter("error", MatrixRankWarning)
        try:
            lu = splu(A, **opts)
        except (RuntimeError, MatrixRankWarning) as err:
            raise SolverError(
                f"the system matrix ({A.shape[0]} unknowns) is singular: {err}. Check the "
                "essential boundary conditions and that every node's support holds quadrature points."
            ) from None
    return lu.solve(b)


def _sa_preconditioner(A, near_nullspace):
    """One V-cycle of pyamg smoothed aggregation on ``A`` itself."""
    from .auxiliary import coarse_solver, smoothed_aggregation, vcycle

    ml = smoothed_aggregation(A, near_nullspace, symmetry="symmetric", max_coarse=500)
    coarse = coarse_solver(ml.levels[-1].A)
    M = LinearOperator(A.shape, matvec=lambda r: vcycle(ml.levels, coarse, np.ravel(r)),
                       dtype=float)
    return M, {"levels": len(ml.levels)}


def _auxiliary(system, auxiliary, K, product=None, bc_terms=None):
    from .auxiliary import auxiliary_preconditioner

    t0 = time.perf_counter()
    space = auxiliary()
    t_phi = time.perf_counter() - t0
    M, info = auxiliary_preconditioner(system.A, csr_array(K), space.x, space.phi, space.D,
                                       free=system.free, domain=space.domain, cuts=space.cuts,
                                       product=product, bc_terms=bc_terms)
    info["t_phi"] = t_phi
    return M, info


def _preconditioner(system, near_nullspace, auxiliary, stiffness, product=None, bc_terms=None):
    """The auxiliary-space preconditioner (with the auxiliary space and the bare stiffness;
    ``product`` and ``bc_terms`` as in :func:`~efgkit.system.auxiliary.auxiliary_preconditioner`)
    or smoothed aggregation on ``system.A``; returns M, info."""
    if auxiliary is not None and stiffness is not None:
        M, info = _auxiliary(system, auxiliary, stiffness, product, bc_terms)
        info["preconditioner"] = "auxiliary"
        return M, info
    ns = None
    if near_nullspace is not None:
        ns = np.asarray(near_nullspace, dtype=float)
        ns = ns[system.free] if system.free is not None else ns
        ns = ns if ns.shape[0] == system.A.shape[0] else None
    M, info = _sa_preconditioner(csr_array(system.A), ns)
    info["preconditioner"] = "smoothed_aggregation"
    return M, info


def _compact(A) -> csr_array:
    """CSR with sorted 32-bit indices when they fit: a quarter less memory traffic per product."""
    A = csr_array(A)
    A.sort_indices()
    if A.nnz < 2**31 - 1:
        A = csr_array((A.data, A.indices.astype(np.int32, copy=False), A.indptr.astype(np.int32)),
                      shape=A.shape)
    return A


def _product(A):
    """``A`` or its compiled product (:func:`~efgkit.system.compiled_operators.product_operator`)."""
    from .compiled_operators import product_operator

    return product_operator(A)


def _iterative(system, near_nullspace, rtol, auxiliary, stiffness):
    """CG with the auxiliary-space (or plain SA) preconditioner; returns z, info with the
    energy-error bound (:func:`~efgkit.system.conjugate_gradient.energy_error_bound`) and,
    given the stiffness, the penalty scale ``max diag(A - K) / max diag(K)``."""
    A = _compact(system.A)
    t0 = time.perf_counter()
    product = _product(A)
    M, info = _preconditioner(system, near_nullspace, auxiliary, stiffness, product)
    t1 = time.perf_counter()
    z, rho, alpha, ok = preconditioned_cg(product, system.b, M,
                                          0.25 * rtol * float(np.linalg.norm(system.b)))
    info.update(setup_time=t1 - t0, cg_time=time.perf_counter() - t1, iterations=len(alpha),
                converged=ok)
    lo, hi = ritz_range(rho, alpha)
    K = csr_array(stiffness) if stiffness is not None and stiffness.shape[0] == system.n_coeffs else None
    if K is not None and system.free is None and K.shape == A.shape:
        info["penalty_scale"] = float((A.diagonal() - K.diagonal()).max() / K.diagonal().max())
    c = system.coefficients(z) if K is not None else None
    info.update(condition_estimate=hi / lo, error_bound=energy_error_bound(A, system.b, z, M, lo, K, c))
    return z, info


def _augmented_lagrangian(system, near_nullspace, rtol, auxiliary, stiffness):
    """The saddle point ``[[K, G^T], [G, 0]] [c; lambda] = [f; q]`` by Uzawa steps.

    With ``D`` the row sums of ``|G|`` (a lumped multiplier mass) and ``A_rho = K +
    rho G^T D^-1 G`` (SPD once the constraints hold the rigid-body modes), each step
    solves ``A_rho c = f + G^T (rho D^-1 q - lambda)`` by CG with one preconditioner
    and sets ``lambda += rho D^-1 (G c - q)``. At a fixed point ``G c = q`` and ``K c
    + G^T lambda = f``: the Lagrange solution itself, not a penalty approximation.
    The multiplier error shrinks by about ``1 / (1 + rho mu)`` per step (``mu`` the
    eigenvalues of the Schur complement in the ``D`` metric); ``rho`` puts the largest
    diagonal entry of the augmentation at ``AUGMENTATION`` times K's, as a penalty
    would (1e6: see the measurements at AUGMENTATION), so two steps usually reach ``rtol``.
    The first step's CG stops at :data:`UZAWA_FIRST_STEP` times the final tolerance (its
    answer carries the multiplier error anyway); the loop ends after a step at the final
    tolerance whose gap ``||G c - q||`` is below ``0.5 rtol ||b||``.
    The ``K c + G^T lambda - f`` part of the residual is each step's CG residual, the other
    ``G c - q``. K is ``stiffness`` when given (it is the K block: no copy of it is made).
    """
    n = system.n_coeffs
    if system.blocks is not None:  # held as its blocks: no copy of K is made
        K, G = system.blocks
    else:
        A = csr_array(system.A)
        K, G = A[:n, :n], A[n:, :n]
    K = stiffness if getattr(stiffness, "shape", None) == (n, n) else K
    f, q = system.b[:n], system.b[n:]
    d_inv = 1.0 / np.asarray(abs(G).sum(axis=1)).ravel()
    P = csr_array(G.T @ diags_array(d_inv) @ G)
    rho = AUGMENTATION * K.diagonal().max() / P.diagonal().max()
    A_rho = _compact(K + rho * P)
    bnorm = float(np.linalg.norm(system.b))
    t0 = time.perf_counter()
    product = _product(A_rho)
    M, info = _preconditioner(LinearSystem(A_rho, f, True, n), near_nullspace, auxiliary,
                              stiffness, product, rho * P)
    t1 = time.perf_counter()
    c, lam, its, steps = np.zeros(n), np.zeros(G.shape[0]), 0, 0
    ok, ritz = False, [np.inf, 0.0]
    while steps < MAX_UZAWA_STEPS:
        rhs = f + G.T @ (rho * d_inv * q - lam)
        loose = steps == 0 and UZAWA_FIRST_STEP > 1  # a first step to a looser tolerance
        atol = 0.25 * rtol * bnorm * (UZAWA_FIRST_STEP if loose else 1.0)
        c, rhos, alphas, converged = preconditioned_cg(product, rhs, M, atol, x0=c)
        if len(alphas):  # every step's CG sees the same M A_rho: keep the widest Ritz range
            lo, hi = ritz_range(rhos, alphas)
            ritz = [min(ritz[0], lo), max(ritz[1], hi)]
        its, steps = its + len(alphas), steps + 1
        gap = G @ c - q
        lam = lam + rho * d_inv * gap
        if not converged:
            break
        if not loose and float(np.linalg.norm(gap)) <= 0.5 * rtol * bnorm:
            ok = True
            break
    info.update(setup_time=t1 - t0, cg_time=time.perf_counter() - t1, iterations=its,
                uzawa_steps=steps, converged=ok)
    ritz = ritz if its else [1.0, 1.0]
    info.update(penalty_scale=AUGMENTATION, condition_estimate=ritz[1] / ritz[0],
                error_bound=energy_error_bound(A_rho, rhs, c, M, ritz[0], K, c))
    return np.concatenate([c, lam]), info


def solve(system: LinearSystem, solver: str = "auto", near_nullspace=None,
          rtol: float = 1e-8, *, auxiliary=None, stiffness=None, dense: int = 0
          ) -> tuple[np.ndarray, dict]:
    """Solve ``system`` and return (solution z, info).

    Parameters
    ----------
    system : LinearSystem
    solver : {"auto", "direct", "amg"}
        "direct": SuperLU. "amg": CG with a multigrid preconditioner: with
        ``auxiliary``, the auxiliary-space preconditioner of
        :mod:`efgkit.system.auxiliary` (LU on the boundary rows, a Chebyshev map and
        one smoothed-aggregation V-cycle on a P1 stiffness of the nodes between two
        damped Jacobi steps, in a symmetric block Gauss-Seidel sweep), else
        one V-cycle of smoothed aggregation on the system matrix; a Lagrange
        saddle point takes Uzawa steps on the augmented Lagrangian, each a CG
        solve with that preconditioner (:func:`_augmented_lagrangian`). "auto"
        takes "amg" above :data:`AUTO_AMG_THRESHOLD` unknowns and SuperLU
        otherwise; if CG misses ``rtol`` there, or its answer cannot be trusted
        (below), it falls back to SuperLU and says why in ``info["fallback"]``.
    near_nullspace : ndarray (n_coeffs, k), optional
        Rigid-body modes, for smoothed aggregation on the system matrix (only
        used without ``auxiliary``).
    rtol : float
        Largest accepted relative residual ||A z - b|| / ||b||. An iterative answer
        must also have a bound on its relative energy error
        (:func:`~efgkit.system.conjugate_gradient.energy_error_bound`) of at most
        ``ERROR_FACTOR * rtol`` (1e-3 by default).
    auxiliary : callable ``() -> AuxiliarySpace``, optional
        With ``stiffness``, enables the auxiliary-space preconditioner
        (:mod:`efgkit.system.auxiliary`); called only if an iterative solve is
        taken, since the nodal shape-function values it holds cost a pass of MLS.
    stiffness : sparse (n_coeffs, n_coeffs), optional
        The stiffness before the essential boundary conditions; ``system.A``
        minus it locates the boundary-layer unknowns.
    dense : int
        SPD systems of at most this many unknowns solved directly by dense Cholesky
        (SuperLU if it fails); 0: SuperLU always. The EFG driver passes :data:`DENSE_SOLVE`.

    Returns
    -------
    z : ndarray (n,)
    info : dict with ``solver``, ``residual`` and (CG) ``iterations``,
        ``preconditioner``, ``setup_time``, ``cg_time``, ``error_bound``,
        ``condition_estimate`` (of the preconditioned operator), ``penalty_scale``
        (given ``stiffness``: ``max diag(A - K) / max diag(K)``), ``uzawa_steps``;
        ``fallback`` when "auto" replaced CG's answer by SuperLU's.

    Raises
    ------
    SolverError
        Singular system, NaN/inf, a residual above ``rtol``, or (solver="amg") an
        energy-error bound above ``ERROR_FACTOR * rtol``.

    Examples
    --------
    >>> from scipy.sparse import csr_array
    >>> from efgkit.system.linear_system import LinearSystem
    >>> z, info = solve(LinearSystem(csr_array(np.diag([2.0, 4.0])), np.ones(2), True, 2))
    >>> z.tolist(), info["solver"]
    ([0.5, 0.25], 'direct')
    """
    b, n = system.b, system.size
    saddle = _check_arguments(system, solver, rtol)
    use_amg = solver == "amg" or (solver == "auto" and (system.spd or saddle)
                                  and n > AUTO_AMG_THRESHOLD)
    info = {"solver": "amg" if use_amg else "direct"}
    bnorm = float(np.linalg.norm(b))
    if bnorm == 0.0:
        info["residual"] = 0.0
        return np.zeros(n), info
    res = None  # CG's residual, measured already
    if use_amg:
        z, res = _iterative_with_fallback(system, solver, near_nullspace, rtol, auxiliary, stiffness,
                                          bnorm, info)
    else:
        z = _direct(system.A, b, system.spd, dense)
    _check_residual(system, z, bnorm, rtol, info, res)
    return z, info


def _check_arguments(system, solver, rtol) -> bool:
    """Whether ``system`` is a Lagrange saddle point; ValueError for a bad ``solver`` or ``rtol``."""
    if solver not in ("auto", "direct", "amg"):
        raise ValueError(f"solver must be 'auto', 'direct' or 'amg', got {solver!r}")
    saddle = not system.spd and system.free is None and system.n_coeffs < system.size
    if solver == "amg" and not (system.spd or saddle):
        raise ValueError("solver='amg' needs an SPD system or a Lagrange-multiplier saddle "
                         "point [[K, G^T], [G, 0]]: use solver='direct'")
    if not (isinstance(rtol, (int, float)) and 0 < rtol < 1):
        raise ValueError(f"rtol must lie in (0, 1), got {rtol!r}")
    return saddle


def _iterative_with_fallback(system, solver, near_nullspace, rtol, auxiliary, stiffness, bnorm, info):
    """(z (n,), its relative residual): CG's (Uzawa steps') z, or under "auto" SuperLU's (residual
    None: not measured yet) if CG missed ``rtol`` or its error bound exceeds ``ERROR_FACTOR * rtol``;
    CG statistics (and fallback) go into ``info``. SolverError for an untrusted answer under "amg" (a
    missed residual is left to :func:`_check_residual`)."""
    iterate = _iterative if system.spd else _augmented_lagrangian
    with single_blas_thread():
        z, extra = iterate(system, near_nullspace, rtol, auxiliary, stiffness)
    info.update(extra)
    finite = bool(np.all(np.isfinite(z)))
    res = float(np.linalg.norm(system.product(z) - system.b)) / bnorm if finite else np.inf
    if not res <= rtol:
        reason = f"CG missed rtol in {extra['iterations']} iterations"
    elif not extra["error_bound"] <= ERROR_FACTOR * rtol:
        reason = _untrusted(extra, res, rtol)
    else:
        return z, res
    if solver == "auto":
        info.update(solver="direct", fallback=reason)
        return _direct(system.A, system.b, system.spd), None
    if res <= rtol:
        raise SolverError(
            f"solver='amg': {reason}. Remedy: solver='direct' (or 'auto', which falls back to it), "
            "or a better-conditioned system: the default penalty factor (1e3 E/h) or bc='lagrange' "
            "or 'variational' instead of a large penalty")
    return z, res


def _untrusted(extra, res, rtol) -> str:
    """Why CG's answer is refused although its relative residual ``res`` meets ``rtol``."""
    scale = extra.get("penalty_scale")
    why = (f"; the largest diagonal entry of the boundary terms is {scale:.1e} times the stiffness's "
           "(about 1e3 at the default penalty)" if scale is not None else "")
    if np.isnan(extra["error_bound"]):
        why += "; CG met a non-positive curvature (the matrix or the preconditioner is not SPD)"
    k = extra["iterations"]
    return (f"its relative residual {res:.1e} meets rtol = {rtol:.0e} after {k} iteration{'s' * (k != 1)}"
            f", but the bound on its relative energy error is {extra['error_bound']:.1e} "
            f"> {ERROR_FACTOR * rtol:.0e} (ERROR_FACTOR * rtol){why}: the system is too ill-conditioned "
            "for a small residual to mean a right answer")


def _check_residual(system, z, bnorm, rtol, info, res=None):
    """Stores the relative residual ``||A z - b|| / ||b||`` of z (n,) in ``info`` (``res``
    when it was measured already); returns None. SolverError for NaN/inf in z or a residual
    above ``rtol``."""
    if not np.all(np.isfinite(z)):
        raise SolverError("the solve produced NaN or inf: the system is singular or overflowed")
    res = float(np.linalg.norm(system.product(z) - system.b)) / bnorm if res is None else res
    info["residual"] = res
    if not np.isfinite(res):  # A z overflowed: loads or stiffness beyond float range
        raise SolverError(f"the residual of the solve is {res} (A z or b overflowed): the loads or "
                          "the stiffness are too large for double precision; rescale the units")
    if res > rtol:
        detail = (f" after {info['iterations']} CG iterations" if info["solver"] == "amg"
                  else "")
        raise SolverError(
            f"relative residual {res:.2e} exceeds {rtol:.0e} ({info['solver']} solver, {system.size} "
            f"unknowns{detail}): the system is near-singular (check supports and the penalty "
            "factor)"
        )
