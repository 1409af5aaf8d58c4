"""Work against accuracy: error of K (singular patch) and of J (SENT) against wall time, for
EFG and MLPG variants and scikit-fem P2, written to docs/performance_work_precision.md.

Run:  python benchmarks/work_precision.py            (full, ~25 minutes)
      python benchmarks/work_precision.py --quick    (a smoke run, small sizes)
      python benchmarks/work_precision.py --mlpg     (MLPG beside EFG extrinsic MLS and graded
                                                      P2 only; prints the section of
                                                      docs/performance.md, ~10 minutes)
      PYTHONPATH=. python benchmarks/work_precision.py --interleaved --rounds 15
                                                     (the deciding EFG and P2 runs timed in
                                                      turns: benchmarks/work_interleaved.py)

Every point is the wall time (time.perf_counter) of the whole pipeline from the scene to
the stress intensity factors: discretisation or meshing, assembly, solve and the domain
integrals, the median of ``--repeat`` runs (one run for points above 5 s), all measured
in this run after a warm-up that compiles the numba kernels. Problems:

* singular patch (seed 003 Sect. 5.6.1): [-1, 1]^2, edge crack to the origin, the exact
  mode-I Williams field (K_I = 1) prescribed on the boundary; error |K_I - 1|;
* SENT of seed 001 (verification/sent.py): error |J / J_ref - 1| with J_ref from a finer
  graded P2 mesh than any timed one.

Each curve is refined until its error falls below 0.01 % or its sizes run out.
Headline: for each EFG variant, the time to reach 0.1 % error (log-log interpolation
between the bracketing points) divided by that of graded P2 with quarter-point tips.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

from efgkit import EFG, MLPG, Rosette, Scene, solve
from efgkit.fem.model import FEM, solve_fem
from efgkit.gallery import sent_seed001, singular_patch
from efgkit.io import write_json

ROOT = Path(__file__).resolve().parents[1]
TARGET = 1e-3  # 0.1 % error
L, W, D = 50.0, 10.0, 0.0253882  # SENT, seed 001 Sect. 4 (mm)

VARIANTS = {  # EFG options beyond the spacing; Nitsche supports (bc="variational")
    "linear + rosette": lambda h: {"rosette": Rosette(h), "enrichment": "none"},
    "radial": lambda h: {"enrichment": "radial", "crack_rule": "visibility"},  # seed 003 5.3.2
    "full intrinsic": lambda h: {"enrichment": "full", "d_max": 3.0},
    "extrinsic MLS": lambda h: {"enrichment": "extrinsic_mls"},
    "PU": lambda h: {"enrichment": "pu"},
}

# MLPG1 (issue 14) as in verification/mlpg_fracture.py: the seed's plain variant (visibility,
# quadratic basis, d_max 2.5) and the diffraction rule with extrinsic MLS enrichment
MLPG_VARIANTS = {
    "plain (seed 002)": lambda h: {},
    "extrinsic MLS": lambda h: {"enrichment": "extrinsic_mls", "crack_rule": "diffraction"},
}


def patch_scene() -> Scene:
    return singular_patch(1.0, 0.0, name="singular patch")  # efgkit.gallery


def sent_scene() -> Scene:
    return sent_seed001()  # efgkit.gallery


PROBLEMS = {  # scene, J-domain radii, EFG spacings (full, quick), FEM sizes (full, quick)
    "singular patch": {
        "scene": patch_scene, "radii": (0.4, 0.6, 0.8),
        "efg": (2.0 / np.array([3, 4, 8, 16, 32, 64]), 2.0 / np.array([4, 8])),
        "efg_full_intrinsic_max": 16,  # finer grids: singular 7-term moment matrices (see report)
        "graded": (((2.0, 1.0), (1.0, 0.5), (1.0, 0.2), (0.5, 0.1), (0.5, 0.05), (0.25, 0.02),
                    (0.25, 0.005)), ((1.0, 0.2), (0.5, 0.05))),
        "uniform": ((0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625), (0.5, 0.25)),
        "mlpg": (2.0 / np.array([4, 8, 16, 32]), 2.0 / np.array([4]))},
    "SENT": {
        "scene": sent_scene, "radii": (1.0, 2.0, 3.0, 4.0),
        "efg": (W / np.array([5, 10, 20, 40, 80]), W / np.array([5, 10])),
        "efg_full_intrinsic_max": 40,
        "graded": (((4.0, 1.0), (4.0, 0.5), (2.0, 0.2), (1.0, 0.1), (1.0, 0.05), (0.5, 0.02), (0.25, 0.01)),
                   ((4.0, 1.0), (2.0, 0.2))),
        "uniform": ((2.0, 1.0, 0.5, 0.25, 0.125), (2.0, 1.0)),
        "mlpg": (W / np.array([5, 10, 20, 40]), W / np.array([5]))},  # 80 across: 32k nodes
}


def _error(problem: str, res, ref: float) -> float:
    return abs(res.KI - 1.0) if problem == "singular patch" else abs(res.J / ref - 1.0)


def _timed(fn, repeat: int) -> tuple[float, object, int]:
    """Median seconds of up to ``repeat`` calls (one if the first takes > 5 s), result, count."""
    times, out = [], None
    for k in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
        if k == 0 and times[0] > 5.0:
            break
    return statistics.median(times), out, len(times)


def efg_point(sc, problem: str, variant: str, h: float, ref: float, repeat: int) -> dict:
    radii = PROBLEMS[problem]["radii"]
    method = EFG(spacing=float(h), bc="variational", **VARIANTS[variant](h))
    def run():
        s = solve(sc, method)
        return s.nodes.n, s.sifs(radii=radii, error=False)[0]  # the estimate is not timed

    t, (n, res), k = _timed(run, repeat)
    return {"h": float(h), "n_nodes": n, "n_dofs": 2 * n, "seconds": t, "runs": k,
            "error": _error(problem, res, ref)}


def mlpg_point(sc, problem: str, variant: str, h: float, ref: float, repeat: int) -> dict:
    radii = PROBLEMS[problem]["radii"]
    method = MLPG(spacing=float(h), **MLPG_VARIANTS[variant](h))
    def run():
        s = solve(sc, method)
        return s.nodes.n, len(s.coeffs), s.sifs(radii=radii, error=False)[0]

    t, (n, nd, res), k = _timed(run, repeat)
    return {"h": float(h), "n_nodes": n, "n_dofs": nd, "seconds": t, "runs": k,
            "error": _error(problem, res, ref)}


def fem_point(sc, problem: str, h: float, tip_h, ref: float, repeat: int) -> dict:
    radii = PROBLEMS[problem]["radii"]
    fem = FEM(h, tip_h=h if tip_h is None else tip_h, quarter_point=tip_h is not None)
    def run():
        s = solve_fem(sc, fem)
        return s.n_dofs, s.sifs(radii=radii, error=False)[0]

    t, (n, res), k = _timed(run, repeat)
    return {"h": h, "tip_h": tip_h, "n_dofs": n, "seconds": t, "runs": k, "error": _error(problem, res, ref)}


def time_to(points: list, target: float = TARGET) -> dict:
    """Time from which the error stays at or below ``target``: log-log interpolation between
    the last point above it and the next one (errors need not fall monotonically: a lucky
    coarse point does not count when a finer one is above the target again); ``bound`` is
    "<=" when every point is at or below the target. Points are taken in the order of
    refinement (DOFs, then time): a fixed cost can make a coarse point the slowest (MLPG's
    tip disc rule, ~1-2 s whatever the cloud)."""
    pts = sorted(points, key=lambda p: (p["n_dofs"], p["seconds"]))
    above = [i for i, p in enumerate(pts) if p["error"] > target]
    if not above:
        return {"seconds": pts[0]["seconds"], "bound": "<="} if pts else \
            {"seconds": None, "bound": "not reached", "best_error": None}
    i = above[-1]
    if i == len(pts) - 1:
        return {"seconds": None, "bound": "not reached", "best_error": min(p["error"] for p in pts)}
    a, b = pts[i], pts[i + 1]
    la, lb = math.log(a["error"]), math.log(max(b["error"], 1e-300))
    s = (math.log(target) - la) / (lb - la)
    lt = math.log(a["seconds"]) + s * (math.log(b["seconds"]) - math.log(a["seconds"]))
    return {"seconds": math.exp(lt), "bound": "="}


def summarise(curves: dict) -> dict:
    """Times to the target, their ratios to graded P2 (with the sense of the bound), the best."""
    reach = {k: time_to([p for p in v if "error" in p]) for k, v in curves.items()}
    fem = reach["FEM P2 graded, quarter-point"]
    ratios, bounds = {}, {}
    for k, r in reach.items():
        if k.startswith(("EFG", "MLPG")) and r["seconds"] is not None and fem["seconds"]:
            ratios[k] = r["seconds"] / fem["seconds"]
            # an upper bound on one time bounds the ratio one way; on both, not at all
            bounds[k] = {("=", "="): "=", ("<=", "="): "<=", ("=", "<="): ">="}.get(
                (r["bound"], fem["bound"]), "undetermined")
    best = min((k for k in ratios if k.startswith("EFG")), key=ratios.get, default=None)
    return {"time_to_target": reach, "ratios": ratios, "ratio_bounds": bounds, "best": best}


def mlpg_curves(sc, problem: str, quick: bool, repeat: int, ref: float) -> dict:
    """The MLPG curves of ``problem``: {"MLPG <variant>": points}, refined until 0.01 %."""
    curves = {}
    for v in MLPG_VARIANTS:
        pts = []
        for h in PROBLEMS[problem]["mlpg"][1 if quick else 0]:
            try:
                pts.append(mlpg_point(sc, problem, v, h, ref, repeat))
            except (ValueError, RuntimeError) as err:  # e.g. a singular moment matrix
                pts.append({"h": float(h), "failed": f"{type(err).__name__}: {str(err)[:160]}"})
            if pts[-1].get("error", 1.0) < TARGET / 10:
                break
        curves[f"MLPG {v}"] = pts
    return curves


def run_problem(problem: str, quick: bool, repeat: int, only_mlpg: bool = False) -> dict:
    spec = PROBLEMS[problem]
    sc = spec["scene"]()
    q = 1 if quick else 0
    if problem == "SENT":  # reference J: one graded step finer than the finest timed mesh
        h, th = spec["graded"][q][-1]
        fine = solve_fem(sc, FEM(h / 2, tip_h=th / 2, quarter_point=True))
        ref = fine.sifs(radii=spec["radii"], error=False)[0].J
    else:
        ref = 1.0  # the prescribed K_I
    curves = {}
    for v in (("extrinsic MLS",) if only_mlpg else VARIANTS):
        pts = []
        for h in spec["efg"][q]:
            if v == "full intrinsic" and (2.0 if problem == "singular patch" else W) / h > \
                    spec["efg_full_intrinsic_max"] + 1e-9:
                continue
            try:
                pts.append(efg_point(sc, problem, v, h, ref, repeat))
            except (ValueError, RuntimeError) as err:  # e.g. a singular moment matrix
                pts.append({"h": float(h), "failed": f"{type(err).__name__}: {str(err)[:160]}"})
            if pts[-1].get("error", 1.0) < TARGET / 10:  # well past the target: stop refining
                break
        curves[f"EFG {v}"] = pts
    curves.update(mlpg_curves(sc, problem, quick, repeat, ref))
    fems = (("FEM P2 graded, quarter-point", spec["graded"][q]),
            ("FEM P2 uniform", [(h, None) for h in spec["uniform"][q]]))
    for name, sizes in fems[:1] if only_mlpg else fems:
        pts = []
        for h, th in sizes:
            pts.append(fem_point(sc, problem, h, th, ref, repeat))
            if pts[-1]["error"] < TARGET / 10:
                break
        curves[name] = pts
    return {"reference": ref, "curves": curves, **summarise(curves)}


def figure(res: dict, path: Path) -> Path:
    import matplotlib.pyplot as plt

    from efgkit.io import write_figure

    fig, axes = plt.subplots(1, len(res["problems"]), figsize=(12, 4.5))
    for ax, (problem, r) in zip(np.atleast_1d(axes), res["problems"].items(), strict=True):
        for k, pts in r["curves"].items():
            ok = [p for p in pts if "error" in p]
            style = "s-" if k.startswith("FEM") else "o--"
            ax.loglog([p["seconds"] for p in ok], [max(p["error"], 1e-9) for p in ok], style, ms=4, label=k)
        ax.axhline(TARGET, color="k", ls=":", lw=1)
        what = "K_I" if problem == "singular patch" else "J"
        ax.set(xlabel="wall time (s): scene to SIFs", ylabel=f"relative error of {what}", title=problem)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return write_figure(fig, path, dpi=100)


def _ratio(value: float, bound: str, bold: bool = False) -> str:
    """'= 0.99', '<= 0.99', ... ('<=': the EFG point was already below the target)."""
    if bound == "undetermined":
        return f"undetermined (both first points below 0.1 %; {value:.2f} of the two bounds)"
    return f"{bound} " + (f"**{value:.2f}**" if bold else f"{value:.2f}")


def markdown(res: dict, cmd: str) -> str:
    lines = ["# Performance: work against accuracy", "",
             f"Generated by `{cmd}` on {res['machine']} ({res['date']}); linked from "
             "[performance.md](performance.md). Wall time of the pipeline from the scene to the "
             "stress intensity factors (discretisation or meshing, assembly, solve, domain "
             f"integrals), median of up to {res['repeat']} runs (one above 5 s), all in one run "
             "after a warm-up. EFG: Nitsche supports (bc='variational'), SuperLU below 20k "
             "unknowns and CG with the auxiliary-space preconditioner above; FEM: scikit-fem P2 "
             "(SuperLU below 20k unknowns, CG with smoothed aggregation above) on Triangle "
             "meshes (graded: size tip h + 0.25 r, 12 quarter-point elements at the tip). The "
             "machine is shared: absolute times drift, the ratios are measured side by side.", "",
             "![error against wall time](figures/work_precision.png)", ""]
    for problem, r in res["problems"].items():
        what = "K_I error |K_I - 1|" if problem == "singular patch" else \
            f"J error |J / J_ref - 1|, J_ref = {r['reference']:.5f} N/mm (finer graded P2)"
        lines += [f"## {problem}", "", f"Error: {what}.", "",
                  "| method | size | DOFs | seconds | error |", "|---|---|---|---|---|"]
        for k, pts in r["curves"].items():
            for p in pts:
                size = f"h = {p['h']:.4g}" + (f", tip h = {p['tip_h']:g}" if p.get("tip_h") else "")
                if "error" in p:
                    lines.append(f"| {k} | {size} | {p['n_dofs']} | {p['seconds']:.3f} | {p['error']:.2e} |")
                else:
                    lines.append(f"| {k} | {size} | | | failed: {p['failed']} |")
        lines += ["", "Time to 0.1 % error, and its ratio to graded P2:", "",
                  "| method | seconds to 0.1 % | ratio to graded P2 |", "|---|---|---|"]
        for k, t in r["time_to_target"].items():
            sec = "not reached (best {:.2e})".format(t["best_error"]) if t["seconds"] is None else \
                f"{'<= ' if t['bound'] == '<=' else ''}{t['seconds']:.3f}"
            ratio = r["ratios"].get(k)
            lines.append(f"| {k} | {sec} | {'' if ratio is None else _ratio(ratio, r['ratio_bounds'][k])} |")
        best = r["best"]
        lines += ["", f"**Headline ({problem})**: best EFG variant {best}, time ratio EFG / graded P2 "
                  f"{_ratio(r['ratios'][best], r['ratio_bounds'][best], bold=True)} (goal <= 1)." if best
                  else f"**Headline ({problem})**: no EFG variant reached 0.1 %.", ""]
    lines += res.get("notes", [])
    return "\n".join(lines) + "\n"


NOTES = [
    "## What limits the ratio", "",
    "* Extrinsic MLS enrichment carries the near-tip Williams fields with global K_I, K_II "
    "unknowns: on both problems it is below 0.1 % on the coarsest cloud (the singular patch's "
    "exact solution *is* the mode-I field; on the SENT, 5 nodes across W give 1e-4). Its time "
    "to 0.1 % is then an upper bound, and so is the ratio. At that size both methods take under "
    "0.1 s, and the ratio is set by per-call work, not by work that grows with accuracy. "
    "Measured on the SENT (medians of 7, 5 nodes across against the graded P2 mesh h = 4, "
    "tip h = 0.5): EFG solve 0.060 s (MLS shape functions with the enrichment 0.028, "
    "stiffness 0.011, Nitsche terms 0.008, quadrature cells 0.006, solve 0.004) plus 0.036 s "
    "for the domain integrals; FEM solve 0.039 s (assembly 0.025, solve 0.010, Triangle "
    "0.004) plus 0.022 s. The ratio between runs moved between 0.87 and 1.23 at these times "
    "on this shared machine.",
    "* PU enrichment reaches 0.1 % at the same clouds but costs 2-5 times more: its enriched "
    "nodes carry 8 extra unknowns each and their rows are denser.",
    "* Intrinsic enrichment and tip rosettes converge algebraically in the spacing (radial "
    "sqrt(r) with the visibility rule about like h, the full basis faster) and an EFG node is "
    "dearer than a P2 DOF "
    "(d_max = 3 for the full basis: about 28 neighbours per point; 8 x 8 Gauss points in the "
    "tip cells): 20 to 60 times graded P2 to 0.1 %, or not reached in the sweep. The full "
    "basis's sweep stops at 16 intervals on the patch and 40 nodes across the SENT: on finer "
    "clouds its 7-term moment matrices were singular near the crack faces (SingularMomentMatrix "
    "at 32 and 64 intervals on the patch with Lagrange supports, and at 80 across the SENT with "
    "enrich_radius = 2 mm, in this session's runs).",
    "* Graded P2 with 12 quarter-point elements at the tip is a strong reference: K within "
    "1e-4 at a few thousand DOFs. Uniform P2 converges only like h (the singularity): about "
    "13 (SENT) and 200 (patch) times slower to 0.1 % than graded P2.",
]


def mlpg_section(res: dict, cmd: str) -> str:
    """The MLPG section of docs/performance.md (between its begin/end markers)."""
    lines = ["<!-- begin:mlpg_work_precision -->",
             "## MLPG1 work against accuracy (`benchmarks/work_precision.py --mlpg`)", "",
             f"Command: `{cmd}` ({res['machine']}, {res['date']}; a shared 2-core machine with "
             "other jobs running: the times drift, the ratios are measured side by side in one "
             "run). Wall time from the scene to the SIFs (discretisation, assembly, solve, domain "
             f"integrals), median of up to {res['repeat']} runs (one above 5 s), as in "
             "[performance_work_precision.md](performance_work_precision.md): singular patch error "
             "|K_I - 1|, SENT |J / J_ref - 1| with J_ref from a finer graded P2 mesh. MLPG: "
             "penalty supports in the local weak form, SuperLU; plain = seed 002 (visibility, "
             "quadratic basis, d_max 2.5), extrinsic MLS with the diffraction rule.", ""]
    for problem, r in res["problems"].items():
        lines += [f"### {problem}", "", "| method | size | DOFs | seconds | error |", "|---|---|---|---|---|"]
        for k, pts in r["curves"].items():
            for p in pts:
                size = f"h = {p['h']:.4g}" + (f", tip h = {p['tip_h']:g}" if p.get("tip_h") else "")
                lines.append(f"| {k} | {size} | {p['n_dofs']} | {p['seconds']:.3f} | {p['error']:.2e} |"
                             if "error" in p else f"| {k} | {size} | | | failed: {p['failed']} |")
        lines += ["", "| method | seconds to 0.1 % | ratio to graded P2 |", "|---|---|---|"]
        for k, t in r["time_to_target"].items():
            sec = "not reached (best {:.2e})".format(t["best_error"]) if t["seconds"] is None else \
                f"{'<= ' if t['bound'] == '<=' else ''}{t['seconds']:.3f}"
            ratio = r["ratios"].get(k)
            lines.append(f"| {k} | {sec} | {'' if ratio is None else _ratio(ratio, r['ratio_bounds'][k])} |")
        lines += ["", mlpg_headline(problem, r), ""]
    lines.append("<!-- end:mlpg_work_precision -->")
    return "\n".join(lines) + "\n"


def mlpg_headline(problem: str, r: dict) -> str:
    """One sentence per problem: which MLPG variant reaches 0.1 %, at what ratio, or its best error."""
    parts = []
    for k, t in r["time_to_target"].items():
        if not k.startswith("MLPG"):
            continue
        errors = [p["error"] for p in r["curves"][k] if "error" in p]
        if t["seconds"] is None:
            parts.append(f"{k} does not reach 0.1 % (best {min(errors, default=float('nan')):.2e} "
                         f"at up to {max(p.get('n_dofs', 0) for p in r['curves'][k])} DOFs)")
        else:
            parts.append(f"{k} reaches it, time ratio to graded P2 "
                         f"{_ratio(r['ratios'][k], r['ratio_bounds'][k])}")
    k = "EFG extrinsic MLS"
    tail = "" if k not in r["ratios"] else f" ({k}: {_ratio(r['ratios'][k], r['ratio_bounds'][k])})"
    return f"**{problem}**: " + "; ".join(parts) + tail + "."


def interleaved_main(args) -> dict:
    """``--interleaved``: the section ``work_interleaved`` of docs/performance.md."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import work_interleaved as wi
    from doc_sections import write_section

    warnings.simplefilter("ignore", UserWarning)
    sc = patch_scene()  # warm-up: numba kernels and imports
    efg_point(sc, "singular patch", "extrinsic MLS", 0.5, 1.0, 1)
    fem_point(sc, "singular patch", 0.5, 0.1, 1.0, 1)
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "problems": wi.run(sys.modules[__name__], args.rounds)}
    print(wi.screened_table(res))
    cmd = f"PYTHONPATH=. python benchmarks/work_precision.py --interleaved --rounds {args.rounds}"
    text = wi.section(res, cmd)
    print(text)
    if not args.no_write:
        write_json(res, ROOT / "benchmarks" / "out" / "work_interleaved.json")
        write_section(text, ROOT / "docs" / "performance.md")
    return res


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-write", action="store_true", help="do not write docs/ and benchmarks/out/")
    ap.add_argument("--mlpg", action="store_true",
                    help="MLPG beside EFG extrinsic MLS and graded P2: the section of docs/performance.md")
    ap.add_argument("--render", action="store_true",
                    help="re-render docs from benchmarks/out/work_precision.json without timing")
    ap.add_argument("--interleaved", action="store_true",
                    help="time the cheapest EFG and P2 runs reaching 0.1 %% in turns "
                         "(benchmarks/work_interleaved.py)")
    ap.add_argument("--rounds", type=int, default=15, help="rounds of --interleaved")
    args = ap.parse_args(argv)
    if args.interleaved:
        return interleaved_main(args)
    if args.render and args.mlpg:  # the MLPG section from benchmarks/out/work_precision_mlpg.json
        res = json.loads((ROOT / "benchmarks" / "out" / "work_precision_mlpg.json").read_text())
        for r in res["problems"].values():
            r.update(summarise(r["curves"]))
        cmd = "python benchmarks/work_precision.py --mlpg" + (" --quick" if res.get("quick") else "")
        from doc_sections import write_section
        write_section(mlpg_section(res, cmd), ROOT / "docs" / "performance.md")
        return res
    if args.render:
        res = json.loads((ROOT / "benchmarks" / "out" / "work_precision.json").read_text())
        for r in res["problems"].values():
            r.update(summarise(r["curves"]))
        res["notes"] = NOTES
        figure(res, ROOT / "docs" / "figures" / "work_precision.png")
        (ROOT / "docs" / "performance_work_precision.md").write_text(
            markdown(res, "python benchmarks/work_precision.py"))
        return res
    warnings.simplefilter("ignore", UserWarning)  # domain-independence notes of coarse runs
    sc = patch_scene()  # warm-up: numba kernels and imports
    for v in VARIANTS:
        efg_point(sc, "singular patch", v, 0.5, 1.0, 1)
    fem_point(sc, "singular patch", 0.5, 0.1, 1.0, 1)
    if args.mlpg:
        for v in MLPG_VARIANTS:
            mlpg_point(sc, "singular patch", v, 0.5, 1.0, 1)
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}", "date": time.strftime("%Y-%m-%d"),
           "repeat": args.repeat, "target": TARGET,
           "problems": {p: run_problem(p, args.quick, args.repeat, args.mlpg) for p in PROBLEMS}}
    if args.mlpg:
        cmd = "python benchmarks/work_precision.py --mlpg" + (" --quick" if args.quick else "")
        text = mlpg_section(res, cmd)
        print(text)
        if not args.no_write:
            write_json(res, ROOT / "benchmarks" / "out" / "work_precision_mlpg.json")
            from doc_sections import write_section
            write_section(text, ROOT / "docs" / "performance.md")
        return res
    res["notes"] = NOTES
    cmd = "python benchmarks/work_precision.py" + (" --quick" if args.quick else "")
    if not args.no_write:
        res["figure"] = str(figure(res, ROOT / "docs" / "figures" / "work_precision.png"))
        (ROOT / "docs" / "performance_work_precision.md").write_text(markdown(res, cmd))
        write_json(res, ROOT / "benchmarks" / "out" / "work_precision.json")
    return res


if __name__ == "__main__":
    out = main()
    if "problems" in out and all("ratios" in r for r in out["problems"].values()):
        print(json.dumps({p: {"ratios": r["ratios"], "time_to_target": r["time_to_target"]}
                          for p, r in out["problems"].items()}, indent=1))
