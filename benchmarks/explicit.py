"""Explicit time stepping: steps per second against bare ``K @ u`` on the same matrix, the
cost of output and SIF evaluation at an interval, and the set-up (mass, stable step).

Run:  python benchmarks/explicit.py            (full: ~80k nodes, d_max 2, a few minutes)
      python benchmarks/explicit.py --quick    (small, a smoke run)
      python benchmarks/explicit.py --method mlpg --side 141 --form petrov_galerkin   (MLPG1, ~20k nodes)

The scene is a unit square with an edge crack to its centre, clamped at the bottom edge
(Lagrange constraints, imposed by projection), a Heaviside traction on the top edge, EFG
with d_max 2, linear basis, 4 x 4 Gauss points per cell, no enrichment. In each of
``--repeat`` rounds, interleaved in one process: ``n`` bare products ``K @ u``, ``n`` steps of
:func:`efgkit.explicit.integrate` without output (the loop alone), and ``n`` steps with
probes, energies, VTU-free output and the default DSIF hook (dynamic J', interaction integral
with inertia, near-tip stresses) every ``--every`` steps. Medians
are reported; the machine is shared, so only ratios within one round mean much.

``--method mlpg``: MLPG1 with its defaults (d_max 2.5, quadratic basis, the trial weight of
explicit runs, ``MLPG.explicit_weight``), the bottom edge held by collocation rows (imposed
by the same projection); its K is unsymmetric, so the critical step comes from Arnoldi, and
the loop is the same sparse product and vector work. Its assembly needs about 40 disc points
per node: ``--side`` sets the nodes per side (default 141, ~20k nodes, for memory).
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from efgkit import EFG, MLPG, Crack, Domain, Elastic, Scene, Support, Traction
from efgkit.explicit import dynamics, integrate, stable_step
from efgkit.io import write_json
from efgkit.methods.discretize import discretize
from efgkit.problem.history import Heaviside, Stepping

ROOT = Path(__file__).resolve().parents[1]


def scene() -> Scene:
    return Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3, "strain", rho=1.0),
                 cracks=(Crack([[0.0, 0.5], [0.5, 0.5]], tips=(False, True)),),
                 supports=(Support("bottom", ux=0.0, uy=0.0),),
                 tractions=(Traction("top", (0.0, 1e-3), history=Heaviside()),), duration=1.0)


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--steps", type=int, default=None)
    p.add_argument("--every", type=int, default=None, help="output interval in steps")
    p.add_argument("--no-write", action="store_true")
    p.add_argument("--method", choices=("efg", "mlpg"), default="efg")
    p.add_argument("--side", type=int, default=None, help="nodes per side")
    p.add_argument("--form", choices=("petrov_galerkin", "galerkin"), default="galerkin",
                   help="MLPG.explicit_form (default: the form explicit MLPG runs take by default)")
    a = p.parse_args(argv)
    mlpg = a.method == "mlpg"
    n_side = a.side or (41 if a.quick else 141 if mlpg else 283)  # 283^2 = 80 089 nodes
    n = a.steps or (50 if a.quick else 200)
    every = a.every or (10 if a.quick else 100)
    sc = scene()
    setup = {}
    t0 = time.perf_counter()
    if mlpg:  # the disc of the explicit run (its trial weight) is built by dynamics
        method = MLPG(spacing=1.0 / (n_side - 1), bc="collocation", enrichment="none",
                      explicit_form=a.form)
        dyn = dynamics(sc, method)
        disc = dyn.disc
        setup["discretize"] = time.perf_counter() - t0 - sum(dyn.timings.values())
    else:
        method = EFG(spacing=1.0 / (n_side - 1), d_max=2.0, bc="lagrange", enrichment="none")
        disc = discretize(sc, method)
        setup["discretize"] = time.perf_counter() - t0
        dyn = dynamics(sc, method, disc)
    setup.update({k: v for k, v in dyn.timings.items()})
    t0 = time.perf_counter()
    crit = stable_step(dyn, tol=1e-6)
    setup["stable_step"] = time.perf_counter() - t0
    K = dyn.K
    u = np.random.default_rng(0).standard_normal(dyn.n_dofs)
    K @ u  # warm-up
    probes = tuple((x, 0.75) for x in np.linspace(0.1, 0.9, 10))
    plain = Stepping(safety=0.9, output_interval=1e30)  # records only the first and last instant
    out = Stepping(safety=0.9, output_interval=every * 0.9 * crit[0], probes=probes)
    kw = dict(dyn=dyn, critical=crit, progress=False)
    t0 = time.perf_counter()  # compiles the kernels and builds the DSIF operators (set-up)
    state = integrate(sc, method, out, steps=5, **kw).state
    setup["first_output"] = time.perf_counter() - t0
    rounds = []
    for _ in range(a.repeat):  # interleaved blocks; each run continues from the last state
        t0 = time.perf_counter()
        for _ in range(n):
            K @ u
        bare = n / (time.perf_counter() - t0)
        s1 = integrate(sc, method, plain, steps=n, dsif=None, state=state, **kw)
        loop = n / (s1.timings["loop"] - s1.timings["output"])
        s2 = integrate(sc, method, out, steps=n, state=s1.state, **kw)
        state = s2.state
        with_out = n / s2.timings["loop"]
        rounds.append({"bare": bare, "loop": loop, "with_output": with_out,
                       "output_seconds": s2.timings["output"], "n_outputs": len(s2.t)})
    med = {k: statistics.median(r[k] for r in rounds) for k in rounds[0]}
    res = {"n_nodes": disc.nodes.n, "n_dofs": dyn.n_dofs, "nnz": int(K.nnz), "steps": n,
           "every": every, "repeat": a.repeat, "setup": setup, "dt_critical": crit[0],
           "rounds": rounds, "median": med,
           "ratio_loop_to_bare": statistics.median(r["loop"] / r["bare"] for r in rounds),
           "slowdown_with_output": statistics.median(1 - r["with_output"] / r["loop"] for r in rounds),
           "constraint_rows": int(dyn.projection.G.shape[0]),
           "machine": f"{platform.machine()}, CPython {platform.python_version()}",
           "date": time.strftime("%Y-%m-%d"), "method": a.method,
           "weight": disc.method.weight, "d_max": disc.method.d_max,
           "form": a.form if mlpg else None}
    cmd = "python benchmarks/explicit.py" + (" --quick" if a.quick else "") + (
        f" --method mlpg --side {n_side}" + (" --form petrov_galerkin" if a.form == "petrov_galerkin" else "")
        if mlpg else "") + (f" --repeat {a.repeat}" if a.repeat != 5 else "")
    if not a.no_write:
        tag = "_mlpg" * mlpg + "_galerkin" * (mlpg and a.form == "galerkin") + "_quick" * a.quick
        write_json(res, ROOT / "benchmarks" / "out" / f"explicit{tag}.json")
        if not a.quick:
            (ROOT / "docs" / f"performance_explicit{tag}.md").write_text(markdown(res, cmd))
    print(json.dumps({k: res[k] for k in ("n_nodes", "nnz", "median", "ratio_loop_to_bare",
                                          "slowdown_with_output", "setup")}, indent=1, default=float))
    return res


def markdown(res: dict, cmd: str) -> str:
    m, s = res["median"], res["setup"]
    rows = ["| round | bare K @ u (1/s) | explicit steps (1/s) | ratio | with output (1/s) | "
            "slowdown |", "|---|---|---|---|---|---|"]
    for k, r in enumerate(res["rounds"]):
        rows.append(f"| {k + 1} | {r['bare']:.1f} | {r['loop']:.1f} | {r['loop'] / r['bare']:.2f} | "
                    f"{r['with_output']:.1f} | {1 - r['with_output'] / r['loop']:.1%} |")
    setup = ", ".join(f"{k} {v:.2f} s" for k, v in s.items())
    return "\n".join([
        "# Performance of the explicit driver", "",
        f"Generated by `{cmd}` on {res['machine']} ({res['date']}), a machine shared with other "
        "jobs: absolute rates drift, the ratios are measured in the same round.", "",
        f"Unit square with an edge crack to the centre, {res['n_nodes']} nodes ({res['n_dofs']} "
        f"unknowns), " + (("MLPG, the Galerkin form of its trial functions on the field cells "
                           "(explicit_form='galerkin'), " if res.get("form") == "galerkin" else
                           "MLPG1, ") + f"d_max {res['d_max']:g}, quadratic basis, trial weight "
                          f"{res['weight']} (explicit runs), " + ("4 x 4 Gauss points per field cell"
                          if res.get("form") == "galerkin" else "5 x 8 Gauss points per disc")
                          + ", no enrichment" if res.get("method") == "mlpg" else
                          "EFG d_max 2, linear basis, 4 x 4 Gauss points per cell, no enrichment")
        + f"; K has {res['nnz'] / 1e6:.1f}M non-zeros. Clamped bottom edge: "
        f"{res['constraint_rows']} " + ("collocation" if res.get("method") == "mlpg" else "Lagrange")
        + " constraint rows, imposed by projection every step. "
        f"Each round: {res['steps']} bare products `K @ u`, {res['steps']} steps without output, "
        f"{res['steps']} steps with output every {res['every']} steps (10 probes: displacement, "
        "velocity, stress; energies; the default DSIF hook `dynamic_dsif`: dynamic J' and the "
        "interaction integral with inertia over three domains, and the near-tip stress "
        "estimates; each run also records its first and last "
        "instant, so a block has one output more than the interval gives). Each run continues "
        "from the state of the previous one. K has 32-bit indices (`explicit.system`).", "",
        *rows, "",
        f"Medians: bare {m['bare']:.1f} products/s, explicit {m['loop']:.1f} steps/s (ratio "
        f"{res['ratio_loop_to_bare']:.2f}; target >= 0.8), with output {m['with_output']:.1f} steps/s "
        f"(slowdown {res['slowdown_with_output']:.1%}; target <= 20 %; {m['output_seconds']:.2f} s "
        f"for {m['n_outputs']:.0f} output instants).", "",
        f"Set-up (once): {setup}; critical step {res['dt_critical']:.4g} from "
        + ("Arnoldi (`eigs`" if res.get("method") == "mlpg" else "Lanczos (`eigsh`")
        + ", tol 1e-6) on the projected M^-1/2 K M^-1/2.", ""])


if __name__ == "__main__":
    main(sys.argv[1:])
