"""Interleaved work against accuracy: the cheapest EFG setting and the cheapest graded
quarter-point P2 mesh that reach 0.1 % error, timed in turns (A, B, A, B, ...).

Run:  PYTHONPATH=. python benchmarks/work_precision.py --interleaved --rounds 15

At the sizes that decide the time to 0.1 % both pipelines take a few hundredths of a
second, and the ratio of two separately measured medians flips with the machine's load.
Here, for each problem of :mod:`work_precision` (the singular patch, error |K_I - 1|
against the prescribed K_I = 1; the SENT, |J / J_ref - 1| with J_ref from a graded P2
mesh finer than any timed one, as in the sweep):

1. every EFG candidate (extrinsic MLS with a BC method and quadrature orders x spacing)
   and every graded P2 candidate (h, tip h) is solved once; a candidate qualifies when it
   and its refinement (EFG: half the spacing; P2: half h and half tip h) are at or below
   0.1 % (an error that dips below the target by chance on one size does not count);
   the qualified ones are timed ``SCREEN`` times and the one with the smallest median
   is the deciding run of its side;
2. the two deciding runs are timed alternately, ``rounds`` times each, in this process
   (time.perf_counter around the whole pipeline: discretisation or meshing, assembly,
   solve, domain integrals);
3. the ratio of each round (EFG / FEM) gives the median ratio, its interquartile range
   and a bootstrap 90 % interval of the median (np.random.default_rng(0), 2000 resamples).
   The ratio is decided when the interval does not contain 1.
"""

from __future__ import annotations

import statistics

import numpy as np

SCREEN = 5
# EFG candidates beyond work_precision's sweep: coarser clouds (extrinsic MLS carries the
# near-tip fields, so a coarse cloud can already be below 0.1 %), the BC methods and lower
# quadrature orders (cells, refined cells, tip fans).
_VARIANTS = {
    "Nitsche": {"enrichment": "extrinsic_mls", "bc": "variational"},
    "Nitsche, order 3/4": {"enrichment": "extrinsic_mls", "bc": "variational", "order": 3,
                           "refined_order": 4},
    "Nitsche, order 2/4, tip 4": {"enrichment": "extrinsic_mls", "bc": "variational", "order": 2,
                                  "refined_order": 4, "tip_order": 4},
    "Nitsche, order 3/4, tip 6": {"enrichment": "extrinsic_mls", "bc": "variational", "order": 3,
                                  "refined_order": 4, "tip_order": 6},
    "Nitsche, order 3/4, tip 5": {"enrichment": "extrinsic_mls", "bc": "variational", "order": 3,
                                  "refined_order": 4, "tip_order": 5},
    "Lagrange": {"enrichment": "extrinsic_mls", "bc": "lagrange"},
    "Lagrange, order 3/4": {"enrichment": "extrinsic_mls", "bc": "lagrange", "order": 3,
                            "refined_order": 4},
}
EFG_CANDIDATES = {
    "singular patch": {"spacing": 2.0 / np.array([2, 3, 4]), "variants": _VARIANTS},
    "SENT": {"spacing": 10.0 / np.array([4, 5, 10]), "variants": _VARIANTS},
}
FEM_CANDIDATES = {  # (h, tip h), graded with 12 quarter-point elements at the tip
    "singular patch": ((2.0, 1.0), (2.0, 0.5), (2.0, 0.3), (1.0, 0.3), (2.0, 0.2), (1.0, 0.2),
                       (0.5, 0.1)),
    "SENT": ((8.0, 1.0), (4.0, 1.0), (8.0, 0.5), (4.0, 0.5), (2.0, 0.5), (4.0, 0.2), (2.0, 0.2),
             (1.0, 0.1)),
}


def _runner(wp, sc, problem, kind, setting):
    """A zero-argument function running one pipeline and returning (DOFs, error function input)."""
    from efgkit import EFG, solve
    from efgkit.fem.model import FEM, solve_fem

    radii = wp.PROBLEMS[problem]["radii"]
    if kind == "EFG":
        variant, h = setting
        method = EFG(spacing=float(h), **EFG_CANDIDATES[problem]["variants"][variant])

        def run():
            s = solve(sc, method)
            return s.coeffs.size, s.sifs(radii=radii, error=False)[0]
    else:
        h, th = setting
        fem = FEM(h, tip_h=th, quarter_point=True)

        def run():
            s = solve_fem(sc, fem)
            return s.n_dofs, s.sifs(radii=radii, error=False)[0]
    return run


def _median_time(fn, k):
    from turns import take_turns

    return statistics.median(take_turns({"fn": fn}, k)["fn"])


def deciding(wp, sc, problem, kind, ref) -> dict:
    """The cheapest candidate of ``kind`` ("EFG" or "FEM") reaching the target."""
    if kind == "EFG":
        spec = EFG_CANDIDATES[problem]
        cands = [(v, float(h)) for v in spec["variants"] for h in spec["spacing"]]
    else:
        cands = list(FEM_CANDIDATES[problem])
    def refined(c):
        return (c[0], c[1] / 2) if kind == "EFG" else (c[0] / 2, c[1] / 2)

    errors = {}

    def error_of(c):
        if c not in errors:
            try:
                n, res = _runner(wp, sc, problem, kind, c)()
                errors[c] = (int(n), float(wp._error(problem, res, ref)))
            except (ValueError, RuntimeError) as err:
                errors[c] = (0, f"{type(err).__name__}: {str(err)[:120]}")
        return errors[c]

    screened = []
    for c in cands:
        n, err = error_of(c)
        if isinstance(err, str):
            screened.append({"setting": c, "failed": err})
            continue
        row = {"setting": c, "dofs": n, "error": err}
        if err <= wp.TARGET:
            row["refined_error"] = error_of(refined(c))[1]
            if not isinstance(row["refined_error"], str) and row["refined_error"] <= wp.TARGET:
                row["seconds"] = _median_time(_runner(wp, sc, problem, kind, c), SCREEN)
        screened.append(row)
    ok = [r for r in screened if "seconds" in r]
    if not ok:
        return {"screened": screened, "best": None}
    return {"screened": screened, "best": min(ok, key=lambda r: r["seconds"])}


def interleave(fa, fb, rounds: int) -> dict:
    """Time ``fa`` and ``fb`` alternately; the ratio fa / fb of each round and its statistics."""
    from turns import median_interval, take_turns

    t = take_turns({"a": fa, "b": fb}, rounds)
    ta, tb = t["a"], t["b"]
    ratio = np.array(ta) / np.array(tb)
    lo, hi = median_interval(ratio, np.random.default_rng(0))
    q1, q3 = np.quantile(ratio, [0.25, 0.75])
    med = float(np.median(ratio))
    return {"rounds": rounds, "efg_s": ta, "fem_s": tb, "ratios": ratio.tolist(),
            "median_efg_s": statistics.median(ta), "median_fem_s": statistics.median(tb),
            "median_ratio": med, "iqr": [float(q1), float(q3)], "ci90": [float(lo), float(hi)],
            "decided": bool(hi < 1.0 or lo > 1.0)}


def run(wp, rounds: int, problems=None) -> dict:
    """Deciding runs and their interleaved ratio for each problem of ``wp.PROBLEMS``."""
    from efgkit.fem.model import FEM, solve_fem

    out = {}
    for problem in problems or wp.PROBLEMS:
        spec = wp.PROBLEMS[problem]
        sc = spec["scene"]()
        if problem == "SENT":  # the reference of the sweep: one graded step past its finest mesh
            h, th = spec["graded"][0][-1]
            fine = solve_fem(sc, FEM(h / 2, tip_h=th / 2, quarter_point=True))
            ref = fine.sifs(radii=spec["radii"], error=False)[0].J
        else:
            ref = 1.0
        efg = deciding(wp, sc, problem, "EFG", ref)
        fem = deciding(wp, sc, problem, "FEM", ref)
        row = {"reference": ref, "efg": efg, "fem": fem}
        if efg["best"] and fem["best"]:
            row["interleaved"] = interleave(_runner(wp, sc, problem, "EFG", efg["best"]["setting"]),
                                            _runner(wp, sc, problem, "FEM", fem["best"]["setting"]),
                                            rounds)
        out[problem] = row
    return out


def section(res: dict, cmd: str) -> str:
    """The marked section of docs/performance.md (the run's table; the notes on it live in the
    hand-written section ``work_interleaved_notes`` right after it)."""
    lines = ["<!-- begin:work_interleaved -->",
             "## Work against accuracy, interleaved (`benchmarks/work_precision.py --interleaved`)", "",
             f"Command: `{cmd}` ({res['machine']}, {res['date']}; a shared 2-core machine with other "
             "jobs running). For each problem the cheapest EFG setting and the cheapest graded "
             "quarter-point P2 mesh reaching 0.1 % error (each candidate solved once; a candidate "
             "counts when it and its refinement, EFG half the spacing, P2 half h and tip h, are "
             f"both at or below 0.1 %; those timed {SCREEN} times, the smallest median kept) "
             "are timed alternately "
             "(EFG, FEM, EFG, FEM, ...) in one process, the whole pipeline from the scene to the "
             "SIFs. Ratio = EFG / FEM of each round; median, interquartile range and a bootstrap "
             "90 % interval of the median (2000 resamples). Errors: singular patch |K_I - 1| "
             "(prescribed K_I = 1), SENT |J / J_ref - 1| (J_ref from a finer graded P2 mesh, as "
             "in [performance_work_precision.md](performance_work_precision.md)).", "",
             "| problem | EFG deciding run | error | FEM deciding run | error | rounds | median EFG s "
             "| median FEM s | median ratio | IQR | 90 % interval | decided |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for problem, r in res["problems"].items():
        e, f, i = r["efg"]["best"], r["fem"]["best"], r.get("interleaved")
        if not (e and f and i):
            lines.append(f"| {problem} | {e and e['setting']} | | {f and f['setting']} | | | | | | | | no |")
            continue
        v, h = e["setting"]
        lines.append(
            f"| {problem} | extrinsic MLS, {v}, h = {h:.4g} ({e['dofs']} DOFs) | {e['error']:.1e} | "
            f"h = {f['setting'][0]:g}, "
            f"tip h = {f['setting'][1]:g} ({f['dofs']} DOFs) | {f['error']:.1e} | {i['rounds']} | "
            f"{i['median_efg_s']:.4f} | {i['median_fem_s']:.4f} | **{i['median_ratio']:.2f}** | "
            f"{i['iqr'][0]:.2f} - {i['iqr'][1]:.2f} | {i['ci90'][0]:.2f} - {i['ci90'][1]:.2f} | "
            f"{'yes' if i['decided'] else 'no'} |")
    lines.append("<!-- end:work_interleaved -->")
    return "\n".join(lines) + "\n"


def screened_table(res: dict) -> str:
    """All candidates with their error and screening time (for the JSON record / stdout)."""
    out = []
    for problem, r in res["problems"].items():
        for kind in ("efg", "fem"):
            for row in r[kind]["screened"]:
                out.append(f"{problem} {kind} {row['setting']} "
                           + (row.get("failed") or f"err {row['error']:.2e}"
                              + (f" refined {row['refined_error']}" if "refined_error" in row else "")
                              + (f" t {row['seconds']:.4f}" if "seconds" in row else "")))
    return "\n".join(out)
