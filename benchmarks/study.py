"""Parameter studies on dask: speed-up of a 64-point study on 1 and 2 local workers, and the
overhead per point against a plain loop of the same solves, written to
docs/performance_study.md.

Run:  python benchmarks/study.py             (64 points, 3 interleaved rounds, ~5 minutes)
      python benchmarks/study.py --quick     (4 points, 1 round, a smoke run)

The study is ``examples/sent_tension.toml`` at spacing 0.2 (default EFG settings), its crack
length a = 0.2 ... 0.6 W over the points, K without the error estimate. Each round runs, one
after the other (the order rotated from round to round): a plain loop of the same solves in
this process (one numba thread, as a worker has), and :func:`efgkit.study.run_study` on a
local cluster of 1 worker and of 2 workers (processes, one thread each), each into a fresh
directory. Reported per variant: the
median over the rounds of the wall time with the cluster's start and without it (the study
running on a cluster already up and warm: each worker has imported efgkit and loaded the
compiled kernels with one tiny solve, as the plain loop's process has), and the time the
workers spent inside the points (the rows' ``time_total``). On the 1-worker cluster the
plain loop also runs as one task in the worker process (before the study in odd rounds,
after it in even ones), so that the study's own cost is measured in the same process.
Speed-up = 1-worker wall / 2-worker wall (both without the start); overhead per point =
(1-worker wall - plain loop) / points.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def study(n: int, spacing: float):
    from efgkit.study import Parameter, Study

    with open(ROOT / "examples" / "sent_tension.toml", "rb") as f:
        base = tomllib.load(f)
    base = copy.deepcopy(base)
    base["efg"]["spacing"] = spacing
    return Study(base, (Parameter.linspace("cracks.0.vertices.1.0", 0.2, 0.6, n, name="a"),),
                 name="bench", error_estimate=False)


def plain_loop(st) -> tuple[float, list]:
    """The points' solves and K in this process, no study machinery: (seconds, K_I)."""
    import numba

    from efgkit.scenefile import efg_from_dict, scene_from_dict
    from efgkit.static import solve

    old = numba.get_num_threads()
    numba.set_num_threads(1)  # as in a worker
    try:
        t0 = time.perf_counter()
        ks = []
        for p in st.points():
            sol = solve(scene_from_dict(p.doc), efg_from_dict(p.doc["efg"]))
            ks.append(sol.sifs(error=False)[0].KI)
        return time.perf_counter() - t0, ks
    finally:
        numba.set_num_threads(old)


def warm_up() -> None:
    """One tiny solve: imports efgkit and loads its compiled kernels in a fresh process."""
    import numba

    numba.set_num_threads(1)
    plain_loop(study(1, 0.4))


def on_cluster(st, workers: int, loop_first: bool | None = None) -> dict:
    """The study on a local cluster of ``workers``; with ``loop_first`` (True or False) also
    the plain loop as one task on the (single) worker, before or after the study."""
    from efgkit.study import open_client, run_study

    t0 = time.perf_counter()
    client, cluster = open_client("local", workers)
    out = {}
    try:
        client.run(warm_up)  # each worker imports efgkit and loads the kernels once
        out["start"] = time.perf_counter() - t0
        steps = ["study"] if loop_first is None else (["loop", "study"] if loop_first
                                                      else ["study", "loop"])
        for step in steps:
            if step == "loop":  # the same solves, one task: the worker's own speed
                out["loop_in_worker"] = client.submit(plain_loop, st, pure=False).result()[0]
                continue
            with tempfile.TemporaryDirectory() as d:
                t1 = time.perf_counter()
                run = run_study(st, out=d, scheduler=client, figures=False)
                out["wall"] = time.perf_counter() - t1
    finally:
        client.close()
        cluster.close()
    t = run.table
    assert (t["status"] == "ok").all(), t[t["status"] != "ok"]["error_message"].tolist()
    return {**out, "with_start": out["start"] + out["wall"],
            "inside": float(t["time_total"].sum()), "KI": t["KI[edge:1]"].tolist()}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--points", type=int, default=None)
    ap.add_argument("--rounds", type=int, default=None)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    n = args.points or (4 if args.quick else 64)
    rounds = args.rounds or (1 if args.quick else 3)
    st = study(n, 0.2)
    plain_loop(study(2, 0.2))  # warm-up: compiles (or loads) the kernels in this process
    import pandas  # noqa: F401  (the table's libraries, loaded once per process)
    import pyarrow  # noqa: F401

    res = {"loop": [], "1": [], "2": []}
    _, ks = plain_loop(study(n, 0.2))
    for r in range(rounds):
        order = ["loop", "1", "2"][r % 3:] + ["loop", "1", "2"][:r % 3]  # rotated each round
        for w in order:
            if w == "loop":
                t, k = plain_loop(st)
                res["loop"].append({"wall": t})
            else:
                res[w].append(on_cluster(st, int(w), loop_first=bool(r % 2) if w == "1" else None))
                k = res[w][-1]["KI"]
            # the same numbers whatever ran them
            assert np.allclose(k, ks, rtol=1e-10, atol=0), (w, r)
        t = res["loop"][-1]["wall"]
        print(f"round {r + 1}/{rounds}: loop {t:.1f} s, 1 worker {res['1'][-1]['wall']:.1f} s "
              f"(+{res['1'][-1]['start']:.1f} s start), 2 workers {res['2'][-1]['wall']:.1f} s "
              f"(+{res['2'][-1]['start']:.1f} s start)", file=sys.stderr)
    med = {k: {q: statistics.median(x[q] for x in v) for q in v[0] if q != "KI"}
           for k, v in res.items()}
    out = {"points": n, "rounds": rounds, "median": med, "runs": res,
           "speedup": med["1"]["wall"] / med["2"]["wall"],
           "speedup_with_start": med["1"]["with_start"] / med["2"]["with_start"],
           "speedups": [a["wall"] / b["wall"] for a, b in zip(res["1"], res["2"], strict=True)],
           "overhead_per_point": (med["1"]["wall"] - med["loop"]["wall"]) / n,
           "overhead": med["1"]["wall"] / med["loop"]["wall"] - 1,
           "overheads": [a["wall"] / b["wall"] - 1 for a, b in zip(res["1"], res["loop"],
                                                                    strict=True)],
           "overhead_with_start": med["1"]["with_start"] / med["loop"]["wall"] - 1,
           "overhead_in_worker": med["1"]["wall"] / med["1"]["loop_in_worker"] - 1,
           "overheads_in_worker": [a["wall"] / a["loop_in_worker"] - 1 for a in res["1"]],
           "overhead_per_point_in_worker": (med["1"]["wall"] - med["1"]["loop_in_worker"]) / n,
           "dispatch_per_point": (med["1"]["wall"] - med["1"]["inside"]) / n,
           "cores": len(os.sched_getaffinity(0)), "load": os.getloadavg(),
           "machine": f"{platform.machine()}, CPython {platform.python_version()}",
           "date": time.strftime("%Y-%m-%d")}
    for v in res.values():
        for x in v:
            x.pop("KI", None)
    cmd = "python benchmarks/study.py" + (" --quick" if args.quick else "")
    if not args.no_write:
        (ROOT / "docs" / "performance_study.md").write_text(markdown(out, cmd))
        (ROOT / "benchmarks" / "out").mkdir(exist_ok=True)
        (ROOT / "benchmarks" / "out" / "study.json").write_text(json.dumps(out, indent=1))
    print(json.dumps({k: out[k] for k in ("speedup", "overhead", "overhead_per_point",
                                          "overhead_in_worker", "dispatch_per_point")}))
    return out


def markdown(r: dict, cmd: str) -> str:
    m = r["median"]
    per = m["loop"]["wall"] / r["points"]
    rows = [("plain loop (this process, 1 numba thread)", m["loop"]["wall"], None, None),
            ("plain loop as one task on the 1-worker cluster", m["1"]["loop_in_worker"], None,
             None),
            ("study, local cluster of 1 worker", m["1"]["wall"], m["1"]["start"], m["1"]["inside"]),
            ("study, local cluster of 2 workers", m["2"]["wall"], m["2"]["start"],
             m["2"]["inside"])]
    load = ", ".join(f"{x:.1f}" for x in r["load"])
    lines = [
        "# Performance of parameter studies", "",
        f"Generated by `{cmd}` on {r['machine']}, {r['cores']} cores ({r['date']}), **on a "
        f"machine shared with other jobs** (load average at the end {load} on {r['cores']} "
        "cores): the absolute times are noisy and the ratios are what to read. "
        f"{r['points']}-point study of `examples/sent_tension.toml` at spacing 0.2 (crack "
        f"length a = 0.2 ... 0.6 W, K without the error estimate), {per:.2f} s per point in the "
        f"plain loop; medians of {r['rounds']} rounds, each running the three variants one "
        "after the other (the order rotated from round to round). The study's wall time "
        "includes writing the rows, the CSV and the Parquet table (pandas and pyarrow loaded "
        "before the timing, as after a first study).", "",
        "| variant | wall s | cluster start and warm-up s | inside the points s |",
        "|---|---|---|---|"]
    for name, wall, start, inside in rows:
        lines.append(f"| {name} | {wall:.1f} | " + (f"{start:.1f}" if start is not None else "-")
                     + " | " + (f"{inside:.1f}" if inside is not None else "-") + " |")
    sp = ", ".join(f"{x:.2f}" for x in r["speedups"])
    ov = ", ".join(f"{x:+.1%}" for x in r["overheads"])
    lines += ["",
              f"- Speed-up 2 workers / 1 worker: **{r['speedup']:.2f}x** (rounds: {sp}; with "
              f"the cluster's start: {r['speedup_with_start']:.2f}x). Target >= 1.7x on 2 cores.",
              f"- Overhead of the study on 1 worker against the plain loop: **{r['overhead']:+.1%}**"
              f", {r['overhead_per_point'] * 1e3:.0f} ms per point (rounds: {ov}; with the "
              f"cluster's start: {r['overhead_with_start']:+.1%}). Target <= 10 %.",
              f"- The same against the plain loop run as one task in the worker process "
              f"(the same process, so only the study's own work differs): "
              f"**{r['overhead_in_worker']:+.1%}**, {r['overhead_per_point_in_worker'] * 1e3:.0f} "
              f"ms per point (rounds: "
              + ", ".join(f"{x:+.1%}" for x in r["overheads_in_worker"]) + ").",
              f"- Wall time of the 1-worker study not spent inside the points (sending the "
              f"tasks, receiving and writing the rows, the table): "
              f"{r['dispatch_per_point'] * 1e3:.0f} ms per point.", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
