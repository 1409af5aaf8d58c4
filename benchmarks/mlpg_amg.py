"""MLPG1 solves at scale: GMRES with the multigrid preconditioner (``efgkit.system.krylov_mlpg``)
against GMRES with ILU and SuperLU on the same system: iterations, setup and solve seconds,
peak memory above the assembled system, and the coefficient difference to the direct solve
(or, without it, between the iterative answers).

Scenes: ``plate`` (unit square, left edge fixed, traction on the right: ``mlpg_assembly``)
and ``sent`` (clamped single-edge-notched strip of ``efgkit.gallery.sent``, crack a = w / 2),
both with bc="penalty". ``--weight`` picks the MLS weight (the preconditioner needs one whose
nodal matrix Phi is positive: "cubic"; with the Gaussian k = 2 default it stagnates).

Run:  python benchmarks/mlpg_amg.py --scene plate --nodes 20000 --solvers amg,ilu,direct
Peak memory: resident set size sampled every 20 ms during each solve, minus the value before.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import threading
import time

import numpy as np

from efgkit import MLPG
from efgkit.gallery import sent
from efgkit.methods.local import DEFAULT_MLPG_PENALTY, discretize_local, local_system
from efgkit.static import mlpg_auxiliary
from efgkit.system.krylov import solve_unsymmetric
from efgkit.system.linear_system import LinearSystem


def rss() -> float:
    """Resident set size of this process, bytes."""
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * 4096.0


def peak_during(fn):
    """(fn(), peak RSS increase in bytes while it ran)."""
    base, peak, done = rss(), [0.0], threading.Event()

    def sample():
        while not done.is_set():
            peak[0] = max(peak[0], rss())
            time.sleep(0.02)

    th = threading.Thread(target=sample, daemon=True)
    th.start()
    try:
        out = fn()
    finally:
        done.set()
        th.join()
    return out, max(peak[0], rss()) - base


def build(scene_name: str, n_nodes: float, weight: str):
    if scene_name == "plate":
        sys.path.insert(0, __file__.rsplit("/", 1)[0])
        from mlpg_assembly import scene

        sc, h = scene(), 1.0 / (math.sqrt(n_nodes) - 1)
    else:  # [0, 1] x [-2, 2]: 4 units^2
        sc, h = sent(ends="clamped"), 2.0 / math.sqrt(n_nodes)
    m = MLPG(spacing=h, weight=weight).for_scene(sc)
    t0 = time.perf_counter()
    d = discretize_local(sc, m)
    K, f = local_system(d, DEFAULT_MLPG_PENALTY * sc.material.E / h)
    return d, m, LinearSystem(K, f, False, K.shape[0]), time.perf_counter() - t0


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", choices=("plate", "sent"), default="plate")
    ap.add_argument("--nodes", type=float, default=2e4)
    ap.add_argument("--weight", default="cubic")
    ap.add_argument("--solvers", default="amg,ilu,direct")
    a = ap.parse_args(argv)
    d, m, system, t_asm = build(a.scene, a.nodes, a.weight)
    out = {"scene": a.scene, "weight": a.weight, "n_nodes": d.nodes.n, "n_unknowns": system.A.shape[0],
           "nnz": system.A.nnz, "assembly_seconds": t_asm, "runs": {}}
    print(json.dumps({k: v for k, v in out.items() if k != "runs"}), flush=True)
    z = {}
    for s in a.solvers.split(","):
        solver = {"amg": "amg", "ilu": "gmres", "direct": "direct"}[s]
        t0 = time.perf_counter()
        try:
            (z[s], info), mem = peak_during(lambda solver=solver: solve_unsymmetric(
                system, solver, auxiliary=lambda: mlpg_auxiliary(d, m.bc)))
        except Exception as err:  # a failed solver is a result, not a crash of the benchmark
            out["runs"][s] = {"error": f"{type(err).__name__}: {err}", "seconds": time.perf_counter() - t0}
            print(s, out["runs"][s], flush=True)
            continue
        keep = ("iterations", "residual", "error_estimate", "setup_time", "krylov_time", "layer",
                "levels", "fallback")
        out["runs"][s] = {"seconds": time.perf_counter() - t0, "peak_mb": mem / 1e6,
                          **{k: info[k] for k in keep if k in info}}
        print(s, json.dumps(out["runs"][s], default=str), flush=True)
    ref = "direct" if "direct" in z else ("ilu" if "ilu" in z else None)
    for s, v in z.items():
        if ref and s != ref:
            out["runs"][s][f"diff_vs_{ref}"] = float(np.linalg.norm(v - z[ref]) / np.linalg.norm(z[ref]))
    print(json.dumps(out, default=str), flush=True)
    return out


if __name__ == "__main__":
    main()
