"""The stiffness call of the cracked plate (examples/edge_crack.toml at a smaller spacing, as
``benchmarks/scaling.py`` builds it): this tree against a revision, interleaved in one
process; written to the ``assembly_cracked`` section of docs/performance.md.

Run:  PYTHONPATH=. NUMBA_NUM_THREADS=2 python benchmarks/assembly_cracked.py
      PYTHONPATH=. NUMBA_NUM_THREADS=2 python benchmarks/assembly_cracked.py --quick --no-write

The scene is discretised once (not streamed: all shape functions formed); timed is
``stiffness(disc.shape, w, D)`` (nodal rows, nodal-enrichment rows of the tip's extrinsic
unknowns, K_ee, blocks stacked) and the same call on the nodal part alone, each by this
tree and by revision ``--before`` (its assemble.py and kernels.py loaded from git), one
after the other in every round; median [quartiles] over the rounds.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from efgkit.approx.shape import Shape
from efgkit.methods.discretize import discretize
from efgkit.system.assemble import stiffness

sys.path.insert(0, str(Path(__file__).resolve().parent))
from assembly import previous_kernels, quartiles  # noqa: E402
from scaling import scaled  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def measure(nodes: float, rounds: int, old) -> dict:
    scene, method = scaled(math.sqrt(nodes / 1170))
    disc = discretize(scene, method)
    sh, w = disc.shape, disc.points.w
    D = np.ascontiguousarray(scene.material.D)
    nodal = Shape(sh.neighbours, sh.values, sh.ddx, sh.ddy, sh.n_functions)
    runs = {"now": lambda: stiffness(sh, w, D), "before": lambda: old.assemble.stiffness(sh, w, D),
            "now nodal": lambda: stiffness(nodal, w, D),
            "before nodal": lambda: old.assemble.stiffness(nodal, w, D)}
    t = {k: [] for k in runs}
    diff = 0.0
    for r in range(rounds + 1):  # round 0 compiles
        out = {}
        for k, fn in runs.items():
            t0 = time.perf_counter()
            out[k] = fn()
            if r:
                t[k].append(time.perf_counter() - t0)
        A, B = out["now"], out["before"]
        A.sort_indices()
        B.sort_indices()
        same = np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
        diff = max(diff, float(abs(A - B).max() / abs(B).max()) if same else np.inf)
        del out, A, B
    ratio = {k: quartiles(np.array(t[f"before{k}"]) / np.array(t[f"now{k}"]))
             for k in ("", " nodal")}
    return {"nodes": int(disc.nodes.n), "points": len(w), "n_extra": int(sh.extra.n),
            "K_nnz": int(stiffness(sh, w, D).nnz), "K_max_rel_diff": diff,
            "s": {k: quartiles(np.array(v)) for k, v in t.items()}, "speedup": ratio}


def markdown(res: dict, cmd: str) -> str:
    def q(v, f=".3f"):
        return f"{v['median']:{f}} [{v['q25']:{f}}, {v['q75']:{f}}]"

    lines = ["<!-- begin:assembly_cracked -->",
             "## Stiffness call of the cracked plate, before and after "
             "(`benchmarks/assembly_cracked.py`)", "",
             f"Command: `{cmd}` ({res['machine']}, {res['date']}, 2 numba threads; a shared "
             f"2-core machine with other jobs running, load average {res['load']}). The edge-"
             "cracked plate of `benchmarks/scaling.py` discretised once (all shape functions "
             "formed); each round times `stiffness(shape, w, D)` with the tip's enrichment "
             "unknowns and on the nodal part alone, by this tree and by revision "
             f"`{res['before']}`; median [quartiles] over {res['rounds']} rounds. K against "
             "the one before: the same pattern, and max |K - K_before| / max |K_before|.", "",
             "| nodes | points | enrichment unknowns | nonzeros | before s | now s | speed-up "
             "| nodal part: before s | now s | speed-up | K difference |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in res["sizes"]:
        s = r["s"]
        lines.append(f"| {r['nodes']} | {r['points']} | {r['n_extra']} | {r['K_nnz']} | "
                     f"{q(s['before'])} | {q(s['now'])} | **{q(r['speedup'][''], '.2f')}** | "
                     f"{q(s['before nodal'])} | {q(s['now nodal'])} | "
                     f"**{q(r['speedup'][' nodal'], '.2f')}** | {r['K_max_rel_diff']:.1e} |")
    lines += ["", "The nodal part is the row kernel of the sections above. The rows of the "
              "enrichment unknowns' columns (K_ne = sum_q B_I^T sigma of each unknown) were "
              "products of the transposed derivative operators, built a chunk of 131072 "
              "points at a time, with the stresses; they are now summed row by row over the "
              "same point lists by `efgkit.system.kernels.extra_rows` (the values to "
              "rounding: the products are grouped differently), and the four blocks are "
              "stacked into one CSR copying each entry once (`bmat` copied K_nn twice).",
              "<!-- end:assembly_cracked -->", ""]
    return "\n".join(lines)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--nodes", type=float, nargs="+", default=[19564])
    ap.add_argument("--before", default="406e76d", help="git revision")
    ap.add_argument("--no-write", action="store_true", help="do not write docs/performance.md")
    args = ap.parse_args(argv)
    sizes = [3000] if args.quick else args.nodes
    rounds = 2 if args.quick else args.rounds
    old = previous_kernels(args.before)
    load = os.getloadavg()[0]
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "rounds": rounds, "before": args.before,
           "sizes": [measure(n, rounds, old) for n in sizes]}
    res["load"] = f"{load:.1f} at the start, {os.getloadavg()[0]:.1f} at the end"
    cmd = ("PYTHONPATH=. NUMBA_NUM_THREADS=2 python benchmarks/assembly_cracked.py"
           + (" --quick" if args.quick else "") + (f" --rounds {rounds}" if rounds != 5 else ""))
    if not args.no_write:
        from doc_sections import write_section

        from efgkit.io import write_json
        text = markdown(res, cmd)
        path = ROOT / "docs" / "performance.md"
        if "<!-- begin:assembly_cracked -->" not in path.read_text():  # below the row pass
            marker = "<!-- end:assembly_rows -->\n"
            path.write_text(path.read_text().replace(marker, marker + text, 1))
        else:
            write_section(text, path)
        write_json(res, ROOT / "benchmarks" / "out" / "assembly_cracked.json")
    return res


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1:]), indent=1, default=str))
