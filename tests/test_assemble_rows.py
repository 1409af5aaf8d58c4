"""The compiled row assembly of K (efgkit.system.kernels): against the scipy.sparse reference
to rounding, with cleared and unordered neighbour lists, and the point lists of the
functions against a sort of the neighbour pairs."""

import numpy as np
import pytest

from efgkit import EFG, Domain, Elastic
from efgkit.approx.mls import mls_shape
from efgkit.approx.shape import Shape
from efgkit.nodes import generate_nodes
from efgkit.search.neighbours import Neighbours
from efgkit.system.assemble import point_to_function_map, stiffness

# max |K - K_ref| / max |K_ref| measured 1.1e-15 ... 1.7e-15 on these cases (the two sum
# the same products in different groupings); the bound is 3x that.
ROUNDING = 5e-15


@pytest.fixture(scope="module")
def setup():
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.1, perturb=0.3))
    xq = np.random.default_rng(0).random((2000, 2))
    return xq, np.full(2000, 1 / 2000), mls_shape(xq, nodes), nodes


def rel(A, B):
    return abs(A - B).max() / abs(B).max()


def variant(sh, nb, take=lambda a: a):
    return Shape(nb, take(sh.values), take(sh.ddx), take(sh.ddy), sh.n_functions)


@pytest.mark.parametrize("case", ["symmetric", "unsymmetric D", "petrov", "cleared"])
def test_rows_equal_the_reference(setup, case):
    xq, w, sh, nodes = setup
    D = Elastic(2.0, 0.3).D.copy()
    test = None
    if case == "unsymmetric D":
        D[0, 2], D[2, 0] = 0.1, -0.05
    elif case == "petrov":
        test = mls_shape(xq, nodes, weight="cubic")
    elif case == "cleared":  # a crack rule clears entries anywhere in a row
        nb = sh.neighbours
        keep = np.random.default_rng(1).random(nb.mask.shape) > 0.1
        sh = variant(sh, Neighbours(nb.idx, nb.mask & keep))
    A = stiffness(sh, w, D, test=test, backend="numba")
    B = stiffness(sh, w, D, test=test, backend="numpy")
    assert A.has_sorted_indices
    assert rel(A, B) <= ROUNDING


def test_unordered_lists_give_the_same_bits(setup):
    # Ascending lists take the short loop over the slots from I's own on; shuffled lists the
    # full loop with the J >= I test. Each block sums the same products over the same points
    # in the same order either way, so K is the same to the last bit.
    _, w, sh, _ = setup
    nb = sh.neighbours
    perm = np.argsort(np.random.default_rng(2).random(nb.idx.shape), axis=1)

    def take(a):
        return np.take_along_axis(a, perm, axis=1)

    shuffled = variant(sh, Neighbours(take(nb.idx), take(nb.mask)), take)
    D = Elastic(1.0, 0.25).D
    A, B = stiffness(sh, w, D, backend="numba"), stiffness(shuffled, w, D, backend="numba")
    assert np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
    assert np.array_equal(A.data, B.data)


def test_point_lists_against_a_stable_sort(setup):
    _, _, sh, _ = setup
    nb = sh.neighbours
    q, a = np.nonzero(nb.mask)  # row-major: points ascending
    I = nb.idx[q, a]
    order = np.argsort(I, kind="stable")
    indptr, point, slot = point_to_function_map(sh)
    np.testing.assert_array_equal(indptr, np.r_[0, np.cumsum(np.bincount(I, minlength=sh.n_functions))])
    np.testing.assert_array_equal(point, q[order])
    np.testing.assert_array_equal(slot, a[order])


def test_functions_without_points_give_empty_rows(setup):
    # Points in the left half only: the functions whose supports miss them have no points,
    # are formed last in the row order and get empty rows (streamed chunks meet this often).
    xq, _, _, nodes = setup
    left = xq[xq[:, 0] < 0.4]
    sh = mls_shape(left, nodes)
    w = np.full(len(left), 1 / len(left))
    D = Elastic(1.0, 0.3).D
    A = stiffness(sh, w, D, backend="numba")
    B = stiffness(sh, w, D, backend="numpy")
    empty = np.bincount(sh.neighbours.idx[sh.neighbours.mask], minlength=nodes.n) == 0
    assert empty.sum() > 10
    rows = np.diff(A.indptr)
    assert np.all(rows[np.repeat(empty, 2)] == 0) and np.all(rows[np.repeat(~empty, 2)] > 0)
    assert rel(A, B) <= ROUNDING


def test_thread_count_does_not_change_the_bits(setup):
    # Every row sums its own points in the order of its point list, whichever thread and
    # chunk forms it: K is the same to the last bit on 1 and on 2 threads.
    import numba

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("needs NUMBA_NUM_THREADS >= 2")
    _, w, sh, _ = setup
    D = Elastic(1.0, 0.3).D
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        A = stiffness(sh, w, D, backend="numba")
        numba.set_num_threads(2)
        B = stiffness(sh, w, D, backend="numba")
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
    assert np.array_equal(A.data, B.data)


def test_vectorised_compile_leaves_numba_config_as_it_was(setup):
    # The row kernel is compiled with numba's SLP vectoriser switched on for that
    # compilation only; the global setting is restored (also when it raises).
    from numba.core import config

    from efgkit.system.kernels import compile_vectorised

    _, w, sh, _ = setup
    before = config.SLP_VECTORIZE
    stiffness(sh, w, Elastic(1.0, 0.3).D, backend="numba")
    assert config.SLP_VECTORIZE == before

    class Failing:
        overloads: dict = {}

        def compile(self, signature):
            assert config.SLP_VECTORIZE == 1
            raise RuntimeError("compile failed")

    with pytest.raises(RuntimeError, match="compile failed"):
        compile_vectorised(Failing(), np.zeros(3))
    assert config.SLP_VECTORIZE == before


@pytest.mark.parametrize("enrichment", ["extrinsic_mls", "pu"])
@pytest.mark.parametrize("symmetric", [True, False])
def test_enrichment_rows_equal_the_reference(enrichment, symmetric):
    # The nodal-enrichment rows by the compiled kernel (three stress components as separate
    # CSR patterns: PU's differ from one another) against the operator products of the
    # numpy path; with an unsymmetric D the enrichment-node block is formed apart.
    from efgkit import Crack, Scene
    from efgkit.methods.discretize import discretize

    sc = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1.0, 0.3),
               cracks=(Crack([[0.0, 0.5], [0.9, 0.5]], tips=(False, True)),))
    d = discretize(sc, EFG(spacing=0.125, enrichment=enrichment, rule_power=1.0))
    D = Elastic(1.0, 0.3).D.copy()
    if not symmetric:
        D[0, 2], D[2, 0] = 0.1, -0.05
    A = stiffness(d.shape, d.points.w, D, backend="numba")
    B = stiffness(d.shape, d.points.w, D, backend="numpy")
    assert d.shape.extra is not None and d.shape.extra.n >= 2
    A.sort_indices()
    B.sort_indices()
    assert np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
    assert rel(A, B) <= ROUNDING
