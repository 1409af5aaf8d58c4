"""The incremental growth update (efgkit.growth.incremental) against full rebuilds.

The reference of every check is the full rebuild of the same scene (discretize, the
stiffness of all quadrature points, the loads): the update must reproduce it to rounding
(1e-10 relative in the max norm; measured 1e-17 to 5e-17).
"""

import warnings
from dataclasses import replace

import numpy as np
import pytest

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, Traction, Zone
from efgkit.growth import Growth, advance, grow
from efgkit.growth.incremental import assemble, update
from efgkit.problem.geometry import Loop
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
    # the automatic enrichment: PU for two tips, extrinsic MLS once one has reached a hole
    hole = _hole_scene(17)
    m = EFG(spacing=1 / 16, zones=(), enrich_radius=1 / 16, **LIGHT)
    one_tip = update(update(None, hole, m), advance(hole, {"a:1": (1 / 16, 0.0)}).scene, m)
    assert one_tip.reason.startswith("the method changed (enrichment: 'pu' -> 'extrinsic_mls' "
                                     "(the automatic enrichment follows the number of tips")


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



LIGHT = dict(order=2, refined_order=3, tip_order=4)  # fewer points: fast; the claim is equality


def _junction_scene(n, b_ends=(0.25, 0.75)):
    """A crack 'a' from the left edge 0.8 spacings short of a free crack 'b' (two tips, from
    ``b_ends[0]`` to ``b_ends[1]``) across its path; biaxial tension: both grow."""
    h = 1.0 / (n - 1)
    xb, y = 0.6 + h / 4, 0.5 + h / 3
    return Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3, "strain"),
                 supports=(Support("bottom", uy=0.0), Support("left", ux=0.0)),
                 tractions=(Traction("top", (0.0, 1.0)), Traction("right", (1.0, 0.0))),
                 cracks=(Crack([[0.0, y], [xb - 0.8 * h, y]], tips=(False, True), name="a"),
                         Crack([[xb, b_ends[0]], [xb, b_ends[1]]], name="b")))


def _hole_scene(n):
    """A centre crack whose right tip is 0.8 spacings short of a square hole."""
    h = 1.0 / (n - 1)
    xh, y = 0.68 + h / 5, 0.5 + h / 3
    hole = Loop.polygon([[xh, 0.4], [0.85, 0.4], [0.85, 0.62], [xh, 0.62]])
    sc = _junction_scene(n)
    return Scene(Domain.rectangle(0, 0, 1, 1, holes=[hole]), sc.material, supports=sc.supports,
                 tractions=sc.tractions, cracks=(Crack([[0.3, y], [xh - 0.8 * h, y]], name="a"),))


@pytest.mark.parametrize("case", ["junction", "hole"])
def test_update_when_a_tip_joins_a_crack_or_a_hole_and_the_others_grow_on(case):
    # Step 1: tip a:1 runs onto b's face (a junction: a's end is prolonged by MOUTH_REACH
    # d_mI, its tip and enrichment go) or onto a hole's edge (a mouth); steps 2 and 3: the
    # other tips grow on and kink. Reference: the full rebuild of the same scene.
    n = 17
    h = 1.0 / (n - 1)
    if case == "junction":  # ramped extrinsic fields, one disc per tip
        sc, m = _junction_scene(n), EFG(spacing=h, zones=(), enrichment="extrinsic_mls",
                                        enrich_radius=1.5 * h, **LIGHT)
        first = {"a:1": (h, 0.0), "b:0": (h, 0.0), "b:1": (h, 0.0)}
        then = {"b:0": (h, 0.3), "b:1": (h, -0.3)}
    else:  # PU: enriched nodes come and go
        sc, m = _hole_scene(n), EFG(spacing=h, zones=(), enrichment="pu",
                                    enrich_radius=1.5 * h, **LIGHT)
        first, then = {"a:1": (h, 0.0), "a:0": (h, 0.0)}, {"a:0": (h, 0.3)}
    sys = update(None, sc, m)
    for k, moves in enumerate((first, then, then)):
        adv = advance(sc, moves)
        assert adv.stop is None and adv.joined == (("a:1",) if k == 0 else ())
        sc = adv.scene
        sys = update(sys, sc, m)
        assert sys.reason is None and sys.recomputed < len(sys.disc.points.w)
        if k in (0, 2):  # after the junction (or mouth) and after two more steps
            ref = assemble(sc, m)
            assert sys.K.shape == ref.K.shape
            assert _rel(sys.K, ref.K) < 1e-10  # measured 2e-17 to 1e-16
            assert _rel(sys.f, ref.f) < 1e-10  # measured 0
    assert sc.cracks[0].tips == ((False, False) if case == "junction" else (True, False))


@pytest.mark.slow  # 30 s on the shared machine (two loops of four solves)
def test_growth_loop_with_a_junction_equals_full_rebuilds(monkeypatch):
    # The loop (grow) with incremental updates against the loop with full rebuilds: a joins
    # b in the first increment (the automatic PU enrichment: three tips, then two), b's tips
    # grow on. Every step's K and f are those of the rebuild to rounding; the SIFs agree.
    import efgkit.growth.loop as loop

    n = 17
    h = 1.0 / (n - 1)
    sc = _junction_scene(n, b_ends=(0.35, 0.7))
    m = EFG(spacing=h, zones=(), d_max=2.5, **LIGHT)  # d_max 2: singular beside b's kinked tips
    seen = []

    def recording(previous, scene, method):
        seen.append(update(previous, scene, method))
        return seen[-1]

    settings = Growth(da=h, max_steps=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = list(grow(sc, m, settings))
        monkeypatch.setattr(loop, "update", recording)
        inc = list(grow(sc, m, replace(settings, incremental=True)))
    assert [s.events for s in inc] == [s.events for s in full]
    assert inc[1].events[0].startswith("tip a:1 joined crack 'b' at [0.615625, ")
    assert [[t.tip.id for t in s.tips] for s in inc] == [["a:1", "b:0", "b:1"]] + [["b:0", "b:1"]] * 3
    assert [len(c.vertices) for c in inc[-1].scene.cracks] == [3, 8]  # b grew at both ends 3 times
    assert [s.reason for s in seen] == ["first step", None, None, None]
    for a, b, sys in zip(inc, full, seen, strict=True):
        # the incremental run's own scene (the two runs' paths differ by ~1e-13), the method
        # the loop uses (auto enrichment ramped at 2 h) resolved for it (PU: several tips)
        ref = assemble(a.scene, loop.growth_method(m, settings).for_scene(a.scene))
        assert sys.K.shape == ref.K.shape
        assert _rel(sys.K, ref.K) < 1e-10
        assert _rel(sys.f, ref.f) < 1e-10
        dK = max(max(abs(ta.KI - tb.KI), abs(ta.KII - tb.KII)) / np.hypot(tb.KI, tb.KII)
                 for ta, tb in zip(a.tips, b.tips, strict=True))
        # the two solves of (to rounding) the same system: the difference is the rounding of
        # K (~1e-17 relative) times the condition number of the enriched system with d_max
        # 2.5 (measured 2.2e-10 of |K| at most, at b:0 after the junction)
        assert dK < 6e-10
