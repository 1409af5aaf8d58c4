"""The row pass of the stiffness kernel alone, on one thread: time per (I, q, J) triple by
row order and against a revision's kernel; written to the ``assembly_rows`` section of
docs/performance.md.

Run:  PYTHONPATH=. NUMBA_NUM_THREADS=1 python benchmarks/assembly_rows.py
      PYTHONPATH=. NUMBA_NUM_THREADS=1 python benchmarks/assembly_rows.py --quick --no-write

The shape functions of ``benchmarks/assembly.py`` (unit square, 4 x 4 Gauss points per cell,
points sorted by box, d_max 2.5). Timed is :func:`efgkit.system.kernels.block_rows` over all
rows (the blocks J >= I), called on the main thread: in node order, in the order the
assembly uses (the middle point of each function's point list, as
``efgkit.system.assemble`` forms it), and in strips of 8 node rows swept along x (which needs
the node coordinates, which ``stiffness(shape, w, D)`` does not have); and the ``block_rows``
of revision ``--before`` (node order, its own signature) on the same lists. Each round runs
every variant once (interleaved); median [quartiles] over the rounds. A triple is a trial
function J >= I met at a point q of test function I.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from efgkit import EFG, Domain, Elastic
from efgkit.nodes import generate_nodes
from efgkit.system.assemble import point_to_function_map
from efgkit.system.kernels import block_rows, compile_vectorised

sys.path.insert(0, str(Path(__file__).resolve().parent))
from assembly import efg_case, previous_kernels, quartiles  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def orders(case: dict, n_dofs: int, t_ptr, t_pos, k: int) -> dict:
    """Row orders: node order, the assembly's (middle point of each list), strips of 8."""
    n = len(t_ptr) - 1
    mid = np.full(n, np.iinfo(np.int64).max)
    has = t_ptr[1:] > t_ptr[:-1]
    mid[has] = t_pos[(t_ptr[:-1][has] + t_ptr[1:][has]) // 2] // k
    n_side = int(round(np.sqrt(n_dofs / 2)))
    h = 1.0 / (n_side - 1)
    x = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=h, d_max=case["d_max"])).x
    strip = np.lexsort((x[:, 1], x[:, 0], np.floor(x[:, 1] / (8 * h) + 1e-9)))
    return {"node order": np.arange(n), "middle point (the assembly's)":
            np.argsort(mid, kind="stable"), "strips of 8 node rows": strip}


def measure(n_dofs: int, rounds: int, old) -> dict:
    case = efg_case(n_dofs, 2.5)
    sh, w = case["shape"], case["w"]
    nb = sh.neighbours
    n, k = sh.n_functions, nb.idx.shape[1]
    D = np.ascontiguousarray(Elastic(1.0, 0.3).D)
    t_ptr, point, slot = point_to_function_map(sh)
    t_pos = (point * k + slot).astype(np.int32 if nb.idx.size < 2**31 else np.int64)
    counts = nb.mask.sum(axis=1)
    triples = int((counts[point] - slot).sum())  # valid entries first and ascending here
    def args(o):
        return (o, 0, n, t_ptr, t_pos, sh.ddx, sh.ddy, nb.idx, nb.mask, sh.ddx, sh.ddy, w, D,
                True, True, n, n * k * 2)

    compile_vectorised(block_rows, *args(np.arange(n)))  # as stiffness() compiles it
    runs = {name: (lambda o=o: block_rows(*args(o)))
            for name, o in orders(case, n_dofs, t_ptr, t_pos, k).items()}
    if old is not None:
        runs[f"revision {old.__name__.split('_')[-1]} (node order)"] = lambda: old.block_rows(
            0, n, t_ptr, t_pos, sh.ddx, sh.ddy, nb.idx, nb.mask, sh.ddx, sh.ddy, w, D, True,
            True, n, n * k * 2)
    ref, t = None, {name: [] for name in runs}
    for r in range(rounds + 1):  # round 0 compiles
        for name, fn in runs.items():
            t0 = time.perf_counter()
            lens, cols, data = fn()
            if r:
                t[name].append(time.perf_counter() - t0)
            total = (len(cols), float(np.abs(data).sum()))
            assert ref is None or total[0] == ref[0], name  # the same blocks in every order
            ref = total
    return {"n_dofs": 2 * n, "n_points": case["n_points"], "triples": triples,
            "rows": {name: {"s": quartiles(np.array(v)),
                            "ns_per_triple": quartiles(np.array(v) / triples * 1e9)}
                     for name, v in t.items()}}


def markdown(res: dict, cmd: str) -> str:
    lines = ["<!-- begin:assembly_rows -->",
             "## The row pass of the stiffness kernel alone, one thread "
             "(`benchmarks/assembly_rows.py`)", "",
             f"Command: `{cmd}` ({res['machine']}, {res['date']}; a shared 2-core machine "
             f"with other jobs running, load average {res['load']}). {res['rounds']} rounds "
             "after a warm-up, every variant once per round; median [quartiles] of the time "
             "over the rounds, and per (I, q, J) triple (a function J >= I met at a point q "
             "of I; d_max 2.5). `block_rows` of this tree in three row orders, and that of "
             f"revision `{res['before']}` (node order) on the same point lists.", "",
             "| unknowns | points | (I, q, J) triples | rows formed | s | ns per triple |",
             "|---|---|---|---|---|---|"]
    for row in res["sizes"]:
        for name, v in row["rows"].items():
            s, p = v["s"], v["ns_per_triple"]
            lines.append(f"| {row['n_dofs']} | {row['n_points']} | {row['triples']} | {name} | "
                         f"{s['median']:.3f} [{s['q25']:.3f}, {s['q75']:.3f}] | "
                         f"{p['median']:.2f} [{p['q25']:.2f}, {p['q75']:.2f}] |")
    lines += ["", "Between the revision's row and this tree's in node order: the indexing (flat "
              "views, unsigned indices: no wrap-around code) and the SLP vectoriser (this "
              "tree's kernel compiled as `stiffness` compiles it, by `compile_vectorised`); "
              "the row orders then change which points are still in cache when a row "
              "needs them. Every variant forms the same blocks.",
              "<!-- end:assembly_rows -->", ""]
    return "\n".join(lines)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--dofs", type=int, nargs="+", default=[20_000, 100_000])
    ap.add_argument("--before", default="406e76d", help="git revision ('' to skip)")
    ap.add_argument("--no-write", action="store_true", help="do not write docs/performance.md")
    args = ap.parse_args(argv)
    sizes = [2_000] if args.quick else args.dofs
    rounds = 2 if args.quick else args.rounds
    old = previous_kernels(args.before) if args.before else None
    load = os.getloadavg()[0]
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "rounds": rounds, "before": args.before,
           "sizes": [measure(n, rounds, old) for n in sizes]}
    res["load"] = f"{load:.1f} at the start, {os.getloadavg()[0]:.1f} at the end"
    cmd = ("PYTHONPATH=. NUMBA_NUM_THREADS=1 python benchmarks/assembly_rows.py"
           + (" --quick" if args.quick else "") + (f" --rounds {rounds}" if rounds != 7 else ""))
    if not args.no_write:
        from doc_sections import write_section

        from efgkit.io import write_json
        write_section(markdown(res, cmd), ROOT / "docs" / "performance.md")
        write_json(res, ROOT / "benchmarks" / "out" / "assembly_rows.json")
    return res


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1:]), indent=1, default=str))
