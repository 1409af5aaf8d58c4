"""The solve stage of the cracked plate before and after the preconditioner's Jacobi steps and
block Gauss-Seidel (efgkit.system.auxiliary), taking turns in one process; written to
docs/performance.md.

Run:  PYTHONPATH=. python benchmarks/solve_stage.py --nodes 2e4 1e5 --rounds 2
      PYTHONPATH=. python benchmarks/solve_stage.py --nodes 1e5 --bcs lagrange variational
      PYTHONPATH=. python benchmarks/solve_stage.py --end-to-end --nodes 2e4 1e5 --rounds 1
      PYTHONPATH=. python benchmarks/solve_stage.py --end-to-end --before 45781c1 --nodes 2e4 1e5

``--end-to-end``: whole solves instead, each in a fresh process as benchmarks/scaling.py runs
them (``scaling.child``: warm-up, then the timed ``solve``), before and after taking turns;
prints one JSON line per run (wall time, stages, CG statistics, K_I) and writes nothing.
With ``--before REV`` the "before" runs are the code of git revision REV (exported with ``git
archive`` to a temporary directory, run from there at its defaults) and "after" this tree at
its defaults; a line per round gives the after / before ratios of wall, solve stage and CPU.

The plate is examples/edge_crack.toml with its spacings divided by a factor
(benchmarks/scaling.py; Lagrange multipliers as in the example). Per size one
discretisation, stiffness and load vector (built as ``efgkit.static.solve`` builds them:
streamed from 2e5 points); then the variants take turns (before, after, before, after, ...)
and each ``solve(scene, method, disc, K, f)`` is timed: its "solve" stage (the auxiliary
space, the preconditioner's set-up, CG and the Uzawa steps, the coefficients) and
"constraints", and the process's CPU time over both (a waiting process accrues none).
"before" is ``auxiliary.SMOOTHER = False``: the additive preconditioner of degree 8 without
Jacobi steps, the code before this change (and, from the commit that added it,
``blas_threads.SINGLE_BLAS_THREAD = False``: BLAS on its default threads). The after / before ratio
of the solve stage is taken per round (the machine is shared: its load moves between rounds).
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import sys
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VARIANTS = {"before": False, "after": True}


def build(n_nodes: float):
    """scene, method, disc, K, f of the cracked plate at about ``n_nodes`` nodes."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import scaling

    from efgkit.approx.point_shapes import PointShapes
    from efgkit.methods.boundary import loads
    from efgkit.methods.discretize import discretize
    from efgkit.problem.graded import modulus_weights
    from efgkit.system.assemble import stiffness
    from efgkit.system.streamed import streamed_stiffness

    scene, method = scaling.scaled(math.sqrt(n_nodes / scaling.BASE_NODES))
    method = method.for_scene(scene)
    disc = discretize(scene, method, chunked="auto")
    wq = modulus_weights(disc.scene, disc.points.x, disc.points.w)
    D = scene.material.D
    K = streamed_stiffness(disc.shape, wq, D) if isinstance(disc.shape, PointShapes) else \
        stiffness(disc.shape, wq, D)
    return scene, method, disc, K, loads(disc)


def run(n_nodes: float, rounds: int, bcs) -> dict:
    from efgkit.static import solve
    from efgkit.system import auxiliary, blas_threads

    t0 = time.perf_counter()
    scene, method, disc, K, f = build(n_nodes)
    out = {"n_nodes": disc.nodes.n, "n_dofs": disc.n_dofs, "n_points": disc.points.n,
           "build_s": time.perf_counter() - t0, "runs": {}}
    keep = auxiliary.SMOOTHER, blas_threads.SINGLE_BLAS_THREAD
    try:
        for _ in range(rounds):
            for bc in bcs:
                for name, flag in VARIANTS.items():
                    auxiliary.SMOOTHER = blas_threads.SINGLE_BLAS_THREAD = flag
                    c0 = time.process_time()
                    sol = solve(scene, replace(method, bc=bc), disc, K, f)
                    cpu = time.process_time() - c0
                    tip = sol.sifs(error=False)[0]
                    info = sol.info
                    out["runs"].setdefault(f"{bc} {name}", []).append(
                        {"solve_s": sol.timings["solve"], "constraints_s": sol.timings["constraints"],
                         "cpu_s": cpu,
                         "setup_s": info.get("setup_time"), "cg_s": info.get("cg_time"),
                         "iterations": info.get("iterations"), "uzawa_steps": info.get("uzawa_steps"),
                         "solver": info.get("solver"), "fallback": info.get("fallback"),
                         "error_bound": info.get("error_bound"), "residual": info.get("residual"),
                         "KI": tip.KI, "KII": tip.KII})
                    print(n_nodes, bc, name, out["runs"][f"{bc} {name}"][-1], flush=True)
    finally:
        auxiliary.SMOOTHER, blas_threads.SINGLE_BLAS_THREAD = keep
    return out


def markdown(res: dict, cmd: str) -> str:
    lines = ["<!-- begin:solve_stage -->",
             "## The solve stage: Jacobi steps and block Gauss-Seidel in the preconditioner", "",
             f"Generated by `{cmd}` on {res['machine']} ({res['date']}), a machine shared with other "
             "jobs (2 cores; absolute times are those of a loaded machine). The cracked plate of "
             "`examples/edge_crack.toml` refined; one process per run, one discretisation per size, "
             "the variants taking turns (before, after, before, after, ...). 'before': the additive "
             "auxiliary-space preconditioner (layer LU + Y V Y^T, Chebyshev degree 8), 'after': "
             "layer - interior - layer block Gauss-Seidel with damped Jacobi steps around Y V Y^T "
             "(degree 6; `efgkit.system.auxiliary`). 'solve' is the stage of `Solution.timings` "
             "(auxiliary space, set-up, CG, Uzawa steps); medians, the after / before ratio of the "
             "solve stage per round; 'CPU s' the process's CPU time over constraints + solve "
             "(a waiting process accrues none: the steadier measure on a shared machine).", "",
             "| nodes | bc | variant | solve s | set-up s | CG s | CPU s | CG iterations | "
             "Uzawa steps | K_I | K_II | solve after / before (per round) | CPU after / before |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for size in res["sizes"]:
        runs = size["runs"]
        for key, rs in runs.items():
            bc, name = key.split()
            med = {k: statistics.median(r[k] or 0.0 for r in rs)
                   for k in ("solve_s", "setup_s", "cg_s", "cpu_s")}
            ratio = cpu_ratio = ""
            if name == "after" and f"{bc} before" in runs:
                ratio, cpu_ratio = (_ratios(rs, runs[f"{bc} before"], k) for k in ("solve_s", "cpu_s"))
            r = rs[-1]
            lines.append(f"| {size['n_nodes']} | {bc} | {name} | {med['solve_s']:.2f} | "
                         f"{med['setup_s']:.2f} | {med['cg_s']:.2f} | {med['cpu_s']:.2f} | "
                         f"{r['iterations']} | {r['uzawa_steps'] or '-'} | {r['KI']:.8f} | "
                         f"{r['KII']:.8f} | {ratio} | {cpu_ratio} |"
                         + (f" fell back: {r['fallback']}" if r["fallback"] else ""))
    lines += ["", "Reference K_I = 34.0, K_II = 4.55 (Wilson 1969, quoted in seed 003 Sect. 5.6.2).",
              "<!-- end:solve_stage -->", ""]
    return "\n".join(lines)


def end_to_end(n_nodes: float, flag: bool | None, root: Path = ROOT) -> dict:
    """``scaling.child`` at about ``n_nodes`` nodes in a fresh process with
    ``auxiliary.SMOOTHER`` and ``SINGLE_BLAS_THREAD`` (of blas_threads; of linalg before it)
    set to ``flag`` (False: the code before both changes; None: the defaults), the package
    and benchmarks of ``root``; the child's CPU time as ``cpu_s``."""
    import json
    import resource
    import subprocess

    factor = math.sqrt(n_nodes / 1170)  # scaling.BASE_NODES
    flags = ("" if flag is None else f"from efgkit.system import auxiliary, linalg; "
             "import importlib, importlib.util as u; name = 'efgkit.system.blas_threads'; "
             "bt = importlib.import_module(name) if u.find_spec(name) else linalg; "
             f"auxiliary.SMOOTHER = {flag!r}; bt.SINGLE_BLAS_THREAD = {flag!r}; ")
    code = (f"import json, sys; sys.path.insert(0, {str(root / 'benchmarks')!r}); import scaling; "
            f"{flags}print(json.dumps(scaling.child({factor!r}, {{'bc': 'lagrange'}})))")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**__import__("os").environ, "PYTHONPATH": str(root)}, cwd=root)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode:
        return {"error": proc.stderr.strip().splitlines()[-1]}
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    out["cpu_s"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out


def export(rev: str) -> Path:
    """The tree of git revision ``rev`` in a temporary directory (``git archive``)."""
    import subprocess
    import tempfile

    out = Path(tempfile.gettempdir()) / f"efgkit_solve_before_{rev}"
    if not (out / "efgkit").exists():
        out.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], capture_output=True, check=True)
        subprocess.run(["tar", "-x", "-C", str(out)], input=archive.stdout, check=True)
    return out


def _ratios(after: list, before: list, key: str) -> str:
    """Median (bold) and per-round after / before ratios of ``key``."""
    q = [a[key] / b[key] for a, b in zip(after, before, strict=False)]
    return f"**{statistics.median(q):.2f}** ({', '.join(f'{v:.2f}' for v in q)})"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=float, nargs="+", default=[2e4, 1e5])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--bcs", nargs="+", default=["lagrange"],
                    choices=("lagrange", "variational", "penalty"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--end-to-end", action="store_true")
    ap.add_argument("--before", default=None, metavar="REV",
                    help="--end-to-end: the code of git revision REV as 'before'")
    args = ap.parse_args(argv)
    if args.end_to_end:
        import json
        import os

        variants = ({name: (flag, ROOT) for name, flag in VARIANTS.items()} if args.before is None
                    else {"before": (None, export(args.before)), "after": (None, ROOT)})
        for _ in range(args.rounds):
            for n in args.nodes:
                runs = {}
                for name, (flag, root) in variants.items():
                    load = os.getloadavg()[0]
                    r = runs[name] = end_to_end(n, flag, root)
                    keep = ("n_nodes", "wall_s", "stages_s", "compile_s", "KI", "KII", "cpu_s", "error")
                    out = {k: r[k] for k in keep if k in r}
                    out["solver"] = {k: r.get("solver", {}).get(k) for k in
                                     ("iterations", "uzawa_steps", "setup_time", "cg_time")}
                    print(json.dumps({"variant": name, "load_1min": load, **out}), flush=True)
                if all("wall_s" in r for r in runs.values()):
                    a, b = runs["after"], runs["before"]
                    print(json.dumps({"nodes": a["n_nodes"], "after/before wall": a["wall_s"] / b["wall_s"],
                                      "solve": a["stages_s"]["solve"] / b["stages_s"]["solve"],
                                      "cpu": a["cpu_s"] / b["cpu_s"]}), flush=True)
        return {}
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "sizes": [run(n, args.rounds, args.bcs) for n in args.nodes]}
    cmd = ("PYTHONPATH=. python benchmarks/solve_stage.py --nodes "
           + " ".join(f"{n:g}" for n in args.nodes) + f" --rounds {args.rounds}"
           + (f" --bcs {' '.join(args.bcs)}" if args.bcs != ["lagrange"] else ""))
    print(markdown(res, cmd))
    if not args.no_write:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        from doc_sections import write_section

        from efgkit.io import write_json
        write_section(markdown(res, cmd), ROOT / "docs" / "performance.md")
        write_json(res, ROOT / "benchmarks" / "out" / "solve_stage.json")
    return res


if __name__ == "__main__":
    main(sys.argv[1:])
