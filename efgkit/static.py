"""Static EFG solve: scene -> stiffness, loads, essential BCs -> coefficients.

A static scene builds no mass matrix and evaluates no shape-function
derivatives at traction points.
"""

from __future__ import annotations

import time

import numpy as np

from .approx.mls import mls_shape
from .assemble import load_vector, stiffness
from .constraints import (
    Dirichlet,
    eliminate,
    lagrange,
    modified_variational,
    penalty,
    rigid_body_modes,
)
from .discretize import (
    Discretization,
    boundary_segments_for,
    discretize,
    edge_rule,
    essential_nodes,
    support_edges,
)
from .linalg import solve as linear_solve
from .methods import EFG
from .quadrature import boundary_points
from .scene import Scene, evaluate_component, evaluate_vector
from .search import find_neighbours
from .solution import Solution

__all__ = ["solve", "loads", "essential_conditions", "DEFAULT_PENALTY", "DEFAULT_STABILISATION"]

# beta h / E of the penalty method. Its consistency error falls like E / (beta h), but
# beta -> infinity is a Lagrange method with one multiplier per boundary Gauss point,
# which over-constrains (locks) whenever ubar is not in the trace space: on the
# cantilever the energy error is lowest for 1e2-1e3 and 20x worse at 1e8 (docs/theory.md).
DEFAULT_PENALTY = 1e3
DEFAULT_STABILISATION = 1e2  # beta h / E of the Nitsche term in the variational method


def _shape(disc: Discretization, x, derivatives):
    m = disc.method
    nb = find_neighbours(x, disc.nodes, disc.boxes)
    return mls_shape(x, disc.nodes, m.weight, m.basis, d_max=m.d_max, alpha=m.alpha,
                     derivatives=derivatives, neighbours=nb, interpolate=disc.interpolate)


def loads(disc: Discretization) -> np.ndarray:
    """External force vector from tractions and body force, shape (2 n_nodes,)."""
    scene, m = disc.scene, disc.method
    f = np.zeros(2 * disc.nodes.n)
    order = max(m.order, 2)
    for tr in scene.tractions:
        pts = boundary_points(scene.domain, tr.edge, order, m.spacing)
        if pts.n == 0:
            continue
        t = evaluate_vector(tr.t, pts.x, pts.normal, scene.material)
        f += load_vector(_shape(disc, pts.x, False), pts.w, t)
    if scene.body_force is not None:
        b = evaluate_vector(scene.body_force, disc.points.x, np.zeros_like(disc.points.x),
                            scene.material)
        f += load_vector(disc.shape, disc.points.w, b)
    return f


def essential_conditions(disc: Discretization, derivatives: bool) -> Dirichlet:
    """Prescribed displacements sampled by a Gauss rule on the supported edges."""
    scene, m = disc.scene, disc.method
    parts, seg0, hat0 = [], 0, 0
    for sup in scene.supports:
        for e in support_edges(scene.domain, sup.edge):
            nseg = boundary_segments_for(e, disc.nodes, m.spacing)
            x, w, nrm, seg, t = edge_rule(e, nseg, max(m.order, 2))
            keep = np.ones(len(x), bool) if isinstance(sup.edge, str) else np.asarray(
                sup.edge(x), bool)
            fixed = np.zeros((len(x), 2), bool)
            value = np.zeros((len(x), 2))
            for c, v in enumerate((sup.ux, sup.uy)):
                if v is not None:
                    fixed[:, c] = keep
                    value[:, c] = evaluate_component(v, x, c, scene.material)
            seg_nodes = hat0 + np.column_stack([np.arange(nseg), np.arange(1, nseg + 1)])
            parts.append((x, w, nrm, fixed, value, seg + seg0, t, seg_nodes))
            seg0 += nseg
            hat0 += nseg + 1
    if not parts:
        x = np.zeros((0, 2))
        return Dirichlet(x, np.zeros(0), x, _shape(disc, x, derivatives), np.zeros((0, 2), bool),
                         x, np.zeros(0, int), np.zeros(0), np.zeros((0, 2), int))
    cat = [np.concatenate([p[i] for p in parts]) for i in range(8)]
    x = cat[0]
    return Dirichlet(x, cat[1], cat[2], _shape(disc, x, derivatives), cat[3], cat[4], cat[5],
                     cat[6], cat[7])


def _eliminated_dofs(disc: Discretization):
    """Coefficient indices and values of the modified-MLS essential nodes (row cross-out)."""
    scene = disc.scene
    dofs, vals = [], []
    for sup in scene.supports:
        on = essential_nodes(scene.with_supports((sup,)), disc.nodes, disc.method.spacing)
        idx = np.flatnonzero(on)
        for c, v in enumerate((sup.ux, sup.uy)):
            if v is not None and len(idx):
                dofs.append(2 * idx + c)
                vals.append(evaluate_component(v, disc.nodes.x[idx], c, scene.material))
    if not dofs:
        return np.zeros(0, int), np.zeros(0)
    dofs, vals = np.concatenate(dofs), np.concatenate(vals)
    dofs, first = np.unique(dofs, return_index=True)  # a node on two supports: first wins
    return dofs, vals[first]


def solve(scene: Scene, method: EFG, disc: Discretization | None = None) -> Solution:
    """Solve a static scene with the EFG method.

    Parameters
    ----------
    scene : Scene
    method : EFG
    disc : Discretization, optional
        Reuse a discretisation of the same scene and method.

    Returns
    -------
    Solution

    Raises
    ------
    RigidBodyModeError
        When the supports leave a rigid-body motion free.
    SolverError
        When the linear solve fails its residual check.

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
    if scene.cracks:
        raise NotImplementedError(
            f"scene {scene.name!r} has {len(scene.cracks)} crack(s), but this version has no crack "
            "rules yet (visibility, diffraction, ...): solving would ignore the crack. Remove the "
            "cracks or wait for the crack module."
        )
    t_all = time.perf_counter()
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
        dofs, vals = _eliminated_dofs(disc)
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
    z, info = linear_solve(system, m.solver, near_nullspace=rigid_body_modes(disc.nodes.x),
                           discretization=disc, stiffness=K)
    timings["solve"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_all + sum(disc.timings.values())
    return Solution(disc, system.coefficients(z), info, timings)
