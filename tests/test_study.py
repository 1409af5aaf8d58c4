"""efgkit.study: expansion of grid, zip and random studies, dotted paths and their errors, a
study that goes on past a failed point, resumed studies, the table and the dask path."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from efgkit.cli import main  # noqa: E402
from efgkit.study import Parameter, Study, get_path, read_study, run_study, set_path  # noqa: E402
from efgkit.study.table import row_path  # noqa: E402

# A 1 x 2 plate, bottom clamped, pulled on the top, with an edge crack at mid-height: a
# coarse discretisation (47 nodes) that solves in well under a second.
DOC = {"name": "tiny", "material": {"E": 1000.0, "nu": 0.3, "plane": "strain"},
       "domain": {"outer": {"rectangle": [0.0, 0.0, 1.0, 2.0]}},
       "supports": [{"edge": "bottom", "ux": 0.0, "uy": 0.0}],
       "tractions": [{"edge": "top", "t": [0.0, 1.0]}],
       "cracks": [{"name": "c", "vertices": [[0.0, 1.0], [0.4, 1.0]], "tips": [False, True]}],
       "efg": {"spacing": 0.25, "enrichment": "none"}}
TINY_TOML = """name = 'tiny'
[material]
E = 1000.0
nu = 0.3
plane = 'strain'
[domain]
outer = { rectangle = [0.0, 0.0, 1.0, 2.0] }
[[supports]]
edge = 'bottom'
ux = 0.0
uy = 0.0
[[tractions]]
edge = 'top'
t = [0.0, 1.0]
[[cracks]]
name = 'c'
vertices = [[0.0, 1.0], [0.4, 1.0]]
tips = [false, true]
[efg]
spacing = 0.25
enrichment = 'none'
"""  # DOC as a scene file
TIP_X = "cracks.0.vertices.1.0"
# the middle point puts the tip outside the plate (x = 1.5 > 1): the scene refuses it
STUDY = Study(DOC, (Parameter(TIP_X, (0.3, 1.5, 0.5), name="a"),), combine="zip", name="tiny",
              error_estimate=False)


def test_grid_zip_random_expansion():
    p, q = Parameter("material.nu", (0.2, 0.3)), Parameter("efg.spacing", (0.5, 0.25, 0.2))
    grid = Study(DOC, (p, q)).points()
    assert [tuple(x.params.values()) for x in grid] == [
        (a, b) for a in (0.2, 0.3) for b in (0.5, 0.25, 0.2)]  # the last varies fastest
    assert all(x.doc["material"]["nu"] == x.params["material.nu"]
               and x.doc["efg"]["spacing"] == x.params["efg.spacing"] for x in grid)
    assert len({x.key for x in grid}) == 6
    zipped = Study(DOC, (p, Parameter("material.E", (1.0, 2.0))), combine="zip").points()
    assert [tuple(x.params.values()) for x in zipped] == [(0.2, 1.0), (0.3, 2.0)]
    rand = Study(DOC, (Parameter("material.E", low=1.0, high=2.0),
                       Parameter("efg.enrichment", ("none", "pu"))),
                 combine="random", samples=50, seed=7)
    vals = np.array([x.params["material.E"] for x in rand.points()])
    assert len(vals) == 50 and np.all((vals >= 1.0) & (vals < 2.0))
    # the same draws as numpy's generator makes from the seed: E first, then the choices
    rng = np.random.default_rng(7)
    assert np.array_equal(vals, rng.uniform(1.0, 2.0, 50))
    assert [x.params["efg.enrichment"] for x in rand.points()] == [
        ("none", "pu")[i] for i in rng.integers(0, 2, 50)]
    assert [x.key for x in rand.points()] == [x.key for x in rand.points()]  # stable
    other = Study(DOC, rand.parameters, combine="random", samples=50, seed=8).points()
    assert [x.params for x in other] != [x.params for x in rand.points()]
    lin = Parameter.linspace("material.E", 1.0, 2.0, 5)
    assert lin.values == (1.0, 1.25, 1.5, 1.75, 2.0)


def test_keys_follow_the_document_not_the_order_of_parameters():
    a = Study(DOC, (Parameter("material.nu", (0.2,)), Parameter("material.E", (5.0,))))
    b = Study(DOC, (Parameter("material.E", (5.0,)), Parameter("material.nu", (0.2,))))
    assert a.points()[0].key == b.points()[0].key
    changed = {**DOC, "tractions": [{"edge": "top", "t": [0.0, 2.0]}]}
    assert Study(changed, a.parameters).points()[0].key != a.points()[0].key
    assert len(Study(DOC, (Parameter("material.nu", (0.2, 0.2)),)).points()) == 1  # one key


def test_dotted_paths():
    assert get_path(DOC, TIP_X) == 0.4
    assert get_path(DOC, "method.spacing") == 0.25  # method stands for [efg]
    new = set_path(DOC, TIP_X, 0.7)
    assert new["cracks"][0]["vertices"] == [[0.0, 1.0], [0.7, 1.0]]
    assert DOC["cracks"][0]["vertices"][1][0] == 0.4  # the base is not touched


@pytest.mark.parametrize("path, match", [
    ("material.EE", r"study parameter 'material.EE': the scene has no key 'EE' in table "
                    r"'material' \(its keys: E, nu, plane\); did you mean 'E'\? To vary a key"),
    ("efg.d_max", r"no key 'd_max' in table 'efg'.*write it in the base scene file"),
    ("matrial.E", r"no key 'matrial' in the top level .*did you mean 'material'"),
    ("cracks.1.vertices", r"'cracks.1.vertices': index 1 is past the end of 'cracks', which "
                          r"has 1 entries \(indices 0 to 0\)"),
    ("cracks.first", r"'cracks.first': 'cracks' is an array; 'first' must be an index 0 to 0"),
    ("material.E.x", r"'material.E' is the value 1000.0, which has no part 'x'"),
    ("material..E", r"empty part in the dotted path"),
])
def test_dotted_path_errors_name_the_path(path, match):
    with pytest.raises(ValueError, match=match):
        set_path(DOC, path, 1.0)
    with pytest.raises(ValueError, match=match):  # and a study refuses it before running
        Study(DOC, (Parameter(path, (1.0,)),))


def test_method_path_needs_a_method_table():
    with pytest.raises(ValueError, match="'method' stands for the scene's method table"):
        get_path({"material": {}}, "method.spacing")
    with pytest.raises(TypeError, match="path must be a string"):
        get_path(DOC, 3)


@pytest.mark.parametrize("make, match", [
    (lambda: Study(DOC, (Parameter("material.nu", (0.2, 0.3)), Parameter("material.E", (1.0,))),
                   combine="zip"),
     r"a zip study takes the i-th value.*\{'material.nu': 2, 'material.E': 1\}"),
    (lambda: Study(DOC, (Parameter("material.E", low=1.0, high=2.0),), combine="random",
                   samples=5), "a random study needs seed = an integer >= 0, got None"),
    (lambda: Study(DOC, (Parameter("material.E", low=1.0, high=2.0),)),
     r"give low/high, which only a random study draws from"),
    (lambda: Study(DOC, (Parameter("material.E", (1.0,), name="x"),
                         Parameter("material.nu", (0.2,), name="x"))), "repeat the name"),
    (lambda: Study({k: v for k, v in DOC.items() if k != "efg"}, (Parameter("material.E", (1,)),)),
     r"the base scene has no \[efg\] table"),
    (lambda: Study(DOC, (Parameter("material.E", (1.0,)),), combine="product"),
     "combine must be one of"),
    (lambda: Study(DOC, ()), "a non-empty sequence of Parameter"),
    (lambda: Parameter("material.E"), r"has no values: give values = \[...\]"),
    (lambda: Parameter("material.E", low=1.0), "give both low and high"),
    (lambda: Parameter("material.E", low=2.0, high=1.0), "needs high > low"),
    (lambda: Parameter("material.E", (1.0, float("nan"))), "every value of a study must be finite"),
    (lambda: Parameter("material.E", 1.0), "values must be a sequence"),
])
def test_study_errors(make, match):
    with pytest.raises((ValueError, TypeError), match=match):
        make()


@pytest.fixture(scope="module")
def done(tmp_path_factory):
    """The tiny study run once in this process: its directory and the run."""
    out = tmp_path_factory.mktemp("study")
    return out, run_study(STUDY, out=out, scheduler="synchronous")


def test_a_failed_point_is_recorded_and_the_study_goes_on(done):
    out, run = done
    t = run.table
    assert list(t["status"]) == ["ok", "failed", "ok"]
    assert (run.total, run.computed, run.failed, run.lost) == (3, 3, 1, 0)
    bad = t.iloc[1]
    assert bad["error_type"] == "ValueError"
    assert "lies outside the domain" in bad["error_message"]
    assert np.isnan(bad["KI[c:1]"])
    # K_I grows with the crack (a/W = 0.3 -> 0.5); the numbers themselves are checked
    # against handbook curves in verification/k_calibration.py
    assert 0 < t["KI[c:1]"].iloc[0] < t["KI[c:1]"].iloc[2]
    assert t["n_warnings"].iloc[0] >= 1  # the coarse tip warns (spread), and says so
    row = json.loads(row_path(out, t["key"].iloc[0]).read_text())
    assert row["params"] == {"a": 0.3} and row["status"] == "ok"
    assert {"solve", "sifs", "total"} <= set(row["timings"])


def test_table_written_as_csv_and_parquet(done):
    import pandas as pd

    out, run = done
    csv, parquet = (out / "tiny.csv", out / "tiny.parquet")
    assert {csv, parquet, out / "tiny_a.png"} <= set(run.files)
    back = pd.read_parquet(parquet)
    assert list(back.columns) == list(run.table.columns)
    assert list(back.columns[:3]) == ["key", "status", "a"]
    assert {"x[c:1]", "KI[c:1]", "KII[c:1]", "J[c:1]", "T[c:1]", "spread[c:1]", "error[c:1]",
            "n_dofs", "time_total", "error_message"} <= set(back.columns)
    np.testing.assert_array_equal(back["KI[c:1]"], run.table["KI[c:1]"])
    assert pd.read_csv(csv)["status"].tolist() == ["ok", "failed", "ok"]


def test_rerun_skips_done_points(done, tmp_path):
    out, first = done
    work = tmp_path / "again"
    shutil.copytree(out, work)
    stamps = {p: p.stat().st_mtime_ns for p in (work / "points").glob("*.json")}
    run = run_study(STUDY, out=work, scheduler="synchronous", figures=False)
    assert (run.skipped, run.computed) == (3, 0)  # the failed point is final too
    assert {p: p.stat().st_mtime_ns for p in (work / "points").glob("*.json")} == stamps
    # a lost row (and an unreadable one) is computed again, and only that one
    key = first.table["key"].iloc[2]
    row_path(work, key).unlink()
    row_path(work, first.table["key"].iloc[0]).write_text("{ cut off")
    run = run_study(STUDY, out=work, scheduler="synchronous", figures=False)
    assert (run.skipped, run.computed) == (1, 2)
    np.testing.assert_allclose(run.table["KI[c:1]"], first.table["KI[c:1]"], rtol=1e-12)
    run = run_study(STUDY, out=work, scheduler="synchronous", figures=False, retry_failed=True)
    assert (run.skipped, run.computed, run.failed) == (2, 1, 1)


def test_a_client_that_dies_keeps_the_rows_it_wrote(tmp_path):
    def die_after_first(done, total, failed):
        if done == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_study(STUDY, out=tmp_path, scheduler="synchronous", progress=die_after_first)
    assert len(list((tmp_path / "points").glob("*.json"))) == 1
    assert not list((tmp_path / "points").glob(".*"))  # no half-written file left
    run = run_study(STUDY, out=tmp_path, scheduler="synchronous", figures=False)
    assert (run.skipped, run.computed) == (1, 2)


def test_in_process_dask_cluster_gives_the_same_rows(done, tmp_path):
    _, first = done
    study = Study(DOC, (Parameter(TIP_X, (0.3, 1.5), name="a"),), combine="zip", name="tiny",
                  error_estimate=False)
    run = run_study(study, out=tmp_path, scheduler="inprocess", workers=2, figures=False)
    assert list(run.table["status"]) == ["ok", "failed"] and run.lost == 0
    assert run.table["KI[c:1]"].iloc[0] == first.table["KI[c:1]"].iloc[0]  # same computation


def test_cli_sweep(done, tmp_path, capsys):
    out, _ = done
    (tmp_path / "tiny.toml").write_text(TINY_TOML)
    study = tmp_path / "tiny_study.toml"
    study.write_text("scene = 'tiny.toml'\nname = 'tiny'\ncombine = 'zip'\n"
                     "error_estimate = false\n[[parameters]]\npath = 'cracks.0.vertices.1.0'\n"
                     "name = 'a'\nvalues = [0.3, 1.5, 0.5]\n")
    assert read_study(study).study.points()[0].key == STUDY.points()[0].key  # same document
    work = tmp_path / "out"
    shutil.copytree(out, work)  # every point done: nothing to compute
    rc = main(["sweep", str(study), "--out", str(work), "--scheduler", "synchronous"])
    text, err = capsys.readouterr()
    assert rc == 1 and err == ""  # a failed point: exit 1; no progress line when not a terminal
    assert "points    3: 3 done before, 0 computed" in text
    assert "failed" in text and "lies outside the domain" in text
    assert (work / "tiny.parquet").is_file()
    study.write_text("scene = 'tiny.toml'\n[[parameters]]\npath = 'material.EE'\nvalues = [1.0]\n")
    assert main(["sweep", str(study), "--out", str(work)]) == 2
    assert "study parameter 'material.EE'" in capsys.readouterr().err


@pytest.mark.parametrize("text, match", [
    ("[[parameters]]\npath = 'material.E'\nvalues = [1.0]\n", "missing required key 'scene'"),
    ("scene = 'tiny.toml'\n", "missing required key 'parameters'"),
    ("scene = 'tiny.toml'\nsheduler = 'x'\n", "unknown key 'sheduler'.*did you mean 'scheduler'"),
    ("scene = 'nope.toml'\n[[parameters]]\npath = 'material.E'\nvalues = [1.0]\n",
     "base scene file .*nope.toml' not found"),
    ("scene = 'tiny.toml'\n[[parameters]]\npath = 'material.E'\nstart = 1.0\nstop = 2.0\n",
     r"start, stop and num go together; missing \['num'\]"),
    ("scene = 'tiny.toml'\n[[parameters]]\npath = 'material.E'\nvalues = [1.0]\nlow = 0.0\n",
     "needs exactly one of"),
    ("scene = 'tiny.toml'\nworkers = 0\n[[parameters]]\npath = 'material.E'\nvalues = [1.0]\n",
     "workers must be an integer >= 1, got 0"),
    ("scene = 'tiny.toml'\nseed = 'a'\n[[parameters]]\npath = 'material.E'\nvalues = [1.0]\n",
     "seed must be an integer"),
])
def test_study_file_errors(tmp_path, text, match):
    (tmp_path / "tiny.toml").write_text(TINY_TOML)
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises((ValueError, TypeError), match=match) as err:
        read_study(path)
    assert str(path) in str(err.value)


def test_scheduler_errors():
    with pytest.raises(ValueError, match="neither one of .* nor an address"):
        run_study(STUDY, out="/nonexistent/never", scheduler="syncronous")
    with pytest.raises(ValueError, match="workers must be an integer >= 1, got 0"):
        run_study(STUDY, out="/nonexistent/never", workers=0)


def test_import_does_not_load_dask():
    code = ("import sys, efgkit, efgkit.study; print(sorted(m for m in ('dask', 'distributed', "
            "'pandas', 'pyarrow', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).resolve().parents[1])
    assert out.stdout.strip() == "[]"


@pytest.mark.parametrize("name, tips", [("calibration_sent", ("edge:1",)),
                                        ("calibration_cct", ("centre:0", "centre:1"))])
def test_shipped_study_files(name, tips):
    """The K-calibration studies: 10 crack lengths a = 0.10, 0.15, ..., 0.55 (solved in
    verification/k_calibration.py)."""
    from efgkit.scenefile import scene_from_dict

    sf = read_study(Path(__file__).resolve().parents[1] / "examples" / f"{name}.toml")
    points = sf.study.points()
    assert [p.params["a"] for p in points] == [round(0.1 + 0.05 * k, 2) for k in range(10)]
    for p in (points[0], points[-1]):
        scene = scene_from_dict(p.doc)
        assert tuple(t.id for t in scene.tips) == tips
        assert max(t.x[0] for t in scene.tips) == p.params["a"]


def test_figures_of_a_grid_draw_a_line_per_combination_of_the_others():
    import pandas as pd

    from efgkit.study import plot_study

    study = Study(DOC, (Parameter("material.nu", (0.2, 0.3)),
                        Parameter(TIP_X, (0.3, 0.4, 0.5), name="a")), name="g")
    pts = study.points()
    df = pd.DataFrame({"key": [p.key for p in pts], "status": ["ok"] * 5 + ["failed"],
                       "material.nu": [p.params["material.nu"] for p in pts],
                       "a": [p.params["a"] for p in pts],
                       "KI[c:1]": np.arange(6.0), "KII[c:1]": np.zeros(6)})
    figs = plot_study(df, study)
    assert list(figs) == ["material.nu", "a"]
    (ax,) = figs["a"].axes  # K_II is zero: K_I alone
    assert [len(line.get_xdata()) for line in ax.get_lines()] == [3, 2]  # nu = 0.2, 0.3 (one failed)
    assert "1 failed or missing" in figs["a"].texts[0].get_text()


def test_an_unreachable_scheduler_is_named():
    from efgkit.study import open_client

    # loopback port 9 (discard): nothing listens there on a test machine
    with pytest.raises(ValueError, match=r"cannot reach the dask scheduler 'tcp://127.0.0.1:9'.*"
                                         r"start one"):
        open_client("tcp://127.0.0.1:9", timeout=1.0)


@pytest.mark.slow
def test_a_worker_that_dies_loses_nothing(tmp_path):
    """A local cluster of 2 worker processes; one is killed (SIGKILL) after the first row:
    dask runs its point again on the restarted worker and every point gets its row."""
    import os
    import signal

    from efgkit.study import open_client

    study = Study(DOC, (Parameter(TIP_X, tuple(np.linspace(0.2, 0.6, 8)), name="a"),),
                  name="tiny", error_estimate=False)
    client, cluster = open_client("local", 2)
    killed = []

    def kill_one(done, total, failed):
        if not killed:
            pid = next(iter(client.run(os.getpid).values()))
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    try:
        run = run_study(study, out=tmp_path, scheduler=client, progress=kill_one, figures=False)
    finally:
        client.close()
        cluster.close()
    assert killed and run.lost == 0 and run.ok and run.computed == 8
    # the killed process finished at most the first point; the rest ran elsewhere
    assert sum(w.endswith(f":{killed[0]}") for w in run.table["worker"]) <= 1


def test_a_local_cluster_that_cannot_start_says_why(monkeypatch):
    import distributed

    from efgkit.study import open_client

    def refuse(*args, **kwargs):  # what dask raises when a script lacks the main guard
        raise RuntimeError("Nanny failed to start.")

    monkeypatch.setattr(distributed, "LocalCluster", refuse)
    with pytest.raises(RuntimeError, match=r"did not start \(Nanny failed to start.\); a script "
                                           r"that starts one must do so under `if __name__"):
        open_client("local", 1)


def test_progress_only_on_a_terminal():
    import io

    from efgkit.study import TerminalProgress

    class Tty(io.StringIO):
        def isatty(self):
            return True

    pipe, tty = io.StringIO(), Tty()
    for stream in (pipe, tty):
        progress = TerminalProgress(stream)
        progress(1, 2, 0)
        progress(2, 2, 1)
    assert pipe.getvalue() == ""  # CI logs and pipes stay silent
    lines = tty.getvalue().split("\r")[1:]
    assert lines[0].startswith("sweep: 1/2 points, ") and "s left" in lines[0]
    assert lines[1].startswith("sweep: 2/2 points, 1 failed") and lines[1].endswith("\n")
