"""A Lagrange saddle point held as its blocks (efgkit.system.linear_system): the product by
blocks is the product by the formed matrix, the matrix is formed only when asked for, and a
large Lagrange solve (CG with Uzawa steps) never forms it."""

import numpy as np
import pytest
from scipy.sparse import bmat, csr_array, random_array

from efgkit.system.linear_system import LinearSystem, saddle_matrix


def _blocks(n=30, m=4, seed=0):
    rng = np.random.default_rng(seed)
    R = random_array((n, n), density=0.2, random_state=rng)
    K = csr_array(R @ R.T + 5.0 * csr_array(np.eye(n)))
    G = csr_array(random_array((m, n), density=0.3, random_state=rng) + csr_array(np.eye(m, n)))
    return K, G


def test_blocks_product_is_the_formed_matrix_product():
    K, G = _blocks()
    s = LinearSystem(None, np.ones(34), False, 30, blocks=(K, G))
    z = np.random.default_rng(1).standard_normal(34)
    by_blocks = s.product(z)
    assert "A" not in s.__dict__  # not formed by the product
    dense = bmat([[K, G.T], [G, None]]).toarray()  # the saddle point by its definition
    np.testing.assert_allclose(by_blocks, dense @ z, rtol=1e-14, atol=1e-14 * np.abs(dense).max())
    assert np.array_equal(s.A.toarray(), dense) and s.A is s.A  # formed once, on demand
    assert s.size == 34 and np.array_equal(saddle_matrix(K, G).toarray(), dense)


def test_neither_matrix_nor_blocks_is_refused():
    with pytest.raises(ValueError, match=r"LinearSystem needs a matrix or the blocks \(K, G\)"):
        LinearSystem(None, np.ones(2), True, 2)


def test_lagrange_cg_solve_does_not_form_the_saddle_matrix(monkeypatch):
    # CG with Uzawa steps: the blocks suffice (forming the matrix fails the test)
    import efgkit.system.linear_system as linear_system
    from efgkit import EFG, Domain, Elastic, Scene, Support, Traction
    from efgkit.static import solve

    scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.3, "stress"),
                  supports=(Support("left", ux=0.0, uy=0.0),), tractions=(Traction("right", (0.3, -1.0)),))
    direct = solve(scene, EFG(spacing=0.04, bc="lagrange", solver="direct"))

    def refuse(K, G):
        raise AssertionError("the saddle-point matrix was formed")

    monkeypatch.setattr(linear_system, "saddle_matrix", refuse)
    it = solve(scene, EFG(spacing=0.04, bc="lagrange", solver="amg"), disc=direct.disc)
    assert it.info["solver"] == "amg" and it.info["uzawa_steps"] >= 1 and it.info["residual"] <= 1e-8
    # the same answer as SuperLU's on the formed matrix (measured 3.7e-11)
    rel = np.linalg.norm(it.coeffs - direct.coeffs) / np.linalg.norm(direct.coeffs)
    assert rel < 1e-10
