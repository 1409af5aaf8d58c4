"""efgkit.fem.mesh: Triangle meshes of scenes (areas, named facets, opened cracks, grading)."""

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from efgkit import Crack, Domain, Elastic, Loop, Scene  # noqa: E402
from efgkit.fem.mesh import TriMesh, mesh_scene, size_field  # noqa: E402
from efgkit.fem.output import plot_mesh  # noqa: E402

MAT = Elastic(1.0, 0.3)
L_SHAPE = Domain(Loop.polygon([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]],
                              ["bottom", "right", "step", "step", "top", "left"]))
PLATE_HOLE = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)])
EDGE = Crack([[-1.0, 0.0], [0.0, 0.0]], tips=(False, True), name="edge")
KINKED = Crack([[0.5, 1.5], [1.0, 1.8], [1.6, 1.5]], tips=(True, True), name="kinked")
FROM_HOLE = Crack([[1.25, 0.5], [1.6, 0.7], [1.8, 0.5]], tips=(False, True), name="k")

SCENES = {
    "square": Scene(Domain.rectangle(-1, -1, 1, 1), MAT),
    "L-shape": Scene(L_SHAPE, MAT),
    "edge crack": Scene(Domain.rectangle(-1, -1, 1, 1), MAT, cracks=(EDGE,)),
    "kinked interior crack": Scene(Domain.rectangle(0, 0, 2, 3), MAT, cracks=(KINKED,)),
    "crack from a hole": Scene(PLATE_HOLE, MAT, cracks=(FROM_HOLE,)),
}
CRACKED = [k for k, s in SCENES.items() if s.cracks]


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _mesh(name, h=0.2, tip_h=0.02, grading=1.3) -> TriMesh:
    return mesh_scene(SCENES[name], h, tip_h, grading)


@pytest.mark.parametrize("name", ["square", "L-shape", "edge crack", "kinked interior crack"])
def test_area_equals_domain_area(name):
    m = _mesh(name)
    assert np.all(m.area > 0)  # counter-clockwise elements
    assert m.area.sum() == pytest.approx(SCENES[name].domain.area, rel=1e-13)


def test_arc_vertices_lie_on_their_circle_and_area_converges():
    # The linear mesh is the inscribed polygon of the arcs: its area error falls as h^2
    # (the isoparametric P2 area is tested in tests/test_fem.py).
    errs = []  # h = 0.2 and 0.1 both give the 16 chords of the pi/8 limit: start at 0.1
    for h in (0.1, 0.05, 0.025):
        m = mesh_scene(Scene(PLATE_HOLE, MAT), h)
        f = m.facets[m.boundary("hole")]
        r = np.linalg.norm(m.x[f] - [1, 0.5], axis=-1)
        assert np.allclose(r, 0.25, rtol=0, atol=1e-14)
        errs.append(m.area.sum() - (2 - math.pi / 16))
    assert np.all(np.array(errs) > 0)  # the polygon is inside the circle: area too large
    assert np.log2(errs[0] / errs[2]) / 2 == pytest.approx(2.0, abs=0.3)


@pytest.mark.parametrize("name", list(SCENES))
def test_boundary_facets_carry_their_edge_names(name):
    scene = SCENES[name]
    m = _mesh(name)
    edges = scene.domain.edges()
    assert m.facets.shape == (len(m.facet_owner), 2)
    for nm in scene.domain.edge_names:
        f = m.facets[m.boundary(nm)]
        mine = [e for e in edges if e.name == nm]
        length = np.linalg.norm(m.x[f[:, 1]] - m.x[f[:, 0]], axis=1).sum()
        if mine[0].is_arc:  # chords of the circle: shorter than the arc by O(h^2)
            assert length == pytest.approx(sum(e.length for e in mine), rel=2e-2)
            continue
        assert length == pytest.approx(sum(e.length for e in mine), rel=1e-13)
        for p in (m.x[f[:, 0]], m.x[f[:, 1]], m.x[f].mean(axis=1)):  # on one of the edges
            d = np.min([np.abs((e.end - e.start)[0] * (p - e.start)[:, 1]
                               - (e.end - e.start)[1] * (p - e.start)[:, 0]) / e.length
                        for e in mine], axis=0)
            assert d.max() < 1e-12
    # material on the left: the outward normal (t_y, -t_x) points away from the element
    tvec = m.x[m.facets[:, 1]] - m.x[m.facets[:, 0]]
    out = np.column_stack([tvec[:, 1], -tvec[:, 0]])
    mid = m.x[m.facets].mean(axis=1)
    assert not np.any(scene.domain.contains(mid + 1e-3 * out) & (m.facet_owner >= 0))


@pytest.mark.parametrize("name", CRACKED)
def test_crack_nodes_are_duplicated_except_at_tips(name):
    scene = SCENES[name]
    m = _mesh(name)
    for k, crack in enumerate(scene.cracks):
        left, right = m.crack_nodes[k]
        assert len(left) >= 3 and np.all(left != right)
        assert np.array_equal(m.x[left], m.x[right])
        assert crack.distance(m.x[left]).max() < 1e-12
        assert np.all(m.origin[right] == left)
        # a mouth is opened, a tip is not
        for end in (0, 1):
            v = crack.vertices[0 if end == 0 else -1]
            at = np.flatnonzero(np.linalg.norm(m.x - v, axis=1) < 1e-12)
            assert len(at) == (1 if crack.tips[end] else 2)
        # no element uses both faces; left elements lie left of the crack, right ones right
        uses_l = np.isin(m.t, left).any(axis=1)
        uses_r = np.isin(m.t, right).any(axis=1)
        assert not np.any(uses_l & uses_r)
        c = m.x[m.t].mean(axis=1)
        seg = np.argmin([Crack(s_, tips=(True, True)).distance(c) for s_ in crack.segments], axis=0)
        side = np.select([seg == k for k in range(len(crack.segments))],
                         [crack.side(c, k) for k in range(len(crack.segments))])
        assert np.all(side[uses_l] > 0) and np.all(side[uses_r] < 0)
        # each tip node is shared by elements of both faces
        for tip, node in zip(scene.tips, m.tip_nodes, strict=True):
            if tip.crack == crack.name:
                around = np.isin(m.t, node).any(axis=1)
                assert np.any(around & uses_l) and np.any(around & uses_r)
    # crack faces: both faces of every crack as boundary facets, length 2 x crack length
    faces = m.facets[m.facet_owner < 0]
    length = np.linalg.norm(m.x[faces[:, 1]] - m.x[faces[:, 0]], axis=1).sum()
    assert length == pytest.approx(2 * sum(c.length for c in scene.cracks), rel=1e-12)


def test_elements_are_graded_toward_the_tip():
    h, tip_h, g = 0.25, 0.005, 1.3
    m = mesh_scene(SCENES["edge crack"], h, tip_h, g)
    tip = SCENES["edge crack"].tips[0]
    # every element meets the size field at its vertex nearest the tip
    target = size_field(m.x, h, [tip], tip_h, g)[m.t].min(axis=1)
    assert np.all(m.size <= target * (1 + 1e-12))
    at_tip = np.isin(m.t, m.tip_nodes[0]).any(axis=1)
    assert m.size[at_tip].max() <= tip_h
    assert m.size[at_tip].min() > 0.3 * tip_h  # graded, not over-refined
    # median size in rings [r, 2 r] around the tip grows with r
    r = np.linalg.norm(m.x[m.t].mean(axis=1) - tip.x, axis=1)
    rings = [np.median(m.size[(r >= lo) & (r < 2 * lo)]) for lo in (0.01, 0.02, 0.04, 0.08, 0.16)]
    assert np.all(np.diff(rings) > 0)
    uniform = mesh_scene(SCENES["edge crack"], h)
    assert m.n_elements > 3 * uniform.n_elements
    assert uniform.size.max() <= h


def test_two_tips_and_a_mouth_in_one_scene():
    scene = Scene(Domain.rectangle(0, 0, 2, 3), MAT, cracks=(
        KINKED, Crack([[0.0, 0.5], [0.8, 0.6]], tips=(False, True), name="e")))
    m = mesh_scene(scene, 0.2, 0.01)
    assert len(m.tip_nodes) == 3 and len(set(m.tip_nodes)) == 3
    assert np.allclose(m.x[list(m.tip_nodes)], [t.x for t in scene.tips])
    assert set(np.unique(m.facet_owner[m.facet_owner < 0])) == {-1, -2}


@pytest.mark.parametrize("kwargs, match", [
    ({"h": 0.0}, "h must be finite and > 0, got 0.0"),
    ({"h": -1.0}, "h must be finite and > 0"),
    ({"h": float("nan")}, "h must be finite and > 0"),
    ({"h": 0.1, "tip_h": 0.2}, "tip_h = 0.2 exceeds h = 0.1"),
    ({"h": 0.1, "tip_h": 0.0}, "tip_h must be finite and > 0"),
    ({"h": 0.1, "grading": 1.0}, r"grading must lie in \(1, 4\]"),
    ({"h": 0.1, "min_angle": 40.0}, r"min_angle must lie in \(0, 33\]"),
    ({"h": 1e-5}, "would give about .* elements"),
])
def test_bad_input_is_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        mesh_scene(SCENES["square"], **kwargs)


def test_bad_types_are_refused():
    with pytest.raises(TypeError, match="scene must be a Scene"):
        mesh_scene(SCENES["square"].domain, 0.1)
    with pytest.raises(TypeError, match="h must be a real number"):
        mesh_scene(SCENES["square"], "0.1")
    with pytest.raises(KeyError, match="no edge named 'lft'"):
        _mesh("square").boundary("lft")


def test_plot_mesh_draws_faces_and_tips():
    fig = plot_mesh(_mesh("edge crack"))
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    red = [ln for ln in ax.lines if ln.get_color() == "tab:red"]
    assert len(red) >= 2  # crack-face segments and the tip marker
    fig2, ax2 = plt.subplots()
    assert plot_mesh(_mesh("square"), ax=ax2) is fig2


@pytest.mark.parametrize("fan", [0, 6, 12])
def test_tip_fan_vertices_surround_every_tip(fan):
    scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
                  cracks=(Crack([[-0.5, 0.0], [0.5, 0.0]], name="c"),))
    m = mesh_scene(scene, 0.25, tip_h=0.02, tip_fan=fan)
    for node in m.tip_nodes:
        count = np.any(m.t == node, axis=1).sum()
        assert count == fan if fan else 4 <= count <= 8  # Triangle alone leaves 4-8
        if fan:  # n - 1 fan vertices at one distance (<= tip_h) and the two on the crack faces
            ring = np.setdiff1d(m.t[np.any(m.t == node, axis=1)], [node])
            d = np.linalg.norm(m.x[ring] - m.x[node], axis=1)
            _, counts = np.unique(np.round(d / 0.02, 9), return_counts=True)
            assert counts.max() >= fan - 1 and d.min() <= 0.02


def test_tip_fan_and_refine_are_validated():
    scene = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3))
    with pytest.raises(ValueError, match="tip_fan must be 0"):
        mesh_scene(scene, 0.5, tip_fan=2)
    with pytest.raises(ValueError, match=r"refine point \[2.0, 2.0\]"):
        mesh_scene(scene, 0.5, 0.1, refine=[[2.0, 2.0]])
    m = mesh_scene(scene, 0.5, 0.05, refine=[[0.5, 0.5]])
    assert np.min(np.linalg.norm(m.x - 0.5, axis=1)) < 1e-12 and m.size.min() < 0.08
