"""The stages of the cracked 1e5-node solve around the linear solve, this tree against a
revision before, in interleaved fresh processes; written to the ``stages`` section of
docs/performance.md.

Run:  PYTHONPATH=. python benchmarks/stage_times.py --before 45781c1
      PYTHONPATH=. python benchmarks/stage_times.py --before 45781c1 --nodes 2e4 --rounds 1 --no-write
      PYTHONPATH=. python benchmarks/stage_times.py --before 45781c1 --compare-k 2e4 1e5
      PYTHONPATH=. python benchmarks/stage_times.py --before 0626a95 --nodes 2e4 1e5 --section stage_slopes

With several ``--nodes`` every round runs each size for each tree, and the log-log slope of
each stage's median time between the first and the last size is given per tree (the issue's
"every stage's slope <= 1.1 from 20k to 100k"), with the range of the slopes of the rounds.

Each run is one process as in benchmarks/scaling.py (the edge-cracked plate of
examples/edge_crack.toml refined to about ``--nodes`` nodes, the same warm-up solves), the
trees taking turns (before, after, before, after, ...). Every stage of ``Solution.timings``
is reported as wall time and as the process's CPU time (user + system, all threads; a
process that waits for a core accrues none, the steadier measure on a shared machine; the
system part, mostly the page faults of fresh memory, is kept as well), with
the 1-minute load average at the start of the run, the peak resident memory of the process
(``ru_maxrss``: the solve's, the warm-ups are smaller) and K_I, K_II of the tip.

``--compare-k N ...``: instead, the streamed stiffness of the plate at about N nodes from
each tree (one process each, written to a temporary .npz) compared entry by entry: the same
pattern, and the largest difference relative to max |K| (0 when bit-identical).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OURS = ("nodes", "quadrature", "approximation", "search", "shape", "stiffness", "loads",
        "constraints")  # the stages around the linear solve

CHILD = r"""
import json, math, os, resource, sys, time
sys.path.insert(0, os.path.join({root!r}, "benchmarks"))
import scaling
import efgkit.timing as tm
from efgkit.static import solve
import efgkit.methods.discretize as dm
solve(*scaling.scaled(1.6))  # the warm-ups of scaling.child: kernels compiled or loaded
keep, dm.STREAM_POINTS = dm.STREAM_POINTS, 0
solve(*scaling.scaled(1.6))
dm.STREAM_POINTS = keep
cpu, sys_, last, lap = {{}}, {{}}, [None, None], tm.Stopwatch.lap
def timed_lap(self, name):
    r = resource.getrusage(resource.RUSAGE_SELF)
    t = r.ru_utime + r.ru_stime
    cpu[name] = cpu.get(name, 0.0) + t - last[0]
    sys_[name] = sys_.get(name, 0.0) + r.ru_stime - last[1]
    last[0], last[1] = t, r.ru_stime
    return lap(self, name)
tm.Stopwatch.lap = timed_lap
scene, method = scaling.scaled(math.sqrt({nodes!r} / scaling.BASE_NODES))
load = os.getloadavg()[0]
r = resource.getrusage(resource.RUSAGE_SELF)
last[0], last[1] = r.ru_utime + r.ru_stime, r.ru_stime
t0 = time.perf_counter()
sol = solve(scene, method)
wall = time.perf_counter() - t0
r = resource.getrusage(resource.RUSAGE_SELF)
tip = sol.sifs(error=False)[0]
print(json.dumps({{"n_nodes": sol.nodes.n, "n_points": sol.disc.points.n, "wall_s": wall,
                  "cpu_s": r.ru_utime + r.ru_stime - (last[0] - sum(cpu.values())),
                  "stages_s": dict(sol.timings), "cpu_stages_s": cpu, "sys_stages_s": sys_, "load": load,
                  "peak_GB": r.ru_maxrss / 1e6, "KI": tip.KI, "KII": tip.KII,
                  "iterations": sol.info.get("iterations")}}))
"""


STIFFNESS = r"""
import math, sys, os, numpy as np
sys.path.insert(0, os.path.join({root!r}, "benchmarks"))
import scaling
from efgkit.methods.discretize import discretize
from efgkit.problem.graded import modulus_weights
from efgkit.system.streamed import streamed_stiffness
scene, method = scaling.scaled(math.sqrt({nodes!r} / scaling.BASE_NODES))
disc = discretize(scene, method.for_scene(scene), chunked=True)
K = streamed_stiffness(disc.shape, modulus_weights(disc.scene, disc.points.x, disc.points.w),
                       scene.material.D)
K.sort_indices()
np.savez({out!r}, data=K.data, indices=K.indices, indptr=K.indptr, n=disc.nodes.n,
         chunks=disc.shape.n_chunks)
"""


def compare_k(trees: dict, nodes: float) -> dict:
    """The streamed K of both trees at about ``nodes`` nodes, entry by entry."""
    got = {}
    for tree, root in trees.items():
        out = Path(tempfile.gettempdir()) / f"efgkit_stages_K_{tree}.npz"
        code = STIFFNESS.format(root=str(root), nodes=float(nodes), out=str(out))
        subprocess.run([sys.executable, "-c", code], check=True, cwd=str(root),
                       env=dict(os.environ, PYTHONPATH=str(root)))
        got[tree] = dict(np.load(out))
        out.unlink()
    a, b = got["before"], got["after"]
    same = all(np.array_equal(a[k], b[k]) for k in ("indptr", "indices"))
    diff = float(np.abs(a["data"] - b["data"]).max() / np.abs(a["data"]).max()) if same else None
    return {"nodes": int(a["n"]), "chunks": int(a["chunks"]), "nnz": len(a["data"]),
            "same_pattern": same, "max_rel_diff": diff,
            "bit_identical": same and bool(np.array_equal(a["data"], b["data"]))}


def tree_of(rev: str) -> Path:
    """The files of git revision ``rev`` in a temporary folder (``git archive``)."""
    path = Path(tempfile.gettempdir()) / f"efgkit_stages_{rev}"
    if not (path / "efgkit").exists():
        path.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True,
                                 capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(path)], input=archive, check=True)
    return path


def run(root: Path, nodes: float) -> dict:
    code = CHILD.format(root=str(root), nodes=float(nodes))
    env = dict(os.environ, PYTHONPATH=str(root))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                          cwd=str(root))
    if proc.returncode:
        raise RuntimeError(proc.stderr.strip().splitlines()[-1])
    return json.loads(proc.stdout.strip().splitlines()[-1])


def ours(r: dict, key: str) -> float:
    return sum(r[key].get(k, 0.0) for k in OURS)


def slopes(runs: list, tree: str, stages: list) -> dict:
    """Per stage: (slope of the medians, smallest and largest slope of a round) of the log-log
    time against nodes between the smallest and the largest size that ``tree`` ran."""
    rs = [r for r in runs if r["tree"] == tree]
    sizes = sorted({r["nodes_asked"] for r in rs})
    lo, hi = ([r for r in rs if r["nodes_asked"] == n] for n in (sizes[0], sizes[-1]))
    out = {}
    dn = np.log(np.median([r["n_nodes"] for r in hi]) / np.median([r["n_nodes"] for r in lo]))
    for k in stages + ["wall"]:
        def t(r, k=k):
            return r["wall_s"] if k == "wall" else r["stages_s"].get(k, 0.0)
        if min(t(r) for r in lo + hi) <= 0:
            continue
        per_round = [np.log(t(b) / t(a)) / np.log(b["n_nodes"] / a["n_nodes"])
                     for a, b in zip(lo, hi, strict=False)]
        out[k] = (float(np.log(np.median([t(r) for r in hi]) / np.median([t(r) for r in lo])) / dn),
                  float(min(per_round)), float(max(per_round)))
    return out


def system_times(runs: list, stages: list) -> str:
    """The median system time of each stage (but the solve) that reaches 0.02 s in some run,
    per tree and size, as text."""
    parts = []
    for tree in ("before", "after"):
        for n in sorted({r["nodes_asked"] for r in runs}):
            rs = [r for r in runs if r["tree"] == tree and r["nodes_asked"] == n]
            shown = [k for k in stages if k != "solve"
                     and max(r["sys_stages_s"].get(k, 0.0) for r in rs) >= 0.02]
            parts.append(f"{tree} {n:g}: " + ", ".join(
                f"{k} {np.median([r['sys_stages_s'].get(k, 0.0) for r in rs]):.2f}" for k in shown))
    return "; ".join(parts)


def markdown(res: dict, cmd: str) -> str:
    runs = res["runs"]
    stages = list(dict.fromkeys(k for r in runs for k in r["stages_s"] if k != "total"))
    head = ("| round | tree | nodes | load | " + " | ".join(stages) + " | around the solve s (CPU s) "
            "| wall s | peak GB | CG iterations | K_I | K_II |")
    section = res.get("section", "stages")
    lines = [
        f"<!-- begin:{section} -->",
        "## The stages around the linear solve of the cracked plate: before and after"
        + (", " + " and ".join(f"{n:g}" for n in sorted({r["nodes_asked"] for r in runs}))
           + " nodes" if len({r["nodes_asked"] for r in runs}) > 1 else ""),
        "",
        f"Generated by `{cmd}` on {platform.machine()}, CPython {platform.python_version()} "
        f"({res['date']}), a machine shared with other jobs (2 cores). The cracked plate of "
        "`examples/edge_crack.toml` refined (streamed assembly, Lagrange BCs), one fresh process "
        f"per run, the trees taking turns; 'before' is `{res['before']}`, 'after' this tree. "
        "Each stage: wall s (CPU s, user + system of all threads); 'around the solve' is the "
        "sum of " + ", ".join(OURS) + " (not setup, compile, solve); compile: numba's kernels "
        "loaded from its cache or compiled, wherever it happened; load: the 1-minute load "
        "average at the start.",
        "",
        head,
        "|" + "---|" * (head.count("|") - 1),
    ]
    for r in runs:
        cells = [f"{r['stages_s'].get(k, 0.0):.2f} ({r['cpu_stages_s'].get(k, 0.0):.2f})"
                 for k in stages]
        lines.append(f"| {r['round']} | {r['tree']} | {r['n_nodes']} | {r['load']:.1f} | " + " | ".join(cells)
                     + f" | **{ours(r, 'stages_s'):.2f}** ({ours(r, 'cpu_stages_s'):.2f}) | "
                     f"{r['wall_s']:.2f} | {r['peak_GB']:.2f} | {r['iterations']} | "
                     f"{r['KI']:.12f} | {r['KII']:.12f} |")
    lines.append("")
    med = {}
    for tree in ("before", "after"):
        rs = [r for r in runs if r["tree"] == tree]
        med[tree] = {k: float(np.median([r["stages_s"].get(k, 0.0) for r in rs])) for k in stages}
        med[tree]["cpu"] = {k: float(np.median([r["cpu_stages_s"].get(k, 0.0) for r in rs]))
                            for k in stages}
        med[tree]["ours"] = float(np.median([ours(r, "stages_s") for r in rs]))
        med[tree]["ours_cpu"] = float(np.median([ours(r, "cpu_stages_s") for r in rs]))
    ratios = [ours(a, "cpu_stages_s") / ours(b, "cpu_stages_s")
              for b, a in zip([r for r in runs if r["tree"] == "before"],
                              [r for r in runs if r["tree"] == "after"], strict=False)]
    several = len({r["nodes_asked"] for r in runs}) > 1
    if several:  # the slopes between the sizes
        for tree in ("before", "after"):
            sl = slopes(runs, tree, stages)
            lines.append(f"Slopes of {tree} (log-log, time against nodes, the medians; the rounds' "
                         "range): " + "; ".join(f"{k} {v[0]:.2f} ({v[1]:.2f}-{v[2]:.2f})"
                                                for k, v in sl.items()) + ".")
            lines.append("")
        lines.append("System time (page faults of fresh memory, mostly) of the stages that have "
                     f"any, medians, per tree and size: {system_times(runs, stages)}.")
        lines.append("")
    lines.append(f"Medians{' over all sizes' * several}, before -> after, wall s (CPU s): " + "; ".join(
        f"{k} {med['before'][k]:.2f} -> {med['after'][k]:.2f} "
        f"({med['before']['cpu'][k]:.2f} -> {med['after']['cpu'][k]:.2f})" for k in stages)
        + f"; around the solve **{med['before']['ours']:.2f} -> {med['after']['ours']:.2f} s** "
        f"(CPU {med['before']['ours_cpu']:.2f} -> {med['after']['ours_cpu']:.2f} s; after / "
        f"before per round: {', '.join(f'{x:.2f}' for x in ratios)}).")
    lines.append(f"<!-- end:{section} -->")
    return "\n".join(lines) + "\n"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", required=True, help="git revision to compare with")
    ap.add_argument("--nodes", type=float, nargs="+", default=[1e5])
    ap.add_argument("--section", default="stages", help="docs/performance.md section to write")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--compare-k", type=float, nargs="+", metavar="N")
    args = ap.parse_args(argv)
    import datetime

    trees = {"before": tree_of(args.before), "after": ROOT}
    if args.compare_k:
        res = {"compare_k": [compare_k(trees, n) for n in args.compare_k]}
        for r in res["compare_k"]:
            print(json.dumps(r))
        return res
    runs = []
    for k in range(args.rounds):
        for tree, root in trees.items():
            for nodes in args.nodes:
                r = run(root, nodes) | {"round": k + 1, "tree": tree, "nodes_asked": nodes}
                runs.append(r)
                print(json.dumps({key: r[key] for key in ("round", "tree", "n_nodes", "load",
                                                          "wall_s", "KI")}
                                 | {"stiffness": round(r["stages_s"].get("stiffness", 0.0), 3),
                                    "around": round(ours(r, "stages_s"), 2),
                                    "around_cpu": round(ours(r, "cpu_stages_s"), 2)}), flush=True)
    res = {"before": args.before, "runs": runs, "section": args.section,
           "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}
    cmd = "PYTHONPATH=. python benchmarks/stage_times.py " + " ".join(argv or sys.argv[1:])
    text = markdown(res, cmd)
    print(text)
    if not args.no_write:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        from doc_sections import write_section

        write_section(text, ROOT / "docs" / "performance.md")
    return res


if __name__ == "__main__":
    main()
