"""Box neighbour search against brute force, uniform and graded clouds."""

import numpy as np
import pytest

from efgkit import EFG, Domain, Zone
from efgkit.nodes import generate_nodes
from efgkit.search import BoxGrid, find_neighbours


@pytest.mark.parametrize("method", [
    EFG(spacing=0.05),
    EFG(spacing=0.05, perturb=0.4, seed=3),
    EFG(spacing=0.1, zones=(Zone((0.3, 0.3), 0.2, 0.02),)),
])
@pytest.mark.parametrize("box_size", [None, 0.03, 0.5])
def test_matches_brute_force(method, box_size):
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), method)
    x = np.random.default_rng(0).uniform(-0.05, 1.05, (500, 2))
    nb = find_neighbours(x, nodes, BoxGrid.build(nodes, box_size))
    d = np.linalg.norm(x[:, None] - nodes.x[None], axis=-1)
    brute = d < nodes.radius[None]
    found = np.zeros_like(brute)
    rows = np.repeat(np.arange(len(x)), nb.mask.sum(1))
    found[rows, nb.idx[nb.mask]] = True
    np.testing.assert_array_equal(found, brute)
    # valid entries come first in every row
    assert np.all(np.diff(nb.mask.astype(int), axis=1) <= 0)


def test_points_outside_all_supports_have_no_neighbours():
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    nb = find_neighbours(np.array([[10.0, 10.0], [0.5, 0.5]]), nodes)
    assert nb.counts.tolist()[0] == 0 and nb.counts[1] > 0


@pytest.mark.parametrize("perturb", [0.0, 0.4])
def test_compiled_and_numpy_paths_agree(perturb):
    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.05, perturb=perturb))
    x = np.random.default_rng(1).uniform(-0.1, 1.1, (3000, 2))
    a = find_neighbours(x, nodes)
    b = find_neighbours(x, nodes, backend="numpy")
    np.testing.assert_array_equal(a.mask, b.mask)
    np.testing.assert_array_equal(np.where(a.mask, a.idx, -1), np.where(b.mask, b.idx, -1))
