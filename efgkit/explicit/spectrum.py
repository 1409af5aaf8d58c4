"""The spectrum of ``M^-1 K``: the critical step of central differences and growing modes.

:func:`stable_step` gives ``dt_c = 2 / omega_max`` (seed 002 Eqs. 29-30) from the assembled
matrices of :func:`~efgkit.explicit.system.dynamics`; :func:`growth_rate` the rate of the
fastest-growing mode of an unsymmetric (MLPG1) K, which no step size removes;
:func:`row_symbol` the Fourier symbol of one row of ``M^-1 K``, whose sign away from the
boundary tells where such modes come from (docs/theory.md, "Explicit MLPG");
:func:`phase_speeds` the speeds of plane waves that symbol gives (numerical dispersion);
:func:`modal_energy` the energy the scheme conserves when K is not symmetric but ``M^-1 K``
has a real non-negative spectrum (small models).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from scipy.sparse.linalg import LinearOperator, eigs, eigsh

from .system import Dynamics

__all__ = ["dense_operator", "growth_rate", "modal_energy", "phase_speeds", "row_symbol", "stable_step"]


def _operator(dyn: Dynamics):
    """``A = Q M^-1/2 K M^-1/2 Q`` as a matvec, whether K is symmetric, and a dense builder."""
    n = dyn.n_dofs
    s = np.sqrt(dyn.minv)  # 0 on fixed coefficients: they drop out
    K, P = dyn.K, dyn.projection

    def proj(y):
        if P is None:
            return y
        return y - s * (P.G.T @ P.lu.solve(P.G @ (s * y)))

    def apply(y):
        y = proj(np.asarray(y).ravel())
        return proj(s * (K @ (s * y)))

    def dense():
        A = s[:, None] * K.toarray() * s[None, :]
        if P is not None:
            Gt = P.G.toarray() * s[None, :]
            Q = np.eye(n) - Gt.T @ np.linalg.solve(Gt @ Gt.T, Gt)
            A = Q @ A @ Q
        return A

    symmetric = abs(K - K.T).max() <= 1e-10 * abs(K).max()  # Petrov-Galerkin (MLPG) K is not
    return apply, symmetric, dense


def dense_operator(dyn: Dynamics) -> np.ndarray:
    """``A = Q M^-1/2 K M^-1/2 Q`` as a dense array (n_dofs, n_dofs), with ``Q`` the
    projector of :func:`stable_step` (the eigenvalues of ``A`` on the moving unknowns are
    those of ``M^-1 K`` on the admissible motions). For small models only.
    Rows and columns of fixed coefficients (``minv == 0``) are zero."""
    return _operator(dyn)[2]()


def stable_step(dyn: Dynamics, tol: float = 1e-8, dense_below: int = 400) -> tuple[float, float]:
    """Critical step ``dt_c = 2 / omega_max`` (seed 002 Eqs. 29-30) and ``omega_max^2``.

    ``omega_max^2`` is the largest eigenvalue of ``K x = lambda M x`` on the admissible
    motions: of ``A = Q M^-1/2 K M^-1/2 Q`` with ``Q`` the orthogonal projector onto
    ``G M^-1/2 y = 0`` (Lagrange constraints; built with the factors of ``G M^-1 G^T``)
    or onto the free coefficients (modified MLS). Lanczos (``eigsh``, largest algebraic,
    relative accuracy ``tol``) or, for fewer than ``dense_below`` unknowns, a dense
    eigensolver; for an unsymmetric K (Petrov-Galerkin MLPG) the largest modulus by Arnoldi
    (``eigs``), where the energy identity of the scheme no longer holds and modes may grow
    at any step (:func:`growth_rate`). For meshless shape functions ``h / c`` is not a
    bound: the matrices decide.

    Returns
    -------
    dt_critical : float
    lambda_max : float
    """
    n = dyn.n_dofs
    apply, symmetric, dense = _operator(dyn)
    if n < dense_below:
        A = dense()
        lam = float(scipy.linalg.eigvalsh(0.5 * (A + A.T), subset_by_index=[n - 1, n - 1])[0]) \
            if symmetric else float(np.abs(np.linalg.eigvals(A)).max())
    else:
        op = LinearOperator((n, n), matvec=apply, dtype=float)
        v0 = np.random.default_rng(0).standard_normal(n)
        lam = float(eigsh(op, k=1, which="LA", tol=tol, v0=v0, return_eigenvectors=False)[0]) \
            if symmetric else float(np.abs(eigs(op, k=1, which="LM", tol=tol, v0=v0,
                                                return_eigenvectors=False)[0]))
    if not (np.isfinite(lam) and lam > 0):
        raise ValueError(f"the largest eigenvalue of M^-1 K is {lam!r}, not positive: the "
                         "stiffness or mass is broken (check the material and the quadrature)")
    return 2.0 / np.sqrt(lam), lam


def growth_rate(dyn: Dynamics, lam_max: float | None = None, k: int = 6,
                dense_below: int = 400) -> tuple[float, complex]:
    """Growth rate of the fastest-growing mode of ``M u'' + K u = 0``, and its eigenvalue.

    A mode ``exp(i omega t)`` with ``omega^2 = lambda`` an eigenvalue of ``M^-1 K`` (on the
    admissible motions) grows like ``exp(gamma t)`` with ``gamma = Im sqrt(lambda)`` (the
    root with Im >= 0): 0 for real ``lambda >= 0``, ``sqrt(-lambda)`` for real negative
    ``lambda``, positive for complex ``lambda``. A symmetric positive semi-definite K (EFG)
    has none; the unsymmetric MLPG1 K has some (docs/theory.md, "Explicit MLPG"): central
    differences then grow like ``exp(gamma t)`` at every step size, and a run of duration
    T amplifies such a mode ``exp(gamma T)`` times.

    All eigenvalues for fewer than ``dense_below`` unknowns; else the ``k`` eigenvalues
    farthest from ``lam_max`` (Arnoldi on ``A - lam_max I``: the leftmost part of the
    spectrum), an estimate that can miss a complex pair with a large real part. Eigenvalues
    below ``1e-10 lam_max`` in modulus (the rigid motions, round-off) count as 0.

    Returns
    -------
    gamma : float
        1 / time.
    lam : complex
        The eigenvalue of M^-1 K it comes from.
    """
    n = dyn.n_dofs
    apply, symmetric, dense = _operator(dyn)
    if n < dense_below:
        ev = np.linalg.eigvalsh(0.5 * (dense() + dense().T)) if symmetric else np.linalg.eigvals(dense())
    else:
        lam_max = stable_step(dyn)[1] if lam_max is None else lam_max
        op = LinearOperator((n, n), matvec=lambda y: apply(y) - lam_max * np.asarray(y).ravel(),
                            dtype=float)
        v0 = np.random.default_rng(1).standard_normal(n)
        solver = eigsh if symmetric else eigs
        ev = solver(op, k=min(k, n - 2), which="LM", tol=1e-8, v0=v0,
                    return_eigenvectors=False) + lam_max
    ev = np.asarray(ev, dtype=complex)
    lam_max = np.abs(ev).max() if lam_max is None else lam_max
    g = np.sqrt(ev).imag  # principal root: Im >= 0
    g[np.abs(ev) <= 1e-10 * lam_max] = 0.0  # the rigid motions' round-off
    i = int(np.argmax(g))
    return float(g[i]), complex(ev[i])


def row_symbol(dyn: Dynamics, node: int, wavenumbers: np.ndarray) -> np.ndarray:
    """Fourier symbol of node ``node``'s rows of ``M^-1 K`` at ``wavenumbers (k, 2)``.

    ``S_pq(xi) = (1 / m_I) sum_J K_{2I+p, 2J+q} exp(i xi . (x_J - x_I))``, shape (k, 2, 2)
    complex: on a regular grid, away from the boundary, K is translation invariant and
    ``S`` is the symbol of the semi-discrete operator; its eigenvalues are the ``omega^2``
    of the plane waves ``exp(i xi . x)`` (for small ``|xi|``: ``E' |xi|^2 / rho`` and
    ``mu |xi|^2 / rho`` in plane stress, ``E' = E / (1 - nu^2)``). A Bubnov-Galerkin K
    (EFG) gives a non-negative symbol; MLPG1's row I pairs the test function v_I with the
    trial functions, ``K_IJ ~ int grad v_I . D grad phi_J``, whose symbol carries the
    product of their Fourier transforms (summed over the aliases of the grid): where it
    changes sign, M^-1 K has negative eigenvalues however the body is supported.
    A central node's symmetric part has real eigenvalues; take ``.real`` of the
    eigenvalues of ``S`` for its stiffness along ``xi``.

    Examples
    --------
    >>> from efgkit import MLPG, Domain, Elastic, Scene
    >>> from efgkit.explicit import dynamics
    >>> sc = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3, rho=1.0), duration=1.0)
    >>> dyn = dynamics(sc, MLPG(spacing=0.25, quadrature="midpoint", explicit_weight="same",
    ...                         explicit_form="petrov_galerkin"))     # MLPG1 itself
    >>> S = row_symbol(dyn, 12, np.zeros((1, 2)))   # xi = 0: rigid translations
    >>> bool(np.abs(S).max() < 1e-10)
    True
    """
    xi = np.asarray(wavenumbers, dtype=float)
    if xi.ndim != 2 or xi.shape[1] != 2 or not np.all(np.isfinite(xi)):
        raise ValueError(f"wavenumbers must be finite with shape (k, 2), got shape {xi.shape}")
    n_nodes = dyn.disc.nodes.n
    if not (0 <= int(node) < n_nodes and int(node) == node):
        raise ValueError(f"node must be an index in [0, {n_nodes}), got {node!r}")
    x = dyn.disc.nodes.x
    K = dyn.K[:, : 2 * n_nodes]  # nodal unknowns only
    rows = K[[2 * node, 2 * node + 1]].toarray()  # (2, 2 n_nodes)
    e = np.exp(1j * (x - x[node]) @ xi.T)  # (n_nodes, k)
    S = np.stack([[rows[p, q::2] @ e for q in range(2)] for p in range(2)])  # (2, 2, k)
    return np.moveaxis(S, -1, 0) / dyn.m[2 * node]


def phase_speeds(dyn: Dynamics, node: int, wavenumbers: np.ndarray,
                 dt: float | None = None) -> np.ndarray:
    """Phase speeds of the two plane waves ``exp(i (xi . x - omega t))`` at ``wavenumbers
    (k, 2)`` in the interior of a regular grid: numerical dispersion.

    ``omega^2`` are the eigenvalues of the symmetric part of :func:`row_symbol` at node
    ``node`` (a node far enough from the boundary that its rows see none of it); the speeds
    ``omega / |xi|`` come sorted, shape (k, 2): the shear-like branch, then the
    dilatational one (exact: ``c_2`` and ``c_1`` of the material at every ``xi``). With
    ``dt`` the speeds of central differences (seed 002 Eq. 28) at that step,
    ``omega_dt = (2 / dt) asin(omega dt / 2)`` (the scheme's phase lead; at the critical
    step of the interior ``omega dt / 2`` reaches 1 at the grid's shortest waves).

    Examples
    --------
    Long waves on a grid of spacing 1 run at the material's speeds:

    >>> from efgkit import EFG, Domain, Elastic, Scene
    >>> from efgkit.explicit import dynamics
    >>> mat = Elastic(1.0, 0.25, "strain", rho=1.0)
    >>> sc = Scene(Domain.rectangle(0, 0, 10, 10), mat, duration=1.0)
    >>> dyn = dynamics(sc, EFG(spacing=1.0))
    >>> c = phase_speeds(dyn, 60, [[2 * np.pi / 40, 0.0]])[0]
    >>> np.round(c / [mat.c_shear, mat.c_dilatational] - 1, 3)
    array([-0.004, -0.004])

    Raises
    ------
    ValueError
        A zero wavenumber (no speed), or ``dt`` beyond the stability of the wave
        (``omega dt / 2 > 1``).
    """
    xi = np.asarray(wavenumbers, dtype=float)
    S = row_symbol(dyn, node, xi)
    k = np.hypot(xi[:, 0], xi[:, 1])
    if np.any(k <= 0):
        raise ValueError("wavenumbers must be non-zero (a plane wave of zero wavenumber has no "
                         f"speed), got {xi[k <= 0][0].tolist()}")
    lam = np.linalg.eigvalsh(0.5 * (S + np.conj(np.swapaxes(S, 1, 2))))  # (k, 2) ascending
    omega = np.sqrt(np.maximum(lam, 0.0))
    if dt is not None:
        if not (np.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be finite and > 0, got {dt!r}")
        z = omega * dt / 2
        if np.any(z > 1):
            raise ValueError(f"dt = {dt:.6g} is above the stable step of the waves at these "
                             f"wavenumbers (omega dt / 2 = {z.max():.4g} > 1): central differences "
                             "do not propagate them; take dt <= the critical step (stable_step)")
        omega = 2 / dt * np.arcsin(z)
    return omega / k[:, None]


def modal_energy(dyn: Dynamics, rtol: float = 1e-9):
    """The energy central differences conserve for an unsymmetric K with a real spectrum.

    With ``y = M^1/2 u`` on the moving unknowns the unforced scheme is ``y^{n+1} - 2 y^n +
    y^{n-1} = -dt^2 A y^n``, ``A`` of :func:`dense_operator`. If ``A = V Lambda V^-1`` with
    ``Lambda`` real and ``>= 0``, then ``H = V^-T V^-1`` makes ``H A = V^-T Lambda V^-1``
    symmetric and

        E_H^{n-1/2} = 1/2 ydot . H ydot + 1/2 y^n . H A y^{n-1},  ydot = (y^n - y^{n-1}) / dt,

    is conserved exactly (the modified-energy identity of :mod:`efgkit.explicit.integrate`
    with ``H`` as metric: it needs only ``H`` symmetric and ``H A`` symmetric); in the modal
    coordinates ``z = V^-1 y`` it is ``1/2 sum_k (zdot_k^2 + lambda_k z_k^n z_k^{n-1})``,
    positive below the critical step. For a symmetric K, ``V`` is orthogonal and ``E_H`` is
    the driver's modified energy. With a projection (Lagrange, collocation rows) ``A`` is
    taken on an orthonormal basis of the admissible ``y``. Such an ``H`` exists exactly when
    ``A`` is diagonalisable
    with real eigenvalues; an eigenvalue off ``[0, inf)`` is a mode that grows at every step
    (:func:`growth_rate`) and no conserved positive energy exists. Dense: small models only.

    Returns
    -------
    energy : callable
        ``energy(state) -> float`` of a :class:`~efgkit.explicit.integrate.State` (``u^n``,
        ``v^{n-1/2}``, ``dt``), unforced runs.

    Raises
    ------
    ValueError
        ``A`` has an eigenvalue with an imaginary part or a negative real part beyond
        ``rtol`` times the largest modulus (no such energy exists).
    """
    free = dyn.minv > 0
    A = dense_operator(dyn)[np.ix_(free, free)]
    N = np.eye(A.shape[0])  # an orthonormal basis of the admissible y (G M^-1/2 y = 0)
    if dyn.projection is not None:
        N = scipy.linalg.null_space(dyn.projection.G.toarray()[:, free] * np.sqrt(dyn.minv[free]))
        A = N.T @ A @ N
    lam, V = scipy.linalg.eig(A)
    top = float(np.abs(lam).max())
    worst = int(np.argmax(np.maximum(np.abs(lam.imag), -lam.real)))
    if abs(lam[worst].imag) > rtol * top or lam[worst].real < -rtol * top:
        raise ValueError(f"M^-1 K has the eigenvalue {complex(lam[worst]):.6g} (largest modulus "
                         f"{top:.6g}), off the non-negative real axis beyond rtol = {rtol:g}: its mode "
                         "grows at every step and central differences conserve no positive energy "
                         "(docs/theory.md, 'Explicit MLPG'); a symmetric K (EFG) has none")
    Vi = np.linalg.inv(V.real) @ N.T
    lam = lam.real
    sm = np.sqrt(dyn.m[free])

    def energy(state) -> float:
        y1 = Vi @ (sm * state.u[free])
        y0 = Vi @ (sm * (state.u - state.dt * state.v)[free])
        ydot = (y1 - y0) / state.dt
        return float(0.5 * (ydot @ ydot + (lam * y1) @ y0))

    return energy
