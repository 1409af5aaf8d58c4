"""Linear displacement patch test (seed 003 Sect. 3; a consistency requirement of any
Galerkin method): a linear field prescribed on the whole boundary of the unit
square must be reproduced inside, on regular and perturbed clouds, for every
weight and essential-BC method. Background-cell quadrature of MLS functions
is not exact, so the error is also reported against the Gauss order.

``bc="collocation"`` (Zhu and Atluri 1998) is also run without its Gamma_u boundary
term (``collocation_without_boundary_term``): the consistency argument of docs/theory.md
says the patch test then fails, and it does. The boundary-only transformation method
(Chen et al. 1996; Chen and Wang 2000), the alternative it was chosen over, is run with and
without the same term (``transformation``; not an efgkit method, a comparison).
"""

from __future__ import annotations

import numpy as np
from _report import Report
from scipy.sparse import csc_array
from scipy.sparse.linalg import splu

from efgkit import EFG, Domain, Elastic, Scene, Support
from efgkit.meshless_solution import MeshlessSolution
from efgkit.methods.boundary import collocation_rows, gamma_u_term, loads
from efgkit.methods.discretize import discretize
from efgkit.static import solve
from efgkit.system.assemble import stiffness
from efgkit.system.collocation import collocation
from efgkit.system.linalg import solve as linear_solve

NAME = "patch"
A = np.array([[1e-3, 2e-3, -1e-3], [-2e-3, 1e-3, 3e-3]])  # u_c = A[c] . (1, x, y)
MATERIAL = Elastic(1000.0, 0.3, "stress")
CLOUDS = {"regular": dict(perturb=0.0), "perturbed": dict(perturb=0.3, seed=7)}
WEIGHTS = ("quartic", "gaussian", "cubic")
BCS = ("penalty", "lagrange", "variational", "modified_mls", "collocation")
# The penalty method's consistency error is ~ E / (beta h): the patch test needs a large
# beta, which on non-polynomial boundary data over-constrains (the default is 1e3).
PATCH_PENALTY = 1e8
# Quadrature reaching 1e-6 on perturbed clouds (see the order study): MLS functions
# have kinks where support circles cross a cell, so cells of h/4 help more than order.
RECOMMENDED = {"cell_fraction": 0.25, "order": 8}


def exact(x):
    """Linear field (n, 2) and its constant stress (n, 3)."""
    u = np.column_stack([A[c, 0] + A[c, 1] * x[:, 0] + A[c, 2] * x[:, 1] for c in (0, 1)])
    eps = np.array([A[0, 1], A[1, 2], A[0, 2] + A[1, 1]])
    return u, np.tile(MATERIAL.D @ eps, (len(x), 1))


def scene() -> Scene:
    supports = tuple(
        Support(edge, ux=lambda x: exact(x)[0][:, 0], uy=lambda x: exact(x)[0][:, 1])
        for edge in ("bottom", "right", "top", "left")
    )
    return Scene(Domain.rectangle(0, 0, 1, 1), MATERIAL, supports=supports, name=NAME)


def errors(sol, x) -> tuple[float, float]:
    u, s = exact(x)
    eu = np.abs(sol.displacement(x) - u).max() / np.abs(u).max()
    es = np.abs(sol.stress(x) - s).max() / np.abs(s).max()
    return float(eu), float(es)


def without_boundary_term(sc: Scene, m: EFG) -> MeshlessSolution:
    """bc="collocation" with K in place of K - H (the Gamma_u term dropped): inconsistent."""
    disc = discretize(sc, m)
    K = stiffness(disc.shape, disc.points.w, sc.material.D)
    rows, vals, dofs = collocation_rows(disc)
    system = collocation(K, loads(disc), rows, vals, dofs, disc.nodes.x)
    z, info = linear_solve(system, "direct")
    return MeshlessSolution(disc, system.coefficients(z), info, {}, resolve=None)


def transformation(sc: Scene, m: EFG, boundary_term: bool) -> MeshlessSolution:
    """Boundary-only transformation method (Chen et al. 1996; Chen and Wang 2000).

    The coefficients ``c_B`` of the constrained components are replaced by the nodal values
    ``g = Phi_BB c_B + Phi_BO c_O`` (the collocation rows), so ``c = c0 + T c_O`` with
    ``T = [-Phi_BB^-1 Phi_BO; I]``, ``c0 = [Phi_BB^-1 g; 0]``; the Galerkin equations are
    tested with ``T^T``: ``T^T A T c_O = T^T (f - A c0)``, ``A = K`` or ``K - H``. Dense
    (patch-test sizes only).
    """
    disc = discretize(sc, m)
    A = stiffness(disc.shape, disc.points.w, sc.material.D)
    A = A - gamma_u_term(disc) if boundary_term else A
    rows, g, dofs = collocation_rows(disc)
    n = A.shape[0]
    other = np.setdiff1d(np.arange(n), dofs)
    lu = splu(csc_array(rows[:, dofs]))
    T = np.zeros((n, len(other)))
    T[dofs] = -lu.solve(rows[:, other].toarray())
    T[other] = np.eye(len(other))
    c = np.zeros(n)
    c[dofs] = lu.solve(g)
    c = c + T @ np.linalg.solve(T.T @ (A @ T), T.T @ (loads(disc) - A @ c))
    return MeshlessSolution(disc, c, {"solver": "dense"}, {}, resolve=None)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    h = 0.2 if quick else 0.1
    x = np.random.default_rng(0).uniform(0.02, 0.98, (400, 2))
    sc = scene()
    table = {}
    for cloud, opts in CLOUDS.items():
        for weight in WEIGHTS:
            for bc in BCS:
                d_max = 2.5 if bc == "modified_mls" else 2.0
                m = EFG(spacing=h, d_max=d_max, weight=weight, alpha=d_max / 4, bc=bc,
                        order=RECOMMENDED["order"], cell_size=h * RECOMMENDED["cell_fraction"],
                        penalty=PATCH_PENALTY if bc == "penalty" else None, **opts)
                eu, es = errors(solve(sc, m), x)
                table[f"{cloud}/{weight}/{bc}"] = {"max_rel_disp_error": eu,
                                                   "max_rel_stress_error": es}
    rep.metrics["errors"] = table
    orders = (2, 4, 8) if quick else (1, 2, 3, 4, 5, 6, 8, 10)
    study = {}
    for cloud, opts in CLOUDS.items():
        for frac in (1.0, 0.25):
            for order in orders:
                m = EFG(spacing=h, bc="lagrange", order=order, cell_size=h * frac, **opts)
                eu, es = errors(solve(sc, m), x)
                study[f"{cloud}/cell{frac:g}h/order{order}"] = {"max_rel_disp_error": eu,
                                                                "max_rel_stress_error": es}
    rep.metrics["order_study"] = study
    m = EFG(spacing=h, bc="penalty", order=RECOMMENDED["order"],
            cell_size=h * RECOMMENDED["cell_fraction"], **CLOUDS["perturbed"])
    eu, es = errors(solve(sc, m), x)
    rep.metrics["penalty_default_beta"] = {"max_rel_disp_error": eu, "max_rel_stress_error": es}
    dropped = {}
    for cloud, opts in CLOUDS.items():
        m = EFG(spacing=h, bc="collocation", order=RECOMMENDED["order"],
                cell_size=h * RECOMMENDED["cell_fraction"], **opts)
        eu, es = errors(without_boundary_term(sc, m), x)
        dropped[cloud] = {"max_rel_disp_error": eu, "max_rel_stress_error": es}
        # Not a bound on an error of efgkit: the check that the consistency argument holds (the
        # term matters). Measured 2.0e-3 (regular) and 1.6e-2 (perturbed) at h = 0.1; 3.7e-3 and
        # 4.3e-2 at h = 0.2 (quick).
        rep.check(f"collocation without the Gamma_u term fails ({cloud})", eu, ">=", 1e-4)
    rep.metrics["collocation_without_boundary_term"] = dropped
    compared = {}
    for cloud, opts in CLOUDS.items():
        m = EFG(spacing=h, bc="collocation", order=RECOMMENDED["order"],
                cell_size=h * RECOMMENDED["cell_fraction"], **opts)
        for term in (True, False):
            eu, es = errors(transformation(sc, m, term), x)
            compared[f"{cloud}/{'with' if term else 'without'}_boundary_term"] = {
                "max_rel_disp_error": eu, "max_rel_stress_error": es}
    rep.metrics["transformation"] = compared
    rep.metrics["settings"] = {"spacing": h, "cell_size": h * RECOMMENDED["cell_fraction"],
                               "order": RECOMMENDED["order"], "d_max": 2.0,
                               "modified_mls_d_max": 2.5, "penalty_beta_h_over_E": PATCH_PENALTY}
    rep.ref("max_rel_disp_error", 0.0, "exact linear field (consistency of the Galerkin method)")
    for key, val in table.items():
        if key.endswith("modified_mls"):
            continue  # seed 002's modified MLS is not conforming: reported, not bounded
        rep.check(f"{key} displacement", val["max_rel_disp_error"], "<=", 1e-6)
        rep.check(f"{key} stress", val["max_rel_stress_error"], "<=", 1e-5)
    return rep.write(out_dir)


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"], indent=1))
