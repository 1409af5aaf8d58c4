"""The paths of small problems give the matrices of the general ones: the dense stiffness
blocks (efgkit.system.dense_stiffness) against the compiled kernel and the scipy.sparse
products, and Nitsche's system formed from one set of triplets against the operator algebra
of seed 003 Eq. (27)."""

import numpy as np
import pytest
from scipy.sparse import csr_array, diags_array

from efgkit import EFG, Domain, Elastic
from efgkit.approx.mls import mls_shape
from efgkit.gallery import singular_patch
from efgkit.methods.boundary import essential_conditions
from efgkit.methods.discretize import discretize
from efgkit.nodes import generate_nodes
from efgkit.search import find_neighbours
from efgkit.system.assemble import stiffness
from efgkit.system.constraints import modified_variational
from efgkit.system.dense_stiffness import DENSE_WORK, dense_enrichment_blocks


@pytest.fixture(scope="module")
def small():
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25, perturb=0.3))
    xq = np.random.default_rng(1).random((300, 2))
    return nodes, xq, np.random.default_rng(2).uniform(0.5, 1.5, 300) / 300, mls_shape(xq, nodes)


@pytest.fixture(scope="module")
def patch():
    scene = singular_patch(1.0, 0.5)  # a tip inside: extrinsic K_I, K_II unknowns (n_extra 2)
    method = EFG(spacing=1.0, enrichment="extrinsic_mls", bc="variational", order=3, refined_order=4,
                 tip_order=6)
    return scene, discretize(scene, method)


def _close(A, B, tol=1e-13):
    return abs(csr_array(A) - csr_array(B)).max() <= tol * abs(csr_array(B)).max()


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_dense_nodal_block_equals_the_kernel(small, plane):
    nodes, xq, w, sh = small
    assert len(xq) * nodes.n**2 <= DENSE_WORK  # the numpy backend takes the dense block here
    D = Elastic(2.0, 0.3, plane).D
    assert _close(stiffness(sh, w, D, backend="numpy"), stiffness(sh, w, D, backend="numba"))


def test_dense_nodal_block_petrov_galerkin_and_unsymmetric_D(small):
    nodes, xq, w, sh = small
    other = mls_shape(xq, nodes, weight="cubic")
    D = Elastic(1.0, 0.3).D
    assert _close(stiffness(sh, w, D, test=other, backend="numpy"),
                  stiffness(sh, w, D, test=other, backend="numba"))
    Du = D + np.array([[0, 0.1, 0], [0, 0, 0], [0.05, 0, 0]])
    assert _close(stiffness(sh, w, Du, backend="numpy"), stiffness(sh, w, Du, backend="numba"))


@pytest.mark.parametrize("unsymmetric", [False, True])
def test_dense_enrichment_blocks_equal_the_sparse_products(patch, unsymmetric):
    scene, disc = patch
    sh, w = disc.shape, disc.points.w
    D = scene.material.D + (np.array([[0, 0.1, 0], [0, 0, 0], [0.05, 0, 0]]) * scene.material.D[0, 0]
                            if unsymmetric else 0.0)
    K_ne, K_en, K_ee = dense_enrichment_blocks(sh, w, D)
    e = sh.extra  # the reference: the sparse algebra of the enrichment columns
    eps = (e.gxx, e.gyy, csr_array(e.gxy + e.gyx))
    W = diags_array(w)

    def rows(C):
        s = [csr_array(W @ sum(C[i, j] * eps[j] for j in range(3) if C[i, j] != 0)) for i in range(3)]
        kx, ky = sh.dx.T @ s[0] + sh.dy.T @ s[2], sh.dy.T @ s[1] + sh.dx.T @ s[2]
        out = np.empty((2 * sh.n_functions, e.n))
        out[0::2], out[1::2] = kx.toarray(), ky.toarray()
        return out, s

    ref_ne, sig = rows(D)
    ref_en = rows(D.T)[0].T
    ref_ee = sum(eps[i].T @ sig[i] for i in range(3))
    assert _close(K_ne, ref_ne) and _close(K_en, ref_en) and _close(K_ee, ref_ee)
    # and the whole enriched matrix, numpy (dense blocks) against the compiled kernels
    assert _close(stiffness(sh, w, D, backend="numpy"), stiffness(sh, w, D, backend="numba"))


@pytest.mark.parametrize("dense", [True, False])
def test_nitsche_system_equals_the_operator_algebra(patch, dense, monkeypatch):
    import efgkit.system.constraints as cons

    scene, disc = patch
    assert disc.n_dofs <= cons.DENSE_DOFS
    if not dense:  # the sparse products of larger systems
        monkeypatch.setattr(cons, "DENSE_DOFS", 0)
    bc = essential_conditions(disc, derivatives=True)
    D, beta = scene.material.D, 100.0 * scene.material.E
    K = stiffness(disc.shape, disc.points.w, D)
    f = np.random.default_rng(3).random(K.shape[0])
    sys = modified_variational(K, f, bc, D, beta, disc.nodes.x)
    # the reference, seed 003 Eq. (27): G and T from the component and gradient operators
    q, c = np.nonzero(bc.fixed)
    n = len(bc.x)
    ux, uy = bc.shape.u_operators()
    G = csr_array(csr_array(np.vstack([ux.toarray(), uy.toarray()]))[c * n + q])
    gxx, gxy, gyx, gyy = (op.toarray() for op in bc.shape.grad_operators())
    eps = (gxx, gyy, gxy + gyx)
    sig = [sum(D[i, j] * eps[j] for j in range(3)) for i in range(3)]
    nx, ny = bc.normal[:, :1], bc.normal[:, 1:]
    T = np.vstack([nx * sig[0] + ny * sig[2], nx * sig[2] + ny * sig[1]])[c * n + q]
    w = bc.w[q]
    ub = bc.value[q, c]
    H = G.T @ (w[:, None] * T)
    A = K.toarray() - H - H.T + beta * (G.T @ diags_array(w) @ G).toarray()
    b = f - T.T @ (w * ub) + beta * (G.T @ (w * ub))
    assert G.shape[1] == disc.n_dofs > 2 * disc.nodes.n  # the enrichment columns take part
    assert np.abs(sys.A.toarray() - A).max() <= 1e-13 * np.abs(A).max()
    assert np.abs(sys.b - b).max() <= 1e-13 * np.abs(b).max()
    z = np.random.default_rng(4).random(K.shape[0])
    x, force = sys.support_forces(z)
    ref = np.zeros(bc.fixed.shape)
    ref[q, c] = w * (T @ z - beta * (G @ z - ub))
    assert np.allclose(x, bc.x) and np.abs(force - ref).max() <= 1e-12 * np.abs(ref).max()


def test_shape_near_a_crack_equals_all_points_then_the_near_rows_redone(patch):
    # numpy path: the crack-free MLS runs on the rows away from the crack only; the values
    # are those of the crack-free MLS of all points with the near rows redone under the rule
    disc = discretize(patch[0], EFG(spacing=0.25, enrichment="extrinsic_mls"))
    ap, x = disc.approx, disc.points.x
    nb = disc.shape.neighbours
    sh = ap.shape(x, neighbours=find_neighbours(x, ap.nodes, ap.boxes))
    rows = ap.cracked_rows(x, sh.neighbours)
    assert 0 < len(rows) < len(x)
    kw = dict(d_max=ap.d_max, alpha=ap.alpha, k=ap.k, backend="numpy")
    plain = mls_shape(x, ap.nodes, ap.weight, ap.basis, neighbours=find_neighbours(x, ap.nodes, ap.boxes),
                      **kw)
    cw = ap.sight_weights(x[rows], find_neighbours(x[rows], ap.nodes, ap.boxes))
    near = mls_shape(x[rows], ap.nodes, ap.weight, ap.basis,
                     neighbours=find_neighbours(x[rows], ap.nodes, ap.boxes), weights=cw, **kw)
    for got, a, b in ((sh.values, plain.values, near.values), (sh.ddx, plain.ddx, near.ddx),
                      (sh.ddy, plain.ddy, near.ddy)):
        ref = a.copy()
        ref[rows] = b
        assert np.array_equal(got, ref)
    assert nb.idx.shape == sh.neighbours.idx.shape


def test_interpolant_equals_the_padded_sum(patch):
    # sum_I phi_I(x) q_I (seed 003 Eq. 44b) by a CSR product: the padded gather's sum
    from efgkit.approx.enrichment import interpolant

    _, disc = patch
    sh, enr = disc.shape, disc.approx.enrichment
    qn = enr.node_q[0].reshape(-1, 4)
    nb = sh.neighbours
    rows = np.arange(1, len(disc.points.x), 3)
    for v in (sh.values, sh.ddx, sh.ddy):
        ref = np.einsum("qk,qkc->qc", np.where(nb.mask[rows], v[rows], 0.0), qn[nb.idx[rows]])
        got = interpolant(v, nb, rows, qn, chunk=50)
        assert np.abs(got - ref).max() <= 1e-14 * np.abs(ref).max()


def test_all_pairs_search_gives_the_tree_s_graph(monkeypatch):
    # a small cloud: every (point, node) pair tested; the same CSR graph as the tree's
    import efgkit.search.kdtree as kd
    from efgkit.nodes import NodeCloud

    rng = np.random.default_rng(5)
    xn = rng.random((40, 2))
    cloud = NodeCloud(xn, rng.uniform(0.1, 0.3, 40), np.zeros(40, bool))
    x = np.vstack([rng.random((300, 2)), xn[:5] + [cloud.radius[0], 0.0]])  # one at r exactly
    assert len(x) * len(xn) <= kd.ALL_PAIRS
    small = kd.kdtree_lists(x, cloud)
    monkeypatch.setattr(kd, "ALL_PAIRS", 0)
    tree = kd.kdtree_lists(x, cloud)
    assert np.array_equal(small[0], tree[0]) and np.array_equal(small[1], tree[1])
    assert small[1].size > len(x)


def test_both_components_of_a_field_at_once():
    from efgkit.problem.exact.fields import Field
    from efgkit.problem.scene import evaluate_component, evaluate_components

    f, mat = Field.named("williams", KI=1.0, KII=0.5), Elastic(1.0, 0.3)
    x = np.random.default_rng(6).uniform(-1, 1, (20, 2))
    ref = np.column_stack([evaluate_component(f, x, c, mat) for c in (0, 1)])
    assert np.array_equal(evaluate_components(f, f, x, mat), ref)
    got = evaluate_components(None, 0.5, x, mat)
    assert np.array_equal(got, np.column_stack([np.zeros(20), np.full(20, 0.5)]))
    with pytest.raises(ValueError, match="too large to square"):
        evaluate_components(1e300, None, x, mat)


def test_small_spd_solve_by_dense_cholesky_equals_superlu(patch):
    import efgkit.system.linalg as la
    from efgkit.methods.boundary import loads
    from efgkit.static import constrained_system

    scene, disc = patch
    system = constrained_system(disc, stiffness(disc.shape, disc.points.w, scene.material.D), loads(disc))
    assert system.spd and system.A.shape[0] <= la.DENSE_SOLVE
    dense = la.solve(system, "direct", dense=la.DENSE_SOLVE)[0]
    sparse = la.solve(system, "direct")[0]
    assert np.abs(dense - sparse).max() <= 1e-14 * np.abs(sparse).max()  # measured 3.5e-15 (cond 160)
    # symmetric but indefinite though flagged SPD: Cholesky fails, SuperLU solves it
    A = csr_array(np.array([[1.0, 2.0], [2.0, 1.0]]))
    z = la.solve(la.LinearSystem(A, np.array([3.0, 3.0]), True, 2), "direct", dense=400)[0]
    assert np.allclose(z, [1.0, 1.0])
    with pytest.raises(la.SolverError, match="singular"):  # PSD singular: SuperLU's error
        la.solve(la.LinearSystem(csr_array(np.ones((2, 2))), np.array([1.0, 0.0]), True, 2), "direct",
                 dense=400)
