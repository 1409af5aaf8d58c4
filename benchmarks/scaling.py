"""Scaling of the cracked solve: the edge-cracked plate of examples/edge_crack.toml with
all its spacings divided by a factor, time and peak memory per stage; written to
docs/performance.md.

Run:  PYTHONPATH=. python benchmarks/scaling.py                  (1e3 ... 1e5 nodes)
      PYTHONPATH=. python benchmarks/scaling.py --nodes 1e3 2e4 1e5 1e6
      PYTHONPATH=. python benchmarks/scaling.py --quick          (two small sizes)

Each size runs in a fresh process (its peak memory is its own) after a warm-up solve of
the coarse example in the same process (kernels compiled or loaded from the cache: the
"compile" stage is the cache load). The resident memory is sampled every 5 ms; a
stage's peak is the largest sample inside its window (the stages run one after the
other in the order of ``Solution.timings``). The log-log slope of each stage's time
against the node count is fitted over the sizes from 2e4 on.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import threading
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "edge_crack.toml"
BASE_NODES = 1170  # nodes of the example itself (factor 1)


def scaled(factor: float, **overrides):
    """The example's scene and method with every spacing divided by ``factor``."""
    from efgkit.scenefile import load_study

    scene, method = load_study(SCENE)
    zones = tuple(replace(z, spacing=z.spacing / factor) for z in method.zones)
    return scene, replace(method, spacing=method.spacing / factor, zones=zones, **overrides)


def rss() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def child(factor: float, overrides: dict, warm: bool = True) -> dict:
    """One size in this process: warm-up, then the timed solve with a memory sampler.
    ``warm=False`` leaves the warm-up solves out (the kernels then load from numba's cache
    inside the timed solve, its "compile" stage), so that the size guard checks the memory
    at the start (the 1e6-node run on a shared machine)."""
    import efgkit.methods.discretize as discretize_module
    from efgkit.static import solve

    if warm:
        solve(*scaled(1.6, **overrides))  # 9e4 points: compile / load the kernels
        keep, discretize_module.STREAM_POINTS = discretize_module.STREAM_POINTS, 0
        try:  # and those of the streamed assembly (chunks of points)
            solve(*scaled(1.6, **overrides))
        finally:
            discretize_module.STREAM_POINTS = keep
    samples, stop = [], threading.Event()

    def sample():
        while not stop.is_set():
            samples.append((time.perf_counter(), rss()))
            time.sleep(0.005)

    th = threading.Thread(target=sample, daemon=True)
    scene, method = scaled(factor, **overrides)
    base = rss()
    th.start()
    t0 = time.perf_counter()
    sol = solve(scene, method)
    wall = time.perf_counter() - t0
    stop.set()
    th.join()
    t1 = time.perf_counter()
    tip = sol.sifs(error=False)[0]  # streamed: the shape functions at the J discs' points formed here
    sifs_s = time.perf_counter() - t1
    t, m = np.array([s[0] - t0 for s in samples]), np.array([s[1] for s in samples])
    stages, peaks, start = {}, {}, 0.0
    # a streamed solve (efgkit.system.streamed) forms, assembles and drops the shape functions
    # a chunk of points at a time: its search, shape and stiffness laps alternate, and the three
    # share the peak of their common window
    streamed = type(sol.disc.shape).__name__ == "PointShapes"
    together = ("search", "shape", "stiffness") if streamed else ()
    for k, v in sol.timings.items():
        if k in ("total", "compile") or (k in together and k != together[0]):
            continue
        span = sum(sol.timings.get(j, 0.0) for j in together) if k in together else v
        inside = (t >= start) & (t <= start + span + 0.005)
        for j in together if k in together else (k,):
            stages[j] = sol.timings.get(j, 0.0)
            peaks[j] = int(m[inside].max()) if inside.any() else None
        start += span
    return {"factor": factor, "n_nodes": sol.nodes.n, "n_points": sol.disc.points.n,
            "n_dofs": sol.disc.n_dofs, "streamed": streamed, "wall_s": wall, "stages_s": stages,
            "compile_s": sol.timings.get("compile", 0.0), "sifs_s": sifs_s, "peak_bytes": peaks,
            "peak_total_bytes": int(m.max()), "rss_before_bytes": base,
            "KI": tip.KI, "KII": tip.KII, "solver": {k: v for k, v in sol.info.items()
                                                     if isinstance(v, (int, float, str))}}


def run_size(n_nodes: float, overrides: dict) -> dict:
    factor = math.sqrt(n_nodes / BASE_NODES)
    code = (f"import json, sys; sys.path.insert(0, {str(ROOT / 'benchmarks')!r}); "
            f"import scaling; print(json.dumps(scaling.child({factor!r}, {overrides!r})))")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    if proc.returncode:
        return {"factor": factor, "error": proc.stderr.strip().splitlines()[-1]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def slopes(rows: list[dict], n_min: float = 2e4) -> dict:
    ok = [r for r in rows if "error" not in r and r["n_nodes"] >= 0.9 * n_min]
    if len(ok) < 2:
        return {}
    n = np.log([r["n_nodes"] for r in ok])
    out = {k: float(np.polyfit(n, np.log([max(r["stages_s"][k], 1e-6) for r in ok]), 1)[0])
           for k in ok[0]["stages_s"] if all(k in r["stages_s"] for r in ok)}
    out["wall"] = float(np.polyfit(n, np.log([r["wall_s"] for r in ok]), 1)[0])
    return out


def markdown(res: dict, cmd: str) -> str:
    rows = [r for r in res["rows"] if "error" not in r]
    names = list(dict.fromkeys(k for r in rows for k in r["stages_s"]))  # "release": large only
    gb = 1e9
    lines = ["<!-- begin:scaling -->", "## Scaling of the cracked solve",
             "", f"Generated by `{cmd}` on {res['machine']} ({res['date']}), a machine shared "
             "with other jobs (2 cores): absolute times are those of a loaded machine. The "
             "edge-cracked plate of `examples/edge_crack.toml` (extrinsic enrichment, "
             f"diffraction, {res['bc']} BCs) with its spacings divided by a factor; one "
             "process per size. Seconds per stage (peak resident GB inside the stage):", "",
             "| nodes | points | " + " | ".join(names) + " | wall s | peak GB | K_I | K_II |",
             "|" + "---|" * (len(names) + 6)]
    for r in rows:
        cells = [f"{r['stages_s'][k]:.2f} ({(r['peak_bytes'][k] or 0) / gb:.2f})"
                 if k in r["stages_s"] else "-" for k in names]
        lines.append(f"| {r['n_nodes']} | {r['n_points']} | " + " | ".join(cells)
                     + f" | {r['wall_s']:.2f} | {r['peak_total_bytes'] / gb:.2f} | "
                     f"{r['KI']:.3f} | {r['KII']:.3f} |")
    for r in res["rows"]:
        if "error" in r:
            lines.append(f"\nFactor {r['factor']:.1f} failed: {r['error']}")
    if res["slopes"]:
        lines += ["", "Log-log slope of time against nodes from 2e4 on: "
                  + ", ".join(f"{k} {v:.2f}" for k, v in res["slopes"].items()) + "."]
    lines += ["", "Reference K_I = 34.0, K_II = 4.55 (Wilson 1969, quoted in seed 003 Sect. 5.6.2).",
              "<!-- end:scaling -->", ""]
    return "\n".join(lines)


def compare_bcs(n_nodes: float, rounds: int) -> dict:
    """The BC methods on one size, taking turns (A, B, C, A, B, C, ...)."""
    bcs = ("lagrange", "variational", "penalty")
    runs = {bc: [] for bc in bcs}
    for _ in range(rounds):
        for bc in bcs:
            runs[bc].append(run_size(n_nodes, {"bc": bc}))
    return runs


def bc_markdown(runs: dict, cmd: str, machine: str, date: str) -> str:
    lines = ["<!-- begin:bc_methods -->", "## Essential-BC methods on the cracked plate", "",
             f"Generated by `{cmd}` on {machine} ({date}), a machine shared with other jobs: "
             "medians over rounds in which the methods take turns. Same discretisation, same "
             "K (stiffness) for all; 'solve' is the linear solve (Uzawa steps included for "
             "Lagrange), 'constraints' the constrained system's set-up.", "",
             "| bc | nodes | constraints s | solve s | wall s | CG iterations | K_I | K_II |",
             "|---|---|---|---|---|---|---|---|"]
    for bc, rs in runs.items():
        ok = [r for r in rs if "error" not in r]
        if not ok:
            lines.append(f"| {bc} | failed: {rs[0]['error']} | | | | | | |")
            continue
        med = {k: float(np.median([r["stages_s"][k] for r in ok])) for k in ("constraints", "solve")}
        lines.append(f"| {bc} | {ok[0]['n_nodes']} | {med['constraints']:.2f} | {med['solve']:.2f} | "
                     f"{np.median([r['wall_s'] for r in ok]):.2f} | "
                     f"{ok[0]['solver'].get('iterations', '-')} | {ok[0]['KI']:.4f} | "
                     f"{ok[0]['KII']:.4f} |")
    lines += ["", "Reference K_I = 34.0, K_II = 4.55 (Wilson 1969, seed 003 Sect. 5.6.2).",
              "<!-- end:bc_methods -->", ""]
    return "\n".join(lines)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=float, nargs="+", default=[1e3, 5e3, 2e4, 5e4, 1e5])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--bc", default="lagrange")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--compare-bc", type=float, metavar="NODES",
                    help="compare the BC methods at this size instead")
    ap.add_argument("--rounds", type=int, default=2)
    args = ap.parse_args(argv)
    machine = f"{platform.machine()}, {platform.python_implementation()} {platform.python_version()}"
    if args.compare_bc:
        runs = compare_bcs(args.compare_bc, args.rounds)
        if not args.no_write:
            sys.path.insert(0, str(ROOT / "benchmarks"))
            from doc_sections import write_section

            from efgkit.io import write_json
            cmd = f"PYTHONPATH=. python benchmarks/scaling.py --compare-bc {args.compare_bc:g}"
            write_section(bc_markdown(runs, cmd, machine, time.strftime("%Y-%m-%d")),
                          ROOT / "docs" / "performance.md")
            write_json(runs, ROOT / "benchmarks" / "out" / "bc_methods.json")
        return {"rows": [r for rs in runs.values() for r in rs], "slopes": {}}
    sizes = [1.2e3, 3e3] if args.quick else args.nodes
    overrides = {"bc": args.bc}
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "bc": args.bc, "rows": []}
    for n in sizes:  # each row printed as it comes (a long run loses nothing)
        res["rows"].append(run_size(n, overrides))
        print(json.dumps(res["rows"][-1]), flush=True)
    res["slopes"] = slopes(res["rows"])
    cmd = "PYTHONPATH=. python benchmarks/scaling.py" + (" --quick" if args.quick else "") + (
        " --nodes " + " ".join(f"{n:g}" for n in args.nodes) if not args.quick else "")
    if not args.no_write:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        from doc_sections import write_section

        from efgkit.io import write_json
        write_section(markdown(res, cmd), ROOT / "docs" / "performance.md")
        write_json(res, ROOT / "benchmarks" / "out" / f"scaling_{args.bc}.json")
    return res


if __name__ == "__main__":
    out = main(sys.argv[1:])
    print(json.dumps({"rows": [{k: v for k, v in r.items() if k != "peak_bytes"}
                               for r in out["rows"]], "slopes": out["slopes"]}, indent=1))
