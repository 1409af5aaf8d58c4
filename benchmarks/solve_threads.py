"""The solve's product with ``A`` and Chebyshev steps on one thread against two
(``compiled_operators.THREADED``), taking turns in one process on one 97k-node cracked plate.

Run:  NUMBA_NUM_THREADS=2 PYTHONPATH=. python benchmarks/solve_threads.py --nodes 1e5 --rounds 4
      NUMBA_NUM_THREADS=2 PYTHONPATH=. python benchmarks/solve_threads.py --end-to-end --rounds 2

``--end-to-end``: whole runs instead, each in a fresh process (``scaling.child``: warm-up, then
the timed ``solve``, as benchmarks/scaling.py runs them), ``THREADED`` off and on in turn; per
run the wall time, stages, CG iterations, K_I, peak memory, the child's CPU time and the load
average at its start.

One discretisation, stiffness and load vector (benchmarks/solve_stage.py's ``build``); a
warm-up solve (compiles or loads the kernels, captures the Chebyshev operators the
preconditioner builds); then per round, one thread (``THREADED = False``, the default: the
one-pass product) and then two (``THREADED = True``) in turn: after a pause of 1 s, the
median wall and CPU time of the product with ``K``'s :class:`SymmetricOperator` (upper
triangle), of the row-parallel product with the full ``K`` (CSR, unsigned indices) and of one
Chebyshev application (6 steps on (n, 2)), then a whole ``solve`` (its "solve" stage, set-up,
CG, iterations, K_I, the process CPU time and the coefficients' difference from the warm-up
one-thread solve). Each measurement carries the load average (``os.getloadavg``) at its
start. Prints one JSON line per measurement; writes nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))


def timed(fn, repeat: int) -> dict:
    """Median wall and CPU milliseconds of ``repeat`` calls of ``fn`` (after one call)."""
    fn()
    wall, cpu = [], []
    for _ in range(repeat):
        w, c = time.perf_counter(), time.process_time()
        fn()
        wall.append(1e3 * (time.perf_counter() - w))
        cpu.append(1e3 * (time.process_time() - c))
    return {"wall_ms": statistics.median(wall), "cpu_ms": statistics.median(cpu)}


def full_product(K, threads: int):
    """``x -> K x`` row-parallel on the full CSR ``K`` over ``threads`` row ranges."""
    import numpy as np

    from efgkit.system import compiled_operators as co
    from efgkit.system.solve_kernels import csr_product

    indptr, indices = K.indptr.astype(np.uint64), K.indices.astype(np.uint32)
    bounds = co.row_split(indptr, threads).tolist()

    def product(x):
        y = np.empty(len(x))
        co.on_threads([lambda lo=lo, hi=hi: csr_product(indptr[lo:hi + 1], indices, K.data, x, y[lo:hi])
                        for lo, hi in zip(bounds[:-1], bounds[1:], strict=True)])
        return y
    return product


def end_to_end(n_nodes: float, threaded: bool) -> dict:
    """``scaling.child`` at about ``n_nodes`` nodes in a fresh process with
    ``compiled_operators.THREADED = threaded``; its CPU time and the load at its start."""
    import resource
    import subprocess

    import scaling

    bench = str(Path(__file__).resolve().parent)
    code = (f"import json, sys; sys.path.insert(0, {bench!r}); import scaling; "
            f"from efgkit.system import compiled_operators as co; co.THREADED = {threaded!r}; "
            f"print(json.dumps(scaling.child({(n_nodes / scaling.BASE_NODES) ** 0.5!r}, "
            "{'bc': 'lagrange'})))")
    load = os.getloadavg()[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    return {"threaded": threaded, "load": load, "wall_s": out["wall_s"], "stages_s": out["stages_s"],
            "iterations": out["solver"].get("iterations"), "KI": out["KI"],
            "peak_gb": out["peak_total_bytes"] / 1e9,
            "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)}


def main(argv=None) -> None:
    import numba
    import numpy as np
    import solve_stage

    from efgkit.static import solve
    from efgkit.system import compiled_operators as co

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=float, default=1e5)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--end-to-end", action="store_true")
    args = ap.parse_args(argv)
    if args.end_to_end:
        for rnd in range(args.rounds):
            for flag in (False, True):
                print(json.dumps({"round": rnd + 1, **end_to_end(args.nodes, flag)}), flush=True)
        return
    threads = numba.get_num_threads()
    t0 = time.perf_counter()
    scene, method, disc, K, f = solve_stage.build(args.nodes)
    print(json.dumps({"n_nodes": disc.nodes.n, "n_dofs": disc.n_dofs, "nnz_K": int(K.nnz),
                      "numba_threads": threads, "build_s": time.perf_counter() - t0}), flush=True)
    made = []
    init = co.CompiledChebyshev.__init__

    def capture(self, *a, **k):
        init(self, *a, **k)
        made.append(self)
    co.CompiledChebyshev.__init__ = capture
    keep = co.THREADED
    try:
        co.THREADED = False
        ref = solve(scene, method, disc, K, f)
        co.CompiledChebyshev.__init__ = init
        S = co.SymmetricOperator(K)
        full = {1: full_product(K, 1), threads: full_product(K, threads)}
        Y = made[-1]
        rng = np.random.default_rng(0)
        x = rng.uniform(-1.0, 1.0, K.shape[0])
        r = rng.uniform(-1.0, 1.0, (Y.indptr.size - 1, 2))
        for rnd in range(args.rounds):
            for flag in (False, True):
                co.THREADED = flag
                nt = co.solve_threads()
                row = {"round": rnd + 1, "threads": nt}
                time.sleep(1.0)  # threads a solve leaves spinning (BLAS) settle first
                for name, fn in (("symmetric_product", lambda: S @ x),
                                 ("full_product", lambda nt=nt: full[nt](x)),
                                 ("chebyshev", lambda: Y(r))):
                    row[name] = {"load": os.getloadavg()[0], **timed(fn, args.repeat)}
                load = os.getloadavg()[0]
                w, c = time.perf_counter(), time.process_time()
                sol = solve(scene, method, disc, K, f)
                wall, cpu = time.perf_counter() - w, time.process_time() - c
                info, tip = sol.info, sol.sifs(error=False)[0]
                row["solve"] = {"load": load, "wall_s": wall, "cpu_s": cpu,
                                "solve_s": sol.timings["solve"], "setup_s": info.get("setup_time"),
                                "cg_s": info.get("cg_time"), "iterations": info.get("iterations"),
                                "KI": tip.KI, "coeffs_rel_diff": float(
                                    np.abs(sol.coeffs - ref.coeffs).max() / np.abs(ref.coeffs).max())}
                row["product_rel_diff"] = float(np.abs(S @ x - K @ x).max() / np.abs(K @ x).max())
                print(json.dumps(row), flush=True)
    finally:
        co.THREADED = keep
        co.CompiledChebyshev.__init__ = init


if __name__ == "__main__":
    main()
