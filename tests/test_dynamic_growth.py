"""Dynamic crack growth: state transfer, prescribed-speed timing, speed fit, criterion, errors."""

import math

import numpy as np
import pytest

from efgkit import EFG, Crack, Domain, Elastic, Scene, Traction
from efgkit.growth.dynamic import PrescribedSpeed, PrincipalStress, principal_stress, run_growing
from efgkit.growth.running_tip import check_speed, copy_state, speed_fit, transfer_state
from efgkit.methods.discretize import discretize
from efgkit.problem.history import Heaviside, Stepping

MAT = Elastic(1.0, 0.3, "strain", rho=1.0)


def _scene(duration=0.6, a=0.6, load=1.0):
    return Scene(Domain.rectangle(-2.0, -1.0, 2.0, 1.0), MAT, duration=duration,
                 cracks=(Crack([[-a, 0.0], [a, 0.0]]),),
                 tractions=(Traction("top", (0.0, load), history=Heaviside()),
                            Traction("bottom", (0.0, -load), history=Heaviside())))


def _method(ny=8):
    X, Y = np.meshgrid(np.linspace(-2, 2, 17), np.linspace(-1, 1, ny))  # ny even: no row on y = 0
    return EFG(spacing=0.25, coordinates=np.column_stack([X.ravel(), Y.ravel()]), d_max=2.5,
               zones=(), enrichment="none")


@pytest.mark.parametrize("ny", [8, 9])
def test_transfer_preserves_nodal_field(ny):
    sc, m = _scene(), _method(ny)
    old = discretize(sc, m)
    new = discretize(sc.with_cracks([sc.cracks[0].extended(0.25, end=1)]), m)
    if ny == 9:  # a row on the crack line: the new segment splits the node at (0.75, 0)
        assert new.nodes.n == old.nodes.n + 1
    rng = np.random.default_rng(0)
    c = np.zeros(old.n_dofs)
    c[: 2 * old.nodes.n] = rng.standard_normal(2 * old.nodes.n)
    u2, v2 = transfer_state(old, new, c, 2 * c)
    x = new.nodes.face_positions(new.approx.lines, 1e-3)
    before = old.shape_at(x, derivatives=False).displacement(c)
    after = new.shape_at(x, derivatives=False).displacement(u2)
    # the refit solves Phi' c' = u(x_I): exact up to the LU round-off
    assert np.max(np.abs(after - before)) <= 1e-10 * np.max(np.abs(before))
    assert np.allclose(new.shape_at(x, derivatives=False).displacement(v2), 2 * before, atol=1e-10)


def test_copy_keeps_coefficients_node_by_node():
    sc, m = _scene(), _method(9)
    old = discretize(sc, m)
    new = discretize(sc.with_cracks([sc.cracks[0].extended(0.25, end=1)]), m)
    c = np.zeros(old.n_dofs)
    c[: 2 * old.nodes.n] = np.random.default_rng(2).standard_normal(2 * old.nodes.n)
    (c2,) = copy_state(old, new, c)
    # every new node sits where an old one did: its coefficients are that node's
    xo, xn = old.nodes.x, new.nodes.x
    j = np.argmin(np.hypot(xn[:, None, 0] - xo[None, :, 0], xn[:, None, 1] - xo[None, :, 1]), axis=1)
    same = np.flatnonzero(np.hypot(*(xn - xo[j]).T) == 0)
    split = np.flatnonzero((new.nodes.face != 0) & np.isclose(xn[:, 0], 0.75) & (xn[:, 1] == 0))
    assert len(split) == 2  # both copies of the node the new segment split
    assert np.allclose(c2[2 * split], c2[2 * split[0]])
    keep = same[(new.nodes.face[same] == 0) & (old.nodes.face[j[same]] == 0)]  # unsplit nodes
    assert len(keep) > 100
    assert np.array_equal(c2[2 * keep], c[2 * j[keep]])
    assert np.array_equal(c2[2 * keep + 1], c[2 * j[keep] + 1])


def test_speed_fit_exact_for_linear_history():
    t = np.sort(np.random.default_rng(1).uniform(0, 1, 30))
    assert np.allclose(speed_fit(t, 0.2 + 3.7 * t), 3.7, rtol=1e-12)  # slope of a line
    # a quadratic: the centred 11-point slope of a(t) = t^2 on a uniform grid is 2 t exactly
    tu = np.linspace(0, 1, 31)
    assert np.allclose(speed_fit(tu, tu**2)[5:-5], 2 * tu[5:-5], rtol=1e-12)


def test_prescribed_speed_advance_timing():
    sc, m = _scene(duration=1.0), _method()
    cr = MAT.c_rayleigh
    V, da = 0.9 * cr, 0.25
    r = run_growing(sc, m, PrescribedSpeed(V, start=0.1, da=da), Stepping(dt=0.05, output_interval=0.1),
                    radii=(0.4, 0.5, 0.6))
    dt = r.info["dt"]
    t = r.advances["t"][::2]  # both tips advance together
    # advance k at start + (k - 1/2) da / V, rounded to the step
    k = np.arange(1, len(t) + 1)
    assert len(t) >= 2
    assert np.all(np.abs(t - (0.1 + (k - 0.5) * da / V)) <= 0.5 * dt + 1e-12)
    assert np.allclose(speed_fit(t, r.advances["extension"][::2]), V, rtol=dt * V / da * 2)
    assert np.all(np.isfinite(r.history["K"]))


@pytest.mark.parametrize("direction", ["straight", "principal"])
def test_criterion_initiates(direction):
    sc, m = _scene(duration=1.6), _method()
    r = run_growing(sc, m, PrincipalStress(1.0, direction=direction),
                    Stepping(dt=0.05, output_interval=0.1), radii=(0.4, 0.5, 0.6))
    assert len(r.advances["t"]) >= 2
    # nothing can happen before the first wave reaches the crack plane (1 / c_d)
    assert r.advances["t"][0] > 1.0 / MAT.c_dilatational
    assert r.scene.cracks[0].vertices.shape[0] > 2
    # symmetric mode I (scene and nodes mirror about y = 0): sigma_1 ahead is along y, so
    # the principal rule runs straight too
    assert np.max(np.abs(r.scene.cracks[0].vertices[:, 1])) <= 1e-9


def test_principal_stress():
    s = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [-2.0, -2.0, 0.0]])
    assert np.allclose(principal_stress(s), [1.0, 1.0, -2.0])  # pure shear: sigma_1 = tau


def test_errors():
    with pytest.raises(ValueError, match="c_R"):
        check_speed(MAT.c_rayleigh, MAT)
    with pytest.raises(ValueError, match="rule.speed"):
        run_growing(_scene(), _method(), PrescribedSpeed(1.01 * MAT.c_rayleigh))
    with pytest.raises(ValueError, match="sigma_c"):
        PrincipalStress(0.0)
    with pytest.raises(ValueError, match="sigma_c"):
        PrincipalStress(-1.0)
    with pytest.raises(ValueError, match="speed"):
        PrescribedSpeed(-1.0)
    with pytest.raises(ValueError, match="transfer"):
        run_growing(_scene(), _method(), PrescribedSpeed(0.1), transfer="nearest")
    with pytest.raises(ValueError, match="direction"):
        PrincipalStress(1.0, direction="hoop")
    with pytest.raises(ValueError, match="check_every"):
        PrincipalStress(1.0, check_every=0)
    with pytest.raises(ValueError, match="not tips"):
        run_growing(_scene(), _method(), PrescribedSpeed(0.1, tips=("x:1",)))
    with pytest.raises(TypeError, match="rule"):
        run_growing(_scene(), _method(), 1.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        speed_fit([0.0, 0.0, 1.0], [0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="half"):
        speed_fit([0.0, 1.0], [0.0, 1.0], half=0)
    assert math.isfinite(check_speed(0.5 * MAT.c_rayleigh, MAT))
