"""Core performance: MLS throughput, stiffness assembly against scikit-fem P2, the
end-to-end 100k-node static solve and the domain integrals of K, written to
docs/performance.md.

Run:  python benchmarks/core.py            (full: 100k nodes, ~2 minutes)
      python benchmarks/core.py --quick    (small sizes, a smoke run)

Timings are medians of ``--repeat`` runs in one process with time.perf_counter, after
one warm-up run that compiles the numba kernels. Comparisons are ratios measured
in the same run, since absolute times on a shared machine drift.
"""

from __future__ import annotations

import argparse
import json
import platform
import re
import statistics
import time
from pathlib import Path

import numpy as np

from efgkit import EFG, Domain, Elastic, Scene, Support, Traction, solve
from efgkit.approx.mls import mls_shape
from efgkit.fracture.integrals import domain_integrals
from efgkit.fracture.qfunctions import QFunction
from efgkit.gallery import singular_patch
from efgkit.io import write_json
from efgkit.nodes import generate_nodes
from efgkit.quadrature.cells import cell_points
from efgkit.search import BoxGrid, find_neighbours
from efgkit.system.assemble import stiffness

ROOT = Path(__file__).resolve().parents[1]


def timed(fn, repeat):
    """Median seconds of ``repeat`` calls (after one warm-up call) and the last result."""
    fn()
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def mls_and_assembly(n_side: int, repeat: int, d_max: float) -> dict:
    """100k-node square (n_side^2 nodes), 4 x 4 Gauss points per cell of one spacing.

    d_max = 2.5 gives ~20 neighbours per point (pi 2.5^2), d_max = 2 about 12.5.
    """
    h = 1.0 / (n_side - 1)
    dom = Domain.rectangle(0, 0, 1, 1)
    nodes = generate_nodes(dom, EFG(spacing=h, d_max=d_max))
    pts = cell_points(dom, h, 4)
    boxes = BoxGrid.build(nodes)
    x = pts.x[np.argsort(boxes.box_of(pts.x), kind="stable")]
    t_search, nb = timed(lambda: find_neighbours(x, nodes, boxes), repeat)
    t_mls, sh = timed(lambda: mls_shape(x, nodes, neighbours=nb), repeat)
    D = Elastic(1.0, 0.3).D
    t_K, K = timed(lambda: stiffness(sh, pts.w, D), repeat)
    return {"d_max": d_max, "n_nodes": nodes.n, "n_points": len(x),
            "neighbours_mean": float(nb.counts.mean()),
            "search_s": t_search, "mls_s": t_mls, "mls_points_per_s": len(x) / t_mls,
            "stiffness_s": t_K, "K_nnz": int(K.nnz)}


def skfem_p2(n_dofs_target: int, repeat: int) -> dict:
    """scikit-fem vector P2 elasticity assembly with about ``n_dofs_target`` unknowns."""
    from skfem import Basis, ElementTriP2, ElementVector, MeshTri, asm
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    # P2 on a structured triangle mesh of m x m cells has (2m + 1)^2 nodes.
    m = int(round((np.sqrt(n_dofs_target / 2) - 1) / 2))
    mesh = MeshTri.init_tensor(np.linspace(0, 1, m + 1), np.linspace(0, 1, m + 1))
    e = ElementVector(ElementTriP2())
    t_basis, basis = timed(lambda: Basis(mesh, e), repeat)
    form = linear_elasticity(*lame_parameters(1.0, 0.3))
    t_asm, K = timed(lambda: asm(form, basis), repeat)
    return {"n_dofs": int(basis.N), "basis_s": t_basis, "assemble_s": t_asm, "K_nnz": int(K.nnz)}


def end_to_end(spacing: float) -> dict:
    """Cantilever-like plate 2 x 1, clamped left, shear on the right; scene to stresses."""
    scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.25, "stress"),
                  supports=(Support("left", ux=0.0, uy=0.0),),
                  tractions=(Traction("right", (0.0, -1.0)),), name="plate")
    warm = EFG(spacing=0.25, bc="variational")
    solve(scene, warm)
    t0 = time.perf_counter()
    sol = solve(scene, EFG(spacing=spacing, bc="variational"))
    t1 = time.perf_counter()
    sol.stress()
    t2 = time.perf_counter()
    stages = {k: v for k, v in sol.timings.items() if k != "total"}
    stages["stress"] = t2 - t1
    return {"n_nodes": sol.nodes.n, "n_dofs": 2 * sol.nodes.n, "n_points": sol.disc.points.n,
            "solver": sol.info, "stages_s": stages, "total_s": t2 - t0}


def sif_integrals(n_side: int, repeat: int) -> dict:
    """Solution.sifs on an edge-cracked square (the singular patch of seed 003 with the Williams
    field by penalty) for 3 and 17 radii, against one pass over the points per domain."""
    scene = singular_patch(1.0, 0.0, material=Elastic(1.0, 0.3))  # efgkit.gallery
    sol = solve(scene, EFG(spacing=2.0 / (n_side - 1), bc="penalty", enrichment="none"))
    radii = {3: (0.3, 0.5, 0.7), 17: tuple(np.linspace(0.1, 0.9, 17))}
    out = {"n_nodes": sol.nodes.n, "n_points": sol.disc.points.n}
    for k, rs in radii.items():
        out[f"sifs_{k}_s"], res = timed(lambda rs=rs: sol.sifs(radii=rs, error=False), repeat)
        out[f"KI_{k}"] = res[0].KI
    x, w, tip, m = sol.disc.points.x, sol.disc.points.w, scene.tips[0], scene.material
    grad = sol.gradient()
    stress = sol.stress()

    def per_domain(rs=radii[17]):  # J, K with Wendland C2 q and T with the plateau q per radius
        return [(domain_integrals(x, w, stress, grad, tip, m, QFunction("wendland_c2", R)),
                 domain_integrals(x, w, stress, grad, tip, m, QFunction("plateau", R)))
                for R in rs]

    out["per_domain_17_s"], _ = timed(per_domain, repeat)
    return out


def markdown(res: dict, cmd: str) -> str:
    f, e, k = res["skfem"], res["end_to_end"], res["sif"]
    ratios = {m["d_max"]: m["stiffness_s"] / f["assemble_s"] for m in res["mls"]}
    lines = [
        "# Performance",
        "",
        f"Generated by `{cmd}` on {res['machine']} ({res['date']}). Medians of "
        f"{res['repeat']} runs after a warm-up that compiles the kernels; the ratio "
        "is measured in the same run.",
        "",
        "Work against accuracy (K and J errors against wall time, EFG variants beside "
        "scikit-fem P2): [performance_work_precision.md](performance_work_precision.md), "
        "generated by `python benchmarks/work_precision.py`.",
        "",
        "Explicit time stepping (steps per second against bare `K @ u`, output and DSIF cost, "
        "set-up): [performance_explicit.md](performance_explicit.md), generated by "
        "`python benchmarks/explicit.py`.",
        "Parameter studies on dask (speed-up on 1 and 2 workers, overhead per point against a "
        "plain loop): [performance_study.md](performance_study.md), generated by "
        "`python benchmarks/study.py`.",
        "",
        "## MLS shape functions (values + gradients, linear basis, quartic weight)",
        "",
        "| d_max | nodes | points (4x4 per cell) | mean neighbours | search s | MLS s | "
        "MLS points/s |",
        "|---|---|---|---|---|---|---|",
        *[f"| {m['d_max']} | {m['n_nodes']} | {m['n_points']} | {m['neighbours_mean']:.1f} | "
          f"{m['search_s']:.2f} | {m['mls_s']:.2f} | {m['mls_points_per_s']:.3g} |"
          for m in res["mls"]],
        "",
        "Target: >= 1.5e6 points/s with ~20 neighbours per point (d_max = 2.5).",
        "",
        "## Stiffness assembly against scikit-fem",
        "",
        "| | unknowns | nonzeros | seconds |",
        "|---|---|---|---|",
        *[f"| efgkit EFG stiffness, d_max = {m['d_max']} | {2 * m['n_nodes']} | {m['K_nnz']} | "
          f"{m['stiffness_s']:.2f} |" for m in res["mls"]],
        f"| scikit-fem `asm` vector P2 elasticity | {f['n_dofs']} | {f['K_nnz']} | "
        f"{f['assemble_s']:.2f} |",
        f"| scikit-fem `Basis` (P2 shape functions) | {f['n_dofs']} | | {f['basis_s']:.2f} |",
        "",
        "Ratio EFG / scikit-fem assembly: "
        + ", ".join(f"**{r:.2f}** (d_max = {d})" for d, r in ratios.items())
        + " (target <= 1.5). The EFG matrix has 4-6 times the nonzeros of P2 (MLS supports "
        "of radius d_max h overlap widely); the row kernel adds each quadrature point's "
        "contributions straight into the row's blocks, for the blocks J >= I only, finding "
        "the row's columns in the same pass, and writes the blocks J < I as transposes (K is "
        "symmetric); the row pass is most of the time (the assembly section below).",
        "",
        "## End-to-end static solve (scene to stresses at all quadrature points)",
        "",
        f"{e['n_nodes']} nodes, {e['n_dofs']} unknowns, {e['n_points']} quadrature points, "
        f"solver `{e['solver'].get('solver')}` (relative residual "
        f"{e['solver'].get('residual', float('nan')):.1e}"
        + (f"; CG with the {e['solver']['preconditioner']} preconditioner, "
           f"{e['solver']['iterations']} iterations, setup {e['solver']['setup_time']:.2f} s, "
           f"iterations {e['solver']['cg_time']:.2f} s" if "iterations" in e["solver"] else "")
        + ").",
        "",
        "| stage | seconds |",
        "|---|---|",
        *[f"| {k} | {v:.2f} |" for k, v in e["stages_s"].items()],
        f"| **total** | **{e['total_s']:.2f}** |",
        "",
        "Target: <= 15 s on this 2-core machine.",
        "",
        "## Stress intensity factors (`Solution.sifs`)",
        "",
        f"Edge-cracked square, {k['n_nodes']} nodes, {k['n_points']} quadrature points; "
        "K_I, K_II, J over each disc (Wendland C2 q) and T (plateau q), the stress and "
        "gradient at every point included.",
        "",
        "| | seconds |",
        "|---|---|",
        f"| `sifs`, 3 radii | {k['sifs_3_s']:.2f} |",
        f"| `sifs`, 17 radii | {k['sifs_17_s']:.2f} |",
        f"| one pass over the points per domain and per q, 17 radii | {k['per_domain_17_s']:.2f} |",
        "",
        "`sifs` forms the integrands once per tip over the largest disc and contracts them "
        "with the gradient of each q: "
        f"**{k['per_domain_17_s'] / k['sifs_17_s']:.1f}x** faster than a pass per domain "
        "for 17 radii (the K-against-radius curve of seed 001 Fig. 15).",
        "",
    ]
    return "\n".join(lines)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-write", action="store_true", help="do not write docs/performance.md")
    args = ap.parse_args(argv)
    n_side = 60 if args.quick else 317  # 317^2 = 100489 nodes
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}",
           "date": time.strftime("%Y-%m-%d"), "repeat": args.repeat}
    res["mls"] = [mls_and_assembly(n_side, args.repeat, d) for d in (2.5, 2.0)]
    res["skfem"] = skfem_p2(2 * res["mls"][0]["n_nodes"], args.repeat)
    res["end_to_end"] = end_to_end(2.0 / 447 if not args.quick else 0.05)
    res["sif"] = sif_integrals(41 if args.quick else 201, args.repeat)
    cmd = "python benchmarks/core.py" + (" --quick" if args.quick else "")
    if not args.no_write:
        path = ROOT / "docs" / "performance.md"
        # keep the sections other benchmarks write (<!-- begin:NAME --> ... <!-- end:NAME -->)
        kept = re.findall(r"<!-- begin:\w+ -->.*?<!-- end:\w+ -->\n?", path.read_text(), re.S) \
            if path.exists() else []
        path.write_text(markdown(res, cmd) + "".join("\n" + k for k in kept))
        write_json(res, ROOT / "benchmarks" / "out" / "core.json")
    return res


if __name__ == "__main__":
    out = main()
    print(json.dumps(out, indent=1, default=str))
