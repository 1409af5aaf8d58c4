"""Refinement along growing crack paths (Growth.path_zones) and the message of a growth step
that cannot be discretised."""

import warnings

import numpy as np
import pytest

from efgkit import EFG, FEM, Crack, Domain, Elastic, Scene, Support, Traction
from efgkit.approx.mls import SingularMomentMatrix
from efgkit.growth import Growth, grow
from efgkit.growth.path_zones import path_zones, with_path_zones
from efgkit.methods.efg import Zone


def overlap(gap_top=0.6, gap_bottom=0.52):
    """2 x 1 plate with two edge cracks that overlap over 1 (x from 0.5 to 1.5) with a
    sliver between ``gap_bottom`` and ``gap_top`` holding no node of an h = 0.25 grid
    (its rows are at y = 0.5 and 0.75)."""
    return Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.3, "stress"),
                 supports=(Support("bottom", uy=0.0),
                           Support(lambda x: (x[:, 0] < 0.25) & (x[:, 1] < 1e-9), ux=0.0)),
                 tractions=(Traction("top", (0.0, 1.0)),),
                 cracks=(Crack([[0.0, gap_top], [1.5, gap_top]], (False, True), "a"),
                         Crack([[2.0, gap_bottom], [0.5, gap_bottom]], (False, True), "b")))


def test_zones_cover_the_path_on_one_lattice():
    sc = overlap()
    zones = path_zones(sc, [(0.2, 0.02)])
    c = np.array([z.centre for z in zones])
    # centres every r / 2 = 0.1 along both cracks (16 on each, ends included), on the lattice
    # 0.02 (i, j) of the corner (0, 0): y = 0.6 and 0.52 are lattice rows
    assert len(zones) == 32 and {z.radius for z in zones} == {0.2} and {z.spacing for z in zones} == {0.02}
    np.testing.assert_allclose(c / 0.02, np.round(c / 0.02), atol=1e-9)
    assert {round(y, 9) for y in c[:, 1]} == {0.6, 0.52}
    # every point of both cracks lies within r sqrt(15) / 4 of a centre (spacing r / 2)
    t = np.linspace(0, 1, 301)[:, None]
    pts = np.vstack([[0.0, 0.6] + t * [1.5, 0.0], [2.0, 0.52] + t * [-1.5, 0.0]])
    d = np.linalg.norm(pts[:, None] - c[None], axis=-1).min(axis=1)
    assert d.max() <= 0.2 * np.sqrt(15) / 4
    # the tips (the last vertices) are centres: the zones follow them
    assert {(1.5, 0.6), (0.5, 0.52)} <= {tuple(np.round(p, 9)) for p in c}


def test_with_path_zones_adds_to_the_methods_zones():
    sc = overlap()
    own = (Zone((1.0, 0.5), 0.3, 0.1),)
    m = with_path_zones(EFG(spacing=0.25, zones=own), sc, ((0.2, 0.05),))
    assert m.zones[:1] == own and len(m.zones) > 1
    none = with_path_zones(EFG(spacing=0.25, enrichment="none"), sc, ((0.2, 0.05),))
    assert none.zones == path_zones(sc, ((0.2, 0.05),), 0.25)  # explicit enrichment: no tip zones
    # graded to h = 0.25: rings of spacing 0.1 (to 0.2 + 4 x 0.1) and 0.2 (to 0.6 + 4 x 0.2)
    assert {(z.radius, z.spacing) for z in none.zones} == {(0.2, 0.05), (0.6000000000000001, 0.1),
                                                           (1.4000000000000001, 0.2)}
    auto = with_path_zones(EFG(spacing=0.25), sc, ((0.2, 0.05),))
    assert len(auto.zones) == 2 * 2 + len(none.zones)  # the two automatic zones of each tip kept
    fem = FEM(h=0.1)
    assert with_path_zones(fem, sc, ((0.2, 0.05),)) is fem
    assert with_path_zones(EFG(spacing=0.25), sc, ()).zones is None


def test_path_zones_setting_is_validated():
    assert Growth(da=0.1, path_zones=[[0.2, 0.05]]).path_zones == ((0.2, 0.05),)
    assert Growth.from_dict({"da": 0.1, "path_zones": [[0.2, 0.05]]}).path_zones == ((0.2, 0.05),)
    with pytest.raises(ValueError, match=r"path_zones must be a sequence of \(radius, spacing\) pairs "
                       r"of finite numbers > 0, e.g. \(\(1.0, 0.05\),\), got \(\(0.2, -1.0\),\)"):
        Growth(da=0.1, path_zones=((0.2, -1.0),))
    with pytest.raises(TypeError, match=r"path_zones must be a sequence .* got 0.2"):
        Growth(da=0.1, path_zones=0.2)
    with pytest.raises(TypeError, match=r"path_zones must be a sequence .* got \(0.2, 0.05\)"):
        Growth(da=0.1, path_zones=(0.2, 0.05))  # a pair, not a sequence of pairs
    with pytest.raises(TypeError, match=r"growth.path_zones must be tuple, got 0.2"):
        Growth.from_dict({"da": 0.1, "path_zones": 0.2})
    with pytest.raises(ValueError, match=r"growth path_zones \(\(0.2, 0.05\),\) refine EFG node clouds, "
                       r"the method is FEM: give its own refinement, or path_zones=\(\)"):
        next(grow(overlap(), FEM(h=0.1), Growth(da=0.1, path_zones=((0.2, 0.05),))))


def test_a_sliver_fails_with_a_remedy_and_path_zones_resolve_it():
    sc = overlap(gap_top=0.64)
    m = EFG(spacing=0.25, enrichment="none", order=2, refined_order=2)  # 2 x 2: a fast test
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(SingularMomentMatrix, match=r"growth step 0: the cracks cannot be "
                           r"discretised: .* Refine along the crack paths with "
                           r"Growth\(path_zones=\(\(radius, spacing\),\)\): a spacing a few times "
                           r"below the narrowest gap .* below da \(0.1\); or enlarge d_max."):
            next(grow(sc, m, Growth(da=0.1)))
        # nodal spacing 0.04: two rows of nodes inside the 0.12 sliver (graded to h = 0.25 by
        # rings of 0.08 and 0.16)
        st = next(grow(sc, m, Growth(da=0.1, path_zones=((0.12, 0.04),))))
    assert st.solution.disc.nodes.n > 300
    # the tips of overlapping cracks under tension: both open
    assert min(t.KI for t in st.tips) > 0
