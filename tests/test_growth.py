"""Crack-growth loops: stops and their reasons, tips joining the boundary, restart, fatigue."""

import json
import math

import numpy as np
import pytest

from efgkit import EFG, FEM, Crack, Domain, Elastic, Scene, Support, Traction
from efgkit.growth import Growth, GrowthState, advance, grow
from efgkit.growth.record import RESTART_NAME, load_state, run, save_state


def plate(cracks, name="plate"):
    """2 x 2 plate, rollers on the bottom, one stretch pinned in x, unit tension on top."""
    return Scene(Domain.rectangle(0, 0, 2, 2), Elastic(1000.0, 0.3, "stress"),
                 supports=(Support("bottom", uy=0.0),
                           Support(lambda x: (x[:, 0] < 0.25) & (x[:, 1] < 1e-9), ux=0.0)),
                 tractions=(Traction("top", (0.0, 1.0)),), cracks=cracks, name=name)


EDGE = Crack([[0.0, 1.0], [0.8, 1.0]], tips=(False, True), name="c")


def test_efg_edge_crack_runs_through_the_plate():
    edge = Crack([[0.0, 1.0], [1.15, 1.0]], tips=(False, True), name="c")
    steps = list(grow(plate((edge,)), EFG(spacing=0.2), Growth(da=0.45, max_steps=10)))
    assert [s.index for s in steps] == [0, 1]
    assert steps[-1].stop.startswith("the cracks 'c' cut the body into separate pieces (tip c:1 "
                                     "reached the boundary at [2.0, ")
    # each step grew the tip by da along its kink angle
    for s0, s1 in zip(steps[:-1], steps[1:], strict=True):
        t0, t1 = s0.tips[0].tip, s1.tips[0].tip
        d = t0.x + 0.45 * np.array([math.cos(t0.angle + s0.kink[0]), math.sin(t0.angle + s0.kink[0])])
        np.testing.assert_allclose(t1.x, d, atol=1e-12)
    # K_I grows with the crack under load control; the FE reference gives the same path
    assert steps[1].tips[0].KI > steps[0].tips[0].KI > 0
    fem = list(grow(plate((edge,)), FEM(h=0.2), Growth(da=0.45, max_steps=10)))
    assert len(fem) == 2
    # measured: tip 1 at 1.9e-5 from the EFG one (EFG h = 0.2, FE h = 0.2; K_I 7.079 and 7.082)
    np.testing.assert_allclose(fem[1].tips[0].tip.x, steps[1].tips[0].tip.x, atol=6e-5)


def test_tip_joins_the_boundary_and_the_other_grows_on():
    crack = Crack([[1.0, 1.0], [1.7, 1.0]], name="m")  # two tips; the right one is 0.3 from the edge
    steps = list(grow(plate((crack,)), FEM(h=0.2), Growth(da=0.25, max_steps=2)))
    assert [t.tip.id for t in steps[0].tips] == ["m:0", "m:1"]
    assert [t.tip.id for t in steps[1].tips] == ["m:0"]  # m:1 is a mouth now
    assert "tip m:1 reached the boundary" in steps[1].events[0]
    c = steps[1].scene.cracks[0]
    assert c.tips == (True, False) and abs(c.vertices[-1, 0] - 2.0) < 1e-12
    assert steps[-1].stop == "maximum number of steps (2) reached"


def test_advance_joins_cracks():  # more in test_junctions.py
    a = Crack([[0.5, 1.0], [0.9, 1.0]], name="a")
    b = Crack([[1.0, 0.5], [1.0, 1.5]], name="b")
    adv = advance(plate((a, b)), {"a:1": (0.3, 0.0)})
    assert adv.joined == ("a:1",) and adv.events[0].startswith("tip a:1 joined crack 'b' at [1.0, 1.0]")
    assert adv.scene.cracks[0].tips == (True, False)


def test_restart_reaches_the_same_result(tmp_path):
    sc, m, g = plate((EDGE,)), FEM(h=0.25), Growth(da=0.2, max_steps=3)
    full = list(grow(sc, m, g))
    save_state(full[1].state, tmp_path / RESTART_NAME)
    resumed = list(grow(sc, m, g, start=load_state(tmp_path / RESTART_NAME)))
    assert [s.index for s in resumed] == [2, 3]
    for a, b in zip(full[2:], resumed, strict=True):
        np.testing.assert_array_equal(a.scene.cracks[0].vertices, b.scene.cracks[0].vertices)
        assert (a.tips[0].KI, a.tips[0].KII, a.stop) == (b.tips[0].KI, b.tips[0].KII, b.stop)


def test_run_writes_log_restart_and_figures(tmp_path):
    res = run(plate((EDGE,)), FEM(h=0.25), Growth(da=0.2, max_steps=1), tmp_path, vtu=True)
    assert (tmp_path / "growth_0000.vtu").exists() and (tmp_path / "growth_0001.vtu").exists()
    lines = (tmp_path / "growth_log.jsonl").read_text().splitlines()
    assert [json.loads(x)["step"] for x in lines] == [0, 1]
    assert json.loads(lines[-1])["stop"] == res["stop"] == "maximum number of steps (1) reached"
    assert (tmp_path / RESTART_NAME).exists() and (tmp_path / "growth_path.png").exists()
    assert load_state(tmp_path / RESTART_NAME).index == 1


def test_unstable_under_load_control():
    # K_I rises with a under a fixed traction, so the load factor K_Ic / K_eq falls
    steps = list(grow(plate((EDGE,)), FEM(h=0.25), Growth(da=0.2, max_steps=5, K_Ic=10.0)))
    assert len(steps) == 2 and steps[-1].stop.startswith("unstable: the load factor fell")
    assert steps[1].load_factor < steps[0].load_factor
    assert steps[0].load_factor == pytest.approx(10.0 / steps[0].K_eq.max(), rel=1e-15)


def test_stops_by_length_and_threshold():
    g = Growth(da=0.3, max_steps=5, max_length=1.0)
    steps = list(grow(plate((EDGE,)), FEM(h=0.25), g))
    assert steps[-1].index == 1 and "at least max_length (1)" in steps[-1].stop
    steps = list(grow(plate((EDGE,)), FEM(h=0.25), Growth(da=0.3, K_threshold=1e3)))
    assert len(steps) == 1 and "at or below K_threshold" in steps[0].stop


def test_paris_cycles_scale_with_load_ratio():
    # same K path; dK = (1 - R) K_max, so N(R = 0.5) = 2^m N(R = 0) (Paris law)
    def life(R):
        g = Growth(da=0.2, max_steps=2, criterion="paris", paris_C=1e-4, paris_m=3.0, R=R)
        return [s.cycles for s in grow(plate((EDGE,)), FEM(h=0.25), g)]

    n0, n5 = life(0.0), life(0.5)
    assert n0[0] == 0.0 and n0[2] > n0[1] > 0
    np.testing.assert_allclose(n5, 8.0 * np.array(n0), rtol=1e-12)
    g = Growth(da=0.2, criterion="paris", paris_C=1e-4, paris_m=3.0, dK_th=1e3)
    steps = list(grow(plate((EDGE,)), FEM(h=0.25), g))
    assert len(steps) == 1 and "no fatigue growth" in steps[0].stop


@pytest.mark.parametrize("kw, match", [
    (dict(da=0.0), "growth da must be a finite number > 0"),
    (dict(da=1.0, max_steps=0), "max_steps must be an integer > 0"),
    (dict(da=1.0, criterion="energy"), "criterion must be one of"),
    (dict(da=1.0, criterion="paris"), "needs paris_C and paris_m"),
    (dict(da=1.0, R=1.0), r"R \(load ratio"),
    (dict(da=1.0, snap=-1.0), "snap must be a finite number >= 0"),
])
def test_growth_settings_errors(kw, match):
    with pytest.raises(ValueError, match=match):
        Growth(**kw)


def test_grow_input_errors(tmp_path):
    g = Growth(da=0.1)
    with pytest.raises(ValueError, match="no crack tip to grow"):
        next(grow(plate(()), FEM(h=0.5), g))
    with pytest.raises(TypeError, match="method must be an EFG, MLPG or FEM"):
        next(grow(plate((EDGE,)), "efg", g))
    with pytest.raises(TypeError, match="settings must be a Growth"):
        next(grow(plate((EDGE,)), FEM(h=0.5), {"da": 0.1}))
    with pytest.raises(TypeError, match="start must be a GrowthState"):
        next(grow(plate((EDGE,)), FEM(h=0.5), g, start={"index": 1}))
    (tmp_path / "x.json").write_text("{}")
    with pytest.raises(ValueError, match="is not a growth restart file"):
        load_state(tmp_path / "x.json")
    with pytest.raises(TypeError, match="state must be a GrowthState"):
        save_state({}, tmp_path / "y.json")
    assert isinstance(GrowthState(0, (EDGE,)), GrowthState)


SCENE_FILE = """
name = "grow_plate"
[material]
E = 1000.0
nu = 0.3
plane = "stress"
[domain]
outer = { rectangle = [0.0, 0.0, 2.0, 2.0] }
[[supports]]
edge = "bottom"
uy = 0.0
[[supports]]
edge = "left"
ux = 0.0
[[tractions]]
edge = "top"
t = [0.0, 1.0]
[[cracks]]
name = "c"
vertices = [[0.0, 1.0], [0.8, 1.0]]
tips = [false, true]
[efg]
spacing = 0.2
[growth]
"""


def test_cli_runs_the_growth_table(tmp_path, capsys):
    from efgkit.cli import main

    f = tmp_path / "g.toml"
    f.write_text(SCENE_FILE + "da = 0.3\nmax_steps = 1\n")
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["stop"] == "maximum number of steps (1) reached" and rep["n_steps"] == 1
    assert rep["steps"][1]["lengths"]["c"] == pytest.approx(1.1, abs=1e-12)  # 0.8 + da
    assert (tmp_path / "o" / "growth_log.jsonl").exists()
    f.write_text(SCENE_FILE + "da = 0.3\nmax_step = 1\n")
    assert main(["run", str(f), "--out", str(tmp_path / "p")]) == 2
    assert "unknown key 'max_step' in table 'growth'; did you mean 'max_steps'?" in capsys.readouterr().err


def test_several_cracks_grow_in_one_loop():
    # two edge cracks; Paris: the leader grows by da, the other by da (dK_i / dK_lead)^m
    left = Crack([[0.0, 0.6], [0.6, 0.6]], tips=(False, True), name="L")
    right = Crack([[2.0, 1.4], [1.6, 1.4]], tips=(False, True), name="R")
    g = Growth(da=0.1, max_steps=1, criterion="paris", paris_C=1e-4, paris_m=3.0)
    s0, s1 = grow(plate((left, right)), FEM(h=0.25), g)
    k = s0.K_eq
    lead = int(np.argmax(k))
    ids = [t.tip.id for t in s0.tips]
    assert s0.da[ids[lead]] == 0.1
    assert s0.da[ids[1 - lead]] == pytest.approx(0.1 * (k[1 - lead] / k[lead]) ** 3, rel=1e-12)
    grown = {n: s1.lengths[n] - s0.lengths[n] for n in ("L", "R")}
    assert grown == pytest.approx({t.tip.crack: s0.da[t.tip.id] for t in s0.tips}, rel=1e-12)


def test_tips_below_the_threshold_stay():
    # the short crack's K_eq is below the threshold: only the long one grows
    long_ = Crack([[0.0, 0.6], [0.9, 0.6]], tips=(False, True), name="L")
    short = Crack([[2.0, 1.4], [1.8, 1.4]], tips=(False, True), name="S")
    probe = next(grow(plate((long_, short)), FEM(h=0.25), Growth(da=0.1, max_steps=1)))
    k = dict(zip([t.tip.id for t in probe.tips], probe.K_eq, strict=True))
    assert k["S:1"] < k["L:1"]
    g = Growth(da=0.1, max_steps=1, K_threshold=0.5 * (k["S:1"] + k["L:1"]))
    s0, s1 = grow(plate((long_, short)), FEM(h=0.25), g)
    assert s0.da == {"L:1": 0.1}
    assert s1.lengths["S"] == s0.lengths["S"] and s1.lengths["L"] == pytest.approx(1.0, abs=1e-12)
