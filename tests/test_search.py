"""Neighbour search: uniform boxes, nonuniform boxes (seed 000 Sect. 4.1) and cKDTree give
the graph of brute force, |x - x_I| < d_mI, on random, graded and degenerate clouds."""

import numpy as np
import pytest

from efgkit import EFG, Domain, Zone
from efgkit.nodes import NodeCloud, generate_nodes
from efgkit.search import BoxGrid, find_neighbours, neighbour_lists, research_interval

METHODS = ["uniform", "nonuniform", "kdtree", "auto"]


def cloud(x, r):
    x = np.asarray(x, float)
    return NodeCloud(x, np.broadcast_to(np.asarray(r, float), (len(x),)).copy(),
                     np.zeros(len(x), bool))


def graded(m):
    """Seed 000 Fig. 1 layout at 1/m the size: 12 x 15 cut into zones of heights 1, 2, 4, 8
    from the bottom, spacing 1/m doubling from zone to zone, support 2h = 3 spacings."""
    parts, radii, y0 = [], [], 0.0
    for k, height in enumerate((1, 2, 4, 8)):
        d = 2 ** k / m
        X, Y = np.meshgrid(np.linspace(0, 12, int(round(12 / d)) + 1),
                           y0 + d * np.arange(0 if k == 0 else 1, int(round(height / d)) + 1))
        parts.append(np.column_stack([X.ravel(), Y.ravel()]))
        radii.append(np.full(X.size, 3 * d))
        y0 += height
    return cloud(np.concatenate(parts), np.concatenate(radii))


def clouds():
    rng = np.random.default_rng(0)
    line = np.column_stack([np.linspace(0, 1, 41), np.zeros(41)])
    dup = np.repeat(rng.uniform(0, 1, (60, 2)), 3, axis=0)  # every node three times
    return {
        "random": cloud(rng.uniform(0, 1, (400, 2)), rng.uniform(0.05, 0.2, 400)),
        "efg_uniform": generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.05)),
        "efg_perturbed": generate_nodes(Domain.rectangle(0, 0, 1, 1),
                                        EFG(spacing=0.05, perturb=0.4, seed=3)),
        "efg_zone": generate_nodes(Domain.rectangle(0, 0, 1, 1),
                                   EFG(spacing=0.1, zones=(Zone((0.3, 0.3), 0.2, 0.02),))),
        "seed000_m5": graded(5),
        "line": cloud(line, 0.06),           # supports of exactly 2.4 spacings: ties at 0.025
        "line_vertical": cloud(line[:, ::-1], 0.05),  # ties |x - x_I| = d_mI: excluded
        "duplicates": cloud(dup, 0.15),
        "one_node": cloud([[0.5, 0.5]], 0.3),
    }


CLOUDS = clouds()


def brute(x, nodes):
    d2 = ((nodes.x[None, :, 0] - x[:, None, 0]) ** 2 + (nodes.x[None, :, 1] - x[:, None, 1]) ** 2)
    return d2 < nodes.radius[None] ** 2


def query_points(nodes):
    rng = np.random.default_rng(1)
    lo, hi = nodes.x.min(0) - 0.1, nodes.x.max(0) + 0.1
    return np.concatenate([nodes.x, rng.uniform(lo, hi, (500, 2))])  # the nodes: ties


@pytest.mark.parametrize("name", sorted(CLOUDS))
@pytest.mark.parametrize("method", METHODS)
def test_graph_is_brute_force(name, method):
    nodes = CLOUDS[name]
    x = query_points(nodes)
    nb = find_neighbours(x, nodes, method=method)
    found = np.zeros((len(x), nodes.n), bool)
    found[np.repeat(np.arange(len(x)), nb.counts), nb.idx[nb.mask]] = True
    np.testing.assert_array_equal(found, brute(x, nodes))
    assert np.all(np.diff(nb.mask.astype(int), axis=1) <= 0)  # valid entries first
    assert nb.idx.shape[1] == nb.counts.max()  # no column wider than the largest count
    assert nb.idx.dtype == np.int32  # half the memory of the padded int64 indices
    # CSR has the same rows, ascending
    indptr, indices = neighbour_lists(x, nodes, method=method)
    np.testing.assert_array_equal(np.diff(indptr), nb.counts)
    np.testing.assert_array_equal(indices, nb.idx[nb.mask])
    rows = np.repeat(np.arange(len(x)), np.diff(indptr))
    assert np.all((np.diff(indices) > 0) | (np.diff(rows) != 0))


@pytest.mark.parametrize("kind", ["uniform", "nonuniform"])
@pytest.mark.parametrize("box_size", [0.03, 0.5])
def test_any_box_size_gives_the_graph(kind, box_size):
    nodes = CLOUDS["efg_zone"]
    x = query_points(nodes)
    grid = BoxGrid.build(nodes, box_size if kind == "uniform" else None, kind=kind,
                         factor=1.0 if kind == "uniform" else box_size * 10)
    a = neighbour_lists(x, nodes, grid)
    b = neighbour_lists(x, nodes, method="kdtree")
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


@pytest.mark.parametrize("kind", ["uniform", "nonuniform"])
@pytest.mark.parametrize("name", ["efg_zone", "seed000_m5", "line", "duplicates"])
def test_compiled_and_numpy_registration_agree(kind, name):
    a = BoxGrid.build(CLOUDS[name], kind=kind, backend="numba")
    b = BoxGrid.build(CLOUDS[name], kind=kind, backend="numpy")
    np.testing.assert_array_equal(a.start, b.start)
    np.testing.assert_array_equal(a.members, b.members)


def test_nonuniform_boxes_follow_the_local_support():
    """Seed 000 Sect. 4.1: box side 2 h-bar, the largest smoothing length reaching the strip;
    in the finest zone (support 3 / m) the boxes are 8 times smaller than in the coarsest."""
    nodes = graded(10)
    g = BoxGrid.build(nodes, kind="nonuniform")
    assert g.axis == 1  # 15 high, 12 wide: strips stacked along y (seed 000 step 1)
    centre = 0.5 * (g.edges[:-1] + g.edges[1:])
    np.testing.assert_allclose(g.side[g.edges[1:] <= 0.6], 0.3)  # zone A (zone B reaches 0.6)
    np.testing.assert_allclose(g.side[centre > 7 + 2.4], 2.4)  # zone D: 3 * 0.8
    u = BoxGrid.build(nodes, kind="uniform")
    np.testing.assert_allclose(u.side, 2.4)  # the seed's uniform grid: 2 h_max


def test_points_outside_all_supports_have_no_neighbours():
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    for method in METHODS:
        nb = find_neighbours(np.array([[10.0, 10.0], [0.5, 0.5]]), nodes, method=method)
        assert nb.counts.tolist()[0] == 0 and nb.counts[1] > 0


def test_research_interval_of_seed_000():
    # seed 000 Sect. 4.2: dt = psi h / (2 |U_max|), box side (2 + psi) h
    res = research_interval(h=0.15, u_max=-2000.0, psi=0.1)
    assert res.dt == pytest.approx(0.1 * 0.15 / 4000.0, rel=1e-15)
    assert res.box_side == pytest.approx(2.1 * 0.15, rel=1e-15)
    assert res.skin == pytest.approx(0.015, rel=1e-15)
    assert research_interval(0.15, 0.0).dt == np.inf


@pytest.mark.parametrize("call, match", [
    (lambda n: find_neighbours(np.zeros((3, 3)), n), r"x must have shape \(n_points, 2\)"),
    (lambda n: find_neighbours(np.array([[0.0, np.nan]]), n), "x must be finite, but point 0"),
    (lambda n: find_neighbours(np.zeros((1, 2)), n, method="octree"), "method must be one of"),
    (lambda n: BoxGrid.build(n, kind="octree"), "kind must be one of"),
    (lambda n: BoxGrid.build(n, kind="nonuniform", factor=0.0), "factor must be a positive"),
    (lambda n: BoxGrid.build(n, -1.0), "size must be a positive number"),
    (lambda n: BoxGrid.build(cloud([[0.0, 0.0]], 0.0)), "positive finite radii"),
    (lambda n: BoxGrid.build(cloud(np.zeros((0, 2)), 1.0)), "nodes is empty"),
    (lambda n: BoxGrid.build(n, backend="gpu"), "backend must be one of"),
    (lambda n: research_interval(0.0, 1.0), "h must be a positive number"),
    (lambda n: research_interval(1.0, 1.0, psi=-1.0), "psi must be a positive number"),
    (lambda n: research_interval(1.0, np.inf), "u_max must be finite"),
])
def test_bad_input(call, match):
    with pytest.raises(ValueError, match=match):
        call(CLOUDS["random"])


@pytest.mark.parametrize("name", ["seed000_m5", "duplicates", "line"])
def test_threaded_count_and_fill_give_the_one_pass_graph(name, monkeypatch):
    """Below PARALLEL points (or on FUSED_THREADS threads or fewer) the CSR lists come from
    one fused pass (kernels.csr_serial); above both from the parallel count and fill
    passes: the same graph."""
    from efgkit.search import neighbours

    nodes = CLOUDS[name]
    x = query_points(nodes)
    a = neighbour_lists(x, nodes, method="nonuniform")
    monkeypatch.setattr(neighbours, "PARALLEL", 0)
    monkeypatch.setattr(neighbours, "FUSED_THREADS", 0)
    b = neighbour_lists(x, nodes, method="nonuniform")
    truth = brute(x, nodes)
    np.testing.assert_array_equal(np.diff(a[0]), truth.sum(axis=1))
    np.testing.assert_array_equal(a[1], np.nonzero(truth)[1])
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_fused_pass_grows_its_output():
    """kernels.csr_serial starts with room for 32 neighbours per point of the first 4096
    and grows from its running estimate: a cloud with ~110 neighbours per point and 6000
    points makes it grow several times; the graph stays that of brute force."""
    rng = np.random.default_rng(4)
    nodes = cloud(rng.uniform(0, 1, (2000, 2)), 0.13)  # pi 0.13^2 2000 = 106 per point
    x = np.concatenate([rng.uniform(0, 1, (5000, 2)), rng.uniform(0, 0.3, (1000, 2))])
    indptr, indices = neighbour_lists(x, nodes, method="uniform")
    truth = brute(x, nodes)
    np.testing.assert_array_equal(np.diff(indptr), truth.sum(axis=1))
    np.testing.assert_array_equal(indices, np.nonzero(truth)[1])
    assert np.diff(indptr).mean() > 64  # twice the starting room
