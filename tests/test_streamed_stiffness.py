"""The stiffness assembled a chunk of points at a time (efgkit.system.streamed) and the shape
functions formed on demand (efgkit.approx.point_shapes): the same K as all points at once (up
to the order of the sums), the same gradients bitwise, and a large solve (chunking forced here
on a small one) that gives the same coefficients and SIFs as the one holding everything."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.sparse import csr_array

import efgkit.approx.point_shapes as point_shapes
import efgkit.methods.discretize as discretize_module
from efgkit import EFG, Domain, Elastic, Scene
from efgkit.approx.point_shapes import PointShapes
from efgkit.methods.discretize import discretize
from efgkit.scenefile import load_study
from efgkit.static import solve
from efgkit.system.assemble import stiffness
from efgkit.system.streamed import chunk_sum, streamed_stiffness

ROOT = Path(__file__).resolve().parents[1]


def _plate():
    """The edge-cracked plate of the example at 1.6x its spacing (extrinsic enrichment at every
    point, diffraction rule, Lagrange BCs; ~500 nodes, ~15k points)."""
    scene, method = load_study(ROOT / "examples" / "edge_crack.toml")
    return scene, replace(method, spacing=method.spacing * 1.6,
                          zones=tuple(replace(z, spacing=z.spacing * 1.6) for z in method.zones))


@pytest.fixture(scope="module")
def plate():
    scene, method = _plate()
    return scene, method, discretize(scene, method)


def test_streamed_k_is_the_k_of_all_points(plate):
    scene, _, d = plate
    K_all = stiffness(d.shape, d.points.w, scene.material.D)
    ps = PointShapes(d.approx, d.points.x, chunk_points=3000)  # 5 chunks
    assert ps.n_chunks == 5 and {e - s for s, e in ps.bounds()} <= {d.points.n // 5, d.points.n // 5 + 1}
    K = streamed_stiffness(ps, d.points.w, scene.material.D)
    assert K.shape == K_all.shape == (d.n_dofs, d.n_dofs)
    assert K.has_sorted_indices and K.indices.dtype == np.int32
    # the chunks' sums are added in another order: rounding only (measured 1.1e-15)
    assert abs(K - K_all).max() <= 4e-15 * abs(K_all).max()
    assert abs(K - K.T).max() <= 1e-15 * abs(K).max()


def test_chunk_rows_are_the_rows_of_all_points(plate):
    _, _, d = plate
    ps = PointShapes(d.approx, d.points.x, chunk_points=4000)
    c = np.random.default_rng(3).standard_normal(d.n_dofs)
    np.testing.assert_array_equal(ps.gradient(c), d.shape.gradient(c))  # bitwise
    np.testing.assert_array_equal(ps.displacement(c), d.shape.displacement(c))
    rows = np.flatnonzero(np.random.default_rng(4).random(d.points.n) < 0.2)
    np.testing.assert_array_equal(ps.strain(c, rows), d.shape.strain(c)[rows])
    mask = np.zeros(d.points.n, bool)
    mask[rows] = True
    np.testing.assert_array_equal(ps.gradient(c, mask), d.shape.gradient(c)[rows])


def test_chunk_sum_adds_every_part_on_its_dofs():
    rng = np.random.default_rng(0)
    n, parts, dense = 40, [], np.zeros((40, 40))
    for _ in range(7):  # parts on overlapping ascending DOF subsets, some rows empty
        dof = np.sort(rng.choice(n, size=int(rng.integers(1, 25)), replace=False))
        block = rng.random((dof.size, dof.size)) * (rng.random((dof.size, dof.size)) < 0.3)
        parts.append((dof, csr_array(block)))
        dense[np.ix_(dof, dof)] += block
    dof = np.arange(n)  # and one that cancels an entry exactly: left out, as scipy's sums do
    i, j = np.argwhere(dense > 0)[0]
    cancel = np.zeros((n, n))
    cancel[i, j] = -dense[i, j]
    parts.append((dof, csr_array(cancel)))
    dense[i, j] = 0.0
    K = chunk_sum(parts, n)
    assert parts == []  # dropped as they were added
    assert K.has_sorted_indices and K.indices.dtype == np.int32 and K.nnz == np.count_nonzero(dense)
    np.testing.assert_allclose(K.toarray(), dense, rtol=1e-15, atol=0)
    assert chunk_sum([], 3).nnz == 0 and chunk_sum([], 3).shape == (3, 3)


@pytest.fixture(scope="module")
def pair():
    """The plate solved holding all shape functions, and streamed in chunks of 2000 points."""
    scene, method = _plate()
    kept = solve(scene, method)
    mp = pytest.MonkeyPatch()
    mp.setattr(discretize_module, "STREAM_POINTS", 0)
    mp.setattr(point_shapes, "CHUNK_POINTS", 2000)
    try:
        streamed = solve(scene, method)
    finally:
        mp.undo()
    return kept, streamed


def test_streamed_solve_matches_the_solve_holding_everything(pair):
    kept, streamed = pair
    assert isinstance(streamed.disc.shape, PointShapes) and streamed.disc.shape.n_chunks >= 7
    assert type(kept.disc.shape).__name__ == "Shape"
    assert "release" not in streamed.timings
    assert {"search", "shape", "stiffness"} <= set(streamed.timings)
    scale = np.abs(kept.coeffs).max()
    assert np.abs(streamed.coeffs - kept.coeffs).max() <= 1e-11 * scale  # K to rounding
    np.testing.assert_allclose(streamed.gradient(), kept.gradient(), rtol=0, atol=1e-10 * np.abs(
        kept.gradient()).max())
    assert streamed.strain_energy() == pytest.approx(kept.strain_energy(), rel=1e-12)
    a, b = kept.sifs(error=False)[0], streamed.sifs(error=False)[0]
    assert b.KI == pytest.approx(a.KI, rel=1e-10) and b.KII == pytest.approx(a.KII, rel=1e-10)
    x = np.array([[1.0, 2.0], [5.0, 12.0]])
    np.testing.assert_allclose(streamed.stress(x), kept.stress(x), rtol=1e-10)


def test_bad_arguments_are_named(plate):
    scene, _, d = plate
    with pytest.raises(ValueError, match="chunk_points must be a positive integer, got 0"):
        PointShapes(d.approx, d.points.x, chunk_points=0)
    ps = PointShapes(d.approx, d.points.x)
    with pytest.raises(ValueError, match=r"coeffs must have shape"):
        ps.gradient(np.zeros(3))
    c = np.zeros(d.n_dofs)
    with pytest.raises(ValueError, match=r"rows must lie in \[0, "):
        ps.gradient(c, [d.points.n])
    with pytest.raises(ValueError, match="rows as a mask must have shape"):
        ps.gradient(c, np.ones(3, bool))
    with pytest.raises(ValueError, match="rows must be point indices"):
        ps.gradient(c, np.ones(3))
    with pytest.raises(ValueError, match=r"w must have shape \("):
        streamed_stiffness(ps, np.ones(3), scene.material.D)
    with pytest.raises(ValueError, match=r"D must have shape \(3, 3\)"):
        streamed_stiffness(ps, d.points.w, np.eye(2))


def test_discretize_says_which_scenes_it_can_chunk():
    scene = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3), body_force=(0.0, -1.0))
    with pytest.raises(ValueError, match="chunked=True needs a scene without body force"):
        discretize(scene, EFG(spacing=0.25), chunked=True)
    with pytest.raises(ValueError, match="chunked must be False, True or 'auto', got 'yes'"):
        discretize(scene, EFG(spacing=0.25), chunked="yes")
    d = discretize(replace(scene, body_force=None), EFG(spacing=0.25), chunked=True)
    assert isinstance(d.shape, PointShapes) and d.shape.n_points == d.points.n


def test_the_size_guard_estimates_the_streamed_solve(monkeypatch):
    """1e6 nodes of the cracked plate: refused at 38 GB when every shape function is held,
    about 15 GB streamed (docs/performance.md, streamed section); the refusal names the parts."""
    import efgkit.memory as memory_module
    from efgkit.methods.size import size_estimate

    scene, method = load_study(ROOT / "examples" / "edge_crack.toml")
    f = 29.2  # benchmarks/scaling.py's factor for 1e6 nodes
    method = replace(method, spacing=method.spacing / f,
                     zones=tuple(replace(z, spacing=z.spacing / f) for z in method.zones))
    full, est = size_estimate(scene, method, chunked=False), size_estimate(scene, method)
    assert est.streamed and not full.streamed
    assert 10e9 < est.bytes < 0.5 * full.bytes
    monkeypatch.setattr(memory_module, "available_memory", lambda: (2.5e9, "a test"))
    with pytest.raises(ValueError, match=r"assembling the stiffness a chunk of points at a time needs "
                                         r"[\d.]+ GB and the solve [\d.]+ GB on top of the [\d.]+ GB of "
                                         r"the points' arrays .* more than the 2\.5 GB"):
        discretize(scene, method, chunked="auto")
