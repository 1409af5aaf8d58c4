"""Crack and enrichment work only where it is non-zero: the prefilters give the results of
the unfiltered computation (to 1e-12)."""

import numpy as np
import pytest

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, Traction
from efgkit.approx.crack_prefilter import points_near
from efgkit.approx.crack_rules import CrackLines
from efgkit.approx.enrichment import interpolant
from efgkit.methods.discretize import discretize
from efgkit.search import find_neighbours

CRACKS = (Crack([[0.2, 0.3], [0.9, 0.45]], name="a"),
          Crack([[0.3, 0.7], [0.55, 0.8], [0.7, 0.6], [0.95, 0.75]], name="kinked"),
          Crack([[0.0, 0.15], [0.45, 0.1]], (False, True), "edge"))


@pytest.mark.parametrize("cracks", [CRACKS[:1], CRACKS])
def test_cracked_rows_equal_the_unfiltered_test(cracks):
    dom = Domain.rectangle(0, 0, 1, 1)
    scene = Scene(dom, Elastic(1.0, 0.3), supports=(Support("bottom", ux=0.0, uy=0.0),),
                  cracks=cracks)
    disc = discretize(scene, EFG(spacing=0.05, zones=(), enrichment="none"))
    ap = disc.approx
    x = np.random.default_rng(0).uniform(-0.1, 1.1, (4000, 2))
    nb = find_neighbours(x, ap.nodes, ap.boxes)
    reach = np.where(nb.mask, ap.nodes.radius[nb.idx], 0.0).max(axis=1)
    unfiltered = np.flatnonzero(ap.lines.distance(x) < reach)
    rows = ap.cracked_rows(x, nb)
    np.testing.assert_array_equal(rows, unfiltered)
    assert 0 < len(rows) < len(x)


def test_within_is_a_superset_of_the_points_near_a_crack():
    lines = CrackLines.from_cracks(CRACKS)
    x = np.random.default_rng(1).uniform(-0.5, 1.5, (5000, 2))
    for radius in (0.01, 0.1, 0.4):
        near = np.flatnonzero(lines.distance(x) < radius)
        assert np.isin(near, points_near(lines, x, radius)).all()
        assert len(points_near(lines, x, radius)) < len(x)


@pytest.mark.parametrize("radius", [None, 0.3])
def test_enrichment_interpolant_equals_the_operator_product(radius):
    """sum_I phi_I q_I from the neighbour arrays of the rows alone = (phi @ q)[rows]."""
    scene = Scene(Domain.rectangle(0, 0, 1, 2), Elastic(1.0, 0.3, "strain"),
                  supports=(Support("bottom", ux=0.0, uy=0.0),),
                  tractions=(Traction("top", (0.0, 1.0)),),
                  cracks=(Crack([[0.0, 1.0], [0.5, 1.0]], (False, True)),))
    disc = discretize(scene, EFG(spacing=0.1, enrichment="extrinsic_mls", enrich_radius=radius))
    sh = disc.shape
    q = np.random.default_rng(2).normal(size=(disc.nodes.n, 4))
    rows = np.flatnonzero(np.random.default_rng(3).random(sh.shape[0]) < 0.3)
    for vals, op in ((sh.values, sh.phi), (sh.ddx, sh.dx), (sh.ddy, sh.dy)):
        got = interpolant(vals, sh.neighbours, rows, q, chunk=97)  # several chunks
        np.testing.assert_allclose(got, (op @ q)[rows], rtol=0, atol=1e-12)
