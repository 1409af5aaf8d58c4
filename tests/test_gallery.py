"""The gallery of canonical specimens: geometry as documented, reference K from the
literature, and the FE model of each specimen against its handbook K."""

import math

import numpy as np
import pytest

from efgkit import FEM, Scene, solve_fem
from efgkit import gallery as g


@pytest.mark.parametrize("name", sorted(g.SPECIMENS))
def test_every_specimen_is_a_valid_scene(name):
    sc = g.SPECIMENS[name](0.3) if name == "inclined" else g.SPECIMENS[name]()
    assert isinstance(sc, Scene) and sc.is_static
    assert sc.supports or sc.point_supports  # held: no rigid-body motion left to the solver


def test_sent_seed001_is_the_seed_specimen():
    # seed 001 Sect. 4: 50 x 10 mm, a/W = 0.5, 0.0253882 mm at each end, E = 210 GPa, nu = 0.3
    sc = g.sent_seed001()
    assert np.allclose(sc.domain.outer.vertices, [[0, 0], [50, 0], [50, 10], [0, 10]])
    assert np.allclose(sc.cracks[0].vertices, [[25, 0], [25, 5]]) and sc.cracks[0].tips == (False, True)
    assert {(s.edge, s.ux, s.uy) for s in sc.supports} == {("left", -0.0253882, 0.0),
                                                           ("right", 0.0253882, 0.0)}
    assert (sc.material.E, sc.material.nu, sc.material.plane) == (210e3, 0.3, "strain")


def test_reference_k_closed_forms():
    # Tada p. 5.11: K_I = sigma sqrt(pi a) cos^2 beta, K_II = ... sin beta cos beta, T = -cos 2 beta
    r = g.reference_k("inclined", beta=math.radians(30.0), a=2.0, sigma=3.0)
    k0 = 3.0 * math.sqrt(2.0 * math.pi)
    assert r["KI"] == pytest.approx(0.75 * k0) and r["KII"] == pytest.approx(math.sqrt(3) / 4 * k0)
    assert r["T"] == pytest.approx(-1.5) and r["accuracy"] == 0.0
    # Tada p. 2.2 at alpha -> 0: the Griffith crack, sigma sqrt(pi a)
    assert g.reference_k("cct", a_over_b=1e-4, b=2.0)["KI"] == pytest.approx(math.sqrt(math.pi * 2e-4), 1e-7)
    # Tada p. 2.11 and p. 2.6 at alpha -> 0: the edge crack in a half-plane, 1.122 sigma sqrt(pi a)
    for name, key in (("sent", "a_over_w"), ("dent", "a_over_b")):
        F = g.reference_k(name, **{key: 1e-5})["KI"] / math.sqrt(math.pi * 1e-5)
        assert F == pytest.approx(1.122, 2e-3)
    assert g.reference_k("shear_edge_crack")["KI"] == 34.0  # Wilson (1969), seed 003 Sect. 5.6.2


@pytest.mark.parametrize("name, scene, fem, bound", [
    # FEM P2 with quarter-point tips; measured: cct +0.028 %, sent -0.097 %, dent +0.55 % (the
    # DENT formula is stated to 0.5 %; a finer mesh gives the same 1.4654, see the docstring)
    ("cct", lambda: g.cct(0.5, 3.0), FEM(0.25, tip_h=0.01), 1e-3),
    ("sent", lambda: g.sent(0.5, 2.0), FEM(0.2, tip_h=0.01), 2e-3),
    ("dent", lambda: g.dent(0.5, 3.0), FEM(0.25, tip_h=0.01), 8e-3),
])
def test_fem_of_the_specimen_meets_its_handbook_k(name, scene, fem, bound):
    ref = g.reference_k(name)["KI"]
    for r in solve_fem(scene(), fem).sifs(error=False):
        assert abs(r.KI / ref - 1) < bound, (name, r.KI, ref)


@pytest.mark.parametrize("call, match", [
    (lambda: g.cct(a_over_b=1.2), "a_over_b must lie in"),
    (lambda: g.sent(ends="pinned"), "ends must be 'free' or 'clamped'"),
    (lambda: g.reference_k("sent", ends="clamped"), "clamped ends has no closed form"),
    (lambda: g.reference_k("kirsch"), "no closed-form or handbook K"),
    (lambda: g.reference_k("cnt"), "unknown specimen 'cnt'"),
])
def test_bad_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()
