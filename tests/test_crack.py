"""Crack geometry: tips and frames, extension, side convention, and bad cracks."""

import math

import numpy as np
import pytest

from efgkit import Crack, Domain, Elastic, Loop, Scene

MAT = Elastic(1.0, 0.3)
PLATE = Domain.rectangle(0, 0, 2, 1)


def test_tip_frames_point_out_of_the_crack():
    c = Crack([[0.5, 0.5], [1.0, 0.5], [1.3, 0.8]])
    t0, t1 = c.tip_list
    assert t0.end == 0 and np.allclose(t0.x, [0.5, 0.5]) and math.isclose(t0.angle, math.pi)
    assert t1.end == 1 and math.isclose(t1.angle, math.pi / 4)
    # rotation maps the tip direction to the local x1 axis
    assert np.allclose(t1.rotation @ np.array([1.0, 1.0]) / math.sqrt(2), [1.0, 0.0])


def test_extended_adds_a_kinked_segment_and_returns_a_new_crack():
    c = Crack([[0.0, 0.5], [1.0, 0.5]], tips=(False, True))
    c2 = c.extended(0.2, -math.pi / 6)
    assert len(c.vertices) == 2 and len(c2.vertices) == 3
    assert np.allclose(c2.vertices[-1], [1.0 + 0.2 * math.cos(math.pi / 6), 0.5 - 0.1])
    assert math.isclose(c2.tip_list[0].angle, -math.pi / 6)
    both = Crack([[0.5, 0.5], [1.0, 0.5]])
    with pytest.raises(ValueError, match="has two tips: give end=0 or end=1"):
        both.extended(0.1)
    assert np.allclose(both.extended(0.1, 0.0, end=0).vertices[0], [0.4, 0.5])
    with pytest.raises(ValueError, match="extension da must be finite and > 0"):
        c.extended(0.0)
    with pytest.raises(ValueError, match=r"kink angle must lie in \(-pi, pi\)"):
        c.extended(0.1, 4.0)


def test_side_convention_points_on_the_line_are_left():
    c = Crack([[0.0, 0.0], [1.0, 0.0]])
    s = c.side(np.array([[0.5, 1e-300], [0.5, 0.0], [0.5, -1e-300], [2.0, 0.0]]), 0)
    assert s.tolist() == [1, 1, -1, 1]


def test_distance_to_polyline():
    c = Crack([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    assert np.allclose(c.distance(np.array([[0.5, -0.5], [2.0, 0.5], [1.5, 1.5]])),
                       [0.5, 1.0, math.hypot(0.5, 0.5)])


@pytest.mark.parametrize("vertices,match", [
    ([[0, 0], [0, 0], [1, 0]], "zero-length segment between vertices 0 and 1"),
    ([[0, 0], [1, 0], [1, 1], [0.5, -0.5]], "intersects itself: segments 0 and 2"),
    ([[0, 0], [1, 0], [0.5, 0]], "doubles back on itself at vertex 1"),
    ([[0, 0], [1, 0], [1, 1], [1, 0.5], [2, 2]], "doubles back on itself at vertex 2"),
    ([[0, 0], [np.nan, 0]], "vertex 1 is not finite"),
    ([[0, 0]], r"vertices must have shape \(n >= 2, 2\)"),
])
def test_bad_polylines(vertices, match):
    with pytest.raises(ValueError, match=match):
        Crack(np.array(vertices, dtype=float), name="c")


def test_a_crack_needs_a_tip():
    with pytest.raises(ValueError, match=r"crack 'c': no tip"):
        Crack([[0, 0], [1, 0]], tips=(False, False), name="c")


@pytest.mark.parametrize("vertices,tips,match", [
    ([[0.5, 0.5], [2.5, 0.5]], (True, True), r"tip 1 \[2.5, 0.5\] lies outside the domain"),
    ([[0.0, 0.0], [1.0, 0.0]], (True, True), r"tip 0 \[0.0, 0.0\] lies on the domain boundary"),
    ([[0.0, 0.0], [1.0, 0.0]], (False, True), r"tip 1 \[1.0, 0.0\] lies on the domain boundary"),
    ([[0.0, 0.5], [1.0, 0.0], [1.5, 0.5]], (False, True), r"vertex 1 \[1.0, 0.0\] lies on the domain"),
    ([[0.3, 0.5], [1.0, 0.5]], (False, True), r"vertex 0 \[0.3, 0.5\] is a mouth"),
    ([[0.5, 0.5], [1.0, 1.5], [1.5, 0.5]], (True, True), r"vertex 1 \[1.0, 1.5\] lies outside"),
])
def test_cracks_must_lie_in_the_body(vertices, tips, match):
    with pytest.raises(ValueError, match=match):
        Scene(PLATE, MAT, cracks=(Crack(vertices, tips, "c"),))


def test_segment_crossing_the_boundary_between_inside_vertices():
    dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1.0, 0.5], 0.2)])
    with pytest.raises(ValueError, match=r"crack 'c': segment 0 \(vertices 0-1\) crosses the domain"):
        Scene(dom, MAT, cracks=(Crack([[0.5, 0.5], [1.5, 0.5]], name="c"),))


def test_edge_crack_from_a_hole_is_accepted():
    dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1.0, 0.5], 0.2)])
    s = Scene(dom, MAT, cracks=(Crack([[1.2, 0.5], [1.6, 0.5]], (False, True), "h"),))
    assert [t.id for t in s.tips] == ["h:1"]


def test_crossing_cracks_and_duplicate_names():
    a = Crack([[0.5, 0.5], [1.5, 0.5]], name="a")
    b = Crack([[1.0, 0.2], [1.0, 0.8]], name="b")
    with pytest.raises(ValueError, match="cracks 'a' .segment 0. and 'b' .segment 0. intersect"):
        Scene(PLATE, MAT, cracks=(a, b))
    with pytest.raises(ValueError, match="two cracks are named 'a'"):
        Scene(PLATE, MAT, cracks=(a, Crack([[0.5, 0.8], [1.5, 0.8]], name="a")))
    with pytest.raises(ValueError, match=r"crack 'a' has no tip at end 2"):
        a.tip(2)
