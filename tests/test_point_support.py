"""Point supports (pins and rollers): they remove the rigid-body motions of a traction-loaded
body without changing its stresses, in every EFG bc method and in FEM."""

import warnings
from dataclasses import replace

import numpy as np
import pytest

from efgkit import EFG, FEM, Domain, Elastic, PointSupport, Scene, Support, Traction, solve, solve_fem
from efgkit.gallery import cct
from efgkit.system.constraints import RigidBodyModeError

BCS = ("lagrange", "penalty", "variational", "modified_mls")
MAT = Elastic(1000.0, 0.25, "stress")
# uniaxial tension 2 on a plate with a hole-free square: the exact stress is (2, 0, 0)
PLATE = Scene(Domain.rectangle(0, 0, 2, 1), MAT,
              tractions=(Traction("right", (2.0, 0.0)), Traction("left", (-2.0, 0.0))),
              point_supports=(PointSupport((0.0, 0.0), ux=0.0, uy=0.0), PointSupport((2.0, 0.0), uy=0.0)))


@pytest.mark.filterwarnings("ignore:bc='modified_mls'")
def test_pinned_plate_in_tension_same_field_in_every_bc_method():
    x = np.array([[0.3, 0.7], [1.9, 0.1], [2.0, 1.0]])
    out = []
    for bc in BCS:
        sol = solve(PLATE, EFG(spacing=0.25, bc=bc))
        u = sol.displacement(np.array([[0.0, 0.0], [2.0, 0.0]]))
        assert np.abs(u[0]).max() < 1e-12 and abs(u[1, 1]) < 1e-12  # the pin and the roller hold
        # no force in the supports: the loads are in equilibrium (measured 1e-15)
        assert np.abs(sol.reaction(lambda x: np.ones(len(x), bool), about=(1.0, 0.5))).max() < 1e-10
        out.append(np.concatenate([sol.stress(x).ravel(), sol.displacement(x).ravel()]))
    # the same discrete field whichever way the point is held (measured 1e-16 apart)
    assert np.ptp(out, axis=0).max() < 1e-10
    # uniaxial stress 2, u(2, 1) = (sigma L / E, -nu sigma H / E) = (4e-3, -5e-4), up to the
    # quadrature error of the default 4 x 4 cell rule (measured 2e-4 relative; the patch test
    # needs order 8)
    assert np.abs(out[0][:6].reshape(2, 3) - [2.0, 0.0, 0.0]).max() < 5e-4
    assert np.abs(out[0][13:] / [4e-3, -5e-4] - 1).max() < 5e-4


def test_fem_pinned_plate_in_tension_is_exact():
    sol = solve_fem(PLATE, FEM(0.5))
    assert np.abs(sol.stress(np.array([[0.3, 0.7]])) - [2.0, 0.0, 0.0]).max() < 1e-9
    assert np.abs(sol.displacement(np.array([[2.0, 0.0]])) - [4e-3, 0.0]).max() < 1e-12


@pytest.mark.filterwarnings("ignore:bc='modified_mls'")
def test_cracked_plate_same_k_in_every_bc_method_and_restraint():
    # the centre-cracked plate held by a pin and a roller (efgkit.gallery.cct); the loads are
    # in equilibrium, so the restraint changes only the rigid motion: K equal to rounding
    sc = cct(0.5, 1.0)
    other = replace(sc, point_supports=(PointSupport((1.0, 1.0), ux=0.0, uy=0.0),
                                        PointSupport((-1.0, 1.0), uy=0.0)))
    ks = [solve(s, EFG(spacing=0.25, bc=bc, enrichment="none")).sifs(error=False)[0].KI
          for bc in BCS for s in ((sc, other) if bc == "lagrange" else (sc,))]
    assert np.ptp(ks) < 1e-10 * ks[0]  # measured 2e-15
    kf = [solve_fem(s, FEM(0.25, tip_h=0.02)).sifs(error=False)[0].KI for s in (sc, other)]
    assert abs(kf[0] - kf[1]) < 1e-10 * kf[0]


def test_fem_point_support_needs_a_mesh_node():
    sc = Scene(PLATE.domain, MAT, tractions=PLATE.tractions, point_supports=(
        PointSupport((0.0, 0.0), ux=0.0, uy=0.0), PointSupport((1.03, 0.0), uy=0.0)))
    with pytest.raises(ValueError, match="the mesh has no node there"):
        solve_fem(sc, FEM(0.5))
    sol = solve_fem(sc, FEM(0.5, refine=((1.03, 0.0),)))  # FEM.refine makes it a vertex
    assert abs(sol.displacement(np.array([[1.03, 0.0]]))[0, 1]) < 1e-12


def test_one_point_leaves_a_rigid_mode():
    sc = Scene(PLATE.domain, MAT, tractions=PLATE.tractions,
               point_supports=(PointSupport((0.0, 0.0), ux=0.0, uy=0.0),))
    with pytest.raises(RigidBodyModeError, match="leave a rigid-body mode free"):
        solve(sc, EFG(spacing=0.25, bc="lagrange"))
    with pytest.raises(RigidBodyModeError, match="leave a rigid-body mode free"):
        solve_fem(sc, FEM(0.5))


def test_line_and_point_supports_together():
    sc = Scene(PLATE.domain, MAT, supports=(Support("left", ux=0.0),), tractions=PLATE.tractions[:1],
               point_supports=(PointSupport((0.0, 0.0), uy=0.0),))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sol = solve(sc, EFG(spacing=0.25, bc="variational"))
    # quadrature error of the default cell rule: measured 1.4e-5
    assert np.abs(sol.stress(np.array([[1.0, 0.5]])) - [2.0, 0.0, 0.0]).max() < 5e-5


@pytest.mark.parametrize("kw, err, match", [
    (dict(x=(0.0, 0.0)), ValueError, "prescribes nothing"),
    (dict(x=(0.0,), ux=0.0), ValueError, "finite point"),
    (dict(x=(0.0, float("nan")), ux=0.0), ValueError, "finite point"),
    (dict(x=(0.0, 0.0), ux=lambda x: x[:, 0]), TypeError, "must be a float"),
    (dict(x=(0.0, 0.0), uy=1e300), ValueError, "too large"),
])
def test_bad_point_support(kw, err, match):
    with pytest.raises(err, match=match):
        PointSupport(**kw)


def test_bad_point_support_in_scene():
    with pytest.raises(ValueError, match="lies outside the domain"):
        Scene(PLATE.domain, MAT, point_supports=(PointSupport((3.0, 0.0), ux=0.0),))
    with pytest.raises(TypeError, match="must hold PointSupport"):
        Scene(PLATE.domain, MAT, point_supports=(Support("left", ux=0.0),))


@pytest.mark.parametrize("width, accepted", [(0.1, True), (0.02, False)])
def test_short_support_segment_same_in_efg_and_fem(width, accepted):
    # a stretch of the left edge holding no FE node (h = 0.25): EFG imposes it at the boundary
    # Gauss points it holds, FEM on the facets with a Gauss point in it; both refuse a stretch
    # holding none (it used to be a rigid-body error in FEM only)
    seg = Support(lambda x: (x[:, 0] < 1e-9) & (np.abs(x[:, 1] - 0.55) <= width / 2), uy=0.0)
    sc = Scene(PLATE.domain, MAT, supports=(Support("left", ux=0.0), seg), tractions=PLATE.tractions[:1])
    runs = (lambda: solve(sc, EFG(spacing=0.25, bc="lagrange")), lambda: solve_fem(sc, FEM(0.25)))
    if not accepted:
        for run, match in zip(runs, ("selects none of the boundary quadrature points",
                                     "selects no node and no boundary Gauss point"), strict=True):
            with pytest.raises(ValueError, match=match):
                run()
        return
    # u_y(2, 1) = -nu sigma (1 - 0.55) / E = -2.25e-4 for a support at y = 0.55; the stretch
    # fixes u_y over its length (measured -2.14e-4 EFG, -1.88e-4 FEM)
    for run in runs:
        assert run().displacement(np.array([[2.0, 1.0]]))[0, 1] == pytest.approx(-2.25e-4, rel=0.25)
