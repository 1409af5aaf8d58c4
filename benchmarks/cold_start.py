"""Cold start: the first ``efgkit run`` of the quick-start example after installation,
when numba's cache is empty, against the second run; written to docs/performance.md.

Run:  PYTHONPATH=. python benchmarks/cold_start.py [--scene examples/edge_crack.toml]

Each run is a fresh ``python -m efgkit run SCENE --json`` subprocess timed with
time.perf_counter around it; "cold" runs with NUMBA_CACHE_DIR set to a new empty
directory (nothing compiled yet: what a fresh install sees), "warm" runs again with the
same directory. The run's own ``timings`` say how much of it was numba compilation
(stage "compile": compiling and loading compiled kernels from the cache). The runs take
turns (cold, warm, cold, warm, ...) and medians are reported.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from efgkit.io import write_json

ROOT = Path(__file__).resolve().parents[1]


def one_run(scene: str, cache: str, out: str) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "efgkit", "run", scene, "--json", "--out", out],
                          env=env, capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - t0
    if proc.returncode:
        raise RuntimeError(proc.stderr)
    rep = json.loads(proc.stdout)
    return {"wall_s": wall, "timings": rep["timings"], "n_nodes": rep["n_nodes"]}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="examples/edge_crack.toml")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    runs = {"cold": [], "warm": []}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.rounds):
            cache = str(Path(tmp) / f"cache{k}")
            for kind in ("cold", "warm"):
                runs[kind].append(one_run(args.scene, cache, str(Path(tmp) / "out")))
    med = {kind: {"wall_s": statistics.median(r["wall_s"] for r in rs),
                  "compile_s": statistics.median(r["timings"].get("compile", 0.0) for r in rs),
                  "total_s": statistics.median(r["timings"]["total"] for r in rs)}
           for kind, rs in runs.items()}
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "scene": args.scene, "rounds": args.rounds, "runs": runs, "median": med}
    if not args.no_write:
        write_json(res, ROOT / "benchmarks" / "out" / "cold_start.json")
    return res


if __name__ == "__main__":
    out = main(sys.argv[1:])
    print(json.dumps(out["median"], indent=1))
    for kind, rs in out["runs"].items():
        print(kind, [{k: round(v, 2) for k, v in r["timings"].items()} for r in rs])
