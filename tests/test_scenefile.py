"""Scene files: shipped examples load, every key round-trips, errors name their key."""

import dataclasses
import math
import re
from pathlib import Path

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib
import pytest

from efgkit import EFG, Elastic, Scene, Support, Traction, Zone
from efgkit.problem.exact.fields import Field
from efgkit.problem.scene import evaluate_vector
from efgkit.scenefile import (
    SCHEMA,
    efg_from_dict,
    efg_to_dict,
    load_scene,
    load_study,
    scene_from_dict,
    scene_to_dict,
)

EXAMPLES = sorted(p for p in (Path(__file__).parents[1] / "examples").glob("*.toml")
                  if "parameters" not in tomllib.loads(p.read_text()))  # study files: test_study

BASE = """
[material]
E = 1000.0
nu = 0.3

[domain]
outer = { rectangle = [0.0, 0.0, 2.0, 1.0] }

[[supports]]
edge = "left"
ux = 0.0
uy = 0.0
"""


def write(tmp_path, text, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_examples_exist():
    names = {p.stem for p in EXAMPLES}
    assert {"kirsch", "cantilever", "patch", "edge_crack"} <= names


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_example_loads_and_round_trips(path):
    scene, efg = load_study(path)
    assert isinstance(scene, Scene) and isinstance(efg, EFG)
    assert scene.name == path.stem
    assert load_scene(path).name == scene.name
    d = scene_to_dict(scene)
    assert scene_to_dict(scene_from_dict(d)) == d
    assert efg_to_dict(efg_from_dict(efg_to_dict(efg))) == efg_to_dict(efg)


def test_kirsch_example_geometry_and_tractions():
    # Seed 003 Sect. 4.5.1: quarter plate l = 5 with a hole a = 1.
    scene, efg = load_study(EXAMPLES[0].parent / "kirsch.toml")
    dom = scene.domain
    assert math.isclose(dom.area, 25 - math.pi / 4, rel_tol=1e-4)
    assert dom.outer.signed_area > 0
    (hole,) = dom.edges("hole")
    x, t = hole.at(np.linspace(0, 1, 5))
    n = np.column_stack([t[:, 1], -t[:, 0]])  # outward normal: out of the material
    np.testing.assert_allclose(n, -x, atol=1e-12)  # points into the hole, towards the centre
    assert scene.exact == Field.named("kirsch", a=1.0, sigma=1.0)
    # the traction on x = 5 is sigma . n with n = (1, 0): (s_xx, s_xy) of seed 003 Eq. (35)
    (right,) = dom.edges("right")
    x, _ = right.at(np.linspace(0, 1, 7))
    n = np.tile([1.0, 0.0], (len(x), 1))
    s = scene.exact.stress(x, scene.material)
    got = evaluate_vector(scene.tractions[0].t, x, n, scene.material)
    np.testing.assert_allclose(got, s[:, [0, 2]], rtol=1e-14)
    assert efg.zones == (Zone((0.0, 0.0), 2.0, 0.125),)


def test_cantilever_and_edge_crack_examples():
    d = EXAMPLES[0].parent
    cant = load_scene(d / "cantilever.toml")
    f = Field.named("cantilever", L=48.0, D=12.0, P=1000.0)
    assert cant.supports[0].ux == f and cant.supports[0].uy == f and cant.tractions[0].t == f
    assert cant.domain.bbox == (0.0, -6.0, 48.0, 6.0) and cant.material.plane == "stress"
    crack = load_scene(d / "edge_crack.toml")
    (c,) = crack.cracks
    assert c.tips == (False, True) and c.vertices.tolist() == [[0.0, 8.0], [3.5, 8.0]]
    assert crack.material == Elastic(3e7, 0.25, "strain")


# --- one key at a time: (extra TOML, accessor, expected) --------------------------------

SCENE_KEYS = {
    "name": ('name = "plate"\n' + BASE, lambda s: s.name, "plate"),
    "duration": ("duration = 2.5\n" + BASE, lambda s: s.duration, 2.5),
    "body_force": ("body_force = [0.0, -9.81]\n" + BASE, lambda s: s.body_force, (0.0, -9.81)),
    "material.plane": (BASE.replace("nu = 0.3", 'nu = 0.3\nplane = "stress"'),
                       lambda s: s.material.plane, "stress"),
    "material.rho": (BASE.replace("nu = 0.3", "nu = 0.3\nrho = 7.8e-9"),
                     lambda s: s.material.rho, 7.8e-9),
    "rectangle edges": (BASE.replace("1.0] }", '1.0], edges = ["s", "e", "n", "w"] }')
                        .replace('"left"', '"w"'),
                        lambda s: s.domain.outer.names, ("s", "e", "n", "w")),
    "supports.uy field": (BASE.replace("uy = 0.0", 'uy = { field = "williams", KI = 2.0 }'),
                          lambda s: s.supports[0].uy, Field.named("williams", KI=2.0)),
    "tractions vector": (BASE + '[[tractions]]\nedge = "right"\nt = [1.0, 0.5]\n',
                         lambda s: s.tractions[0], Traction("right", (1.0, 0.5))),
    "tractions field": (BASE + '[[tractions]]\nedge = "top"\n'
                        't = { field = "kirsch", a = 0.2, centre = [1.0, 0.5] }\n',
                        lambda s: s.tractions[0].t,
                        Field.named("kirsch", a=0.2, centre=(1.0, 0.5))),
    "cracks": (BASE + '[[cracks]]\nvertices = [[0.5, 0.5], [1.0, 0.5], [2.0, 0.6]]\n'
               'tips = [true, false]\nname = "c1"\n',
               lambda s: (s.cracks[0].vertices.tolist(), s.cracks[0].tips, s.cracks[0].name),
               ([[0.5, 0.5], [1.0, 0.5], [2.0, 0.6]], (True, False), "c1")),
    "cracks defaults": (BASE + "[[cracks]]\nvertices = [[0.5, 0.5], [1.0, 0.5]]\n",
                        lambda s: (s.cracks[0].tips, s.cracks[0].name), ((True, True), "crack")),
    "exact": (BASE + '[exact]\nfield = "cantilever"\nL = 2.0\nD = 1.0\n',
              lambda s: s.exact, Field.named("cantilever", L=2.0, D=1.0)),
    "holes circle": (BASE.replace("1.0] }", "1.0] }\nholes = [{ circle = { centre = [1.0, 0.5]"
                                  ', radius = 0.25 }, name = "h" }]'),
                     lambda s: (s.domain.holes[0].names, s.domain.holes[0].sweeps.tolist()),
                     (("h",), [-2 * math.pi])),  # made clockwise
    "holes vertices": (BASE.replace("1.0] }", "1.0] }\nholes = [{ vertices = [[0.5, 0.25], "
                                    "[0.5, 0.75], [1.5, 0.75], [1.5, 0.25]], edges = "
                                    '["a", "b", "c", "d"] }]'),
                       lambda s: s.domain.holes[0].signed_area < 0
                       and set(s.domain.holes[0].names) == set("abcd"), True),
    "outer vertices + arcs": (
        BASE.replace("outer = { rectangle = [0.0, 0.0, 2.0, 1.0] }",
                     "[domain.outer]\nvertices = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]\n"
                     'edges = ["bottom", "arc", "left"]\n'
                     'arcs."1" = { centre = [0.0, 0.0], sweep = 1.5707963267948966 }'),
        lambda s: round(s.domain.area, 4), round(math.pi / 4, 4)),
    "outer clockwise": (
        BASE.replace("outer = { rectangle = [0.0, 0.0, 2.0, 1.0] }",
                     "outer = { vertices = [[0, 0], [0, 1], [1, 1], [1, 0]], "
                     'edges = ["left", "top", "right", "bottom"] }'),
        lambda s: (s.domain.outer.signed_area > 0, s.domain.edges("left")[0].start.tolist()),
        (True, [0.0, 1.0])),  # reversed, names kept: left now runs down
}


@pytest.mark.parametrize("key", SCENE_KEYS)
def test_scene_key_round_trip(tmp_path, key):
    text, get, expected = SCENE_KEYS[key]
    scene = load_scene(write(tmp_path, text))
    assert get(scene) == expected
    d = scene_to_dict(scene)
    assert get(scene_from_dict(d)) == expected
    assert scene_to_dict(scene_from_dict(d)) == d


EFG_VALUES = {  # key: (TOML value, its value in efg_to_dict)
    "zones": ("[{ centre = [1, 2], radius = 0.5, spacing = 0.05 }]",
              [{"centre": [1.0, 2.0], "radius": 0.5, "spacing": 0.05}]),
    "perturb": ("0.2", 0.2), "seed": ("3", 3),
    "coordinates": ("[[0, 0], [1.0, 0.5]]", [[0.0, 0.0], [1.0, 0.5]]),
    "d_max": ("3", 3.0), "weight": ('"gaussian"', "gaussian"), "alpha": ("0.75", 0.75),
    "basis": ('"quadratic"', "quadratic"), "quadrature": ('"triangles"', "triangles"),
    "order": ("3", 3), "refined_order": ("8", 8), "cell_size": ("0.05", 0.05),
    "bc": ('"variational"', "variational"), "penalty": ("50.0", 50.0),
    "solver": ('"direct"', "direct"),
    "crack_rule": ('"transparency"', "transparency"), "rule_power": ("3.0", 3.0),
    "kappa": ("0.25", 0.25), "hole_rule": ('"diffraction"', "diffraction"),
    "rosette": ("{ radius = 0.3, rings = 3, per_ring = 13 }",
                {"radius": 0.3, "rings": 3, "per_ring": 13}),
    "enrichment": ('"full"', "full"), "enrich_radius": ("0.5", 0.5),
    "ramp": ('"linear"', "linear"), "ramp_inner": ("0.05", 0.05), "tip_order": ("10", 10),
}


@pytest.mark.parametrize("key", [k for k in SCHEMA["efg"][2] if k != "spacing"])
def test_efg_key_round_trip(tmp_path, key):
    text, expected = EFG_VALUES[key]
    _, efg = load_study(write(tmp_path, BASE + f"[efg]\nspacing = 0.1\n{key} = {text}\n"))
    d = efg_to_dict(efg)
    assert d[key] == expected and d["spacing"] == 0.1
    default = efg_to_dict(EFG(spacing=0.1))
    assert {k: v for k, v in d.items() if k != key} == {k: v for k, v in default.items()
                                                         if k != key}
    assert efg_to_dict(efg_from_dict(d)) == d


@pytest.mark.parametrize("table", SCHEMA)
def test_schema_is_one_to_one_with_the_dataclasses(table):
    # a field added to a dataclass must be added to the scene file schema, and back
    cls, required, readers = SCHEMA[table]
    fields = {f.name: f for f in dataclasses.fields(cls)}
    assert {k for k, read in readers.items() if read} == set(fields)
    no_default = {k for k, f in fields.items()
                  if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING}
    assert set(required) == no_default


# --- errors -----------------------------------------------------------------------------

@pytest.mark.parametrize("text, match", [
    (BASE.replace("[[supports]]", "[[suports]]"),
     r"unknown key 'suports' in scene file \(top level\); did you mean 'supports'\?"),
    (BASE.replace("nu = 0.3", "nuu = 0.3\nnu = 0.3"),
     r"unknown key 'nuu' in table 'material'; did you mean 'nu'\?"),
    (BASE.replace("uy = 0.0", "uxx = 0.0"),
     r"unknown key 'uxx' in table 'supports\[0\]'; did you mean 'ux'\?"),
    (BASE + "[efg]\nspacng = 0.1\n", r"unknown key 'spacng' in table 'efg'; did you mean"),
    (BASE.replace("1.0] }", "1.0], edgez = [] }"),
     r"unknown key 'edgez' in table 'domain.outer'; did you mean 'edges'\?"),
    (BASE.replace("nu = 0.3", "nu = 0.3\nzzz = 1"),
     r"unknown key 'zzz' in table 'material'; valid keys: E, nu, plane, rho"),
], ids=["top", "material", "support", "efg", "outer", "no-suggestion"])
def test_unknown_key_names_table_and_suggestion(tmp_path, text, match):
    with pytest.raises(ValueError, match=match):
        load_scene(write(tmp_path, text))


@pytest.mark.parametrize("old, new, where", [
    ("E = 1000.0", "E = nan", "material.E"),
    ("ux = 0.0", "ux = inf", r"supports\[0\].ux"),
    ("2.0, 1.0]", "2.0, -inf]", r"domain.outer.rectangle\[3\]"),
    ("uy = 0.0", 'uy = { field = "williams", KI = nan }', r"supports\[0\].uy.KI"),
])
def test_nan_or_inf_names_the_key(tmp_path, old, new, where):
    with pytest.raises(ValueError, match=f"{where} = .*must be finite"):
        load_scene(write(tmp_path, BASE.replace(old, new)))


def test_nan_in_efg(tmp_path):
    with pytest.raises(ValueError, match="efg.d_max = nan"):
        load_study(write(tmp_path, BASE + "[efg]\nspacing = 0.1\nd_max = nan\n"))


def test_missing_keys(tmp_path):
    no_material = BASE.replace("[material]\nE = 1000.0\nnu = 0.3\n", "")
    with pytest.raises(ValueError, match=r"missing required key 'material' in scene file"):
        load_scene(write(tmp_path, no_material))
    with pytest.raises(ValueError, match=r"missing required key 'nu' in table 'material'"):
        load_scene(write(tmp_path, BASE.replace("nu = 0.3", "")))
    with pytest.raises(ValueError, match=r"missing required key 'efg'"):
        load_study(write(tmp_path, BASE))
    with pytest.raises(ValueError, match=r"missing required key 'field' in table 'exact'"):
        load_scene(write(tmp_path, BASE + "[exact]\na = 1.0\n"))
    with pytest.raises(ValueError, match="exactly one of the keys 'vertices', 'rectangle'"):
        load_scene(write(tmp_path, BASE.replace("rectangle = [0.0, 0.0, 2.0, 1.0]",
                                                'edges = ["a"]')))


def test_dataclass_errors_propagate_with_file_path(tmp_path):
    path = write(tmp_path, BASE.replace('edge = "left"', 'edge = "lft"'))
    with pytest.raises(ValueError, match=r"s\.toml: .*'lft'.*no such edge.*'left'"):
        load_scene(path)
    with pytest.raises(ValueError, match=r"material: plane must be one of \('strain', 'stress'\)"):
        load_scene(write(tmp_path, BASE.replace("nu = 0.3", 'nu = 0.3\nplane = "strian"')))
    with pytest.raises(ValueError, match=r"material: nu must lie in \[0, 0.5\)"):
        load_scene(write(tmp_path, BASE.replace("nu = 0.3", "nu = 0.7")))
    with pytest.raises(ValueError, match=r"efg: weight must be one of"):
        load_study(write(tmp_path, BASE + '[efg]\nspacing = 0.1\nweight = "quartc"\n'))
    with pytest.raises(ValueError, match=r"supports\[0\].ux: field 'kirsch' has no parameter 'r'"):
        load_scene(write(tmp_path, BASE.replace("ux = 0.0", 'ux = { field = "kirsch", r = 1 }')))
    with pytest.raises(ValueError, match=r"tractions\[0\].t: unknown field 'kirsh'"):
        load_scene(write(tmp_path, BASE + '[[tractions]]\nedge = "top"\nt = { field = "kirsh" }'))


@pytest.mark.parametrize("old, new, error, match", [
    ("E = 1000.0", 'E = "big"', TypeError, r"material.E must be a number, got 'big'"),
    ("ux = 0.0", "ux = [0.0]", TypeError, r"supports\[0\].ux must be a number"),
    ('edge = "left"', "edge = 3", TypeError, r"supports\[0\].edge must be a string"),
    ("[[supports]]", "[supports]", TypeError, r"supports must be an array of tables"),
    ("2.0, 1.0]", "2.0]", ValueError, r"domain.outer.rectangle must have 4 entries"),
    ("2.0, 1.0]", "2.0, 1.0], edges = [1, 2, 3, 4]", TypeError, r"domain.outer.edges\[0\]"),
])
def test_type_errors_name_the_key(tmp_path, old, new, error, match):
    with pytest.raises(error, match=match):
        load_scene(write(tmp_path, BASE.replace(old, new)))


def test_bad_arcs_and_tips(tmp_path):
    tri = BASE.replace("outer = { rectangle = [0.0, 0.0, 2.0, 1.0] }",
                       "outer = { vertices = [[0, 0], [1, 0], [0, 1]], edges = "
                       '["bottom", "arc", "left"], arcs = { 3 = { centre = [0, 0], sweep = 1 } } }')
    with pytest.raises(ValueError, match=r"key '3' is not an edge index.*edges 0 to 2"):
        load_scene(write(tmp_path, tri))
    wrong = tri.replace("3 = {", "1 = {")  # sweep 1 rad does not reach the end vertex
    with pytest.raises(ValueError, match=r"domain.outer: arc edge 1 \('arc'\).*disagree"):
        load_scene(write(tmp_path, wrong))
    with pytest.raises(TypeError, match=r"cracks\[0\].tips\[1\] must be true or false"):
        load_scene(write(tmp_path, BASE + "[[cracks]]\nvertices = [[0.5, 0.5], [1, 0.5]]\n"
                                          "tips = [true, 1]\n"))
    with pytest.raises(TypeError, match=r"efg.order must be an integer, got 4.0"):
        load_study(write(tmp_path, BASE + "[efg]\nspacing = 0.1\norder = 4.0\n"))


def test_load_scene_checks_efg_and_bad_toml(tmp_path):
    with pytest.raises(ValueError, match=r"efg: spacing must be finite and > 0"):
        load_scene(write(tmp_path, BASE + "[efg]\nspacing = -1.0\n"))
    with pytest.raises(ValueError, match=r"s\.toml: not a valid TOML file"):
        load_scene(write(tmp_path, BASE + "E = = 3\n"))


def test_to_dict_rejects_callables():
    scene = scene_from_dict({"material": {"E": 1.0, "nu": 0.3},
                             "domain": {"outer": {"rectangle": [0, 0, 1, 1]}}})
    scene = scene.with_supports([Support("left", ux=lambda x: 0 * x[:, 0])])
    with pytest.raises(TypeError, match=r"supports\[0\].ux is a Python callable"):
        scene_to_dict(scene)


# --- the reference in docs/scenes.md stays true ------------------------------------------

DOC = Path(__file__).parents[1] / "docs" / "scenes.md"


def _blocks(lang):
    return re.findall(rf"```{lang}\n(.*?)```", DOC.read_text(), flags=re.S)


def test_doc_shows_the_kirsch_file_and_its_python_equivalent():
    path = EXAMPLES[0].parent / "kirsch.toml"
    assert path.read_text() in _blocks("toml")
    (code,) = [b for b in _blocks("python") if "Scene(" in b]
    ns = {}
    exec(code, ns)
    scene, efg = load_study(path)
    assert scene_to_dict(ns["scene"]) == scene_to_dict(scene)
    assert efg_to_dict(ns["efg"]) == efg_to_dict(efg)


@pytest.mark.parametrize("table", SCHEMA)
def test_doc_documents_every_key(table):
    text = DOC.read_text()
    for key in SCHEMA[table][2]:
        assert f"`{key}`" in text, f"docs/scenes.md does not document {table}.{key}"
