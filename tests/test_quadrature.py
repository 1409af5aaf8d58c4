"""Quadrature: exactness of the Gauss rules, integrals over clipped cells and boundary lines."""

import doctest
import math

import numpy as np
import pytest

import efgkit.quadrature as quadrature
from efgkit.methods.efg import Zone
from efgkit.problem.geometry import Domain, Loop
from efgkit.quadrature.boundary import boundary_points
from efgkit.quadrature.cells import cell_points, triangle_points
from efgkit.quadrature.rules import Points, gauss_legendre, triangle_rule

RECT = Domain.rectangle(0, 0, 2, 1)  # grid-aligned for cell sizes dividing 1
SKEW_RECT = Domain.rectangle(0.03, -0.1, 1.07, 0.83)  # cut cells on the right and top
L_HOLE = Domain(  # skewed L-shape with a tilted square hole: every kind of cut cell
    Loop.polygon([[0, 0], [1.3, 0.1], [1.25, 0.6], [0.65, 0.55], [0.6, 1.2], [-0.05, 1.1]]),
    (Loop.polygon([[0.45, 0.35], [0.3, 0.5], [0.15, 0.35], [0.3, 0.2]]),),
)
CIRCLE_HOLE = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1.03, 0.47], 0.3)])
DOMAINS = {"rect": RECT, "skew_rect": SKEW_RECT, "l_hole": L_HOLE, "circle_hole": CIRCLE_HOLE}
MONOMIALS = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (3, 0)]


def polygon_moment(domain: Domain, a: int, b: int) -> float:
    """Exact integral of x^a y^b over the domain's polylines (outer CCW, holes CW).

    Green's theorem: int x^a y^b dA = oint x^(a+1) y^b / (a+1) dy; on a straight
    segment the integrand is a polynomial of degree a + b + 1 in the segment
    parameter, integrated exactly by numpy's (a + b + 2)-point Gauss rule.
    """
    s, ws = np.polynomial.legendre.leggauss(a + b + 2)
    s, ws = (s + 1) / 2, ws / 2
    total = 0.0
    for loop in domain.loops:
        p, _ = loop.polyline()
        q = np.roll(p, -1, axis=0)
        x = p[:, None, :] + s[None, :, None] * (q - p)[:, None, :]
        f = x[..., 0] ** (a + 1) * x[..., 1] ** b / (a + 1)
        total += float(np.sum((f @ ws) * (q[:, 1] - p[:, 1])))
    return total


def test_doctests():
    assert doctest.testmod(quadrature).failed == 0


# --- Points -------------------------------------------------------------------------------------


def test_points_concatenate_keeps_owner_and_normal_only_if_all_have_them():
    a = Points(np.zeros((2, 2)), np.ones(2), np.array([0, 1]), np.tile([1.0, 0.0], (2, 1)))
    b = Points(np.ones((3, 2)), np.full(3, 2.0), np.array([5, 5, 6]))
    ab = Points.concatenate(a, b)
    assert ab.n == 5 and ab.normal is None
    np.testing.assert_array_equal(ab.owner, [0, 1, 5, 5, 6])
    np.testing.assert_array_equal((a + a).normal, np.tile([1.0, 0.0], (4, 1)))
    assert (a + b).w.sum() == 8.0


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"x": np.zeros((3, 3)), "w": np.ones(3)}, "Points.x"),
        ({"x": np.zeros((3, 2)), "w": np.ones(2)}, "Points.w"),
        ({"x": np.zeros((2, 2)), "w": np.ones(2), "owner": [0.5, 1.0]}, "Points.owner"),
        ({"x": np.zeros((2, 2)), "w": np.ones(2), "normal": np.ones((2, 3))}, "Points.normal"),
    ],
)
def test_points_validates_shapes(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Points(**kwargs)


# --- reference rules ----------------------------------------------------------------------------


@pytest.mark.parametrize("order", range(1, 9))
def test_gauss_legendre_exact_to_degree_2n_minus_1(order):
    xi, w = gauss_legendre(order)
    assert xi.shape == w.shape == (order,)
    for k in range(2 * order):
        exact = 2 / (k + 1) if k % 2 == 0 else 0.0
        assert w @ xi**k == pytest.approx(exact, abs=1e-14)


@pytest.mark.parametrize("degree", range(0, 16))
def test_triangle_rule_exact_positive_interior(degree):
    bary, w = triangle_rule(degree)
    assert bary.shape == (len(w), 3)
    assert np.all(w > 0) and np.all(bary > 0)
    np.testing.assert_allclose(bary.sum(axis=1), 1.0, atol=1e-15)
    x, y = bary[:, 1], bary[:, 2]
    for a in range(degree + 1):
        for b in range(degree + 1 - a):
            # int_T x^a y^b = a! b! / (a + b + 2)! on the reference triangle
            exact = math.factorial(a) * math.factorial(b) / math.factorial(a + b + 2)
            assert w @ (x**a * y**b) == pytest.approx(exact, rel=1e-13, abs=1e-16)


@pytest.mark.parametrize("func, arg", [(gauss_legendre, 0), (triangle_rule, -1)])
def test_rules_reject_bad_orders(func, arg):
    with pytest.raises(ValueError, match=">="):
        func(arg)
    with pytest.raises(TypeError, match="integer"):
        func(2.0)


# --- background cells ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "name, cell_size, order, rtol",
    [
        ("rect", 0.1, 2, 1e-12),
        ("rect", 0.37, 3, 1e-12),  # cells overhang the domain
        ("skew_rect", 0.1, 2, 1e-12),
        ("l_hole", 0.05, 2, 1e-12),
        ("l_hole", 0.13, 4, 1e-12),
        ("circle_hole", 0.1, 3, 1e-9),  # vs Domain.area: the same arc polylines
        ("circle_hole", 5.0, 3, 1e-9),  # one cell holding the whole domain
    ],
)
def test_cell_weights_sum_to_area(name, cell_size, order, rtol):
    dom = DOMAINS[name]
    pts = cell_points(dom, cell_size, order)
    assert pts.w.sum() == pytest.approx(dom.area, rel=rtol)
    assert np.all(pts.w > 0)
    assert np.all(dom.contains(pts.x))


@pytest.mark.parametrize("name", DOMAINS)
@pytest.mark.parametrize("a, b", MONOMIALS)
def test_cell_moments_exact(name, a, b):
    # order 2: tensor Gauss exact to degree 3 per direction, triangles to total degree 3
    dom = DOMAINS[name]
    pts = cell_points(dom, 0.07, 2)
    exact = polygon_moment(dom, a, b)
    assert pts.w @ (pts.x[:, 0] ** a * pts.x[:, 1] ** b) == pytest.approx(exact, rel=1e-11)


def random_star(rng, r0, n):
    """Star-shaped polygon about the origin with n random vertices, shape (n, 2)."""
    th = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = r0 * rng.uniform(0.4, 1.0, n)
    return np.column_stack([r * np.cos(th), r * np.sin(th)])


@pytest.mark.parametrize("seed", range(6))
def test_cell_moments_exact_on_random_star_domains(seed):
    rng = np.random.default_rng(seed)
    dom = Domain(Loop.polygon(random_star(rng, 1.0, 12)), (Loop.polygon(random_star(rng, 0.2, 7)),))
    pts = cell_points(dom, rng.uniform(0.02, 0.3), 2)
    assert np.all(pts.w > 0) and np.all(dom.contains(pts.x))
    for a, b in MONOMIALS:
        exact = polygon_moment(dom, a, b)
        assert pts.w @ (pts.x[:, 0] ** a * pts.x[:, 1] ** b) == pytest.approx(exact, abs=1e-12)


def test_cell_owner_numbers_cells_holding_material():
    h = 0.1
    pts = cell_points(L_HOLE, h, 3)
    n_cells = pts.owner.max() + 1
    np.testing.assert_array_equal(np.unique(pts.owner), np.arange(n_cells))
    cell_area = np.bincount(pts.owner, pts.w)
    assert np.all(cell_area <= h**2 * (1 + 1e-12))
    full = np.isclose(cell_area, h**2, rtol=1e-12)
    assert np.all(np.bincount(pts.owner)[full] >= 9)  # 3 x 3 Gauss (or a cut rule)
    # points of one cell lie in one h x h square
    lo = np.full((n_cells, 2), np.inf)
    hi = np.full((n_cells, 2), -np.inf)
    np.minimum.at(lo, pts.owner, pts.x)
    np.maximum.at(hi, pts.owner, pts.x)
    assert np.all(hi - lo < h)


@pytest.mark.parametrize("name", ["rect", "circle_hole"])
def test_cell_zones_refine_cells_and_order(name):
    dom, h = DOMAINS[name], 0.1
    zone = Zone(centre=(1.0, 0.5), radius=0.45, spacing=0.03)  # k = ceil(0.1 / 0.03) = 4
    pts = cell_points(dom, h, 2, zones=[zone], refined_order=5)
    assert pts.w.sum() == pytest.approx(dom.area, rel=1e-12)
    for a, b in MONOMIALS:
        exact = polygon_moment(dom, a, b)
        assert pts.w @ (pts.x[:, 0] ** a * pts.x[:, 1] ** b) == pytest.approx(exact, rel=1e-11)
    cell_area = np.bincount(pts.owner, pts.w)
    count = np.bincount(pts.owner)
    centre = np.zeros((len(count), 2))
    np.add.at(centre, pts.owner, pts.x)
    centre /= count[:, None]
    near = np.linalg.norm(centre - zone.centre, axis=1) < zone.radius - h  # surely refined
    far = np.linalg.norm(centre - zone.centre, axis=1) > zone.radius + h  # surely coarse
    sub = (h / 4) ** 2
    assert np.all(cell_area[near] <= sub * (1 + 1e-12))
    assert np.all(count[near & np.isclose(cell_area, sub, rtol=1e-12)] == 25)
    assert np.all(count[far & np.isclose(cell_area, h**2, rtol=1e-12)] == 4)


def test_cell_points_reject_bad_arguments():
    with pytest.raises(ValueError, match="cell_size"):
        cell_points(RECT, -0.1, 2)
    with pytest.raises(ValueError, match="order"):
        cell_points(RECT, 0.1, 0)
    with pytest.raises(TypeError, match="refined_order"):
        cell_points(RECT, 0.1, 2, refined_order=2.5)
    with pytest.raises(TypeError, match="Domain"):
        cell_points("rect", 0.1, 2)


# --- triangles of the nodes ---------------------------------------------------------------------


def grid_nodes(x0, y0, x1, y1, n):
    gx, gy = np.meshgrid(np.linspace(x0, x1, 2 * n + 1), np.linspace(y0, y1, n + 1))
    return np.column_stack([gx.ravel(), gy.ravel()])


@pytest.mark.parametrize("perturb", [0.0, 0.3])
def test_triangle_points_on_rectangle_integrate_exactly(perturb):
    nodes = grid_nodes(0, 0, 2, 1, 8)
    inner = (nodes > 1e-9).all(1) & (nodes < [2 - 1e-9, 1 - 1e-9]).all(1)
    rng = np.random.default_rng(0)
    nodes[inner] += perturb / 8 * rng.uniform(-1, 1, (inner.sum(), 2))
    pts = triangle_points(RECT, nodes, 2)
    assert np.all(pts.w > 0)
    assert np.all(RECT.contains(pts.x))
    for a, b in MONOMIALS:
        exact = polygon_moment(RECT, a, b)
        assert pts.w @ (pts.x[:, 0] ** a * pts.x[:, 1] ** b) == pytest.approx(exact, rel=1e-12)
    np.testing.assert_array_equal(np.unique(pts.owner), np.arange(pts.owner.max() + 1))


def test_triangle_points_integrate_the_node_polygon_not_a_curved_domain():
    # nodes on a circular hole: the kept triangles end at the chords, so they cover the
    # rectangle minus the inscribed 48-gon, not minus the disc
    c, R, m = np.array([1.03, 0.47]), 0.3, 48
    nodes = grid_nodes(0, 0, 2, 1, 20)
    nodes = nodes[np.abs(np.linalg.norm(nodes - c, axis=1) - R) > 0.02]
    th = np.linspace(0, 2 * np.pi, m, endpoint=False)
    ring = c + R * np.column_stack([np.cos(th), np.sin(th)])
    pts = triangle_points(CIRCLE_HOLE, np.concatenate([nodes, ring]), 2)
    polygon_area = 2.0 - 0.5 * m * R**2 * np.sin(2 * np.pi / m)
    assert pts.w.sum() == pytest.approx(polygon_area, rel=1e-12)
    assert pts.w.sum() > CIRCLE_HOLE.area


def test_triangle_points_reject_bad_nodes():
    with pytest.raises(ValueError, match="nodes"):
        triangle_points(RECT, np.zeros((2, 2)), 2)


# --- boundary lines -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "dom, where, length",
    [
        (RECT, "bottom", 2.0),
        (RECT, "left", 1.0),
        (CIRCLE_HOLE, "hole", 2 * np.pi * 0.3),
        (CIRCLE_HOLE, None, 6.0 + 2 * np.pi * 0.3),
    ],
)
@pytest.mark.parametrize("h", [0.07, 0.5])
def test_boundary_weights_sum_to_edge_length(dom, where, length, h):
    pts = boundary_points(dom, where, 3, h)
    assert pts.w.sum() == pytest.approx(length, rel=1e-12)
    assert np.all(pts.w > 0)
    np.testing.assert_allclose(np.linalg.norm(pts.normal, axis=1), 1.0, atol=1e-14)
    assert np.all(dom.distance_to_boundary(pts.x) < 1e-5)


def test_boundary_points_on_arc_lie_on_circle_with_normal_into_the_hole():
    pts = boundary_points(CIRCLE_HOLE, "hole", 4, 0.1)
    r = pts.x - [1.03, 0.47]
    np.testing.assert_allclose(np.linalg.norm(r, axis=1), 0.3, rtol=1e-14)
    np.testing.assert_allclose(pts.normal, -r / 0.3, atol=1e-14)
    edges = CIRCLE_HOLE.edges()
    assert {edges[k].name for k in pts.owner} == {"hole"}


@pytest.mark.parametrize("name", ["l_hole", "circle_hole"])
def test_boundary_normal_integrates_to_zero_on_closed_boundary(name):
    pts = boundary_points(DOMAINS[name], None, 3, 0.1)
    np.testing.assert_allclose(pts.w @ pts.normal, 0.0, atol=1e-14)


@pytest.mark.parametrize(
    "dom, area",
    [
        (L_HOLE, L_HOLE.area),  # polygonal: the polyline area is exact
        (CIRCLE_HOLE, 2.0 - np.pi * 0.3**2),  # arcs are integrated on the exact circle
    ],
)
def test_boundary_divergence_theorem(dom, area):
    # int_Omega div(x, 0) dA = oint x n_x ds (and the same for y)
    pts = boundary_points(dom, None, 4, 0.05)
    assert pts.w @ (pts.x[:, 0] * pts.normal[:, 0]) == pytest.approx(area, rel=1e-12)
    assert pts.w @ (pts.x[:, 1] * pts.normal[:, 1]) == pytest.approx(area, rel=1e-12)


def test_boundary_callable_mask_selects_points_of_all_edges():
    pts = boundary_points(RECT, lambda x: x[:, 0] < 1e-12, 2, 0.1)
    assert pts.w.sum() == pytest.approx(1.0, rel=1e-14)
    left = [k for k, e in enumerate(RECT.edges()) if e.name == "left"]
    np.testing.assert_array_equal(np.unique(pts.owner), left)
    np.testing.assert_allclose(pts.normal, np.tile([-1.0, 0.0], (pts.n, 1)), atol=1e-15)


def test_boundary_points_errors():
    with pytest.raises(KeyError, match="no edge named 'nope'.*'bottom'"):
        boundary_points(RECT, "nope", 2, 0.1)
    with pytest.raises(TypeError, match="where"):
        boundary_points(RECT, 3, 2, 0.1)
    with pytest.raises(ValueError, match="bool mask"):
        boundary_points(RECT, lambda x: x[:, 0], 2, 0.1)
    with pytest.raises(ValueError, match="h must"):
        boundary_points(RECT, "left", 2, 0.0)


@pytest.mark.parametrize("angle", [20.0, 30.0, 45.0, 60.0])
@pytest.mark.parametrize("cell", [1 / 8, 1 / 16, 1 / 32])
def test_cells_split_by_an_inclined_crack_keep_their_area(angle, cell):
    # regression: the two sides of a slit were ordered by rounding, dropping material
    from efgkit import Crack

    t = np.tan(np.radians(angle))
    pts = cell_points(Domain.rectangle(-1, -1, 1, 1), cell, 4,
                      cracks=[Crack([[-0.8, -0.8 * t], [0.0, 0.0]])])
    assert abs(pts.w.sum() - 4.0) < 1e-11 and pts.w.min() > 0


def test_tip_fans_stay_in_their_cells_with_a_rosette():
    # regression: a rosette node 2e-17 off the crack line sent a fan ray backwards
    from efgkit import EFG, Crack, Elastic, Rosette, Scene
    from efgkit.methods.discretize import discretize

    scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
                  cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]], (False, True)),))
    d = discretize(scene, EFG(spacing=1 / 12, rosette=Rosette(1 / 6, 4, 9)))
    assert abs(d.points.w.sum() - 4.0) < 1e-11


@pytest.mark.parametrize("vertices, tips", [
    ([[1.03, 0.55], [1.01, 0.55]], (False, True)),  # tip cell cut by the right edge
    ([[0.0, 0.5], [0.52, 0.5], [0.55, 0.53]], (False, True)),  # kink inside the tip cell
    ([[0.31, 0.5], [0.35, 0.5]], (True, True)),  # both tips in one cell
])
def test_tip_cells_entered_by_boundary_or_another_segment_keep_the_body_area(vertices, tips):
    # regression: the fan rule covered the whole square of a tip cell cut by the boundary
    from efgkit import Crack

    dom = Domain.rectangle(0, 0, 1.03, 1)
    pts = cell_points(dom, 0.1, 4, cracks=[Crack(vertices, tips)])
    assert abs(pts.w.sum() - dom.area) < 1e-12 and pts.w.min() > 0
    assert dom.contains(pts.x).all()


def test_tip_fan_exit_near_a_corner_keeps_the_cell_area():
    # regression: exits within 1e-5 of a corner took the corner's perimeter value (rtol)
    from efgkit.quadrature.tip_cells import tip_cell_rule

    x, w = tip_cell_rule(np.zeros(2), 1.0, np.array([0.5, 0.5]), np.array([[0.499995, 0.5]]), 8)
    assert abs(w.sum() - 1.0) < 1e-14


# --- the rule held per cell ------------------------------------------------------------------


def _cracked_rule():
    """A rule of 103k points (above COMPILED_MIN: the compiled writes) with a zone, a hole,
    a crack with its tip fans and cut cells: every kind of segment, two tensor rules."""
    from efgkit import Crack
    from efgkit.quadrature.cells import cell_rule

    dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1.4, 0.5], 0.2)])
    rule = cell_rule(dom, 1 / 60, 3, zones=(Zone((0.8, 0.5), 0.1, 1 / 200),), refined_order=4,
                     cracks=[Crack([[0.0, 0.5], [0.8, 0.5]], (False, True))])
    return dom, rule


def test_cell_rule_compiled_writes_equal_numpy_bit_for_bit(monkeypatch):
    import efgkit.quadrature.cell_rule as cr

    dom, rule = _cracked_rule()
    assert rule.n >= cr.COMPILED_MIN and (rule.rule < 0).any() and len(rule.q) == 2
    compiled = rule.points()
    monkeypatch.setattr(cr, "COMPILED_MIN", 10**9)
    plain = rule.points()
    for a, b in [(compiled.x, plain.x), (compiled.w, plain.w), (compiled.owner, plain.owner)]:
        assert a.dtype == b.dtype and np.array_equal(a, b)
    # the rule's points are cell_points' (numbered over the cells with material)
    assert abs(plain.w.sum() - dom.area) < 1e-12 * dom.area and plain.w.min() > 0
    assert np.array_equal(np.unique(plain.owner), np.arange(plain.owner.max() + 1))


def test_cell_rule_sorted_by_is_the_stable_sort_of_its_points(monkeypatch):
    import efgkit.quadrature.cell_rule as cr

    _, rule = _cracked_rule()

    def key(x):  # many ties: stability shows
        return np.floor(7 * x[:, 0]).astype(np.int64)

    expect = rule.points().sorted_by(key)
    for block in (cr.KEY_BLOCK, 10_007):  # one block, and many with a partial last one
        monkeypatch.setattr(cr, "KEY_BLOCK", block)
        got = rule.sorted_by(key)
        assert all(np.array_equal(getattr(got, a), getattr(expect, a)) for a in ("x", "w", "owner"))
    assert not np.array_equal(expect.owner, rule.points().owner)  # the key did reorder
