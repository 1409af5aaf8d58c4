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
    assert len(tip["domains"]) >= 3 and "KI_enriched" in tip  # extrinsic MLS scene
    assert any(Path(p).name == "edge_crack_sif.png" for p in rep["outputs"])
    main(["run", str(ROOT / "examples" / "edge_crack.toml"), "--out", str(tmp_path),
          "--samples", "2000"])
    assert "edge:1 at (3.5, 8): K_I 34.0" in capsys.readouterr()[0]


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
