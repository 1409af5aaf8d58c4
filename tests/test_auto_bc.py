"""bc="auto" by size (issue [perf]): Nitsche instead of Lagrange multipliers where CG solves."""

from dataclasses import replace
from types import SimpleNamespace

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, Traction, solve
from efgkit.static import large_system_bc
from efgkit.system.linalg import AUTO_AMG_THRESHOLD

SCENE = Scene(Domain.rectangle(0, 0, 7, 16), Elastic(3e7, 0.25, "strain"),  # seed 003 Sect. 5.6.2
              supports=(Support("bottom", ux=0.0, uy=0.0),), tractions=(Traction("top", (1.0, 0.0)),),
              cracks=(Crack([[0.0, 8.0], [3.5, 8.0]], tips=(False, True), name="edge"),))


def test_rule():
    auto = EFG(spacing=0.5).for_scene(SCENE)
    assert auto.bc == "lagrange"
    big, small = SimpleNamespace(n_dofs=AUTO_AMG_THRESHOLD + 1), SimpleNamespace(n_dofs=AUTO_AMG_THRESHOLD)
    assert large_system_bc(auto, big, True).bc == "variational"
    assert large_system_bc(auto, small, True).bc == "lagrange"
    assert large_system_bc(auto, big, False).bc == "lagrange"  # asked for: kept
    assert large_system_bc(replace(auto, solver="direct"), big, True).bc == "lagrange"
    plain = EFG(spacing=0.5).for_scene(Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3)))
    assert large_system_bc(plain, big, True).bc == "penalty"  # no tips: penalty stays


def test_solve_reports_the_bc_it_used(monkeypatch):
    """With the threshold lowered to this small plate, bc="auto" solves with Nitsche and says so;
    K_I equals the Lagrange solve's (both consistent: measured 2.6e-6 apart here, 2.3e-8 at
    19.6k nodes, docs/performance.md), and Lagrange's is within 0.09 % (measured) of Wilson's
    34.0 (seed 003 Sect. 5.6.2; 3 digits)."""
    import efgkit.static as static

    monkeypatch.setattr(static, "AUTO_AMG_THRESHOLD", 100)
    nitsche = solve(SCENE, EFG(spacing=0.7))
    lagrange = solve(SCENE, EFG(spacing=0.7, bc="lagrange"))
    assert nitsche.method.bc == "variational" and lagrange.method.bc == "lagrange"
    k_n, k_l = nitsche.sifs(error=False)[0].KI, lagrange.sifs(error=False)[0].KI
    assert abs(k_n / k_l - 1) < 8e-6 and abs(k_l / 34.0 - 1) < 2.5e-3


def test_solver_auto_switches_to_cg_above_the_threshold(monkeypatch):
    """solver="auto" takes SuperLU up to AUTO_AMG_THRESHOLD unknowns and CG above it, for SPD
    systems and Lagrange saddle points alike; static's bc choice and the size guard's memory
    model read the same threshold (benchmarks/auto_threshold.py measured where CG wins)."""
    import numpy as np
    from scipy.sparse import diags_array

    import efgkit.methods.size as size
    import efgkit.static as static
    from efgkit.system import linalg
    from efgkit.system.linear_system import LinearSystem

    assert static.AUTO_AMG_THRESHOLD == size.AUTO_AMG_THRESHOLD == AUTO_AMG_THRESHOLD
    n = 60
    A = diags_array([-np.ones(n - 1), 2.5 * np.ones(n), -np.ones(n - 1)], offsets=[-1, 0, 1]).tocsr()
    system = LinearSystem(A, np.ones(n), spd=True, n_coeffs=n)
    monkeypatch.setattr(linalg, "AUTO_AMG_THRESHOLD", n)
    z_direct, info = linalg.solve(system)
    assert info["solver"] == "direct"
    monkeypatch.setattr(linalg, "AUTO_AMG_THRESHOLD", n - 1)
    z_cg, info = linalg.solve(system)
    assert info["solver"] == "amg"
    np.testing.assert_allclose(z_cg, z_direct, rtol=1e-7)  # rtol 1e-8 on the residual, cond ~9
