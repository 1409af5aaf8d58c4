"""MLPG1 unsymmetric solve at scale: GMRES with ILU (``efgkit.system.krylov``) on the plate of
``mlpg_assembly`` (default 100k nodes): iterations, residual, seconds.

Run:  python benchmarks/mlpg_solve.py [n_side]     (317: 100k nodes)
"""

from __future__ import annotations

import json
import sys
import time

from mlpg_assembly import scene

from efgkit import MLPG
from efgkit.methods.local import DEFAULT_MLPG_PENALTY, discretize_local, local_system
from efgkit.system.krylov import solve_unsymmetric
from efgkit.system.linear_system import LinearSystem


def main(n_side: int = 317, solver: str = "gmres") -> dict:
    h = 1.0 / (n_side - 1)
    sc = scene()
    t0 = time.perf_counter()
    d = discretize_local(sc, MLPG(spacing=h))
    K, f = local_system(d, DEFAULT_MLPG_PENALTY * sc.material.E / h)
    t1 = time.perf_counter()
    z, info = solve_unsymmetric(LinearSystem(K, f, False, K.shape[0]), solver)
    t2 = time.perf_counter()
    return {"n_nodes": d.nodes.n, "n_unknowns": K.shape[0], "nnz": K.nnz,
            "assembly_seconds": t1 - t0, "solve_seconds": t2 - t1, "info": info}


if __name__ == "__main__":
    print(json.dumps(main(int(sys.argv[1]) if len(sys.argv) > 1 else 317), indent=1, default=str))
