"""Static EFG solve: scene -> stiffness, loads, essential BCs -> coefficients.

A static scene builds no mass matrix and evaluates no shape-function
derivatives at traction points.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
from scipy.sparse import csr_array

from .meshless_solution import MeshlessSolution
from .methods.boundary import eliminated_dofs, essential_conditions, loads
from .methods.discretize import Discretization, discretize
from .methods.efg import EFG
from .methods.mlpg import MLPG
from .problem.scene import Scene
from .system.assemble import stiffness
from .system.auxiliary import AuxiliarySpace
from .system.constraints import eliminate, lagrange, modified_variational, penalty, rigid_body_modes
from .system.linalg import solve as linear_solve

__all__ = ["DEFAULT_PENALTY", "DEFAULT_STABILISATION", "LOCKING_PENALTY", "auxiliary_space", "solve",
           "solve_mlpg"]

# beta h / E of the penalty method. Its consistency error falls like E / (beta h), but
# beta -> infinity is a Lagrange method with one multiplier per boundary Gauss point,
# which over-constrains (locks) whenever ubar is not in the trace space: on the
# cantilever the energy error is lowest for 1e2-1e3 and 20x worse at 1e8 (docs/theory.md).
DEFAULT_PENALTY = 1e3
DEFAULT_STABILISATION = 1e2  # beta h / E of the Nitsche term in the variational method
# bc="penalty" warns from this beta h / E on. Energy error over bc="lagrange"'s on the Timoshenko
# cantilever (48 x 12, E = 3e7, 6-48 spacings through the depth; and 8 x 2, 16 spacings), SuperLU:
# 1.00-1.04 at 1e3, 1.1-2.5 at 1e5, 2.2-6.2 at 1e6, 11-68 (energy error 0.10-0.22) from 1e8 to 1e14.
LOCKING_PENALTY = 1e6


def auxiliary_space(disc: Discretization) -> AuxiliarySpace:
    """The nodal data of the auxiliary-space preconditioner (:mod:`efgkit.system.auxiliary`):
    node positions nudged onto their crack face, the shape functions there, the elasticity
    matrix, the domain and the crack segments."""
    x = disc.nodes.face_positions(disc.approx.lines, 1e-3)
    phi = csr_array(disc.shape_at(x, derivatives=False).phi)[:, : len(x)]
    cracks = disc.scene.cracks
    cuts = np.concatenate([c.segments for c in cracks]) if cracks else None
    return AuxiliarySpace(x, phi, disc.scene.material.D, disc.scene.domain, cuts)


def solve(scene: Scene, method: EFG | MLPG, disc: Discretization | None = None) -> MeshlessSolution:
    """Solve a static scene with the EFG method (or MLPG: :func:`solve_mlpg`).

    Parameters
    ----------
    scene : Scene
    method : EFG
    disc : Discretization, optional
        Reuse a discretisation of the same scene and method.

    Returns
    -------
    MeshlessSolution

    Raises
    ------
    RigidBodyModeError
        When the supports leave a rigid-body motion free.
    SolverError
        When the linear solve fails its residual check, or CG's answer (solver="amg") its
        energy-error bound (:func:`efgkit.system.linalg.solve`).

    Warns
    -----
    UserWarning
        bc="penalty" with ``penalty >= LOCKING_PENALTY`` (1e6): the boundary locks.

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic, Scene, Support, Traction
    >>> scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.25, "stress"),
    ...               supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
    ...               tractions=(Traction("right", (1.0, 0.0)),))
    >>> sol = solve(scene, EFG(spacing=0.25, bc="lagrange"))
    >>> round(float(sol.displacement([[2.0, 0.5]])[0, 0]), 6)   # sigma L / E = 0.002
    0.002
    """
    if isinstance(method, MLPG):
        return solve_mlpg(scene, method, disc)
    t_all = time.perf_counter()
    method = method.for_scene(scene)  # the automatic choices (tip zones, enrichment, bc)
    if method.bc == "penalty" and (method.penalty or DEFAULT_PENALTY) >= LOCKING_PENALTY:
        warnings.warn(
            f"penalty={method.penalty:g} (beta = penalty * E / h) with bc='penalty' over-constrains the "
            "supported edges (locking): on the Timoshenko cantilever the energy error was 2-6 times "
            "that of bc='lagrange' at 1e6 and 11-68 times (0.10-0.22) from 1e8 on, where CG's answer "
            "(solver='amg') can no longer be trusted either. Remedy: the default penalty=None (1e3), "
            "or bc='lagrange'", UserWarning, stacklevel=2)
    disc = discretize(scene, method) if disc is None else disc
    timings = dict(disc.timings)
    mat, m = scene.material, method
    t0 = time.perf_counter()
    K = stiffness(disc.shape, disc.points.w, mat.D)
    timings["stiffness"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    f = loads(disc)
    timings["loads"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    h = m.spacing
    if m.bc == "modified_mls":
        dofs, vals = eliminated_dofs(disc)
        system = eliminate(K, f, dofs, vals, disc.nodes.x)
    else:
        bc = essential_conditions(disc, derivatives=m.bc == "variational")
        if m.bc == "penalty":
            system = penalty(K, f, bc, (m.penalty or DEFAULT_PENALTY) * mat.E / h, disc.nodes.x)
        elif m.bc == "lagrange":
            system = lagrange(K, f, bc, disc.nodes.x)
        else:
            beta = (m.penalty or DEFAULT_STABILISATION) * mat.E / h
            system = modified_variational(K, f, bc, mat.D, beta, disc.nodes.x)
    timings["constraints"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    modes = np.zeros((disc.n_dofs, 3))
    modes[: 2 * disc.nodes.n] = rigid_body_modes(disc.nodes.x)
    z, info = linear_solve(system, m.solver, near_nullspace=modes,
                                auxiliary=lambda: auxiliary_space(disc), stiffness=K)
    timings["solve"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_all + sum(disc.timings.values())
    return MeshlessSolution(disc, system.coefficients(z), info, timings,
                            resolve=lambda coarse: solve(scene, coarse))


def solve_mlpg(scene: Scene, method: MLPG, disc: Discretization | None = None) -> MeshlessSolution:
    """Solve a static scene with MLPG1 (seed 002 Eqs. 20-24, :mod:`efgkit.methods.local`).

    bc="penalty": the penalty term is part of the local weak forms; "modified_mls": the
    coefficients of the essential nodes are the prescribed values (row cross-out,
    :func:`~efgkit.system.constraints.eliminate`); "collocation": the equations of the
    essential nodes are replaced by u^h_c(x_I) = ubar_c(x_I)
    (:func:`~efgkit.system.collocation.collocation`). The unsymmetric system goes to
    :func:`~efgkit.system.krylov.solve_unsymmetric` (SuperLU, GMRES or BiCGSTAB).

    Examples
    --------
    >>> from efgkit import Domain, Elastic, Scene, Support, Traction
    >>> scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.25, "stress"),
    ...               supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
    ...               tractions=(Traction("right", (1.0, 0.0)),))
    >>> sol = solve(scene, MLPG(spacing=0.25))
    >>> round(float(sol.displacement([[2.0, 0.5]])[0, 0]), 6)   # sigma L / E = 0.002
    0.002
    """
    from dataclasses import replace

    from .methods.boundary import eliminated_dofs
    from .methods.local import DEFAULT_MLPG_PENALTY, discretize_local, local_system
    from .system.collocation import collocation
    from .system.constraints import LinearSystem, check_rigid_modes, eliminate
    from .system.krylov import solve_unsymmetric

    t_all = time.perf_counter()
    method = method.for_scene(scene)
    disc = discretize_local(scene, method) if disc is None else disc
    timings = dict(disc.timings)
    mat, m = scene.material, method
    t0 = time.perf_counter()
    alpha = (m.penalty or DEFAULT_MLPG_PENALTY) * mat.E / m.spacing if m.bc == "penalty" else None
    K, f = local_system(disc, alpha)
    timings["stiffness"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    if m.bc == "penalty":
        loc = disc.local
        check_rigid_modes(_fixed_operator(loc), disc.nodes.x)
        system = LinearSystem(K, f, spd=False, n_coeffs=K.shape[0])
    else:
        dofs, vals = eliminated_dofs(disc)
        if m.bc == "modified_mls":
            system = replace(eliminate(K, f, dofs, vals, disc.nodes.x), spd=False)
        else:
            rows = _nodal_rows(disc, dofs)
            check_rigid_modes(rows, disc.nodes.x)
            system = collocation(K, f, rows, vals, dofs)
    timings["constraints"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    z, info = solve_unsymmetric(system, m.solver)
    timings["solve"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_all + sum(disc.timings.values())
    return MeshlessSolution(disc, system.coefficients(z), info, timings,
                            resolve=lambda coarse: solve(scene, coarse))


def _fixed_operator(loc) -> csr_array:
    """Rows (boundary point, fixed component) of u^h at the sub-domains' supported pieces."""
    Ux, Uy = loc.trial.u_operators()
    q, c = np.nonzero(loc.fixed)
    from scipy.sparse import vstack

    n = loc.fixed.shape[0]
    return csr_array(vstack([Ux, Uy], format="csr")[c * n + q])


def _nodal_rows(disc: Discretization, dofs: np.ndarray) -> csr_array:
    """u^h_c(x_I) for the equations ``dofs = 2 I + c``: rows (len(dofs), n_dofs)."""
    from scipy.sparse import vstack

    nodes = dofs // 2
    x = disc.nodes.face_positions(disc.approx.lines, 1e-3)[nodes]
    Ux, Uy = disc.shape_at(x, derivatives=False).u_operators()
    k = len(nodes)
    return csr_array(vstack([Ux, Uy], format="csr")[(dofs % 2) * k + np.arange(k)])
