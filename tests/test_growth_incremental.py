"""The incremental growth update (efgkit.growth.incremental) against full rebuilds.

The reference of every check is the full rebuild of the same scene (discretize, the
stiffness of all quadrature points, the loads): the update must reproduce it to rounding
(1e-10 relative in the max norm; measured 1e-17 to 5e-17).
"""

import numpy as np
import pytest

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, Traction, Zone
from efgkit.growth import Growth, grow
from efgkit.growth.incremental import assemble, update
from efgkit.system.assemble import stiffness

N = 23  # grid nodes per side: coarse and fast
H = 1.0 / (N - 1)


def _scene():
    return Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3, "strain"),
                 supports=(Support("bottom", uy=0.0), Support("left", ux=0.0)),
                 tractions=(Traction("top", (0.0, 1.0)),),
                 cracks=(Crack([[0.0, 0.5 + H / 3], [0.3, 0.5 + H / 3]], tips=(False, True)),))


def _rel(a, b):
    return float(abs(a - b).max() / abs(b).max())


@pytest.mark.parametrize("kw", [dict(enrich_radius=2 * H),  # auto: ramped extrinsic MLS
                                dict(enrichment="pu", enrich_radius=1.5 * H)])
def test_update_equals_full_rebuild_after_several_steps(kw):
    sc = _scene()
    m = EFG(spacing=H, zones=(), **kw)
    sys = update(None, sc, m)
    dofs = {sys.K.shape[0]}
    for angle in (0.3, -0.25, 0.4):
        sc = sc.with_cracks((sc.cracks[0].extended(1.3 * H, angle),))
        sys = update(sys, sc, m)
        assert sys.reason is None
        assert sys.recomputed < 0.7 * len(sys.disc.points.w)  # only part of the points
        dofs.add(sys.K.shape[0])
    ref = assemble(sc, m)  # after three steps
    assert sys.K.shape == ref.K.shape
    assert _rel(sys.K, ref.K) < 1e-10
    assert _rel(sys.f, ref.f) < 1e-10
    # the composed shape rows are those of the rebuild: the same K from them
    assert _rel(stiffness(sys.disc.shape, sys.disc.points.w, sc.material.D), ref.K) < 1e-10
    if kw.get("enrichment") == "pu":  # enriched nodes came and went: n_dofs changed
        assert len(dofs) > 1


def test_growth_loop_same_path_sifs_and_solution_with_and_without_update():
    sc = _scene()
    m = EFG(spacing=H, zones=(), enrich_radius=2 * H)
    runs = [list(grow(sc, m, Growth(da=1.5 * H, max_steps=3, incremental=inc)))
            for inc in (False, True)]
    assert [s.stop for s in runs[0]] == [s.stop for s in runs[1]]
    assert all("incremental" in s.solution.disc.timings for s in runs[1][1:])  # not rebuilt
    for a, b in zip(*runs, strict=True):
        va, vb = a.scene.cracks[0].vertices, b.scene.cracks[0].vertices
        assert np.abs(np.asarray(va) - np.asarray(vb)).max() < 1e-10
        for ta, tb in zip(a.tips, b.tips, strict=True):
            assert abs(ta.KI - tb.KI) < 1e-10 * abs(ta.KI)
            assert abs(ta.KII - tb.KII) < 1e-10 * abs(ta.KI)
        ca, cb = a.solution.coeffs, b.solution.coeffs
        assert _rel(cb, ca) < 1e-10
        Ka = stiffness(a.solution.disc.shape, a.solution.disc.points.w, sc.material.D)
        Kb = stiffness(b.solution.disc.shape, b.solution.disc.points.w, sc.material.D)
        assert _rel(Kb, Ka) < 1e-10


def test_update_falls_back_and_says_why():
    sc = _scene()
    nxt = sc.with_cracks((sc.cracks[0].extended(1.3 * H, 0.2),))
    def tip_zone(scene):  # as the automatic zones: a refinement that follows the tip
        return EFG(spacing=H, zones=(Zone(tuple(scene.tips[0].x), 3 * H, H / 2),),
                   enrich_radius=2 * H)

    moved = update(update(None, sc, tip_zone(sc)), nxt, tip_zone(nxt))
    assert "zones" in moved.reason and moved.recomputed == len(moved.disc.points.w)
    m = EFG(spacing=H, zones=(), enrichment="extrinsic_mls")
    glob = update(update(None, sc, m), nxt, m)
    assert "enrich_radius" in glob.reason


def test_update_errors():
    sc = _scene()
    m = EFG(spacing=H, zones=())
    with pytest.raises(TypeError, match="scene must be a Scene"):
        update(None, "scene", m)
    with pytest.raises(TypeError, match="method must be an EFG"):
        update(None, sc, "efg")
    with pytest.raises(TypeError, match="previous must be an Assembled"):
        update("old", sc, m)
    with pytest.raises(TypeError, match="growth incremental must be a bool"):
        Growth(da=0.1, incremental=1)


def test_update_when_a_tip_runs_onto_the_boundary():
    # a centre crack's right tip becomes a mouth: one tip and its enrichment disappear
    y = 0.5 + H / 3
    sc = _scene().with_cracks((Crack([[0.5, y], [0.9, y]], tips=(True, True)),))
    nxt = sc.with_cracks((Crack([[0.5, y], [0.9, y], [1.0, y]], tips=(True, False)),))
    m = EFG(spacing=H, zones=(), enrichment="radial", enrich_radius=2 * H,
            crack_rule="visibility")  # sqrt(r) with diffraction between rows is refused
    sys = update(update(None, sc, m), nxt, m)
    ref = assemble(nxt, m)
    assert sys.reason is None and sys.K.shape == ref.K.shape
    assert _rel(sys.K, ref.K) < 1e-10
    assert _rel(sys.f, ref.f) < 1e-10
