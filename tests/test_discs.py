"""Disc and sector quadrature of MLPG (efgkit.quadrature.discs) and the Gaussian weight of
exponent k (seed 002 Eq. 7)."""

import math

import numpy as np
import pytest

from efgkit.approx.weights import gaussian
from efgkit.quadrature import discs

FULL = np.full(1, 2 * np.pi)
NO_SEGMENTS = np.zeros((0, 2, 2))


def _disc(rule, nr, na, r=1.0):
    return discs.disc_points(np.zeros((1, 2)), np.full(1, r), NO_SEGMENTS, np.zeros(1), FULL,
                             rule, nr, na)


# Closed forms on the disc of radius 1 about the origin: int x^2 = pi/4, int x^4 = pi/8,
# int x^2 y^2 = pi/24, odd moments 0.
MOMENTS = [((0, 0), math.pi), ((1, 0), 0.0), ((2, 0), math.pi / 4), ((1, 1), 0.0),
           ((4, 0), math.pi / 8), ((2, 2), math.pi / 24), ((3, 1), 0.0)]


@pytest.mark.parametrize(("ab", "exact"), MOMENTS)
def test_gauss_disc_exact_to_degree(ab, exact):
    # exact for total degree <= min(2 n_r - 1, n_theta - 1) = 4 with n_r = 3, n_theta = 5
    p = _disc("gauss", 3, 5)
    val = p.w @ (p.x[:, 0] ** ab[0] * p.x[:, 1] ** ab[1])
    assert abs(val - exact) < 1e-14


def test_midpoint_disc_exact_for_linear_not_quadratic():
    p = _disc("midpoint", 5, 8)
    assert abs(p.w.sum() - math.pi) < 1e-14
    assert abs(p.w @ p.x[:, 0]) < 1e-14 and abs(p.w @ p.x[:, 1]) < 1e-14
    # x^2 is not exact: the ring centroid radius integrates r, not r^3 (error 0.4 % at 5 rings)
    err = abs(p.w @ p.x[:, 0] ** 2 - math.pi / 4)
    assert 1e-4 < err < 1e-2


def test_midpoint_weights_are_ring_sector_areas():
    # seed 002 Eq. 39: r_j = (j^2 - j + 1/3) / (j - 1/2) dr, weight (j - 1/2) dr^2 dtheta
    t, wt, rho, wr = discs.polar_rule("midpoint", 5, 8, True)
    j = np.arange(1, 6)
    assert np.allclose(rho, (j * j - j + 1 / 3) / (j - 0.5) / 5)
    assert np.allclose(wr * 2 * np.pi / 8 * 1.0, (j - 0.5) * 0.2**2 * (2 * np.pi / 8))
    assert np.allclose(t * 2 * np.pi, (np.arange(8) + 0.5) * 2 * np.pi / 8)


def test_cut_disc_area_converges_to_circular_segment():
    # node at distance R/2 from a straight boundary: area R^2 (pi - (phi - sin phi) / 2),
    # phi = 2 acos(1/2) (closed form of the circular segment)
    seg = np.array([[[0.0, 1.0], [0.0, 0.0]]])
    x, r = np.array([[0.05, 0.5]]), np.array([0.1])
    ta, sp = discs.sectors(x, r, seg, lambda p: p[:, 0] > 0)
    phi = 2 * math.acos(0.5)
    exact = 0.01 * (math.pi - 0.5 * (phi - math.sin(phi)))
    errs = [abs(discs.disc_points(x, r, seg, ta, sp, "gauss", n, n).w.sum() - exact) / exact
            for n in (8, 16)]
    assert errs[0] < 2e-6 and errs[1] < 1e-12  # measured 6.8e-7 and 2.8e-13
    mid = abs(discs.disc_points(x, r, seg, ta, sp, "midpoint", 5, 8).w.sum() - exact) / exact
    assert 1e-3 < mid < 1e-1  # the seed's rule on a cut disc: 2.3 %


def test_sectors_of_boundary_nodes():
    from efgkit.problem.geometry import Domain

    dom = Domain.rectangle(0, 0, 1, 1)
    seg, _, _ = discs.edge_segments(dom.edges())
    x = np.array([[0.5, 0.5], [0.5, 0.0], [0.0, 0.0], [1.0, 1.0]])
    ta, sp = discs.sectors(x, np.full(4, 0.1), seg, dom.contains)
    assert np.allclose(sp, [2 * np.pi, np.pi, np.pi / 2, np.pi / 2])
    pts = discs.disc_points(x, np.full(4, 0.1), seg, ta, sp)
    assert np.allclose(np.bincount(pts.owner, pts.w) / (np.pi * 0.01), [1, 0.5, 0.25, 0.25])
    assert dom.contains(pts.x, tol=1e-12).all()


def test_boundary_pieces_lengths_and_owner():
    from efgkit.problem.geometry import Domain

    dom = Domain.rectangle(0, 0, 1, 1)
    seg, edge, s = discs.edge_segments(dom.edges())
    x = np.array([[0.5, 0.5], [0.5, 0.0], [0.0, 0.0], [0.05, 0.5]])
    pts, e = discs.boundary_pieces(x, np.full(4, 0.1), seg, edge, s, dom.edges())
    # chord length 2 sqrt(r^2 - d^2) = 0.1 sqrt(3) for the node at d = r/2
    assert np.allclose(np.bincount(pts.owner, pts.w, minlength=4), [0, 0.2, 0.2, 0.1 * math.sqrt(3)])
    assert np.allclose(np.hypot(*pts.normal.T), 1.0)


def test_ray_lengths_stop_at_first_segment():
    seg = np.array([[[1.0, -1.0], [1.0, 1.0]], [[2.0, -1.0], [2.0, 1.0]]])
    out = discs.ray_lengths(np.zeros((1, 2)), np.array([[0.0, np.pi / 4, np.pi]]), np.array([3.0]), seg)
    assert np.allclose(out, [[1.0, math.sqrt(2), 3.0]])


def test_polar_rule_rejects_unknown_rule():
    with pytest.raises(ValueError, match="rule must be one of"):
        discs.polar_rule("simpson", 5, 8, True)


@pytest.mark.parametrize("k", [1, 2, 3])
def test_gaussian_k_ends_and_derivative(k):
    beta = 1 / 0.365
    w, _ = gaussian(np.array([0.0, 1.0, 1.2]), beta, k)
    assert w.tolist() == [1.0, 0.0, 0.0]
    s = np.linspace(0.05, 0.95, 19)
    _, g = gaussian(s, beta, k)
    h = 1e-6
    fd = (gaussian(s + h, beta, k)[0] - gaussian(s - h, beta, k)[0]) / (2 * h)
    assert np.allclose(g * s, fd, atol=1e-7)


def test_gaussian_k1_unchanged():
    # k = 1 must evaluate the seed 003 Eq. (1a) expressions bit for bit
    s, beta = np.linspace(0, 1.1, 23), 4.0
    e, eb = np.exp(-((beta * np.minimum(s, 1.0)) ** 2)), np.exp(-(beta**2))
    w, g = gaussian(s, beta)
    assert np.array_equal(w, np.where(s < 1, (e - eb) / (1 - eb), 0.0))
    assert np.array_equal(g, np.where(s < 1, -2.0 * beta**2 * e / (1 - eb), 0.0))


@pytest.mark.parametrize("basis", ["linear", "quadratic"])
def test_gaussian_k2_kernel_matches_numpy_reference(basis):
    from efgkit import EFG, Domain
    from efgkit.approx.mls import mls_shape
    from efgkit.nodes import generate_nodes

    nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.1, d_max=2.5, perturb=0.2))
    x = np.random.default_rng(1).uniform(0.05, 0.95, (300, 2))
    a = mls_shape(x, nodes, "gaussian", basis, d_max=2.5, alpha=1.25, k=2)
    b = mls_shape(x, nodes, "gaussian", basis, d_max=2.5, alpha=1.25, k=2, backend="numpy")
    assert np.abs(a.values - b.values).max() < 1e-12 and np.abs(a.ddx - b.ddx).max() < 1e-11
    # quadratic reproduction with the k = 2 weight
    u = nodes.x[:, 0] ** 2 - 2 * nodes.x[:, 0] * nodes.x[:, 1]
    if basis == "quadratic":
        assert np.abs(a.phi @ u - (x[:, 0] ** 2 - 2 * x[:, 0] * x[:, 1])).max() < 1e-12
