"""The benchmark scripts run (smoke test, quick sizes); timings are not asserted here."""

import importlib.util
from pathlib import Path

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def test_core_benchmark_quick_runs():
    spec = importlib.util.spec_from_file_location("bench_core", BENCH / "core.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.main(["--quick", "--repeat", "1", "--no-write"])
    assert res["mls"][0]["n_points"] > 0 and res["end_to_end"]["solver"]["residual"] < 1e-8
