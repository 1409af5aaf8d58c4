"""Properties of MLS shape functions: partition of unity, polynomial reproduction,
derivatives against finite differences, kernel agreement, modified MLS, errors."""

import numpy as np
import pytest

from efgkit import EFG, Domain
from efgkit.approx.mls import SingularMomentMatrix, mls_shape
from efgkit.nodes import NodeCloud, generate_nodes

CASES = [(w, b) for w in ("quartic", "gaussian", "cubic") for b in ("linear", "quadratic")]


def cloud(basis, perturb=0.3, seed=0):
    d_max = 2.0 if basis == "linear" else 2.6
    return generate_nodes(Domain.rectangle(-1.0, 2.0, 1.0, 3.0),
                          EFG(spacing=0.1, perturb=perturb, seed=seed, d_max=d_max)), d_max


def points(n=400, seed=1):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-1, 1, n), rng.uniform(2, 3, n)])


def poly(basis, x):
    """A complete polynomial of the basis degree and its gradient."""
    X, Y = x[:, 0], x[:, 1]
    if basis == "linear":
        return 1 + 2 * X - 3 * Y, np.full_like(X, 2.0), np.full_like(X, -3.0)
    return (1 + 2 * X - 3 * Y + 0.5 * X * X - X * Y + 0.25 * Y * Y,
            2 + X - Y, -3 - X + 0.5 * Y)


@pytest.mark.parametrize("weight,basis", CASES)
def test_partition_of_unity(weight, basis):
    nodes, d_max = cloud(basis)
    sh = mls_shape(points(), nodes, weight, basis, d_max=d_max, alpha=d_max / 4)
    np.testing.assert_allclose(sh.phi.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(sh.dx.sum(axis=1), 0.0, atol=1e-9)
    np.testing.assert_allclose(sh.dy.sum(axis=1), 0.0, atol=1e-9)


@pytest.mark.parametrize("weight,basis", CASES)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_polynomial_reproduction_random_cloud(weight, basis, seed):
    nodes, d_max = cloud(basis, seed=seed)
    x = points(seed=seed + 10)
    sh = mls_shape(x, nodes, weight, basis, d_max=d_max, alpha=d_max / 4)
    u, ux, uy = poly(basis, x)
    coeff = poly(basis, nodes.x)[0]
    np.testing.assert_allclose(sh.phi @ coeff, u, atol=1e-10)
    np.testing.assert_allclose(sh.dx @ coeff, ux, atol=1e-8)
    np.testing.assert_allclose(sh.dy @ coeff, uy, atol=1e-8)


@pytest.mark.parametrize("weight,basis", CASES)
def test_derivatives_match_finite_differences(weight, basis):
    nodes, d_max = cloud(basis)
    x = points(50)
    eps = 1e-6
    kw = dict(weight=weight, basis=basis, d_max=d_max, alpha=d_max / 4)
    sh = mls_shape(x, nodes, **kw)
    for k, op in ((0, sh.dx), (1, sh.dy)):
        dx = np.zeros(2)
        dx[k] = eps
        fd = (mls_shape(x + dx, nodes, derivatives=False, **kw).phi.toarray()
              - mls_shape(x - dx, nodes, derivatives=False, **kw).phi.toarray()) / (2 * eps)
        np.testing.assert_allclose(op.toarray(), fd, atol=1e-6 * np.abs(fd).max())


@pytest.mark.parametrize("weight,basis", CASES)
def test_numba_kernel_equals_numpy_reference(weight, basis):
    nodes, d_max = cloud(basis)
    kw = dict(weight=weight, basis=basis, d_max=d_max, alpha=d_max / 4)
    a = mls_shape(points(), nodes, **kw)
    b = mls_shape(points(), nodes, backend="numpy", **kw)
    for name in ("values", "ddx", "ddy"):
        ref = getattr(b, name)
        assert np.abs(getattr(a, name) - ref).max() <= 1e-12 * np.abs(ref).max()


@pytest.mark.parametrize("offset,scale", [(0.0, 1e-3), (1e6, 1.0), (0.0, 1e3)])
def test_invariant_to_units_and_offset(offset, scale):
    nodes, _ = cloud("linear")
    x = points()
    ref = mls_shape(x, nodes)
    moved = NodeCloud(nodes.x * scale + offset, nodes.radius * scale, nodes.boundary)
    sh = mls_shape(x * scale + offset, moved)
    np.testing.assert_allclose(sh.values, ref.values, atol=1e-9)
    np.testing.assert_allclose(sh.ddx * scale, ref.ddx, atol=1e-7 * np.abs(ref.ddx).max())


@pytest.mark.parametrize("basis", ["linear", "quadratic"])
def test_modified_mls_kronecker_delta_and_reproduction(basis):
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1),
                           EFG(spacing=0.1, d_max=2.5 if basis == "linear" else 3.2))
    interp = nodes.boundary
    r = nodes.radius.copy()
    from scipy.spatial import cKDTree

    d, _ = cKDTree(nodes.x[interp]).query(nodes.x[interp], k=2)
    r[interp] = d[:, 1] * (1 - 1e-9)
    nodes = NodeCloud(nodes.x, r, nodes.boundary)
    b = np.flatnonzero(interp)
    sh = mls_shape(nodes.x[b], nodes, basis=basis, interpolate=interp)
    np.testing.assert_allclose(sh.phi.toarray(), np.eye(nodes.n)[b], atol=1e-12)
    x = points(300, seed=4) - [0, 2]
    x = np.abs(x)
    sh = mls_shape(x, nodes, basis=basis, interpolate=interp)
    u, ux, uy = poly("linear", x)
    c = poly("linear", nodes.x)[0]
    np.testing.assert_allclose(sh.phi @ c, u, atol=1e-10)
    np.testing.assert_allclose(sh.dx @ c, ux, atol=1e-7)
    np.testing.assert_allclose(sh.dy @ c, uy, atol=1e-7)


def test_modified_mls_too_many_collinear_boundary_nodes_is_explained():
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.1))
    with pytest.raises(SingularMomentMatrix, match="modified MLS.*reduce d_max"):
        mls_shape(nodes.x, nodes, interpolate=nodes.boundary)


def test_too_small_support_names_point_count_and_remedy():
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.1, d_max=1.05))
    with pytest.raises(SingularMomentMatrix,
                       match=r"point \d+ \[.*\] has \d neighbour\(s\).*Remedy: enlarge the support"):
        mls_shape(points() - [0, 2], nodes, basis="quadratic")


def test_collinear_neighbours_detected_by_condition_not_by_luck():
    # Three collinear nodes: A is exactly singular for a linear basis.
    x = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    nodes = NodeCloud(x, np.full(3, 3.0), np.zeros(3, bool))
    with pytest.raises(SingularMomentMatrix, match=r"rcond = .*with 3 neighbour\(s\)"):
        mls_shape(np.array([[1.0, 0.5]]), nodes)


def test_bad_points_shape():
    nodes, _ = cloud("linear")
    with pytest.raises(ValueError, match=r"x must have shape \(n_points, 2\)"):
        mls_shape(np.zeros((3, 3)), nodes)


@pytest.mark.parametrize("m", [3, 6, 7])
def test_compiled_and_numpy_condition_estimates_agree(m):
    # regression: for m > 3 the numpy path measured rcond after Jacobi scaling, the compiled
    # one did not (27 times apart on a quadratic-basis point), so they refused different points
    from efgkit.approx.kernels import _invert
    from efgkit.approx.mls import _inv_rcond

    rng = np.random.default_rng(m)
    B = rng.standard_normal((m, m + 4)) * np.logspace(0, -4, m)[:, None]  # badly scaled rows
    A = B @ B.T
    inv = np.empty((m, m))
    r_compiled = _invert(A, inv, m)
    inv_np, r_np = _inv_rcond(A[None])
    assert r_compiled == pytest.approx(r_np[0], rel=1e-8)
    assert np.allclose(inv, inv_np[0], rtol=1e-8, atol=0)
