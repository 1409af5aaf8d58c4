"""The [dsif] table of a scene file (efgkit.explicit.dsif_table): keys, defaults, errors,
and that `efgkit run` hands them to dynamics() and integrate()."""

import pytest

import efgkit.explicit as explicit
from efgkit.cli import main
from efgkit.explicit import DynamicDSIF
from efgkit.explicit.dsif_table import DSIF_KEYS, DSIFSettings, dsif_from_dict, load_dsif
from efgkit.scenefile import load_scene, scene_from_dict

BAR = """
name = "bar"
[material]
E = 1000.0
nu = 0.0
plane = "stress"
rho = 1.0
[domain]
outer = { rectangle = [0.0, 0.0, 4.0, 0.5] }
[[supports]]
edge = "left"
ux = 0.0
[[tractions]]
edge = "right"
t = [1.0, 0.0]
[time]
duration = 0.02
output_interval = 0.01
[efg]
spacing = 0.5
"""

RECOMMENDED = '[dsif]\nenrichment_mass = "abs_row_sum"\nmass_iterations = 16\n'


def test_keys_map_onto_dynamics_and_the_hook():
    s = dsif_from_dict({"enrichment_mass": "abs_row_sum", "mass_iterations": 16,
                        "decomposition": True})
    assert s.enrichment_mass == "abs_row_sum"
    assert s.dsif.mass_iterations == 16 and s.dsif.decomposition is True
    assert set(DSIF_KEYS) == {"enrichment_mass", "mass_iterations", "decomposition", "q", "face_fit"}
    s = dsif_from_dict({"q": "plateau_fit", "face_fit": False})
    assert (s.dsif.q, s.dsif.face_fit) == ("plateau_fit", False)


def test_defaults_are_those_of_python():
    # an empty table and no table give what dynamics() and DynamicDSIF() default to
    d = DynamicDSIF()
    for s in (dsif_from_dict({}), DSIFSettings()):
        assert s.enrichment_mass == "diagonal"
        assert (s.dsif.mass_iterations, s.dsif.decomposition) == (d.mass_iterations, d.decomposition)
        assert (s.dsif.radii, s.dsif.q, s.dsif.inertia, s.dsif.face_terms, s.dsif.domains,
                s.dsif.face_fit) == (d.radii, d.q, d.inertia, d.face_terms, d.domains, d.face_fit)


@pytest.mark.parametrize("table, err, match", [
    ({"mass_iteration": 16}, ValueError,
     r"unknown key 'mass_iteration' in table 'dsif'; did you mean 'mass_iterations'\?"),
    ({"enrichment_masses": "abs_row_sum"}, ValueError, "did you mean 'enrichment_mass'"),
    ({"decompose": True}, ValueError, "did you mean 'decomposition'"),
    ({"enrichment_mass": "row_sum"}, ValueError,
     r"dsif.enrichment_mass = 'row_sum'; expected one of 'diagonal', 'abs_row_sum'"),
    ({"enrichment_mass": 1}, TypeError, "dsif.enrichment_mass must be a string"),
    ({"mass_iterations": 16.0}, TypeError, r"dsif.mass_iterations must be an integer in 0..100, got 16.0"),
    ({"mass_iterations": True}, TypeError, "dsif.mass_iterations must be an integer"),
    ({"mass_iterations": 101}, ValueError,
     r"dsif.mass_iterations: mass_iterations must be an integer in 0..100"),
    ({"mass_iterations": -1}, ValueError, r"in 0..100 .*got -1"),
    ({"decomposition": 1}, TypeError, "dsif.decomposition must be true or false, got 1"),
    ({"face_fit": "yes"}, TypeError, "dsif.face_fit must be true or false, got 'yes'"),
    ({"q": "power"}, ValueError, r"dsif.q = 'power'; expected one of .*'plateau_fit'"),
    ([1, 2], TypeError, r"dsif must be a table \[dsif\]"),
])
def test_error_messages(table, err, match):
    with pytest.raises(err, match=match):
        dsif_from_dict(table)


def test_settings_validate_in_python():
    with pytest.raises(ValueError, match="enrichment_mass must be one of 'diagonal', 'abs_row_sum'"):
        DSIFSettings("consistent")
    with pytest.raises(TypeError, match="dsif must be a DynamicDSIF, got int"):
        DSIFSettings("diagonal", 4)


def test_load_dsif_reads_the_file(tmp_path):
    path = tmp_path / "bar.toml"
    path.write_text(BAR + RECOMMENDED)
    s = load_dsif(path)
    assert (s.enrichment_mass, s.dsif.mass_iterations) == ("abs_row_sum", 16)
    assert load_scene(path).duration == 0.02  # the scene reader accepts the table
    path.write_text(BAR)
    assert load_dsif(path) == DSIFSettings()
    path.write_text(BAR + "[dsif]\nmass_iterations = 200\n")
    with pytest.raises(ValueError, match=r"bar.toml: dsif.mass_iterations: .*got 200"):
        load_dsif(path)


def test_static_scene_refuses_the_table(tmp_path):
    static = BAR.replace("[time]\nduration = 0.02\noutput_interval = 0.01\n", "")
    path = tmp_path / "static.toml"
    path.write_text(static + RECOMMENDED)
    with pytest.raises(ValueError, match=r"static.toml: a \[dsif\] table .*add a \[time\] table or "
                                         r"remove \[dsif\]"):
        load_dsif(path)
    with pytest.raises(ValueError, match=r"this scene is static: add a \[time\] table"):
        load_scene(path)
    import tomllib

    with pytest.raises(ValueError, match=r"a \[dsif\] table"):
        scene_from_dict(tomllib.loads(static + RECOMMENDED))


def test_cli_hands_the_settings_to_the_run(tmp_path, monkeypatch, capsys):
    seen = {}
    dynamics, integrate = explicit.dynamics, explicit.integrate

    def spy_dynamics(scene, method, disc=None, enrichment_mass="diagonal"):
        seen["enrichment_mass"] = enrichment_mass
        return dynamics(scene, method, disc, enrichment_mass)

    def spy_integrate(*args, **kw):
        seen["dsif"] = kw["dsif"]
        return integrate(*args, **kw)

    monkeypatch.setattr(explicit, "dynamics", spy_dynamics)
    monkeypatch.setattr(explicit, "integrate", spy_integrate)
    path = tmp_path / "bar.toml"
    path.write_text(BAR + RECOMMENDED + "decomposition = true\n")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    assert seen["enrichment_mass"] == "abs_row_sum"
    assert (seen["dsif"].mass_iterations, seen["dsif"].decomposition) == (16, True)
    path.write_text(BAR + "[dsif]\nenrichment_mass = \"lumped\"\n")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    assert "dsif.enrichment_mass = 'lumped'" in capsys.readouterr().err
