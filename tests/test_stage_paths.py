"""The faster paths of the stages around the linear solve against the paths they replace,
on small cases: the enrichment blocks of the compiled stiffness (efgkit.system.assemble):
K_ne summed point by point into a dense array (kernels.extra_dense) against the rows over
the functions' point lists (kernels.extra_rows), the stresses and K_ee of one shared pattern
(enriched_kernels.ee_block) against the sparse sums and products, the compiled stack of the
four blocks (the same K to the bit); the box of
every point by the compiled loop against numpy (efgkit.search.boxes)."""

import numpy as np
import pytest
from scipy.sparse import csr_array

import efgkit.system.assemble as assemble
from efgkit import EFG, Crack, Domain, Elastic, Scene
from efgkit.approx.shape import Extra, Shape
from efgkit.methods.discretize import discretize


def cracked(enrichment: str):
    sc = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1.0, 0.3),
               cracks=(Crack([[0.0, 0.5], [0.9, 0.5]], tips=(False, True)),))
    return discretize(sc, EFG(spacing=0.1, enrichment=enrichment, rule_power=1.0))


def bits(A: csr_array, B: csr_array) -> bool:
    A, B = csr_array(A), csr_array(B)
    A.sort_indices(), B.sort_indices()
    return (np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
            and np.array_equal(A.data, B.data))


@pytest.mark.parametrize("enrichment", ["extrinsic_mls", "pu"])
@pytest.mark.parametrize("symmetric", [True, False])
def test_dense_extra_block_equals_the_rows(monkeypatch, enrichment, symmetric):
    d = cracked(enrichment)
    D = Elastic(1.0, 0.3).D.copy()
    if not symmetric:
        D[0, 2], D[2, 0] = 0.1, -0.05
    assert d.shape.extra is not None
    monkeypatch.setattr(assemble, "DENSE_EXTRA_FILL", 0.0)  # dense also for PU's sparse rows
    dense = assemble.stiffness(d.shape, d.points.w, D, backend="numba")
    monkeypatch.setattr(assemble, "DENSE_EXTRA_MAX", 0)  # the rows over the point lists
    rows = assemble.stiffness(d.shape, d.points.w, D, backend="numba")
    assert bits(dense, rows)
    # and both against the scipy.sparse reference, to rounding (measured 2.1e-15 and 2.3e-15
    # of max |K| on these cases: the two group the sums differently; bound ~2.5x that)
    ref = assemble.stiffness(d.shape, d.points.w, D, backend="numpy")
    assert abs(dense - ref).max() <= 5e-15 * abs(ref).max()


def test_one_pattern_stresses_equal_the_sparse_sums():
    # the extrinsic columns share one pattern (the data-array stresses, the compiled K_ee); gyx
    # with each row's entries reversed is the same matrix on another index order (the sparse
    # sums and products). Summing K_ee's points in reverse order fails this test.
    d = cracked("extrinsic_mls")
    e = d.shape.extra
    g = csr_array(e.gyx)
    lens = np.diff(g.indptr)
    rows = np.repeat(np.arange(len(lens)), lens)
    order = np.lexsort((-g.indices, rows))  # row by row, columns descending
    assert lens.max() > 1 and not np.array_equal(order, np.arange(g.nnz))
    shuffled = csr_array((g.data[order], g.indices[order], g.indptr), shape=g.shape)
    other = Shape(d.shape.neighbours, d.shape.values, d.shape.ddx, d.shape.ddy,
                  d.shape.n_functions, Extra(e.ux, e.uy, e.gxx, e.gxy, shuffled, e.gyy))
    D = Elastic(1.0, 0.3).D
    for backend in ("numba", "numpy"):
        assert bits(assemble.stiffness(d.shape, d.points.w, D, backend=backend),
                    assemble.stiffness(other, d.points.w, D, backend=backend))


def test_compiled_stack_equals_the_index_arrays():
    from scipy.sparse import random_array

    from efgkit.system.block_stack import stack_2x2

    rng = np.random.default_rng(3)
    A, B, C, E = (csr_array(random_array(s, density=0.3, rng=rng))
                  for s in ((40, 40), (40, 3), (3, 40), (3, 3)))
    ref = stack_2x2(A, B, C, E)
    out = stack_2x2(A, B, C, E, compiled=True)
    assert bits(out, ref) and np.array_equal(out.indices, ref.indices)  # same order too
    assert np.array_equal(ref.toarray()[:40, 40:], B.toarray())


def test_compiled_box_of_equals_numpy(monkeypatch):
    import efgkit.search.boxes as boxes
    from efgkit.nodes import generate_nodes

    nodes = generate_nodes(Domain.rectangle(0, 0, 2, 1), EFG(spacing=0.05, perturb=0.3))
    rng = np.random.default_rng(4)
    x = np.concatenate([rng.uniform(-0.2, 2.2, (3000, 2)), nodes.x])  # some outside the grid
    for kind in ("uniform", "nonuniform"):
        grid = boxes.BoxGrid.build(nodes, kind=kind)
        monkeypatch.setattr(boxes, "COMPILED_MIN", 10**12)
        ref = grid.box_of(x)
        monkeypatch.setattr(boxes, "COMPILED_MIN", 1)
        out = grid.box_of(x)
        assert np.array_equal(out, ref) and (ref < 0).any() and (ref >= 0).any()


def test_abs_max_without_the_copy_equals_abs():
    import efgkit.system.constraints as constraints

    rng = np.random.default_rng(5)
    for sign in (1.0, -1.0):
        K = csr_array(sign * abs(csr_array(rng.standard_normal((40, 40)) * (rng.random((40, 40)) < 0.2))))
        assert constraints._abs_max(K) == abs(K).max() > 0
    assert constraints._abs_max(csr_array((5, 5))) == abs(csr_array((5, 5))).max() == 0


@pytest.mark.parametrize("backend", ["numba", "numpy"])
@pytest.mark.parametrize("enrichment", ["extrinsic_mls", "none"])
def test_chunk_stiffness_over_the_nodes_held_equals_all_nodes(backend, enrichment, monkeypatch):
    # chunks of ~300 points among 240 nodes: assembled over the nodes they hold, placed at
    # those DOFs (the enrichment DOFs last) -- the same K_c as over all nodes, to the bit.
    # The numpy path's dense nodal block (points x functions^2 <= DENSE_WORK) would take the
    # compact chunk and not the full one (sums in another order: 3e-16 apart); pinned off here,
    # its own equality is in test_small_paths.
    from efgkit.approx.point_shapes import PointShapes
    from efgkit.system.streamed import chunk_stiffness

    monkeypatch.setattr(assemble, "DENSE_WORK", 0)

    d = cracked(enrichment)
    ps = PointShapes(d.approx, d.points.x, chunk_points=300)
    D = Elastic(1.0, 0.3).D
    for s, e in ps.bounds()[::4]:
        sh = ps.chunk(s, e)
        ref = assemble.stiffness(sh, d.points.w[s:e], D, backend=backend)
        dof, K_c = chunk_stiffness(sh, d.points.w[s:e], D, backend)
        assert len(dof) < sh.n_dofs and np.all(np.diff(dof) > 0)  # the DOFs the chunk touches
        C = K_c.tocoo()
        out = csr_array((C.data, (dof[C.row], dof[C.col])), shape=ref.shape)
        assert out.shape == ref.shape and bits(out, ref)


def test_compact_numbering_keeps_the_order():
    from efgkit.search.neighbours import Neighbours

    rng = np.random.default_rng(6)
    idx = np.sort(rng.integers(0, 500, (200, 12)), axis=1).astype(np.int32)
    mask = rng.random((200, 12)) < 0.7
    local, nodes = Neighbours(idx, mask).compact(500)
    assert np.array_equal(nodes, np.unique(idx[mask]))
    assert np.array_equal(nodes[local.idx[mask]], idx[mask]) and (local.idx[~mask] == 0).all()
    assert local.idx.dtype == np.int32 and np.array_equal(local.mask, mask)
