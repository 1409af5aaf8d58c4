"""MLPG1 assembly against EFG assembly on the same cloud (the issue's target: MLPG <= 3x EFG).

Unit square, n_side^2 nodes, left edge fixed, uniform traction on the right. "Assembly" is
the discretisation (nodes, quadrature points, neighbour search, shape functions: the
``timings`` of the Discretization) plus the stiffness and load vector: for EFG
:func:`~efgkit.methods.discretize.discretize` + :func:`~efgkit.system.assemble.stiffness` +
:func:`~efgkit.methods.boundary.loads`, for MLPG
:func:`~efgkit.methods.local.discretize_local` + :func:`~efgkit.methods.local.local_system`.
EFG runs with the quadratic basis and d_max = 2.5 (the MLS MLPG uses) and with its defaults.

Run:  python benchmarks/mlpg_assembly.py            (100k nodes; several minutes)
      python benchmarks/mlpg_assembly.py --quick    (small, a smoke run)

A/B runs are interleaved in one process; medians of ``--repeat`` after one warm-up run.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

from efgkit import EFG, MLPG, Domain, Elastic, Scene, Support, Traction
from efgkit.methods.boundary import loads
from efgkit.methods.discretize import discretize
from efgkit.methods.local import DEFAULT_MLPG_PENALTY, discretize_local, local_system
from efgkit.system.assemble import stiffness


def scene() -> Scene:
    return Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1000.0, 0.3, "stress"),
                 supports=(Support("left", ux=0.0, uy=0.0),),
                 tractions=(Traction("right", (1.0, 0.0)),))


def efg_assembly(sc, m):
    t0 = time.perf_counter()
    d = discretize(sc, m)
    t1 = time.perf_counter()
    K = stiffness(d.shape, d.points.w, sc.material.D)
    loads(d)
    t2 = time.perf_counter()
    return {**d.timings, "stiffness+loads": t2 - t1, "total": t2 - t0,
            "n_points": d.points.n, "nnz": K.nnz}


def mlpg_assembly(sc, m):
    t0 = time.perf_counter()
    d = discretize_local(sc, m)
    t1 = time.perf_counter()
    K, _ = local_system(d, DEFAULT_MLPG_PENALTY * sc.material.E * (1.0 / m.spacing))
    t2 = time.perf_counter()
    return {**d.timings, "stiffness+loads": t2 - t1, "total": t2 - t0,
            "n_points": d.points.n + d.local.points.n, "nnz": K.nnz}


def main(argv=None) -> dict:
    p = argparse.ArgumentParser()
    p.add_argument("--quick", action="store_true")
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args(argv)
    n_side = 41 if args.quick else 317
    h = 1.0 / (n_side - 1)
    sc = scene()
    def runs_at(h):
        return {"mlpg": lambda: mlpg_assembly(sc, MLPG(spacing=h)),
                "efg_quadratic": lambda: efg_assembly(sc, EFG(spacing=h, basis="quadratic", d_max=2.5,
                                                              bc="penalty")),
                "efg_default": lambda: efg_assembly(sc, EFG(spacing=h, bc="penalty"))}

    for f in runs_at(1.0 / 20).values():  # warm-up on a small cloud: numba compilation
        f()
    runs = runs_at(h)
    res = {k: [] for k in runs}
    for _ in range(args.repeat):  # interleaved
        for k, f in runs.items():
            res[k].append(f())
    out = {"n_nodes": n_side**2, "repeat": args.repeat}
    for k, rs in res.items():
        keys = dict.fromkeys(key for r in rs for key in r)  # a stage such as 'compile' may be in one run only
        out[k] = {key: statistics.median(r.get(key, 0.0) for r in rs) for key in keys}
    out["ratio_mlpg_efg_quadratic"] = statistics.median(
        m["total"] / e["total"] for m, e in zip(res["mlpg"], res["efg_quadratic"], strict=True))
    out["ratio_mlpg_efg_default"] = statistics.median(
        m["total"] / e["total"] for m, e in zip(res["mlpg"], res["efg_default"], strict=True))
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
