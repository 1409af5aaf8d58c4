"""Stiffness assembly against scikit-fem P2 at equal unknowns, interleaved in one process;
written to the ``assembly`` section of docs/performance.md (``--before`` a revision with the
row kernel, e.g. 406e76d: the ``assembly_flat`` section).

Run:  PYTHONPATH=. NUMBA_NUM_THREADS=2 python benchmarks/assembly.py   (~20k and ~100k unknowns)
      PYTHONPATH=. NUMBA_NUM_THREADS=2 python benchmarks/assembly.py --before 406e76d
      PYTHONPATH=. python benchmarks/assembly.py --quick --before ""  (a smoke run)

EFG: unit square of n x n nodes, 4 x 4 Gauss points per cell of one spacing (points sorted
by box, as the discretisation does), MLS linear basis, d_max 2.5 and 2.0; timed is the call
``stiffness(shape, w, D)`` (point lists of the functions, pattern and blocks, CSR) and,
apart, the point lists alone; with ``--before REV`` also the row kernels of git
revision REV (pattern pass, blocks pass, mirror, BSR to CSR) on the same shape
functions, whose K is compared with today's, and their pattern alone (point lists and
column pattern); when REV already has the row kernel (``block_rows``), its whole
``stiffness`` path (its kernels.py and assemble.py loaded from git) and its point lists.
scikit-fem: ``asm(linear_elasticity, basis)`` of vector P2 on a structured triangle mesh
with (2m + 1)^2 nodes, the ``Basis`` built once outside the timing. Each round times EFG
(every d_max) then scikit-fem, one after the other (A, B, A, B, ...); each ratio of each
round is EFG / scikit-fem of that round, reported as the median with its quartiles over the
rounds. One warm-up round compiles the kernels.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import subprocess
import sys
import tempfile
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


def previous_kernels(rev: str):
    """efgkit/system/kernels.py of git revision ``rev`` as a module (None without git); when
    it has the row kernel (``block_rows``), its ``assemble`` module too, as ``.assemble``."""
    kernels = load_revision(rev, "kernels", {"from ..timing import": "from efgkit.timing import"})
    if kernels is not None and hasattr(kernels, "block_rows"):
        kernels.assemble = load_revision(rev, "assemble", {
            "from ..approx.shape import": "from efgkit.approx.shape import",
            "from ..jit import": "from efgkit.jit import",
            "from .kernels import": f"from {kernels.__name__} import"})
    return kernels


def load_revision(rev: str, name: str, imports: dict):
    """efgkit/system/``name``.py of git revision ``rev`` as the module ``name_rev``, its
    relative imports rewritten by ``imports`` (None without git)."""
    try:
        src = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:efgkit/system/{name}.py"],
                             capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    path = Path(tempfile.gettempdir()) / "efgkit_assembly_before" / f"{name}_{rev}.py"
    for a, b in imports.items():
        src = src.replace(a, b)
    if not path.exists() or path.read_text() != src:  # keep numba's cache of it
        path.parent.mkdir(exist_ok=True)
        path.write_text(src)
    spec = importlib.util.spec_from_file_location(f"{name}_{rev}", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # numba's cache looks the module up by name
    spec.loader.exec_module(mod)
    return mod


def stiffness_before(old, sh, w, D, pattern_only=False):
    """Symmetric K by the kernels ``old`` of :func:`previous_kernels`. With the row kernel:
    that revision's ``_compiled`` (``pattern_only``: its point lists alone); before it: point
    lists, column pattern (two passes; ``pattern_only``: up to here), blocks J >= I, mirror,
    BSR to CSR."""
    import numba
    from scipy.sparse import bsr_array, csr_array

    if hasattr(old, "block_rows"):
        if pattern_only:
            return old.assemble.point_to_function_map(sh)
        return old.assemble._compiled(sh, sh, w, np.ascontiguousarray(D, float))
    threads, nb = numba.get_num_threads(), sh.neighbours
    t_ptr, t_point, t_slot = old.transpose_padded(nb.idx, nb.mask, sh.n_functions)
    indptr, cols = old.pattern(t_ptr, t_point, nb.idx, nb.mask, sh.n_functions, threads)
    if pattern_only:
        return indptr, cols
    data = old.stiffness_blocks(indptr, cols, t_ptr, t_point, t_slot, sh.ddx, sh.ddy, nb.idx,
                                nb.mask, sh.ddx, sh.ddy, w, D, True, threads)
    old.mirror_upper(indptr, cols, data)
    n2 = 2 * sh.n_functions
    return csr_array(bsr_array((data, cols, indptr), shape=(n2, n2)).tocsr())


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


def measure(n_dofs: int, rounds: int, old=None, d_maxes=(2.5, 2.0)) -> dict:
    """Interleaved rounds at about ``n_dofs`` unknowns (``old``: kernels of a revision)."""
    from skfem import asm

    D = Elastic(1.0, 0.3).D
    cases = [efg_case(n_dofs, d) for d in d_maxes]
    basis, form = fem_case(n_dofs)
    t = {"fem": []}
    nnz, diff = {}, {}
    for r in range(rounds + 1):  # round 0: warm-up (compiles), not counted
        for c in cases:
            sh, w, d = c["shape"], c["w"], c["d_max"]
            runs = {f"efg_{d}": lambda sh=sh, w=w: stiffness(sh, w, D),
                    f"lists_{d}": lambda sh=sh: point_to_function_map(sh)}
            if old is not None:
                runs[f"before_{d}"] = lambda sh=sh, w=w: stiffness_before(old, sh, w, D)
                runs[f"before_pattern_{d}"] = \
                    lambda sh=sh, w=w: stiffness_before(old, sh, w, D, True)
            out = {}
            for key, fn in runs.items():
                dt, out[key] = clock(fn)
                if r:
                    t.setdefault(key, []).append(dt)
                if key == f"before_{d}":  # same pattern, values to rounding
                    K, Kb = out[f"efg_{d}"], out[key]
                    Kb.sort_indices()
                    rel = float(abs(K - Kb).max() / abs(Kb).max())
                    pattern = np.array_equal(K.indptr, Kb.indptr) and np.array_equal(
                        K.indices, Kb.indices)
                    diff[d] = max(diff.get(d, 0.0), rel if pattern else np.inf)
            nnz[d] = int(out[f"efg_{d}"].nnz)
            del out
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
        efg, lists = np.array(t[f"efg_{d}"]), np.array(t[f"lists_{d}"])
        row = {"d_max": d, "n_dofs": c["n_dofs"], "n_points": c["n_points"],
               "neighbours_mean": c["neighbours_mean"], "K_nnz": nnz[d],
               "stiffness_s": quartiles(efg), "lists_s": quartiles(lists),
               "ratio": quartiles(efg / fem)}
        if old is not None:
            b, bp = np.array(t[f"before_{d}"]), np.array(t[f"before_pattern_{d}"])
            row.update({"before_s": quartiles(b), "before_pattern_s": quartiles(bp),
                        "before_ratio": quartiles(b / fem), "speedup": quartiles(b / efg),
                        "K_max_rel_diff": diff[d]})
        out["efg"].append(row)
    return out


def markdown(res: dict, cmd: str) -> str:
    if res.get("before_kind") == "rows":
        return markdown_rows(res, cmd)
    lines = ["<!-- begin:assembly -->", "## Stiffness assembly against scikit-fem P2, interleaved "
             "(`benchmarks/assembly.py`)", "",
             f"Command: `{cmd}` ({res['machine']}, {res['date']}, {res['threads']} numba "
             f"threads; a shared 2-core machine with other jobs running). {res['rounds']} "
             "rounds after a warm-up, each round timing the EFG `stiffness(shape, w, D)` "
             "call, its point lists of the functions alone, the kernels of revision "
             f"`{res['before']}` (before) on the same shape functions and their pattern "
             "alone, then scikit-fem `asm` of vector P2 elasticity at about the same number "
             "of unknowns (the `Basis` built outside the timing); each ratio is taken per "
             "round, median [quartiles] over the rounds. K against the one before: the same "
             "indptr and indices, and max |K - K_before| / max |K_before| (rounding: the "
             "products are grouped differently).", "",
             "| unknowns EFG / P2 | d_max | points | nonzeros EFG / P2 | P2 asm s | before s "
             "(of which pattern) | **EFG / P2 before** | now s (of which point lists) | "
             "**EFG / P2 now** | speed-up | K difference |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]

    for row in res["rows"]:
        f = row["fem_s"]
        for e in row["efg"]:
            before = (f"{e['before_s']['median']:.3f} ({e['before_pattern_s']['median']:.3f}) | "
                      f"{q(e['before_ratio'])}" if "before_s" in e else "| ")
            lines.append(
                f"| {e['n_dofs']} / {row['n_dofs_fem']} | {e['d_max']} | {e['n_points']} | "
                f"{e['K_nnz']} / {row['K_nnz_fem']} | {f['median']:.3f} | {before} | "
                f"{e['stiffness_s']['median']:.3f} ({e['lists_s']['median']:.3f}) | "
                f"{q(e['ratio'])} | "
                + (f"{q(e['speedup'])} | {e['K_max_rel_diff']:.1e} |"
                   if "before_s" in e else " | |"))
    worst = max(e["ratio"]["median"] for row in res["rows"] for e in row["efg"]
                if e["d_max"] == 2.5)
    lines += ["", "Target: EFG / P2 <= 1.5 at d_max 2.5 "
              + ("(reached at every size of this run)." if worst <= 1.5 else
                 f"(not reached at every size of this run: worst median {worst:.2f})."),
              "Before, the point lists of the functions (serial), the column pattern (two "
              "passes over the points of every row) and the blocks (a third pass) each "
              "visited every (row, point, neighbour) triple, then the blocks were mirrored "
              "and BSR converted to CSR. Now the point lists are one array `q k + a` filled "
              "in parallel (count, then fill), and one pass per row both lists the columns "
              "met (a marker per column) and sums the 2 x 2 blocks into a dense accumulator "
              "(Gustavson's row-by-row sparse product), for the blocks J >= I only and, when "
              "the neighbour lists ascend, from the row's own slot on; chunks of rows of "
              "equal work run on threads (the kernel releases the GIL). The scalar CSR "
              "(int32 indices) is written straight from these upper rows, the blocks J < I "
              "as transposes. Each (I, q) pair forms 6 coefficients of w_q B_I^T D once, "
              "leaving 8 products per (I, q, J).", "<!-- end:assembly -->", ""]
    return "\n".join(lines)


def q(v):
    return f"**{v['median']:.2f}** [{v['q25']:.2f}, {v['q75']:.2f}]"


def markdown_rows(res: dict, cmd: str) -> str:
    """The section against a revision that already had the row kernel (``before_kind`` rows)."""
    lines = ["<!-- begin:assembly_flat -->", "## Stiffness assembly against scikit-fem P2 after "
             "the row-kernel tuning (`benchmarks/assembly.py --before "
             f"{res['before']}`)", "",
             f"Command: `{cmd}` ({res['machine']}, {res['date']}, {res['threads']} numba "
             f"threads; a shared 2-core machine with other jobs running, load average "
             f"{res['load']}). {res['rounds']} rounds after a warm-up, each round timing "
             "the EFG `stiffness(shape, w, D)` call of this tree and its point lists alone, "
             f"the same call of revision `{res['before']}` (before) and its point lists "
             "alone on the same shape functions, then scikit-fem `asm` of vector P2 "
             "elasticity at about the same number of unknowns (the `Basis` built outside the "
             "timing); each ratio is taken per round, median [quartiles] over the rounds. K "
             "against the one before: the same indptr and indices, and max |K - K_before| / "
             "max |K_before| (0: the same sums in the same order).", "",
             "| unknowns EFG / P2 | d_max | points | nonzeros EFG / P2 | P2 asm s | before s "
             "(of which point lists) | **EFG / P2 before** | now s (of which point lists) | "
             "**EFG / P2 now** | speed-up | K difference |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in res["rows"]:
        f = row["fem_s"]
        for e in row["efg"]:
            lines.append(
                f"| {e['n_dofs']} / {row['n_dofs_fem']} | {e['d_max']} | {e['n_points']} | "
                f"{e['K_nnz']} / {row['K_nnz_fem']} | {f['median']:.3f} | "
                f"{e['before_s']['median']:.3f} ({e['before_pattern_s']['median']:.3f}) | "
                f"{q(e['before_ratio'])} | {e['stiffness_s']['median']:.3f} "
                f"({e['lists_s']['median']:.3f}) | {q(e['ratio'])} | {q(e['speedup'])} | "
                f"{e['K_max_rel_diff']:.1e} |")
    worst = max(e["ratio"]["median"] for row in res["rows"] for e in row["efg"]
                if e["d_max"] == 2.5)
    lines += ["", "Target: EFG / P2 <= 1.5 at d_max 2.5 "
              + ("(reached at every size of this run)." if worst <= 1.5 else
                 f"(not reached at every size of this run: worst median {worst:.2f}).")]
    lines += NOTES_FLAT + ["<!-- end:assembly_flat -->", ""]
    return "\n".join(lines)


NOTES_FLAT = [
    "What changed against the revision before (the same algorithm: Gustavson's row-by-row "
    "accumulation of the 2 x 2 blocks J >= I, point lists `q k + a`, scalar CSR written "
    "from the upper rows; the same sums in the same order, so K is unchanged to the bit): "
    "(1) the padded (point, slot) arrays and the accumulator are read through flat views "
    "indexed with unsigned integers, so numba emits no negative-index wrap-around code (a "
    "sign test and a masked add per index) in the inner loop over (I, q, J); (2) the row "
    "kernel is compiled with LLVM's SLP vectoriser on (numba's default is off), which "
    "packs the four read-modify-writes of block (I, J) and their eight products into "
    "vector instructions, the same operations lane by lane; (3) the rows are formed in "
    "the order of the middle point of each function's point list: the points come sorted "
    "by box, so consecutive rows have nearby supports and the points they share are still "
    "in cache; (4) the point lists (count, then fill) and the scalar CSR writing are nogil "
    "kernels over ranges of points or rows handed out by a thread pool, as the row pass "
    "already was, instead of `prange` loops, whose OpenMP barrier waits for a thread the "
    "shared machine has descheduled. The next section has the row pass alone: (1) and "
    "(2) together against the revision, and the row orders of (3). The upper rows are "
    "stored in the order they are formed and addressed by offset and length. On this "
    "loaded machine the times of a variant move by up to 2x between rounds (hence the "
    "quartiles); what is left is mostly the row pass: about 160M (I, q, J) triples at "
    "100k unknowns and d_max 2.5, each a read of phi_J's gradient, the marker test that "
    "lists J the first time it is met, and the update of "
    "block (I, J) in the accumulator.",
]


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--dofs", type=int, nargs="+", default=[20_000, 100_000])
    ap.add_argument("--before", default="d11158e",
                    help="git revision of the old row kernels ('' to skip)")
    ap.add_argument("--no-write", action="store_true", help="do not write docs/performance.md")
    args = ap.parse_args(argv)
    from numba import get_num_threads

    sizes = [20_000] if args.quick else args.dofs
    rounds = 2 if args.quick else args.rounds
    old = previous_kernels(args.before) if args.before else None
    load = os.getloadavg()[0]
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "threads": get_num_threads(), "rounds": rounds, "before": args.before,
           "before_kind": "rows" if hasattr(old, "block_rows") else "passes",
           "rows": [{"n_dofs": n, **measure(n, rounds, old)} for n in sizes]}
    res["load"] = f"{load:.1f} at the start, {os.getloadavg()[0]:.1f} at the end"
    cmd = ("PYTHONPATH=. NUMBA_NUM_THREADS=2 python benchmarks/assembly.py"
           + (" --quick" if args.quick else "") + (f" --rounds {rounds}" if rounds != 7 else "")
           + (f" --before {args.before}" if args.before != "d11158e" else ""))
    if not args.no_write:
        from doc_sections import write_section
        write_section(markdown(res, cmd), ROOT / "docs" / "performance.md")
        write_json(res, ROOT / "benchmarks" / "out" / "assembly.json")
    return res


if __name__ == "__main__":
    out = main(sys.argv[1:])
    print(json.dumps(out, indent=1, default=str))
