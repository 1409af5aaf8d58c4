"""efgkit.cli: ``efgkit run`` and ``efgkit verify`` through ``main(argv)``."""

import json
import re
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402

from efgkit.cli import main  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PATCH = ROOT / "examples" / "patch.toml"
KEYS = {"scene", "method", "n_nodes", "n_dofs", "timings", "outputs", "energy", "errors",
        "solver", "tips"}


def test_run_json_report(tmp_path, capsys):
    rc = main(["run", str(PATCH), "--out", str(tmp_path), "--json", "--samples", "2000"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    rep = json.loads(out)  # exactly one JSON object on stdout
    assert KEYS <= set(rep)
    name = rep["scene"]
    assert sorted(Path(p).name for p in rep["outputs"]) == sorted(
        [f"{name}.vtu", f"{name}_nodes.vtu", f"{name}_nodes.png", f"{name}_stress.png"])
    assert all(Path(p).parent == tmp_path and Path(p).stat().st_size > 0 for p in rep["outputs"])
    assert rep["n_nodes"] > 0 and rep["n_dofs"] >= 2 * rep["n_nodes"]
    assert "coordinates" not in rep["method"] and rep["method"]["spacing"] > 0
    t = rep["timings"]
    assert {"load", "solve", "vtu", "figures", "total"} <= set(t)
    assert all(isinstance(v, float) and v >= 0 for v in t.values())
    assert t["total"] >= t["solve"]
    assert rep["energy"] > 0
    assert rep["errors"] is None or {"l2", "energy"} <= set(rep["errors"])
    assert "solver" in rep["solver"] and "residual" in rep["solver"]
    assert rep["tips"] == []


def test_run_crack_scene_reports_tips(tmp_path, capsys):
    rc = main(["run", str(ROOT / "examples" / "edge_crack.toml"), "--out", str(tmp_path), "--json",
               "--samples", "2000"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    rep = json.loads(out)
    (tip,) = rep["tips"]
    assert {"id", "x", "y", "KI", "KII", "J", "T", "spread", "domains", "warnings"} <= set(tip)
    assert (tip["id"], tip["x"], tip["y"]) == ("edge:1", 3.5, 8.0)
    # seed 003 Sect. 5.6.2 (Wilson 1969): K_I = 34.0, K_II = 4.55
    assert abs(tip["KI"] / 34.0 - 1) < 0.01 and abs(tip["KII"] / 4.55 - 1) < 0.01
    assert len(tip["domains"]) >= 3
    # extrinsic MLS scene: the enrichment coefficients are reported, under a name that says
    # what they are and with a note, never as a K
    coeff = tip["enrichment_coefficients"]
    assert {"KI", "KII", "note"} <= set(coeff) and "not stress intensity factors" in coeff["note"]
    assert not any("enriched" in k for k in tip)
    assert any(Path(p).name == "edge_crack_sif.png" for p in rep["outputs"])
    main(["run", str(ROOT / "examples" / "edge_crack.toml"), "--out", str(tmp_path),
          "--samples", "2000"])
    out = capsys.readouterr()[0]
    assert "edge:1 at (3.5, 8): K_I 34.0" in out
    assert "extrinsic" not in out and "enrich" not in out


def test_run_text_summary_default_out_dir(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["run", str(PATCH), "--samples", "1000"]) == 0
    out = capsys.readouterr().out
    (sub,) = (tmp_path / "out").iterdir()  # out/<scene name>
    assert len(list(sub.glob("*.vtu"))) == 2 and len(list(sub.glob("*.png"))) == 2
    for word in ("scene", "nodes", "dofs", "solver", "energy", "timings", "wrote"):
        assert word in out
    assert f"{sub.name}_stress.png" in out


def _assert_one_line_error(capsys, *fragments):
    out, err = capsys.readouterr()
    assert out == ""
    assert err.startswith("efgkit: error:") and err.count("\n") == 1
    assert "Traceback" not in err
    for f in fragments:
        assert f in err
    return err


def test_run_missing_file(tmp_path, capsys):
    missing = tmp_path / "nowhere.toml"
    assert main(["run", str(missing)]) == 2
    _assert_one_line_error(capsys, "nowhere.toml", "not found")


def test_run_bad_scene_file(tmp_path, capsys):
    bad = tmp_path / "broken.toml"
    bad.write_text("[domain\nthis is = not toml\n")
    assert main(["run", str(bad), "--out", str(tmp_path / "o")]) == 2
    _assert_one_line_error(capsys, "broken.toml")
    assert not (tmp_path / "o").exists()


def test_run_unsolvable_scene(tmp_path, capsys):
    # the patch scene without its supports: rigid-body modes, reported, not a traceback
    free = tmp_path / "free.toml"
    free.write_text(re.sub(r"\[\[supports\]\][^\[]*", "", PATCH.read_text()))
    assert main(["run", str(free), "--out", str(tmp_path / "o")]) == 2
    _assert_one_line_error(capsys, "free.toml", "cannot solve")


def _patch_variant(tmp_path, name, edit):
    f = tmp_path / name
    f.write_text(edit(PATCH.read_text()))
    return f


def test_run_unknown_key(tmp_path, capsys):
    bad = _patch_variant(tmp_path, "typo.toml", lambda t: t.replace("[[supports]]", "[[suports]]"))
    assert main(["run", str(bad), "--out", str(tmp_path / "o")]) == 2
    _assert_one_line_error(capsys, "typo.toml", "'suports'", "did you mean 'supports'")


def test_run_tiny_crack(tmp_path, capsys):
    # a crack 1e-12 long: refused by the scene (shorter than 1e-9 of the domain size)
    crack = ('[[cracks]]\nname = "c"\nvertices = [[0.5, 0.5], [0.500000000001, 0.5]]\n'
             'tips = [true, true]\n\n[efg]')
    tiny = _patch_variant(tmp_path, "tiny.toml", lambda t: t.replace("[efg]", crack))
    assert main(["run", str(tiny), "--out", str(tmp_path / "o")]) == 2
    _assert_one_line_error(capsys, "tiny.toml", "crack 'c' is 1e-12 long", "remove it")


@pytest.mark.filterwarnings("default::RuntimeWarning")  # as outside pytest: numpy's overflow
def test_run_overflowing_traction_is_refused(tmp_path, capsys):
    huge = _patch_variant(tmp_path, "huge.toml", lambda t: t.replace("t = [1.0, 0.0]",
                                                                     "t = [1e300, 0.0]"))
    assert main(["run", str(huge), "--out", str(tmp_path / "o")]) == 2  # refused as input
    _assert_one_line_error(capsys, "huge.toml", "rescale")
    assert not (tmp_path / "o").exists()


def test_run_too_large_is_refused_before_allocating(tmp_path, capsys):
    big = _patch_variant(tmp_path, "big.toml", lambda t: t.replace("spacing = 0.1",
                                                                   "spacing = 1e-5"))
    assert main(["run", str(big), "--out", str(tmp_path / "o")]) == 2
    _assert_one_line_error(capsys, "big.toml", "cannot solve", "spacing = 1e-05", "nodes",
                           "quadrature points", "GB", "available", "coarser")


@pytest.fixture
def no_solve(monkeypatch):
    """Fail the test if ``efgkit run`` reaches the solve."""
    import efgkit.static

    def solve(*args, **kwargs):
        raise AssertionError("the solve was reached")

    monkeypatch.setattr(efgkit.static, "solve", solve)


def test_out_an_existing_file_is_refused_before_the_solve(tmp_path, capsys, no_solve):
    f = tmp_path / "taken"
    f.write_text("mine")
    assert main(["run", str(PATCH), "--out", str(f)]) == 2
    _assert_one_line_error(capsys, "--out", "taken", "existing file, not a directory")
    assert main(["run", str(PATCH), "--out", str(f / "sub")]) == 2
    _assert_one_line_error(capsys, "--out", "cannot be created", "is a file")
    assert f.read_text() == "mine"


def test_scene_argument_a_directory(tmp_path, capsys):
    assert main(["run", str(tmp_path)]) == 2
    _assert_one_line_error(capsys, "is not a file")


@pytest.mark.parametrize("where", ["before", "after"])
def test_debug_shows_the_traceback(tmp_path, capsys, where):
    argv = ["run", str(tmp_path / "nowhere.toml")]
    argv = ["--debug", *argv] if where == "before" else [*argv, "--debug"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("Traceback") and "CLIError" in err
    assert err.splitlines()[-1].startswith("efgkit: error: scene file")


def test_debug_shows_the_cause(tmp_path, capsys):
    free = _patch_variant(tmp_path, "free.toml", lambda t: re.sub(r"\[\[supports\]\][^\[]*", "", t))
    assert main(["--debug", "run", str(free), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "RigidBodyModeError" in err and "direct cause" in err
    assert err.splitlines()[-1].startswith("efgkit: error:")


def test_warnings_are_one_line_each(tmp_path, capsys):
    soft = _patch_variant(tmp_path, "nu.toml", lambda t: t.replace("nu = 0.3", "nu = 0.495"))
    assert main(["run", str(soft), "--out", str(tmp_path / "o"), "--samples", "1000"]) == 0
    err = capsys.readouterr().err
    assert err.startswith("efgkit: warning: ") and "0.495" in err and err.count("\n") == 1


def test_help_documents_the_exit_status(capsys):
    assert main(["run", "--help"]) == 0
    out = capsys.readouterr().out
    assert "exit status" in out and "--debug" in out
    assert "1  the computation failed" in out and "2  the input was refused" in out


@pytest.mark.parametrize("argv", [[], ["run"], ["bogus"], ["run", "x.toml", "--samples", "5"]])
def test_usage_errors_return_2(argv, capsys):
    assert main(argv) == 2
    assert "usage" in capsys.readouterr().err


SCRIPTS = {
    # passes only in quick mode: checks that --quick reaches main()
    "good": "import warnings\n"
            "def main(quick=False):\n"
            "    warnings.warn('careful')\n"
            "    return {'name': 'good', 'passed': quick, 'metrics': {}, 'reference': {},\n"
            "            'checks': [{'what': 'q', 'passed': quick}]}\n",
    "bad": "def main(quick=False):\n"
           "    return {'name': 'bad', 'passed': False, 'metrics': {}, 'reference': {}}\n",
    "crash": "def main(quick=False):\n    raise RuntimeError('boom')\n",
    "_helper": "X = 1\n",
}


@pytest.fixture
def verification_dir(tmp_path, monkeypatch):
    d = tmp_path / "verification"
    d.mkdir()
    for name, text in SCRIPTS.items():
        (d / f"{name}.py").write_text(text)
    monkeypatch.chdir(tmp_path)
    return d


def test_verify_list(verification_dir, capsys):
    assert main(["verify", "--list"]) == 0
    assert capsys.readouterr().out.split() == ["bad", "crash", "good"]


def test_verify_pass_and_fail(verification_dir, capsys):
    assert main(["verify", "good", "--quick"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("PASS  good") and out.count("\n") == 1
    assert "1/1 checks (1 warning: UserWarning)" in out
    assert main(["verify", "good"]) == 1
    assert capsys.readouterr().out.startswith("FAIL  good")


def test_verify_all_reports_every_script(verification_dir, capsys):
    assert main(["verify", "--quick"]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert [ln.split()[:2] for ln in lines] == [["FAIL", "bad"], ["FAIL", "crash"],
                                                ["PASS", "good"]]
    assert "RuntimeError: boom" in lines[1]


def test_verify_unknown_name_lists_available(verification_dir, capsys):
    assert main(["verify", "good", "nope"]) == 2
    _assert_one_line_error(capsys, "'nope'", "bad, crash, good")


def test_verify_falls_back_to_the_repository(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # no ./verification here
    assert main(["verify", "--list"]) == 0
    names = capsys.readouterr().out.split()
    assert names == sorted(p.stem for p in (ROOT / "verification").glob("[!_]*.py"))


def test_python_dash_m(tmp_path):
    r = subprocess.run([sys.executable, "-m", "efgkit", "run", str(tmp_path / "none.toml")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "none.toml" in r.stderr and "Traceback" not in r.stderr


def test_run_summary_reports_cg_iterations_and_uzawa_steps(tmp_path, capsys):
    """With solver="amg" the summary line says how the answer was reached (issue [perf]:
    iterations reported): CG iterations and, for Lagrange multipliers, the Uzawa steps."""
    scene = tmp_path / "patch_amg.toml"
    scene.write_text(PATCH.read_text() + 'solver = "amg"\n')
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--samples", "200"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("solver"))
    assert re.fullmatch(r"solver    amg, residual \S+, \d+ CG iterations in [12] Uzawa steps", line), line
