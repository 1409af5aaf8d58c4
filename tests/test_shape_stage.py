"""The compiled paths of the shape stage of a cracked solve give the numpy results: the extrinsic
MLS columns by one kernel pass and their CSR written directly, the crack rows on the chunk's
kernel, the crack rules on the crossing pairs only, the chunk exit of the crack prefilter.
The references are the plain-numpy formulas of the same quantities (efgkit's reference paths,
each tested against closed forms and finite differences in test_enrichment.py,
test_crack_rules.py and test_mls.py)."""

import numpy as np
import pytest
from scipy.sparse import csr_array

import efgkit.jit as jit
from efgkit import EFG, Crack, Domain, Elastic, Scene
from efgkit.approx.crack_prefilter import points_near
from efgkit.approx.crack_rules import CrackLines, CrackRule, crack_distances, pair_arrays, sight_positions
from efgkit.approx.enrichment import extra_columns
from efgkit.approx.extrinsic import KEYS, column_operators
from efgkit.approx.kernels import mls_linear
from efgkit.approx.shape import Shape
from efgkit.methods.discretize import approximation
from efgkit.nodes import generate_nodes
from efgkit.search import find_neighbours

A = 1.0
SQUARE = Domain.rectangle(-A, -A, A, A)
MAT = Elastic(1000.0, 0.3, "strain")
CRACKS = {"edge": (Crack([[-A, 0.0], [0.0, 0.0]], (False, True), "edge"),),
          "kinked": (Crack([[-A, 0.1], [-0.3, 0.0], [0.2, 0.25]], (False, True), "k"),),
          "two_tips": (Crack([[-0.5, 0.05], [0.5, -0.05]], (True, True), "c"),)}


def _case(name, radius, spacing=0.1, n_points=3000, rule="diffraction"):
    scene = Scene(SQUARE, MAT, cracks=CRACKS[name])
    method = EFG(spacing=spacing, crack_rule=rule, enrichment="extrinsic_mls",
                 enrich_radius=radius, ramp_inner=0.1 if radius else 0.0).for_scene(scene)
    nodes = generate_nodes(SQUARE, method, scene.cracks)
    ap = approximation(scene, method, nodes)
    x = np.random.default_rng(3).uniform(-A, A, (n_points, 2))
    return ap, x


def _nodal(ap, x):
    sh = ap.shape(x)
    return Shape(sh.neighbours, sh.values, sh.ddx, sh.ddy, sh.n_functions)


@pytest.mark.parametrize("name,radius", [("edge", None), ("edge", 0.3), ("kinked", None),
                                         ("kinked", 0.3), ("two_tips", 0.3)])
@pytest.mark.parametrize("derivatives", [True, False])
def test_compiled_extrinsic_columns_equal_the_numpy_ones(name, radius, derivatives):
    """Same rows, same CSR structure and index types, values to 1e-13 of the largest (the
    kernel sums the interpolant and the modes in another order: measured 1.5e-14)."""
    ap, x = _case(name, radius)
    nodal = _nodal(ap, x)
    ref = extra_columns(x, nodal, ap.enrichment, derivatives, ap.spacing, backend="numpy")
    got = extra_columns(x, nodal, ap.enrichment, derivatives, ap.spacing, backend="numba")
    for key in KEYS:
        a, b = getattr(ref, key), getattr(got, key)
        if not derivatives and key not in ("ux", "uy"):
            assert a is None and b is None
            continue
        assert a.shape == b.shape and a.has_canonical_format and b.has_canonical_format
        np.testing.assert_array_equal(a.indptr, b.indptr)
        np.testing.assert_array_equal(a.indices, b.indices)
        assert (a.indices.dtype, a.indptr.dtype) == (b.indices.dtype, b.indptr.dtype) == \
            (np.int32, np.int32)
        assert abs(a - b).max() <= 1e-13 * abs(a).max()
    if radius is not None:  # ramped: only the rows near the tips
        assert 0 < ref.ux.nnz < ap.enrichment.n_extra * len(x)


def test_compiled_extrinsic_columns_refuse_a_point_at_the_tip():
    ap, x = _case("edge", None, n_points=50)
    nodal = _nodal(ap, x)  # (the shape itself refuses the tip: formed off it)
    x[7] = [0.0, 0.0]  # the tip
    for backend in ("numpy", "numba"):
        with pytest.raises(ValueError, match=r"point \[0.0, 0.0\] is at crack tip edge:1"):
            extra_columns(x, nodal, ap.enrichment, True, ap.spacing, backend=backend)


def test_column_operators_equal_scipy_from_triplets():
    """Tips at overlapping row sets: the operator is the canonical CSR of the triplets."""
    rng = np.random.default_rng(0)
    n, per_tip, trip = 40, [], ([], [], [])
    for t in range(3):
        rows = np.sort(rng.choice(n, 15 + 5 * t, replace=False))
        out = rng.standard_normal((1, len(rows), 2))
        per_tip.append((rows, out))
        for mode in (0, 1):
            trip[0].append(rows)
            trip[1].append(np.full(len(rows), 2 * t + mode))
            trip[2].append(out[0, :, mode])
    got = column_operators(n, 6, per_tip, ("ux",))["ux"]
    ref = csr_array((np.concatenate(trip[2]), (np.concatenate(trip[0]), np.concatenate(trip[1]))),
                    shape=(n, 6))
    ref.sum_duplicates()
    np.testing.assert_array_equal(got.indptr, ref.indptr)
    np.testing.assert_array_equal(got.indices, ref.indices)
    np.testing.assert_array_equal(got.data, ref.data)
    assert got.has_canonical_format


def test_shape_on_the_compiled_paths_equals_numpy(monkeypatch):
    """The whole shape of a cracked, enriched approximation with every kernel (the rows near
    the crack included) against the numpy paths, to 1e-12 of the largest value."""
    ap, x = _case("edge", None, spacing=0.1, n_points=2000)
    nb = find_neighbours(x, ap.nodes, ap.boxes)
    ref = ap.shape(x, neighbours=nb)
    monkeypatch.setattr(jit, "COMPILED_MIN", 1)  # every backend="auto" takes the kernels
    got = ap.shape(x, neighbours=nb)
    assert len(ap.cracked_rows(x, got.neighbours)) > 100
    np.testing.assert_array_equal(ref.neighbours.mask, got.neighbours.mask)
    for a, b in ((ref.values, got.values), (ref.ddx, got.ddx), (ref.ddy, got.ddy)):
        assert np.abs(a - b).max() <= 1e-12 * np.abs(a).max()
    for key in KEYS:
        a, b = getattr(ref.extra, key), getattr(got.extra, key)
        assert abs(a - b).max() <= 1e-12 * abs(a).max()


@pytest.mark.parametrize("rule", ["visibility", "diffraction", "transparency", "see_through"])
def test_crack_distances_with_the_nodes_sight_positions_are_unchanged(rule):
    """The rule formulas on the crossing pairs only, and the sight positions gathered per node,
    give bitwise the distances of the per-pair computation (split nodes: crack on a node row)."""
    scene = Scene(SQUARE, MAT, cracks=CRACKS["kinked"])
    m = EFG(spacing=0.1, crack_rule=rule, enrichment="none").for_scene(scene)
    nodes = generate_nodes(SQUARE, m, scene.cracks)
    ap = approximation(scene, m, nodes)
    x = np.random.default_rng(5).uniform(-A, A, (1500, 2))
    nb = find_neighbours(x, nodes, ap.boxes)
    rows, cols, I, xq, xn, dm = pair_arrays(x, nodes, nb)
    lines = CrackLines.from_cracks(scene.cracks)
    rule_ = CrackRule(rule, 2.0, 0.5, 0.1)
    ref = crack_distances(xq, xn, dm, I, nodes, lines, rule_)
    node_sight = sight_positions(nodes.x, nodes.radius, np.arange(nodes.n), nodes, lines)
    got = crack_distances(xq, xn, dm, I, nodes, lines, rule_, sight=node_sight[I])
    assert ref[0].sum() > 0  # some pairs cross
    for a, b in zip(ref, got, strict=True):
        np.testing.assert_array_equal(a, b)


def test_points_near_skips_a_chunk_away_from_the_cracks():
    lines = CrackLines.from_cracks(CRACKS["edge"])
    rng = np.random.default_rng(2)
    away = rng.uniform(0.5, 1.0, (500, 2))  # y >= 0.5 > radius 0.4 from the crack line y = 0
    assert points_near(lines, away, 0.4).size == 0
    both = np.vstack([away, rng.uniform(-1.0, 1.0, (500, 2))])
    got = points_near(lines, both, 0.4)
    near = np.flatnonzero(lines.distance(both) < 0.4)
    assert np.isin(near, got).all() and got.min() >= 500  # the far block is never listed
    assert points_near(lines, np.zeros((0, 2)), 0.4).size == 0


def test_linear_kernel_gives_zeros_at_a_singular_point():
    """The outputs hold the pair weights during the pass; a point whose moment matrix is
    singular (three collinear neighbours) gets zeros and rcond 0, not the weights."""
    nx = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    radius = np.full(4, 3.0)
    x = np.array([[0.5, 0.0], [0.5, 0.2]])
    idx = np.array([[0, 1, 2, 3], [0, 1, 2, 3]], np.int32)
    mask = np.array([[True, True, True, False], [True, True, True, True]])
    z = np.zeros((0, 0))
    phi, gx, gy, rcond = mls_linear(x, nx, radius, idx, mask, 0, 4.0, True, z, z, z)
    assert rcond[0] == 0.0 and not phi[0].any() and not gx[0].any() and not gy[0].any()
    assert rcond[1] > 0 and phi[1].sum() == pytest.approx(1.0, abs=1e-14)  # partition of unity
    np.testing.assert_allclose(phi[1] @ nx, x[1], atol=1e-14)  # linear reproduction
    assert abs(gx[1].sum()) < 1e-13 and abs(gy[1].sum()) < 1e-13


def test_operators_share_one_int32_pattern():
    """phi, dx, dy hold one pattern (formed once, int32, each operator its own copy) and the
    entries of the padded arrays at the valid neighbours, also with rows cleared by a crack
    rule; an in-place change of one operator's pattern leaves the others as they were."""
    ap, x = _case("edge", None, n_points=800)
    sh = _nodal(ap, x)
    nb = sh.neighbours
    assert not nb.mask.all()  # padded rows and the crack's cleared pairs
    for op, vals in ((sh.phi, sh.values), (sh.dx, sh.ddx), (sh.dy, sh.ddy)):
        assert op.indices.dtype == op.indptr.dtype == np.int32 and op.has_sorted_indices
        dense = np.zeros(op.shape)
        rows, cols = np.nonzero(nb.mask)
        dense[rows, nb.idx[rows, cols]] = vals[rows, cols]
        np.testing.assert_array_equal(op.toarray(), dense)
    np.testing.assert_array_equal(sh.phi.indices, sh.dx.indices)
    np.testing.assert_array_equal(sh.phi.indptr, sh.dy.indptr)
    phi = sh.phi.toarray()
    sh.dx.data[:] = 0.0
    sh.dx.eliminate_zeros()  # compacts dx's indices in place
    assert sh.dx.nnz == 0
    np.testing.assert_array_equal(sh.phi.toarray(), phi)
