"""The benchmark scripts run (smoke test, quick sizes); timings are not asserted here."""

import importlib.util
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def test_core_benchmark_quick_runs():
    spec = importlib.util.spec_from_file_location("bench_core", BENCH / "core.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.main(["--quick", "--repeat", "1", "--no-write"])
    assert res["mls"][0]["n_points"] > 0 and res["end_to_end"]["solver"]["residual"] < 1e-8
    # the prescribed Williams field has K_I = 1 (seed 003 Sect. 5.6.1); 41 x 41 nodes, linear
    # basis: measured K_I - 1 = +5.1e-3
    assert abs(res["sif"]["KI_3"] - 1.0) < 0.015 and "`sifs`, 17 radii" in mod.markdown(res, "cmd")


def test_work_precision_quick_runs_and_reports_every_curve():
    spec = importlib.util.spec_from_file_location("bench_wp", BENCH / "work_precision.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.main(["--quick", "--repeat", "1", "--no-write"])
    for problem, r in res["problems"].items():
        assert set(r["curves"]) == {f"EFG {v}" for v in mod.VARIANTS} | {
            f"MLPG {v}" for v in mod.MLPG_VARIANTS} | {
            "FEM P2 graded, quarter-point", "FEM P2 uniform"}, problem
        for pts in r["curves"].values():
            assert all(p["error"] >= 0 and p["seconds"] > 0 for p in pts if "error" in p)
        # the prescribed Williams field has K_I = 1 (seed 003 Sect. 5.6.1); SENT: J of a finer mesh
        assert r["reference"] == 1.0 if problem == "singular patch" else r["reference"] > 0
        # graded quarter-point P2 reaches 0.1 % on both problems even at quick sizes
        # (measured: K_I error 2e-4 at 3.6k DOFs, J error 2e-5 at 11k DOFs)
        assert r["time_to_target"]["FEM P2 graded, quarter-point"]["seconds"] is not None
    md = mod.markdown(res, "cmd")
    assert "## SENT" in md and "Time to 0.1 % error" in md


@pytest.mark.slow
def test_work_precision_mlpg_quick_runs():
    spec = importlib.util.spec_from_file_location("bench_wp", BENCH / "work_precision.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.main(["--mlpg", "--quick", "--repeat", "1", "--no-write"])
    for r in res["problems"].values():
        assert set(r["curves"]) == {"EFG extrinsic MLS", "FEM P2 graded, quarter-point"} | {
            f"MLPG {v}" for v in mod.MLPG_VARIANTS}


def test_work_precision_mlpg_section(tmp_path):
    spec = importlib.util.spec_from_file_location("bench_wp", BENCH / "work_precision.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    pt = {"h": 1.0, "n_dofs": 10, "seconds": 1.0, "error": 1e-2}
    curves = {"EFG extrinsic MLS": [{**pt, "error": 1e-4}],
              "MLPG extrinsic MLS": [{**pt, "seconds": 2.0}, {**pt, "seconds": 8.0, "error": 1e-4}],
              "FEM P2 graded, quarter-point": [pt, {**pt, "seconds": 4.0, "error": 1e-4}]}
    r = mod.summarise(curves)
    res = {"machine": "m", "date": "d", "repeat": 1, "problems": {"SENT": {"curves": curves, **r}}}
    text = mod.mlpg_section(res, "cmd")
    assert text.startswith("<!-- begin:mlpg_work_precision -->") and "| MLPG extrinsic MLS | h = 1 |" in text
    # 0.1 % lies midway (log-log) between 1e-2 and 1e-4: MLPG 4 s, graded P2 2 s
    assert "MLPG extrinsic MLS reaches it, time ratio to graded P2 = 2.00" in text
    page = tmp_path / "performance.md"
    a, b = "<!-- begin:mlpg_work_precision -->", "<!-- end:mlpg_work_precision -->"
    page.write_text(f"intro\n{a}\nold\n{b}\ntail\n")
    _load("doc_sections").write_section(text, page)
    new = page.read_text()
    assert new.startswith("intro\n") and new.endswith("tail\n") and "old" not in new
    assert new.count("<!-- begin:mlpg_work_precision -->") == 1


def test_time_to_target_interpolates_in_log_log():
    spec = importlib.util.spec_from_file_location("bench_wp", BENCH / "work_precision.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    pts = [{"n_dofs": 10, "seconds": 1.0, "error": 1e-2}, {"n_dofs": 40, "seconds": 100.0, "error": 1e-4}]
    assert mod.time_to(pts)["seconds"] == pytest.approx(10.0)  # midway in log error and log time
    assert mod.time_to(pts[1:]) == {"seconds": 100.0, "bound": "<="}
    assert mod.time_to(pts[:1])["bound"] == "not reached"
    # a lucky coarse point below the target does not count when a finer one is above it again
    wobbly = [{"n_dofs": 10, "seconds": 1.0, "error": 1e-4}, {"n_dofs": 40, "seconds": 2.0, "error": 1e-2},
              {"n_dofs": 160, "seconds": 20.0, "error": 1e-4}]
    assert mod.time_to(wobbly)["seconds"] == pytest.approx(2.0 * 10**0.5)
    # refinement order, not time order: a fixed cost can make the coarse point the slowest
    # (MLPG's tip disc rule); the target is reached between it and the next refinement
    fixed = [{"n_dofs": 10, "seconds": 2.0, "error": 1e-2}, {"n_dofs": 40, "seconds": 0.5, "error": 1e-4}]
    assert mod.time_to(fixed)["seconds"] == pytest.approx(1.0)  # 2 * (0.5 / 2)^(1/2)


def _load(name):
    spec = importlib.util.spec_from_file_location(f"bench_{name}", BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_search_benchmark_reproduces_the_layout_of_seed_000_table_1():
    mod = _load("search")
    res = mod.main(["--quick", "--repeat", "1", "--no-write", "--before", ""])
    # seed 000 Table 1: N = 2,411 at dA = 1/10 mm and 9,321 at 1/20 mm
    assert [r["N"] for r in res["rows"]] == [2411, 9321]
    assert all(all(r["same_graph"].values()) for r in res["rows"])
    assert "| 1/20 | 9321 (9321) |" in mod.markdown(res, "cmd")


@pytest.mark.slow
def test_scaling_benchmark_quick_runs():
    mod = _load("scaling")
    res = mod.main(["--quick", "--no-write"])
    # Wilson 1969 (seed 003 Sect. 5.6.2): K_I = 34.0, K_II = 4.55; coarse sizes within 2 %
    for r in res["rows"]:
        assert abs(r["KI"] / 34.0 - 1) < 0.02 and abs(r["KII"] / 4.55 - 1) < 0.02
        assert sum(r["stages_s"].values()) <= r["wall_s"] * 1.05


@pytest.mark.slow
def test_bc_methods_and_uzawa_benchmarks_run():
    """Smoke test of benchmarks/bc_methods.py and benchmarks/uzawa.py at small sizes: every
    method converges with CG and agrees with SuperLU on the same discretisation."""
    bc = _load("bc_methods").main(["--nodes", "1500", "--rounds", "1", "--no-write"])
    for method, runs in bc["runs"].items():
        assert runs[0]["solver"] == "amg" and runs[0]["residual"] <= 1e-8, method
        # K_I of the cracked plate against SuperLU's of the same method: both checked to rtol 1e-8
        assert abs(runs[0]["KI"] / bc["reference"][method]["KI"] - 1) < 1e-6, method
    uz = _load("uzawa").main(["--scene", "kirsch", "--nodes", "2200", "--no-write"])
    assert all(r[0]["vs_direct"] < 1e-6 for r in uz["runs"].values())


@pytest.mark.slow
def test_auto_threshold_benchmark_runs():
    """Smoke test of benchmarks/auto_threshold.py: both choices of bc="auto" solve the small
    cracked plate, SuperLU on the Lagrange system and CG on the Nitsche one, and their K_I
    agree (both consistent: 2.6e-6 apart at this size in tests/test_auto_bc.py)."""
    res = _load("auto_threshold").main(["--nodes", "1500", "--rounds", "1", "--no-write"])
    runs = res["rows"][0]["runs"]
    assert runs["superlu"][0]["solver"] == "direct" and runs["cg"][0]["solver"] == "amg"
    assert abs(runs["cg"][0]["KI"] / runs["superlu"][0]["KI"] - 1) < 1e-5
