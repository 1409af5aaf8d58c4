"""Essential-BC methods per second at equal accuracy: Lagrange (Uzawa steps on the augmented
Lagrangian), Nitsche (``bc="variational"``) and penalty on one discretisation, solved with
CG (``solver="amg"``), against SuperLU references; written to docs/performance.md.

Run:  PYTHONPATH=. python benchmarks/bc_methods.py [--nodes 2e4] [--rounds 3]
      PYTHONPATH=. python benchmarks/bc_methods.py --scene kirsch --nodes 2e4

The cracked plate (default) is examples/edge_crack.toml with its spacings divided by a
factor (benchmarks/scaling.py); ``--scene kirsch`` is the Kirsch plate of
verification/kirsch.py (exact solution known). One process: the discretisation, the
stiffness and the loads are built once; then the methods take turns (A, B, C, A, B, C,
...) and each solve is timed (its "constraints" and "solve" stages). Accuracy: the
relative difference of K_I (cracked plate; the mean over the J domains) or of the
energy-norm error (Kirsch, against the exact field), and of the strain energy, against
SuperLU's solution of the Lagrange system on the same discretisation (the exactly
constrained discrete answer), and against SuperLU's solution of the same BC method (the
part of the difference that is the iterative solver's, not the BC method's).
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import sys
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BCS = ("lagrange", "variational", "penalty")


def problem(name: str, n_nodes: float):
    """(scene, method) of about ``n_nodes`` nodes."""
    if name == "kirsch":
        sys.path.insert(0, str(ROOT / "verification"))
        import kirsch

        # 8203 nodes at h = 0.0625 (verification/out/kirsch.json): nodes ~ 1 / h^2
        return kirsch.scene(), kirsch.method(0.0625 * math.sqrt(8203 / n_nodes))
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import scaling

    return scaling.scaled(math.sqrt(n_nodes / scaling.BASE_NODES))


def measures(sol, name: str) -> dict:
    """K_I, K_II (cracked) or the energy-norm error (Kirsch), and the strain energy."""
    out = {"energy": sol.strain_energy()}
    if name == "kirsch":
        out["energy_error"] = sol.errors()["energy"]
    else:
        tip = sol.sifs(error=False)[0]
        out.update(KI=tip.KI, KII=tip.KII)
    return out


def main(argv=None) -> dict:
    from efgkit.methods.boundary import loads
    from efgkit.methods.discretize import discretize
    from efgkit.static import solve
    from efgkit.system.assemble import stiffness

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", choices=("edge_crack", "kirsch"), default="edge_crack")
    ap.add_argument("--nodes", type=float, default=2e4)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--bcs", nargs="+", choices=BCS, default=list(BCS), help="methods to time")
    ap.add_argument("--references", nargs="*", choices=BCS, default=list(BCS),
                    help="methods also solved by SuperLU (none: give the flag alone)")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    scene, method = problem(args.scene, args.nodes)
    method = method.for_scene(scene)
    t0 = time.perf_counter()
    disc = discretize(scene, method)
    K = stiffness(disc.shape, disc.points.w, scene.material.D)
    f = loads(disc)
    t_build = time.perf_counter() - t0
    solve(scene, replace(method, bc="penalty", solver="amg"), disc, K, f)  # warm-up
    ref = {}
    for bc in args.references:
        sol = solve(scene, replace(method, bc=bc, solver="direct"), disc, K, f)
        ref[bc] = measures(sol, args.scene) | {"seconds": sol.timings["constraints"]
                                               + sol.timings["solve"]}
    runs = {bc: [] for bc in args.bcs}
    for _ in range(args.rounds):
        for bc in args.bcs:
            sol = solve(scene, replace(method, bc=bc, solver="amg"), disc, K, f)
            info = sol.info
            runs[bc].append({"constraints_s": sol.timings["constraints"],
                             "solve_s": sol.timings["solve"],
                             "iterations": info.get("iterations"),
                             "uzawa_steps": info.get("uzawa_steps"),
                             "setup_s": info.get("setup_time"), "cg_s": info.get("cg_time"),
                             "solver": info.get("solver"), "fallback": info.get("fallback"),
                             "error_bound": info.get("error_bound"),
                             "residual": info.get("residual"), **measures(sol, args.scene)})
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "scene": args.scene, "nodes_asked": args.nodes, "n_nodes": disc.nodes.n, "n_dofs": disc.n_dofs,
           "n_points": disc.points.n, "build_s": t_build, "rounds": args.rounds,
           "reference": ref, "runs": runs}
    if not args.no_write:
        from doc_sections import write_section

        from efgkit.io import write_json

        cmd = (f"PYTHONPATH=. python benchmarks/bc_methods.py --scene {args.scene} "
               f"--nodes {args.nodes:g} --rounds {args.rounds}"
               + (f" --bcs {' '.join(args.bcs)}" if list(args.bcs) != list(BCS) else "")
               + (f" --references {' '.join(args.references)}"
                  if list(args.references) != list(BCS) else ""))
        write_section(markdown(res, cmd), ROOT / "docs" / "performance.md")
        write_json(res, ROOT / "benchmarks" / "out" / f"bc_methods_{args.scene}.json")
    return res


def rel(a, b) -> float:
    return abs(a / b - 1.0) if b else math.inf


def markdown(res: dict, cmd: str) -> str:
    name = res["scene"]
    key = "energy_error" if name == "kirsch" else "KI"
    what = "energy-norm error" if name == "kirsch" else "K_I"
    ref = res["reference"]
    tag = f"bc_methods_{name}" + ("" if res["nodes_asked"] == 2e4 else f"_{int(res['nodes_asked'])}")
    lines = [f"<!-- begin:{tag} -->",
             f"## BC methods per second at equal accuracy ({name}, {res['n_nodes']} nodes)", "",
             f"Generated by `{cmd}` on {res['machine']} ({res['date']}), a machine shared with "
             f"other jobs (2 cores): one process, one discretisation ({res['n_dofs']} unknowns, "
             f"{res['n_points']} points, built in {res['build_s']:.1f} s), the methods taking "
             f"turns over {res['rounds']} rounds; medians. 'solve' = constraints + CG "
             "(solver=\"amg\", Uzawa steps for Lagrange). Accuracy against SuperLU on the same "
             "discretisation: of the Lagrange system (the exactly constrained answer) and of "
             "the same method's system (the CG part alone).", "",
             f"| bc | solve s | of which CG s | CG iterations | Uzawa steps | {what} | "
             f"vs Lagrange (direct) | vs own direct | energy vs Lagrange (direct) | "
             "error bound |", "|---|---|---|---|---|---|---|---|---|---|"]
    for bc, rs in res["runs"].items():
        t = statistics.median(r["constraints_s"] + r["solve_s"] for r in rs)
        cg = statistics.median((r["cg_s"] or 0.0) for r in rs)
        r = rs[-1]
        lag, own = ref.get("lagrange"), ref.get(bc)
        lines.append(
            f"| {bc} | {t:.2f} | {cg:.2f} | {r['iterations']} | {r['uzawa_steps'] or '-'} | "
            f"{r[key]:.6g} | {rel(r[key], lag[key]) if lag else math.nan:.1e} | "
            f"{rel(r[key], own[key]) if own else math.nan:.1e} | "
            f"{rel(r['energy'], lag['energy']) if lag else math.nan:.1e} | "
            f"{r['error_bound']:.1e} |" + (f" fell back: {r['fallback']}" if r["fallback"] else ""))
    if ref:
        lines += ["", "SuperLU references (s, " + what + "): " + ", ".join(
            f"{bc} {v['seconds']:.1f} s, {v[key]:.6g}" for bc, v in ref.items()) + "."]
    lines += ["", "What the default does with it: `bc=\"auto\"` on a scene with crack tips takes Nitsche "
              "(`variational`) instead of Lagrange multipliers where CG solves (more than "
              "`AUTO_AMG_THRESHOLD` unknowns; `efgkit.static.large_system_bc`): as consistent as the "
              "multipliers, one SPD solve instead of Uzawa steps. The penalty method stays the choice "
              "without tips only: its K error reaches 13 times the multipliers' (docs/verification.md, "
              "`defaults`).",
              f"<!-- end:{tag} -->", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    import json

    out = main(sys.argv[1:])
    print(markdown(out, "bc_methods.py"))
    print(json.dumps({bc: [{k: v for k, v in r.items()} for r in rs] for bc, rs in out["runs"].items()},
                     indent=None, default=str))
