"""Stiffness assembly against scikit-fem P2 at equal unknowns, interleaved in one process;
written to the ``assembly`` section of docs/performance.md.

Run:  NUMBA_NUM_THREADS=2 python benchmarks/assembly.py             (~20k and ~100k unknowns)
      python benchmarks/assembly.py --quick                         (a smoke run)

EFG: unit square of n x n nodes, 4 x 4 Gauss points per cell of one spacing (points sorted
by box, as the discretisation does), MLS linear basis, d_max 2.5 and 2.0; timed is the call
``stiffness(shape, w, D)`` (pattern, point lists of the functions, blocks, CSR) and, apart,
the pattern with the point lists alone. scikit-fem: ``asm(linear_elasticity, basis)`` of
vector P2 on a structured triangle mesh with (2m + 1)^2 nodes, the ``Basis`` built once
outside the timing. Each round times EFG (every d_max) then scikit-fem, one after the other
(A, B, A, B, ...); the ratio of each round is EFG / scikit-fem of that round, reported as
the median with its quartiles over the rounds. One warm-up round compiles the kernels.
"""

from __future__ import annotations

import argparse
import json
import platform
import re
import sys
import time
from pathlib import Path

import numpy as np

from efgkit import EFG, Domain, Elastic
from efgkit.approx.mls import mls_shape
from efgkit.io import write_json
from efgkit.nodes import generate_nodes
from efgkit.quadrature.cells import cell_points
from efgkit.search import BoxGrid, find_neighbours
from efgkit.system.assemble import point_to_function_map, stiffness

ROOT = Path(__file__).resolve().parents[1]


def efg_case(n_dofs: int, d_max: float) -> dict:
    """Shape functions on the square with about ``n_dofs`` unknowns (n_dofs / 2 nodes)."""
    n_side = int(round(np.sqrt(n_dofs / 2)))
    h = 1.0 / (n_side - 1)
    dom = Domain.rectangle(0, 0, 1, 1)
    nodes = generate_nodes(dom, EFG(spacing=h, d_max=d_max))
    pts = cell_points(dom, h, 4)
    boxes = BoxGrid.build(nodes)
    order = np.argsort(boxes.box_of(pts.x), kind="stable")
    x, w = pts.x[order], pts.w[order]
    nb = find_neighbours(x, nodes, boxes)
    return {"d_max": d_max, "shape": mls_shape(x, nodes, neighbours=nb), "w": w,
            "n_dofs": 2 * nodes.n, "n_points": len(x), "neighbours_mean": float(nb.counts.mean())}


def efg_pattern(sh):
    """The pattern of K alone (the point lists of the functions and the column pattern)."""
    import numba

    from efgkit.system.kernels import pattern

    t_ptr, t_point, _ = point_to_function_map(sh)
    nb = sh.neighbours
    return pattern(t_ptr, t_point, nb.idx, nb.mask, sh.n_functions, numba.get_num_threads())


def fem_case(n_dofs: int):
    """scikit-fem vector P2 basis and elasticity form with about ``n_dofs`` unknowns."""
    from skfem import Basis, ElementTriP2, ElementVector, MeshTri
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    m = int(round((np.sqrt(n_dofs / 2) - 1) / 2))  # (2m + 1)^2 P2 nodes
    mesh = MeshTri.init_tensor(np.linspace(0, 1, m + 1), np.linspace(0, 1, m + 1))
    basis = Basis(mesh, ElementVector(ElementTriP2()))
    return basis, linear_elasticity(*lame_parameters(1.0, 0.3))


def clock(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def quartiles(v):
    q = np.percentile(v, [25, 50, 75])
    return {"median": float(q[1]), "q25": float(q[0]), "q75": float(q[2])}


def measure(n_dofs: int, rounds: int, d_maxes=(2.5, 2.0)) -> dict:
    """Interleaved rounds at about ``n_dofs`` unknowns."""
    from skfem import asm

    D = Elastic(1.0, 0.3).D
    cases = [efg_case(n_dofs, d) for d in d_maxes]
    basis, form = fem_case(n_dofs)
    t = {"fem": [], **{f"efg_{c['d_max']}": [] for c in cases},
         **{f"pattern_{c['d_max']}": [] for c in cases}}
    nnz = {}
    for r in range(rounds + 1):  # round 0: warm-up (compiles), not counted
        for c in cases:
            tk, K = clock(lambda c=c: stiffness(c["shape"], c["w"], D))
            tp, _ = clock(lambda c=c: efg_pattern(c["shape"]))
            nnz[c["d_max"]] = int(K.nnz)
            del K
            if r:
                t[f"efg_{c['d_max']}"].append(tk)
                t[f"pattern_{c['d_max']}"].append(tp)
        tf, Kf = clock(lambda: asm(form, basis))
        nnz["fem"] = int(Kf.nnz)
        del Kf
        if r:
            t["fem"].append(tf)
    fem = np.array(t["fem"])
    out = {"n_dofs_fem": int(basis.N), "K_nnz_fem": nnz["fem"], "fem_s": quartiles(fem),
           "efg": []}
    for c in cases:
        d = c["d_max"]
        efg, pat = np.array(t[f"efg_{d}"]), np.array(t[f"pattern_{d}"])
        out["efg"].append({"d_max": d, "n_dofs": c["n_dofs"], "n_points": c["n_points"],
                           "neighbours_mean": c["neighbours_mean"], "K_nnz": nnz[d],
                           "stiffness_s": quartiles(efg), "pattern_s": quartiles(pat),
                           "ratio": quartiles(efg / fem),
                           "pattern_share": quartiles(pat / efg)})
    return out


def markdown(res: dict, cmd: str) -> str:
    lines = ["<!-- begin:assembly -->", "## Stiffness assembly against scikit-fem P2, interleaved "
             "(`benchmarks/assembly.py`)", "",
             f"Command: `{cmd}` ({res['machine']}, {res['date']}, {res['threads']} numba "
             f"threads; a shared 2-core machine with other jobs running). {res['rounds']} "
             "rounds after a warm-up, each round timing the EFG `stiffness(shape, w, D)` "
             "calls and the pattern alone, then scikit-fem `asm` of vector P2 elasticity at "
             "about the same number of unknowns (the `Basis` built outside the timing); the "
             "ratio is taken per round, median [quartiles] over the rounds.", "",
             "| unknowns EFG / P2 | d_max | points | nonzeros EFG / P2 | EFG stiffness s | "
             "of which pattern s | P2 asm s | ratio EFG / P2 |",
             "|---|---|---|---|---|---|---|---|"]
    for row in res["rows"]:
        f = row["fem_s"]
        for e in row["efg"]:
            r = e["ratio"]
            lines.append(
                f"| {e['n_dofs']} / {row['n_dofs_fem']} | {e['d_max']} | {e['n_points']} | "
                f"{e['K_nnz']} / {row['K_nnz_fem']} | {e['stiffness_s']['median']:.3f} | "
                f"{e['pattern_s']['median']:.3f} | {f['median']:.3f} | "
                f"**{r['median']:.2f}** [{r['q25']:.2f}, {r['q75']:.2f}] |")
    lines += ["", *res.get("notes", []), "<!-- end:assembly -->", ""]
    return "\n".join(lines)


def write_section(text: str, path: Path) -> None:
    """Put the ``<!-- begin:NAME -->`` ... ``<!-- end:NAME -->`` section ``text`` into
    ``path``, replacing the section of the same name or appending it."""
    name = re.search(r"<!-- begin:(\w+) -->", text).group(1)
    old = path.read_text() if path.exists() else ""
    pat = re.compile(rf"<!-- begin:{name} -->.*?<!-- end:{name} -->\n?", re.S)
    new = pat.sub(lambda _: text, old) if pat.search(old) else old.rstrip("\n") + "\n\n" + text
    path.write_text(new)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--dofs", type=int, nargs="+", default=[20_000, 100_000])
    ap.add_argument("--no-write", action="store_true", help="do not write docs/performance.md")
    args = ap.parse_args(argv)
    from numba import get_num_threads

    sizes = [20_000] if args.quick else args.dofs
    rounds = 2 if args.quick else args.rounds
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "threads": get_num_threads(), "rounds": rounds,
           "rows": [{"n_dofs": n, **measure(n, rounds)} for n in sizes]}
    cmd = "NUMBA_NUM_THREADS=2 python benchmarks/assembly.py" + (" --quick" if args.quick else "")
    if not args.no_write:
        write_section(markdown(res, cmd), ROOT / "docs" / "performance.md")
        write_json(res, ROOT / "benchmarks" / "out" / "assembly.json")
    return res


if __name__ == "__main__":
    out = main(sys.argv[1:])
    print(json.dumps(out, indent=1, default=str))
