"""Linear solvers: CG with the auxiliary-space preconditioner agrees with SuperLU for
every SPD essential-BC method, residuals and error bounds are checked, and bad systems raise."""

import re
import warnings

import numpy as np
import pytest
from scipy.sparse import csr_array

from efgkit import EFG, Domain, Elastic, Loop, Scene, Support, Traction, solve
from efgkit.methods.boundary import essential_conditions, loads
from efgkit.system import linalg
from efgkit.system.assemble import stiffness
from efgkit.system.auxiliary import chebyshev_inverse, p1_stiffness
from efgkit.system.constraints import penalty, rigid_body_modes
from efgkit.system.linalg import ERROR_FACTOR, SolverError
from efgkit.system.linalg import solve as linear_solve
from efgkit.system.linear_system import LinearSystem


def _plate(hole=False):
    holes = [Loop.circle([1.0, 0.5], 0.2)] if hole else []
    return Scene(Domain.rectangle(0, 0, 2, 1, holes=holes), Elastic(1000.0, 0.3, "stress"),
                 supports=(Support("left", ux=0.0, uy=0.0),),
                 tractions=(Traction("right", (0.3, -1.0)),))


@pytest.mark.parametrize("bc", ["penalty", "variational", "modified_mls"])
@pytest.mark.parametrize("hole", [False, True])
def test_cg_with_auxiliary_preconditioner_matches_direct(bc, hole):
    scene = _plate(hole)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # modified_mls warns for EFG
        direct = solve(scene, EFG(spacing=0.04, bc=bc, solver="direct"))
        it = solve(scene, EFG(spacing=0.04, bc=bc, solver="amg"), disc=direct.disc)
    assert it.info["preconditioner"] == "auxiliary" and it.info["converged"]
    # Both residuals are checked against rtol = 1e-8; the solutions agree accordingly.
    rel = np.linalg.norm(it.coeffs - direct.coeffs) / np.linalg.norm(direct.coeffs)
    assert rel < 1e-6
    # The energy-error bound that certifies CG's answer (measured 1.7e-10 to 2.8e-10).
    assert it.info["error_bound"] < 1e-9
    # A good preconditioner: the iteration count stays small (about 30-50 here).
    assert it.info["iterations"] < 150


@pytest.mark.parametrize("hole", [False, True])
def test_lagrange_by_uzawa_steps_matches_direct(hole):
    """solver="amg" on the Lagrange saddle point: Uzawa steps on the augmented Lagrangian,
    each a CG solve with the auxiliary-space preconditioner, give the multiplier solution."""
    scene = _plate(hole)
    direct = solve(scene, EFG(spacing=0.04, bc="lagrange", solver="direct"))
    it = solve(scene, EFG(spacing=0.04, bc="lagrange", solver="amg"), disc=direct.disc)
    assert it.info["preconditioner"] == "auxiliary" and it.info["converged"]
    assert it.info["residual"] <= 1e-8 and it.info["uzawa_steps"] <= 5
    rel = np.linalg.norm(it.coeffs - direct.coeffs) / np.linalg.norm(direct.coeffs)
    assert rel < 1e-6
    assert it.info["error_bound"] < 1e-9  # measured 1.9e-10 and 2.8e-10


def test_cracked_square_with_one_node_aggregates():
    """The edge-cracked square of seed 003 Sect. 5.6.1 on 61 x 61 nodes: the coarsest
    multigrid level is singular (measured: LU fails, 'Factor is exactly singular'), and the
    pseudo-inverse takes over; penalty and Lagrange both converge. With the Williams field
    prescribed on every edge the default penalty has the largest energy-error bound seen at
    default settings (measured 1.3e-4, true error 5.7e-5), still below ERROR_FACTOR * rtol."""
    from efgkit import Crack, Field

    W = Field.named("williams", KI=1.0)
    scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
                  supports=tuple(Support(e, ux=W, uy=W) for e in ("left", "bottom", "right", "top")),
                  cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]], tips=(False, True)),))
    # pyamg's setup draws from numpy's global random state, so the bound varies from run to run
    # (measured over seeds 0-4 and unseeded runs: penalty 1.32e-4 to 1.33e-4, Lagrange 1.41e-7 to
    # 3.0e-7); seeded here so that the test is repeatable, bounds ~3x the seeded values.
    for bc, bound in (("penalty", 4e-4), ("lagrange", 4.5e-7)):  # measured 1.33e-4, 1.41e-7 (seed 0)
        np.random.seed(0)  # noqa: NPY002 (pyamg draws from the legacy global generator)
        sol = solve(scene, EFG(spacing=2 / 60, bc=bc, solver="amg"))
        assert sol.info["converged"] and sol.info["residual"] <= 1e-8, bc
        assert sol.info["error_bound"] < min(bound, ERROR_FACTOR * 1e-8), bc


def test_coarse_solver_falls_back_to_the_pseudo_inverse():
    from efgkit.system.auxiliary import coarse_solver

    A = csr_array(np.array([[2.0, -2.0, 0.0], [-2.0, 2.0, 0.0], [0.0, 0.0, 1.0]]))  # singular
    b = np.array([1.0, -1.0, 3.0])  # in the range of A
    x = coarse_solver(A).solve(b)
    assert np.allclose(A @ x, b) and abs(x[0] + x[1]) < 1e-12  # minimum-norm solution
    assert np.allclose(coarse_solver(csr_array(np.diag([2.0, 4.0]))).solve(np.ones(2)), [0.5, 0.25])


def test_smoothed_aggregation_without_discretisation():
    scene = _plate()
    sol = solve(scene, EFG(spacing=0.1, bc="penalty", solver="direct"))
    d = sol.disc
    K = stiffness(d.shape, d.points.w, scene.material.D)
    system = penalty(K, loads(d), essential_conditions(d, False), 1e3 * 1000.0 / 0.1, d.nodes.x)
    z, info = linear_solve(system, "amg", near_nullspace=rigid_body_modes(d.nodes.x))
    assert info["preconditioner"] == "smoothed_aggregation" and info["residual"] <= 1e-8


def _cantilever():
    """The Timoshenko cantilever of verification/cantilever.py: 48 x 12, E = 3e7, end shear 1000."""
    from efgkit import Field

    f = Field.named("cantilever", L=48.0, D=12.0, P=1000.0)
    return Scene(Domain.rectangle(0.0, -6.0, 48.0, 6.0), Elastic(3e7, 0.3, "stress"),
                 supports=(Support("left", ux=f, uy=f),), tractions=(Traction("right", f),), exact=f)


def _tip_uy(sol):
    return float(sol.displacement([[48.0, 0.0]])[0, 1])


@pytest.mark.filterwarnings(r"ignore:penalty=1e\+10:UserWarning")  # the locking warning: test_static
def test_large_penalty_cg_answer_refused_or_replaced(monkeypatch):
    """Issue [trust] at 1274 unknowns (h = 1): with penalty 1e10 E/h the prescribed-displacement
    rows dominate b, and CG stops after one step at a relative residual of 3.4e-10 with the tip
    deflection 13.6 % off (7.45e-3 against SuperLU's 8.62e-3; 37 % in the coefficients at 18.9k
    unknowns, h = 0.25). With the Jacobi steps and block Gauss-Seidel of the preconditioner
    (efgkit.system.auxiliary) the one step lands closer, but still wrong: residual 1.9e-10, tip
    4.4 % off, energy error 0.125 (residual 3.3e-10, tip 8.3 % off, energy error 0.145 with
    the hierarchy of the P1 matrix without stored cancelled couplings). The energy-error bound
    sees it: "amg" refuses, "auto" takes SuperLU."""
    scene = _cantilever()
    method = EFG(spacing=1.0, bc="penalty", penalty=1e10, solver="amg")
    direct = solve(scene, EFG(spacing=1.0, bc="penalty", penalty=1e10, solver="direct"))
    tip = _tip_uy(direct)
    # Without the check the old answer comes back, and the bound (measured 0.1436; 0.222 with the
    # additive preconditioner) tracks the true stiffness-energy error (measured 0.1445; 0.216).
    # After one CG step the Ritz value is a single Rayleigh quotient, above lambda_min, so the
    # "bound" is an estimate here: 0.99 of the error with the multigrid hierarchy of the P1
    # matrix without stored cancelled couplings, 1.006 (0.126 / 0.125) with the one before.
    monkeypatch.setattr(linalg, "ERROR_FACTOR", 1e20)
    wrong = solve(scene, method, disc=direct.disc)
    assert wrong.info["residual"] < 1e-9 and wrong.info["iterations"] == 1
    assert abs(_tip_uy(wrong) - tip) > 0.03 * abs(tip)  # measured 0.083 (0.044 before, 0.136 additive)
    K = stiffness(direct.disc.shape, direct.disc.points.w, scene.material.D)
    e = wrong.coeffs - direct.coeffs
    err = np.sqrt(e @ (K @ e) / (direct.coeffs @ (K @ direct.coeffs)))
    assert 0.1 < err < 0.5 and 0.97 * err <= wrong.info["error_bound"] <= 3 * err
    monkeypatch.undo()

    with pytest.raises(SolverError) as exc:
        solve(scene, method, disc=direct.disc)
    msg = str(exc.value)
    assert msg.startswith("solver='amg': its relative residual ")
    assert "meets rtol = 1e-08 after 1 iteration, but the bound on its relative energy error is" in msg
    assert re.search(r"error is [1-4]\.\de-01 > 1e-03 \(ERROR_FACTOR \* rtol\)", msg)  # 2.2e-01
    assert re.search(r"boundary terms is 8\.8e\+09 times the stiffness's", msg)
    assert "Remedy: solver='direct'" in msg and "bc='lagrange'" in msg

    monkeypatch.setattr(linalg, "AUTO_AMG_THRESHOLD", 1000)
    auto = solve(scene, EFG(spacing=1.0, bc="penalty", penalty=1e10), disc=direct.disc)
    assert auto.info["solver"] == "direct" and auto.info["iterations"] == 1
    assert "the bound on its relative energy error is" in auto.info["fallback"]
    assert abs(_tip_uy(auto) - tip) <= 1e-6 * abs(tip)
    rel = np.linalg.norm(auto.coeffs - direct.coeffs) / np.linalg.norm(direct.coeffs)
    assert rel <= 1e-6


def test_p1_stiffness_has_rigid_body_kernel():
    rng = np.random.default_rng(3)
    x = rng.random((200, 2))
    P = p1_stiffness(x, Elastic(1.0, 0.25).D)
    R = rigid_body_modes(x)
    assert np.abs(P @ R).max() < 1e-10 * abs(P).max()
    assert abs(P - P.T).max() < 1e-12 * abs(P).max()


def test_chebyshev_inverse_is_linear_and_converges():
    F = csr_array(np.diag(np.linspace(0.05, 1.0, 30)))
    r = np.random.default_rng(0).random(30)
    exact = r / F.diagonal()
    assert np.linalg.norm(chebyshev_inverse(F, r, 40, (0.05, 1.0)) - exact) < 1e-6 * np.linalg.norm(exact)
    a, b = chebyshev_inverse(F, r, 8), chebyshev_inverse(F, 2 * r, 8)
    assert np.allclose(b, 2 * a)


def test_singular_system_raises():
    A = csr_array(np.array([[1.0, 1.0], [1.0, 1.0]]))
    with pytest.raises(SolverError, match="singular"):
        linear_solve(LinearSystem(A, np.array([1.0, 0.0]), True, 2), "direct")


def test_amg_on_an_unsymmetric_system_refused():
    # not SPD and not a Lagrange saddle point (no multiplier rows after the coefficients)
    A = csr_array(np.array([[1.0, 1.0], [0.0, 1.0]]))
    with pytest.raises(ValueError, match=r"solver='amg' needs an SPD system or a Lagrange-multiplier"
                                         r" saddle point .*use solver='direct'"):
        linear_solve(LinearSystem(A, np.ones(2), False, 2), "amg")


@pytest.mark.parametrize("rtol", [0.0, 1.0, -1e-3, "1e-8"])
def test_bad_rtol(rtol):
    A = csr_array(np.eye(2))
    with pytest.raises(ValueError, match="rtol must lie in"):
        linear_solve(LinearSystem(A, np.ones(2), True, 2), rtol=rtol)


def test_unknown_solver():
    with pytest.raises(ValueError, match="solver must be"):
        linear_solve(LinearSystem(csr_array(np.eye(2)), np.ones(2), True, 2), "cholmod")


def test_uzawa_converges_on_the_kirsch_plate():
    """The quarter Kirsch plate (symmetry supports: one component per edge; verification/kirsch.py
    at h = 0.125, 2103 nodes). With the augmentation weight at 1e3 a multiplier mode shrank by
    about 1 % per Uzawa step: 20 steps and 340 CG iterations left the relative residual at
    1.9e-7 (solver="amg" raised; "auto" fell back to SuperLU). At the default 1e6: 2 steps,
    116 iterations (measured), the energy-norm error of SuperLU's answer."""
    from dataclasses import replace

    from efgkit import Zone
    from efgkit.gallery import kirsch

    scene = kirsch(1.0, 5.0, 1.0, Elastic(3e7, 0.3, "strain"), "kirsch")
    method = EFG(spacing=0.125, zones=(Zone((0.0, 0.0), 2.0, 0.0625),), order=5, refined_order=9,
                 bc="lagrange")
    direct = solve(scene, method)
    assert direct.info["solver"] == "direct"
    it = solve(scene, replace(method, solver="amg"), disc=direct.disc)
    assert it.info["converged"] and it.info["uzawa_steps"] <= 3 and it.info["iterations"] <= 250
    e_it, e_direct = it.errors()["energy"], direct.errors()["energy"]
    assert abs(e_it / e_direct - 1) < 1e-6  # measured 2.0703365e-3 both (exact Kirsch field)
