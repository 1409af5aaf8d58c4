"""Loads in scene files: pressure on an edge (``t = { pressure = p }``) and named load cases
(``[[load_cases]]``) solved with one factorisation, from the reader to ``efgkit run``."""

import json
import re
import warnings

import numpy as np
import pytest

from efgkit import Domain, Elastic, Scene, Support, Traction, solve
from efgkit.cli import main
from efgkit.problem.geometry import Loop
from efgkit.problem.supports import Pressure
from efgkit.scenefile import (
    cases_from_dict,
    cases_to_list,
    load_cases,
    load_scene,
    load_study,
    scene_from_dict,
    scene_to_dict,
)

HOLE = """
name = "pressurised_hole"
[material]
E = 1000.0
nu = 0.3
plane = "strain"
[domain]
outer = { rectangle = [0.0, 0.0, 4.0, 4.0] }
holes = [{ circle = { centre = [2.0, 2.0], radius = 0.5 }, name = "hole" }]
[[supports]]
edge = "left"
ux = 0.0
[[supports]]
edge = "bottom"
uy = 0.0
[[tractions]]
edge = "hole"
t = { pressure = 2.0 }
[efg]
spacing = 0.5
bc = "lagrange"
"""


def test_pressure_in_a_scene_file_is_the_python_scene(tmp_path):
    f = tmp_path / "hole.toml"
    f.write_text(HOLE)
    scene, efg = load_study(f)
    assert scene.tractions[0].t == Pressure(2.0)
    py = Scene(Domain(Loop.polygon([[0, 0], [4, 0], [4, 4], [0, 4]], ("bottom", "right", "top", "left")),
                      (Loop.circle((2.0, 2.0), 0.5, "hole"),)),
               Elastic(1000.0, 0.3, "strain"), supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
               tractions=(Traction("hole", Pressure(2.0)),), name="pressurised_hole")
    d = scene_to_dict(scene)
    assert d["tractions"] == [{"edge": "hole", "t": {"pressure": 2.0}}]
    assert d == scene_to_dict(py) and scene_to_dict(scene_from_dict(d)) == d  # round trip
    x = np.array([[3.9, 2.0], [2.0, 2.6], [1.0, 1.0], [2.55, 2.0]])
    u_file, u_py = solve(scene, efg).displacement(x), solve(py, efg).displacement(x)
    assert np.abs(u_file - u_py).max() <= 1e-12 * np.abs(u_py).max()
    # the hole opens: a pressure p > 0 pushes the rim outwards (radial u > 0 at (2.55, 2))
    assert u_py[3, 0] > 0


@pytest.mark.parametrize("edit, match", [
    ("t = { pressure = 2.0, p = 1.0 }",
     r"unknown key 'p' in table 'tractions\[0\]\.t'; valid keys: pressure"),
    ('t = { pressure = "2" }', r"tractions\[0\]\.t\.pressure must be a number"),
])
def test_bad_pressure(tmp_path, edit, match):
    f = tmp_path / "bad.toml"
    f.write_text(HOLE.replace("t = { pressure = 2.0 }", edit))
    with pytest.raises((ValueError, TypeError), match=match):
        load_scene(f)


CASES = """
name = "two_cases"
[material]
E = 3.0e7
nu = 0.25
plane = "strain"
[domain]
outer = { rectangle = [0.0, 0.0, 7.0, 16.0] }
[[supports]]
edge = "bottom"
ux = 0.0
uy = 0.0
[[cracks]]
name = "edge"
vertices = [[0.0, 8.0], [3.5, 8.0]]
tips = [false, true]
[[load_cases]]
name = "shear"
tractions = [{ edge = "top", t = [1.0, 0.0] }]
[[load_cases]]
name = "tension"
tractions = [{ edge = "top", t = [0.0, 1.0] }]
body_force = [0.0, -0.01]
[[load_cases]]
name = "crack pressure"
crack_pressure = [1.0]
[efg]
spacing = 1.0
bc = "lagrange"
enrichment = "none"
"""


def test_load_cases_equal_separate_solves(tmp_path):
    from efgkit.loadcases import solve_cases

    f = tmp_path / "cases.toml"
    f.write_text(CASES)
    scene, efg = load_study(f)
    cases = load_cases(f)
    assert list(cases) == ["shear", "tension", "crack pressure"]
    assert scene.tractions == () and scene.body_force is None  # the top level holds no load
    assert cases["tension"].body_force == (0.0, -0.01) and cases["crack pressure"].cracks[0].pressure == 1.0
    back = cases_from_dict({**scene_to_dict(scene), "load_cases": cases_to_list(cases)})  # round trip
    assert {n: scene_to_dict(s) for n, s in back.items()} == {n: scene_to_dict(s) for n, s in cases.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sols = solve_cases(cases, efg)
        for n, sc in cases.items():
            k, r = sols[n].sifs(error=False)[0], solve(sc, efg).sifs(error=False)[0]
            scale = max(abs(r.KI), abs(r.KII))
            assert abs(k.KI - r.KI) <= 1e-10 * scale and abs(k.KII - r.KII) <= 1e-10 * scale, n
    assert scene_to_dict(load_scene(f)) == scene_to_dict(scene)  # a file with cases is still a scene


def test_run_load_cases_json_and_text(tmp_path, capsys):
    f = tmp_path / "cases.toml"
    f.write_text(CASES)
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "--json", "--samples", "500"]) == 0
    rep = json.loads(capsys.readouterr()[0])
    assert [c["name"] for c in rep["cases"]] == ["shear", "tension", "crack pressure"]
    assert rep["solver"]["factorised_once"] and len(rep["outputs"]) == 3
    k = {c["name"]: c["tips"][0]["KI"] for c in rep["cases"]}
    assert all(np.isfinite(v) and v != 0 for v in k.values())
    assert main(["run", str(f), "--out", str(tmp_path / "o2"), "--samples", "500"]) == 0
    text = capsys.readouterr()[0]
    assert "factorised once for 3 load cases" in text
    row = next(line for line in text.splitlines() if line.startswith("edge:1 K_I "))
    assert row.split()[2:] == [format(v, ".5g") for v in k.values()]


def _cases(tmp_path, old, new):
    f = tmp_path / "bad.toml"
    f.write_text(CASES.replace(old, new, 1))
    return f


@pytest.mark.parametrize("old, new, match", [
    ('name = "tension"', 'name = "shear"',
     r"load_cases\[1\]\.name: duplicate load case name 'shear' \(also load_cases\[0\]\)"),
    ('name = "tension"', 'name = "tension"\ntraction = []',
     r"unknown key 'traction' in table 'load_cases\[1\]' .*did you mean 'tractions'\?"),
    ('name = "tension"\n', '', r"missing required key 'name' in table 'load_cases\[1\]'"),
    ("crack_pressure = [1.0]", "crack_pressure = [1.0, 2.0]",
     r"load_cases\[2\]\.crack_pressure must be an array of 1 numbers, one per \[\[cracks\]\]"),
    ('t = [1.0, 0.0] }', 't = [1.0] }', r"load_cases\[0\]\.tractions\[0\]\.t must have 2 entries"),
    ('edge = "top", t = [1.0, 0.0]', 'edge = "lid", t = [1.0, 0.0]', r"load_cases\[0\]: .*'lid'"),
    ("[[load_cases]]", "[[tractions]]\nedge = \"top\"\nt = [1.0, 0.0]\n[[load_cases]]",
     r"the top level holds loads \(tractions\) besides \[\[load_cases\]\]"),
    ('tips = [false, true]', 'tips = [false, true]\npressure = 1.0',
     r"the top level holds loads \(cracks\[0\]\.pressure\) besides"),
])
def test_bad_load_cases(tmp_path, old, new, match):
    f = _cases(tmp_path, old, new)
    assert new in f.read_text()
    with pytest.raises((ValueError, TypeError), match=match):
        load_cases(f)
    with pytest.raises((ValueError, TypeError), match=match):
        load_scene(f)


def test_run_load_cases_error_is_one_line(tmp_path, capsys):
    f = _cases(tmp_path, 'name = "tension"', 'name = "shear"')
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr()[1].strip()
    assert err.startswith("efgkit: error:") and "duplicate load case name 'shear'" in err
    assert "\n" not in err


def test_cases_need_a_non_empty_array():
    base = scene_to_dict(scene_from_dict({"material": {"E": 1.0, "nu": 0.3},
                                          "domain": {"outer": {"rectangle": [0, 0, 1, 1]}}}))
    with pytest.raises(TypeError, match=r"load_cases must be a non-empty array of tables"):
        cases_from_dict({**base, "load_cases": []})
    assert cases_from_dict(base) is None


@pytest.mark.parametrize("old, new, match", [
    ('name = "two_cases"', 'name = "two_cases"\nmethod = "mlpg"',
     r"\[\[load_cases\]\] are solved by EFG \(one factorisation\); the file's method is MLPG"),
    ('plane = "strain"', 'plane = "strain"\nrho = 1.0\n[time]\nduration = 1e-3',
     r"\[\[load_cases\]\] are for static scenes; remove \[time\] or \[growth\]"),
])
def test_run_load_cases_refused(tmp_path, capsys, old, new, match):
    f = _cases(tmp_path, old, new)
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr()[1].strip()
    assert re.search(match, err) and "\n" not in err, err


def test_a_study_of_a_file_with_load_cases_is_refused():
    # a study point solves one scene: without this check it would solve the unloaded body
    import tomllib

    from efgkit.study import Parameter, Study

    with pytest.raises(ValueError, match=r"the base scene has \[\[load_cases\]\]: a study point "
                                         r"solves one load"):
        Study(tomllib.loads(CASES), (Parameter("material.E", (1.0, 2.0)),))
