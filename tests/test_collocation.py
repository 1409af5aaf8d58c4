"""bc="collocation": the modified collocation method of Zhu and Atluri (1998, Comput. Mech.
21:211-222): equations of the prescribed components of the essential nodes replaced by
u^h(x_I) = ubar(x_I), the Gamma_u boundary term kept in the others."""

import re

import numpy as np
import pytest
from scipy.sparse import csr_array

from efgkit import EFG, Domain, Elastic, Scene, Support
from efgkit.methods.boundary import collocation_rows, gamma_u_term, loads
from efgkit.methods.discretize import discretize
from efgkit.scenefile import load_study
from efgkit.static import solve
from efgkit.system.assemble import stiffness
from efgkit.system.collocation import SingularRowsError, collocation
from efgkit.system.constraints import RigidBodyModeError
from efgkit.system.linalg import solve as linear_solve

A = np.array([[1e-3, 2e-3, -1e-3], [-2e-3, 1e-3, 3e-3]])  # u_c = A[c] . (1, x, y)
MAT = Elastic(1000.0, 0.3, "stress")


def linear(x):
    return np.column_stack([A[c, 0] + A[c, 1] * x[:, 0] + A[c, 2] * x[:, 1] for c in (0, 1)])


def patch_scene():
    sup = tuple(Support(e, ux=lambda x: linear(x)[:, 0], uy=lambda x: linear(x)[:, 1])
                for e in ("bottom", "right", "top", "left"))
    return Scene(Domain.rectangle(0, 0, 1, 1), MAT, supports=sup)


# The patch-test settings of verification/patch.py (cells of h/4, 8 x 8 Gauss), perturbed cloud.
PATCH = dict(spacing=0.2, perturb=0.3, seed=7, order=8, cell_size=0.05, bc="collocation")
X = np.random.default_rng(0).uniform(0.02, 0.98, (200, 2))


@pytest.fixture(scope="module")
def patch_solution():
    return solve(patch_scene(), EFG(**PATCH))


def test_patch_test_on_perturbed_cloud(patch_solution):
    # Exact: the linear field and its constant stress (consistency of the Galerkin method);
    # measured 5.0e-7 (displacement) and 3.9e-6 (stress) relative, the quadrature error (Lagrange
    # multipliers give 5.2e-7 and 4.5e-6 on the same cloud).
    u = linear(X)
    sig = MAT.D @ np.array([A[0, 1], A[1, 2], A[0, 2] + A[1, 1]])
    eu = np.abs(patch_solution.displacement(X) - u).max() / np.abs(u).max()
    es = np.abs(patch_solution.stress(X) - sig).max() / np.abs(sig).max()
    assert eu < 1e-6 and es < 1e-5


def test_constraint_rows_hold_at_the_essential_nodes(patch_solution):
    # Collocation imposes u^h(x_I) = ubar(x_I) exactly at every node on the boundary (measured
    # 1e-18 in absolute terms; the values are ~1e-3).
    x = patch_solution.nodes.x
    on = (np.minimum(x, 1 - x).min(axis=1) < 1e-9)
    assert on.sum() == 20  # 6 x 6 grid: the perturbation moves interior nodes only
    assert np.abs(patch_solution.displacement(x[on]) - linear(x[on])).max() < 1e-12


def test_boundary_term_is_what_makes_it_consistent():
    # Dropping -int_{Gamma_u} phi_I t(u^h): the patch test fails (3.7e-3 relative, measured), since
    # MLS test functions of nodes near Gamma_u do not vanish there.
    sc = patch_scene()
    disc = discretize(sc, EFG(**{**PATCH, "perturb": 0.0}))
    K = stiffness(disc.shape, disc.points.w, MAT.D)
    f = loads(disc)
    rows, vals, dofs = collocation_rows(disc)
    errs = []
    for H in (gamma_u_term(disc), None):
        system = collocation(K if H is None else K - H, f, rows, vals, dofs, disc.nodes.x)
        c = system.coefficients(linear_solve(system, "direct")[0])
        errs.append(np.abs(disc.shape_at(X).displacement(c) - linear(X)).max() / np.abs(linear(X)).max())
    assert errs[0] < 1e-6 < 1e-4 < errs[1]


def test_crack_mouth_nodes_take_their_own_face_value():
    # The singular patch of seed 003 Sect. 5.6.1 (Williams K_I = 1 on all edges, a crack from the
    # left edge's midpoint to the centre): the two copies of the mouth node must each interpolate
    # the exact field of their own face. With one value for both (the field's at y = 0 exactly)
    # the energy error was 1.86 against Lagrange's 0.249 (9 x 9 nodes, plane stress, measured).
    from efgkit import Crack
    from efgkit.problem.exact.fields import Field

    W = Field.named("williams", KI=1.0, KII=0.0)
    sc = Scene(Domain.rectangle(-1, -1, 1, 1), MAT, cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]],
               tips=(False, True)),), supports=tuple(Support(e, ux=W, uy=W)
               for e in ("left", "bottom", "right", "top")), exact=W)
    sol = solve(sc, EFG(spacing=0.25, bc="collocation", enrichment="none", zones=()))
    disc = sol.disc
    x = disc.nodes.face_positions(disc.approx.lines, 1e-3)
    mouth = np.flatnonzero(np.hypot(disc.nodes.x[:, 0] + 1, disc.nodes.x[:, 1]) < 1e-12)
    assert len(mouth) == 2  # the split node, one copy per face
    u = W.displacement(x[mouth], MAT)
    assert abs(u[0, 1] - u[1, 1]) > 1e-3  # the faces open: u_y differs by 3.2e-3
    assert np.abs(sol.displacement(x[mouth]) - u).max() < 1e-12
    lag = solve(sc, EFG(spacing=0.25, bc="lagrange", enrichment="none", zones=()))
    # Same accuracy as Lagrange multipliers (0.248734 and 0.248732, measured)
    assert abs(sol.errors()["energy"] / lag.errors()["energy"] - 1) < 0.01


def test_unsymmetric_system_goes_to_the_direct_solver():
    sc = patch_scene()
    disc = discretize(sc, EFG(spacing=0.25, bc="collocation"))
    K = stiffness(disc.shape, disc.points.w, MAT.D)
    rows, vals, dofs = collocation_rows(disc)
    system = collocation(K - gamma_u_term(disc), loads(disc), rows, vals, dofs, disc.nodes.x)
    assert not system.spd and system.free is None and system.A.shape == K.shape
    assert abs(system.A - system.A.T).max() > 1e-3 * abs(system.A).max()  # really unsymmetric
    z, info = linear_solve(system, "auto")
    assert info["solver"] == "direct" and info["residual"] < 1e-12
    with pytest.raises(ValueError, match="solver='amg' needs an SPD system"):
        linear_solve(system, "amg")
    with pytest.raises(ValueError, match=re.escape("solver='amg' needs an SPD system or a Lagrange")):
        solve(sc, EFG(spacing=0.25, bc="collocation", solver="amg"))


def test_collocation_replaces_exactly_the_given_equations():
    # A random unsymmetric K: the result must be the dense replaced system, solved by numpy.
    rng = np.random.default_rng(3)
    n = 8
    K = csr_array(rng.standard_normal((n, n)) + n * np.eye(n))
    f = rng.standard_normal(n)
    rows = csr_array(rng.standard_normal((3, n)))
    vals, dofs = rng.standard_normal(3), np.array([5, 0, 3])
    system = collocation(K, f, rows, vals, dofs, rng.standard_normal((4, 2)))
    Ad, bd = K.toarray(), f.copy()
    Ad[dofs], bd[dofs] = rows.toarray(), vals
    c = system.coefficients(linear_solve(system, "direct")[0])
    np.testing.assert_allclose(c, np.linalg.solve(Ad, bd), rtol=1e-12, atol=1e-14)


def test_scene_file_accepts_collocation(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text('[material]\nE = 1000.0\nnu = 0.3\n[domain]\nouter = { rectangle = [0.0, 0.0, 2.0, 1.0] }\n'
                 '[[supports]]\nedge = "left"\nux = 0.0\n[[supports]]\nedge = "bottom"\nuy = 0.0\n'
                 '[[tractions]]\nedge = "right"\nt = [1.0, 0.0]\n[efg]\nspacing = 0.25\nbc = "collocation"\n')
    scene, efg = load_study(p)
    assert efg.bc == "collocation"
    # Tension on rollers, a linear field (closed form): u_x = sigma L (1 - nu^2) / E at the loaded
    # end in plane strain (the default), 1.82e-3; measured relative error 2.9e-7 (4 x 4 Gauss).
    u = solve(scene, efg).displacement([[2.0, 0.5]])[0, 0]
    assert abs(u / (2.0 * (1 - 0.3**2) / 1000.0) - 1) < 1e-6


# --- bad input -------------------------------------------------------------------------------

def small():
    """A 4-node, 8-unknown problem: nodes at the unit square's corners."""
    x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    K = csr_array(np.eye(8) * 2.0 - np.eye(8, k=2) - np.eye(8, k=-2))
    return K, np.ones(8), x


def test_rigid_body_mode_left_free_is_refused():
    K, f, x = small()
    rows = csr_array(np.eye(8)[[0, 2]])  # u_x of two nodes: u_y translation free
    with pytest.raises(RigidBodyModeError, match="rigid-body mode free .mostly translation in y"):
        collocation(K, f, rows, [0.0, 0.0], [0, 2], x)


def test_dependent_rows_are_refused():
    K, f, x = small()
    rows = csr_array(np.eye(8)[[0, 3, 1, 3]])  # u_y of node 1 twice (rows 1 and 3)
    with pytest.raises(SingularRowsError, match=r"linearly dependent .*row [13], replacing equation "
                       r"[15], depends on the others.*Give each constrained point and component once"):
        collocation(K, f, rows, [0.0, 0.0, 0.0, 0.0], [0, 1, 3, 5], x)
    # nearly dependent: two rows 1e-7 apart in direction (condition number ~1e7 > 1e6)
    r = np.eye(8)[[0, 1, 3, 3]]
    r[3, 5] = 1e-7
    with pytest.raises(SingularRowsError, match=r"smallest pivot of their Gram matrix \d.\de-1[45] < 1e-12"):
        collocation(K, f, csr_array(r), np.zeros(4), [0, 1, 3, 5], x)


def test_support_without_nodes_is_refused():
    # Supports on the left edge and on a stretch of the bottom between two nodes (h = 0.25).
    sc = Scene(Domain.rectangle(0, 0, 1, 1), MAT, supports=(
        Support("left", ux=0.0), Support(lambda x: (np.abs(x[:, 0] - 0.6) < 0.05) & (x[:, 1] < 1e-9),
                                         uy=0.0)))
    with pytest.raises(ValueError, match="support <function .*> holds no node: bc='collocation'"):
        solve(sc, EFG(spacing=0.25, bc="collocation"))


def test_zero_row_is_refused():
    K, f, x = small()
    rows = csr_array(np.vstack([np.eye(8)[[0, 1, 3]], np.zeros(8)]))
    with pytest.raises(SingularRowsError, match="row 3 .replacing equation 6. is zero"):
        collocation(K, f, rows, np.zeros(4), [0, 1, 3, 6], x)


@pytest.mark.parametrize("change, error, message", [
    (dict(K=np.eye(8)), TypeError, "K must be a square scipy.sparse matrix"),
    (dict(K=csr_array(np.eye(8)[:7])), TypeError, "K must be a square scipy.sparse matrix"),
    (dict(f=np.ones(7)), ValueError, "f must have shape (8,) like K, got (7,)"),
    (dict(rows=np.eye(8)[[0, 1, 3]]), TypeError, "rows must be a scipy.sparse matrix"),
    (dict(rows=csr_array(np.eye(9)[[0, 1, 3]])), ValueError, "rows must have 8 columns"),
    (dict(values=[0.0, 0.0]), ValueError, "values must have shape (3,), one per row, got (2,)"),
    (dict(dofs=[0, 1]), ValueError, "dofs must be an integer array of shape (3,)"),
    (dict(dofs=[0.0, 1.0, 3.0]), ValueError, "dofs must be an integer array"),
    (dict(dofs=[0, 1, 8]), ValueError, "dofs must lie in [0, 8), got values from 0 to 8"),
    (dict(dofs=[0, 1, 1]), ValueError, "dofs must be distinct (each equation replaced once), got dof 1 2"),
    (dict(values=[0.0, np.nan, 0.0]), ValueError, "values holds NaN or inf"),
    (dict(f=np.full(8, np.inf)), ValueError, "f holds NaN or inf"),
    (dict(node_x=np.zeros((5, 2))), ValueError, "node_x must have shape (n_nodes, 2) with 2 n_nodes <= 8"),
])
def test_bad_arguments_are_named(change, error, message):
    K, f, x = small()
    args = dict(K=K, f=f, rows=csr_array(np.eye(8)[[0, 1, 3]]), values=np.zeros(3),
                dofs=np.array([0, 1, 3]), node_x=x)
    args.update(change)
    with pytest.raises(error, match=re.escape(message)):
        collocation(**args)
