"""Load cases: ``efgkit.loadcases.solve_cases`` (one discretisation, one factorisation)
against separate ``solve`` calls, interleaved, median of ``--repeat`` runs.

Run:  python benchmarks/loadcases.py [--cases 8] [--repeat 5] [--spacing 0.175]

The shear edge crack of seed 003 (``efgkit.gallery.shear_edge_crack``) with ``--cases``
shear-plus-tension tractions on its top edge; EFG defaults at the given spacing.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings
from dataclasses import replace

from efgkit import EFG, Traction, solve
from efgkit.gallery import shear_edge_crack
from efgkit.loadcases import solve_cases


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--spacing", type=float, default=0.175)
    args = ap.parse_args(argv)
    base = shear_edge_crack()
    cases = {f"t{k}": replace(base, tractions=(Traction("top", (1.0, 0.1 * k)),)) for k in range(args.cases)}
    m = EFG(spacing=args.spacing)
    warnings.simplefilter("ignore")
    n = solve(base, m).nodes.n  # also the warm-up (numba)
    one, separate = [], []
    for _ in range(args.repeat):
        t = time.perf_counter()
        solve_cases(cases, m)
        one.append(time.perf_counter() - t)
        t = time.perf_counter()
        for sc in cases.values():
            solve(sc, m)
        separate.append(time.perf_counter() - t)
    res = {"cases": args.cases, "n_nodes": n, "solve_cases_s": statistics.median(one),
           "separate_s": statistics.median(separate),
           "ratio": statistics.median(separate) / statistics.median(one)}
    print(res)
    return res


if __name__ == "__main__":
    main()
