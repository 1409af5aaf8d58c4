"""Static EFG solve: scene -> stiffness, loads, essential BCs -> coefficients.

A static scene builds no mass matrix and evaluates no shape-function
derivatives at traction points.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import replace

import numpy as np
from scipy.sparse import csr_array

from .approx.point_shapes import PointShapes
from .meshless_solution import MeshlessSolution
from .methods.boundary import (
    collocation_rows,
    eliminated_dofs,
    essential_conditions,
    gamma_u_term,
    loads,
    point_springs,
)
from .methods.discretize import Discretization, discretize
from .methods.efg import EFG
from .methods.mlpg import MLPG
from .methods.size import RELEASE_POINTS  # from here on the padded shape arrays are released
from .problem.graded import modulus_weights, refuse_grading
from .problem.scene import Scene
from .problem.symmetry import without_mirror_conditions
from .system.assemble import stiffness
from .system.auxiliary import AuxiliarySpace
from .system.collocation import collocation
from .system.constraints import (
    LinearSystem,
    eliminate,
    lagrange,
    modified_variational,
    penalty,
    rigid_body_modes,
)
from .system.linalg import AUTO_AMG_THRESHOLD, DENSE_SOLVE
from .system.linalg import solve as linear_solve
from .system.streamed import streamed_stiffness
from .timing import Stopwatch

__all__ = ["DEFAULT_PENALTY", "DEFAULT_STABILISATION", "LOCKING_PENALTY", "auxiliary_space",
           "constrained_system", "large_system_bc", "mlpg_auxiliary", "solve", "solve_mlpg"]

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


def large_system_bc(method: EFG, disc: Discretization, bc_was_auto: bool) -> EFG:
    """``method`` with bc="variational" (Nitsche) instead of the "lagrange" that ``bc="auto"``
    gives scenes with crack tips (:meth:`EFG.for_scene`), when the system is solved by CG:
    more than :data:`~efgkit.system.linalg.AUTO_AMG_THRESHOLD` unknowns and a solver other
    than "direct". Both are consistent (the penalty method is not: up to 13x the K error,
    docs/verification.md ``defaults``); on the cracked plate of 19.6k nodes Nitsche gave the
    same K_I to 2.3e-8 in 139 CG iterations against 172 in 2 Uzawa steps, 1.4x faster
    (docs/performance.md, ``benchmarks/bc_methods.py``). Otherwise ``method`` unchanged."""
    if (bc_was_auto and method.bc == "lagrange" and method.solver != "direct"
            and disc.n_dofs > AUTO_AMG_THRESHOLD):
        return replace(method, bc="variational")
    return method


def constrained_system(disc: Discretization, K, f: np.ndarray, method: EFG | None = None):
    """``K c = f`` with the scene's essential conditions imposed by ``method.bc`` (default
    ``disc.method``, as given by :meth:`EFG.for_scene`: ``bc`` not "auto"): the
    :class:`~efgkit.system.linear_system.LinearSystem` to solve."""
    m, mat = method or disc.method, disc.scene.material
    h = m.spacing
    check = getattr(disc, "images", None) is None  # half/quarter model: ImageTie.reduce checks
    if not check:
        disc = replace(disc, scene=without_mirror_conditions(disc.scene))
        if not (disc.scene.supports or disc.scene.point_supports):  # the tie holds them all
            return LinearSystem(csr_array(K), f, spd=True, n_coeffs=K.shape[0])
    if m.bc == "modified_mls":
        dofs, vals = eliminated_dofs(disc)
        springs = point_springs(disc, (m.penalty or DEFAULT_PENALTY) * mat.E)  # point supports
        return eliminate(K, f, dofs, vals, disc.nodes.x, springs)
    if m.bc == "collocation":  # Zhu and Atluri 1998: unsymmetric, solved by SuperLU
        if disc.scene.point_supports:
            raise ValueError(
                f"bc='collocation' takes supports on edges only, but scene {disc.scene.name!r} has "
                f"{len(disc.scene.point_supports)} point support(s): a point support is not a node "
                "whose equation could be replaced. Use bc='lagrange' (or 'penalty', 'variational', "
                "'modified_mls'), which impose point supports")
        rows, vals, dofs = collocation_rows(disc)
        return collocation(K - gamma_u_term(disc), f, rows, vals, dofs, disc.nodes.x)
    bc = essential_conditions(disc, derivatives=m.bc == "variational")
    if m.bc == "penalty":
        return penalty(K, f, bc, (m.penalty or DEFAULT_PENALTY) * mat.E / h, disc.nodes.x, check)
    if m.bc == "lagrange":
        return lagrange(K, f, bc, disc.nodes.x, check)
    beta = (m.penalty or DEFAULT_STABILISATION) * mat.E / h
    return modified_variational(K, f, bc, mat.D, beta, disc.nodes.x, check)


def solve(scene: Scene, method: EFG | MLPG, disc: Discretization | None = None, K=None,
          f=None) -> MeshlessSolution:
    """Solve a static scene with the EFG method (or MLPG: :func:`solve_mlpg`).

    Parameters
    ----------
    scene : Scene
    method : EFG
    disc : Discretization, optional
        Reuse a discretisation of the same scene and method.
    K, f : csr_array (n_dofs, n_dofs) and ndarray (n_dofs,), optional
        The stiffness and load vector of ``disc`` when already assembled (the incremental
        growth update, :mod:`efgkit.growth.incremental`); built from ``disc`` otherwise.

    Returns
    -------
    MeshlessSolution

    Raises
    ------
    RigidBodyModeError
        When the supports leave a rigid-body motion free.
    SingularRowsError
        bc="collocation" with linearly dependent constraint rows (two nodes at one point).
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
        refuse_grading(scene, "MLPG")
        return solve_mlpg(scene, method, disc)
    t_all = time.perf_counter()
    sw = Stopwatch()  # laps: stages that add up to the wall time, compilation apart
    bc_was_auto = method.bc == "auto"
    method = method.for_scene(scene)  # the automatic choices (tip zones, enrichment, bc)
    if method.bc == "penalty" and (method.penalty or DEFAULT_PENALTY) >= LOCKING_PENALTY:
        warnings.warn(
            f"penalty={method.penalty:g} (beta = penalty * E / h) with bc='penalty' over-constrains the "
            "supported edges (locking): on the Timoshenko cantilever the energy error was 2-6 times "
            "that of bc='lagrange' at 1e6 and 11-68 times (0.10-0.22) from 1e8 on, where CG's answer "
            "(solver='amg') can no longer be trusted either. Remedy: the default penalty=None (1e3), "
            "or bc='lagrange'", UserWarning, stacklevel=2)
    sw.lap("setup")
    own = disc is None
    if disc is None:  # the discretisation's stages are this call's (a given one's are not)
        disc = discretize(scene, method, chunked="auto")  # large: shape functions in chunks
        sw = Stopwatch(disc.timings | {k: v + disc.timings.get(k, 0.0) for k, v in sw.timings.items()})
    method = large_system_bc(method, disc, bc_was_auto)  # CG-sized: Nitsche for Lagrange
    if method is not disc.method and method.bc != disc.method.bc:
        disc = replace(disc, method=method)  # the solution reports the bc it was solved with
    mat, m = scene.material, method
    streamed = isinstance(disc.shape, PointShapes)  # formed, assembled and dropped a chunk at a time
    if own and not streamed and disc.points.n >= RELEASE_POINTS and scene.body_force is None:
        disc = replace(disc, shape=disc.shape.without_values())  # the stiffness needs no values
    if K is None:
        wq = modulus_weights(disc.scene, disc.points.x, disc.points.w)
        K = streamed_stiffness(disc.shape, wq, mat.D, clock=sw) if streamed else \
            stiffness(disc.shape, wq, mat.D)
        del wq
    sw.lap("stiffness")
    f = loads(disc) if f is None else f
    sw.lap("loads")
    if own and not streamed and disc.points.n >= RELEASE_POINTS:  # post-processing: derivatives
        disc = replace(disc, shape=disc.shape.gradients_only())
        sw.lap("release")
    system = constrained_system(disc, K, f, m)
    sw.lap("constraints")
    modes = np.zeros((disc.n_dofs, 3))
    modes[: 2 * disc.nodes.n] = rigid_body_modes(disc.nodes.x)
    aux, solver = (lambda: auxiliary_space(disc)), m.solver
    if disc.images is not None:  # a half or quarter model: image coefficients tied (system.images);
        # no auxiliary space for the tied (component-wise) functions: "auto" is SuperLU
        system, modes, aux, K = disc.images.reduce(system), disc.images.part_modes(modes), None, None
        solver = "direct" if solver == "auto" else solver
    z, info = linear_solve(system, solver, near_nullspace=modes, auxiliary=aux, stiffness=K,
                           dense=DENSE_SOLVE)  # small SPD: dense Cholesky (full enrichment columns)
    coefficients = system.coefficients(z)
    forces = system.support_forces(z) if system.support_forces is not None else None
    sw.lap("solve")
    timings = sw.timings | {"total": time.perf_counter() - t_all}
    return MeshlessSolution(disc, coefficients, info, timings,
                            resolve=lambda coarse: solve(scene, coarse), support_forces=forces)


def solve_mlpg(scene: Scene, method: MLPG, disc: Discretization | None = None) -> MeshlessSolution:
    """Solve a static scene with MLPG1 (seed 002 Eqs. 20-24, :mod:`efgkit.methods.local`).

    bc="penalty": the penalty term is part of the local weak forms; "modified_mls": the
    coefficients of the essential nodes are the prescribed values (row cross-out,
    :func:`~efgkit.system.constraints.eliminate`); "collocation": the equations of the
    essential nodes are replaced by u^h_c(x_I) = ubar_c(x_I)
    (:func:`~efgkit.system.collocation.collocation`). The unsymmetric system goes to
    :func:`~efgkit.system.krylov.solve_unsymmetric` (SuperLU, GMRES or BiCGSTAB with ILU, or
    GMRES with the multigrid preconditioner of :mod:`efgkit.system.krylov_mlpg`, whose nodal
    data :func:`mlpg_auxiliary` gives on demand).

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
    from .methods.local import DEFAULT_MLPG_PENALTY, discretize_local, local_system
    from .system.constraints import check_rigid_modes
    from .system.krylov import solve_unsymmetric
    from .system.linear_system import LinearSystem

    t_all = time.perf_counter()
    sw = Stopwatch()  # laps: stages that add up to the wall time, compilation apart
    method = method.for_scene(scene)
    sw.lap("setup")
    if disc is None:  # the discretisation's stages are this call's (a given one's are not)
        disc = discretize_local(scene, method)
        sw = Stopwatch(disc.timings | {k: v + disc.timings.get(k, 0.0) for k, v in sw.timings.items()})
    mat, m = scene.material, method
    alpha = (m.penalty or DEFAULT_MLPG_PENALTY) * mat.E / m.spacing if m.bc == "penalty" else None
    K, f = local_system(disc, alpha)
    sw.lap("stiffness")
    if m.bc == "penalty":
        check_rigid_modes(_fixed_operator(disc.local), disc.nodes.x)
        system = LinearSystem(K, f, spd=False, n_coeffs=K.shape[0])
    else:
        dofs, vals = eliminated_dofs(disc)
        if m.bc == "modified_mls":
            system = replace(eliminate(K, f, dofs, vals, disc.nodes.x), spd=False)
        else:  # collocation checks the rows for rigid-body modes itself
            system = collocation(K, f, _nodal_rows(disc, dofs), vals, dofs, disc.nodes.x)
    sw.lap("constraints")
    z, info = solve_unsymmetric(system, m.solver, auxiliary=lambda: mlpg_auxiliary(disc, m.bc))
    coefficients = system.coefficients(z)
    sw.lap("solve")
    timings = sw.timings | {"total": time.perf_counter() - t_all}
    return MeshlessSolution(disc, coefficients, info, timings,
                            resolve=lambda coarse: solve(scene, coarse))


def mlpg_auxiliary(disc: Discretization, bc: str):
    """The nodal data of the MLPG multigrid preconditioner (:mod:`efgkit.system.krylov_mlpg`):
    :func:`auxiliary_space` and the coefficients whose rows are boundary rows -- both components
    of the nodes whose discs carry the penalty term (bc="penalty") or of the essential nodes
    (bc="collocation": their rows are replaced); none for "modified_mls" (eliminated)."""
    loc = disc.local
    if bc == "penalty":
        hit = loc.fixed.any(axis=1) & (True if loc.penalised is None else loc.penalised)
        nodes = np.unique(loc.points.owner[hit])
    elif bc == "collocation":
        nodes = np.unique(eliminated_dofs(disc)[0] // 2)
    else:
        nodes = np.zeros(0, dtype=np.int64)
    return auxiliary_space(disc), (2 * nodes[:, None] + np.arange(2)).ravel()


def _fixed_operator(loc) -> csr_array:
    """Rows (boundary point, fixed component) of u^h at the penalised supported pieces
    (those of the discs of nodes on Gamma_u, :meth:`LocalBoundary.penalty_mask`)."""
    Ux, Uy = loc.trial.u_operators()
    q, c = np.nonzero(np.column_stack([loc.penalty_mask(0), loc.penalty_mask(1)]) > 0)
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
