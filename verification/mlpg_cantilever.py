"""Timoshenko cantilever (the exact field of ``cantilever``) with MLPG1 beside EFG: energy-norm
convergence rates for the linear and quadratic bases, and a quadrature study (energy error,
and the displacement difference from a converged rule, against the points per sub-domain:
the piecewise-midpoint rule of seed 002 Eq. 39 against the Gauss rule).

MLPG settings: quadratic basis with the defaults (seed 002 Sect. 4 with c_I = 0.5 r_I, and
the Gaussian exponent k = 1 with test discs of 1.5 spacings instead of the seed's k = 2 and
1.1) and with a smooth wide Gaussian (k = 1, c_I = h, r_I = 4 h, as Atluri and Zhu use);
linear basis with the smooth one only: with
r_I = 2.5 h the gradient of a linear-basis MLS has a ripple of period h that the small
test discs do not average out, and the error stalls (docs/theory.md, MLPG1).

The disc-rule study runs for the default weight and for the seed's (``SEED_WEIGHT``: k = 2,
r_s = 1.1 h): the k = 1 Gaussian cut off at r_I has a slope there (dw/ds = -0.149), so the
MLS gradients kink on every support circle crossing a disc and no rule converges fast; the
k = 2 one is smooth (slope 7e-6) and the Gauss rule converges spectrally.
"""

from __future__ import annotations

import numpy as np
from _report import Report
from cantilever import BASES as EFG_BASES
from cantilever import scene

from efgkit import EFG, MLPG
from efgkit.static import solve

NAME = "mlpg_cantilever"
SMOOTH = dict(weight_k=1, shape_factor=0.25, d_max=4.0)  # Gaussian k = 1, c_I = h, r_I = 4 h
MLPG_BASES = {"linear": dict(basis="linear", **SMOOTH),
              "quadratic": dict(basis="quadratic"),  # the defaults
              "quadratic_smooth": dict(basis="quadratic", **SMOOTH)}
SEED_WEIGHT = dict(weight_k=2, test_radius=1.1)  # seed 002 Sect. 4 (Eq. 7 with k = 2)
WEIGHTS = {"default": {}, "seed": SEED_WEIGHT}
RULES = {"midpoint": ((5, 8), (10, 32), (3, 6), (8, 16), (20, 64)),
         "gauss": ((5, 8), (8, 16), (3, 6), (8, 8), (10, 32))}  # quick mode: the first two


def _rate(h, e) -> float:
    return float(np.polyfit(np.log(h), np.log(e), 1)[0])

TITLE = 'MLPG1 Timoshenko cantilever and disc-rule study'


def markdown(r: dict) -> list[str]:
    """The section of docs/verification.md for a full-mode record."""
    m = r["metrics"]
    hs = m["spacings"]
    rows = ["| method / basis | " + " | ".join(f"h = {h:g}" for h in hs) + " | rate |",
            "|---" * (len(hs) + 2) + "|"]
    for key, rate in m["rate_energy"].items():
        errs = [m["errors"][f"{key}/h={h:g}"]["energy"] for h in hs]
        rows.append(f"| {key} | " + " | ".join(f"{e:.2e}" for e in errs) + f" | {rate:.2f} |")
    q = m["quadrature_study"]
    study = ["| weight / rule | points per disc | energy error | displacement difference from the "
             "converged rule |", "|---|---|---|---|"]
    study += [f"| {k} | {v['points_per_disc']} | {v['energy']:.3e} | {v['quadrature_error']:.2e} |"
              for k, v in q["rows"].items()]
    return ["The cantilever of ``cantilever``; relative energy-norm errors. MLPG quadratic: the "
            "defaults; MLPG linear and quadratic_smooth: Gaussian k = 1, c_I = h, r_I = 4 h; "
            "EFG: the settings of "
            "``cantilever`` (quartic weight, Lagrange multipliers).", "", *rows, "",
            f"Disc rules at h = {q['spacing']:g} (MLPG quadratic; default weight k = 1, r_s = 1.5 h, "
            f"and seed 002's k = 2, r_s = 1.1 h), against {q['reference']} with the same weight:",
            "", *study]


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    spacings = (3.0, 2.0, 1.5) if quick else (2.0, 1.0, 0.5, 0.25)
    sc = scene()
    results, rates = {}, {}
    for basis in ("linear", "quadratic") if quick else MLPG_BASES:
        for method in ("mlpg", "efg"):
            if method == "efg" and basis not in EFG_BASES:
                continue
            errs = []
            for h in spacings:
                m = (MLPG(spacing=h, **MLPG_BASES[basis]) if method == "mlpg" else
                     EFG(spacing=h, basis=basis, weight="quartic", bc="lagrange", **EFG_BASES[basis]))
                sol = solve(sc, m)
                e = sol.errors()
                errs.append(e["energy"])
                results[f"{method}/{basis}/h={h:g}"] = {"energy": e["energy"], "l2": e["l2"],
                                                        "n_nodes": sol.nodes.n,
                                                        "seconds": sol.timings["total"]}
            rates[f"{method}/{basis}"] = _rate(spacings, errs)
    rep.metrics["rate_energy"] = rates
    rep.metrics["errors"] = results
    rep.metrics["spacings"] = list(spacings)
    h, (nr_ref, na_ref) = (3.0, (10, 32)) if quick else (1.0, (12, 48))
    study, ref_energy = {}, {}
    for wname, wkw in WEIGHTS.items():
        ref = solve(sc, MLPG(spacing=h, radial=nr_ref, angular=na_ref, cut_angular=na_ref, **wkw))
        x = ref.disc.post_points.x
        u_ref = ref.displacement()
        ref_energy[wname] = ref.errors()["energy"]
        for rule, sizes in RULES.items():
            for nr, na in sizes[:2] if quick else sizes:
                sol = solve(sc, MLPG(spacing=h, quadrature=rule, radial=nr, angular=na,
                                     cut_angular=2 * na, **wkw))
                diff = np.abs(sol.displacement(x) - u_ref).max() / np.abs(u_ref).max()
                study[f"{wname}/{rule}/{nr}x{na}"] = {"points_per_disc": nr * na,
                                                      "energy": sol.errors()["energy"],
                                                      "quadrature_error": float(diff)}
    rep.metrics["quadrature_study"] = {"spacing": h, "basis": "quadratic", "rows": study,
                                       "weights": {k: v or "defaults" for k, v in WEIGHTS.items()},
                                       "reference": f"gauss {nr_ref}x{na_ref}, {na_ref} per cut piece",
                                       "reference_energy": ref_energy}
    rep.ref("rate_energy/linear", 1.0, "energy-norm rate h^p of a degree-p basis")
    rep.ref("rate_energy/quadratic", 2.0, "energy-norm rate h^p of a degree-p basis")
    if quick:  # coarse grids (3 to 1.5): bounds under the measured 2.09 (quadratic) and 1.35 (linear;
        # 1.72 and 0.70 with the seed's k = 2, r_s = 1.1 h)
        rep.check("rate_energy mlpg/quadratic (coarse)", rates["mlpg/quadratic"], ">=", 1.6)
        rep.check("rate_energy mlpg/linear (coarse)", rates["mlpg/linear"], ">=", 0.55)
    else:  # the targets
        rep.check("rate_energy mlpg/quadratic_smooth", rates["mlpg/quadratic_smooth"], ">=", 1.9)
        rep.check("rate_energy mlpg/quadratic (defaults)", rates["mlpg/quadratic"], ">=", 1.9)
        rep.check("rate_energy mlpg/linear", rates["mlpg/linear"], ">=", 0.95)
    # displacement difference from the converged rule, seed weight (quick, h = 3): Gauss 8 x 16
    # (128 points per disc) 3.1e-5, the midpoint rule 10 x 32 (320 points) 2.8e-4; at 5 x 8
    # 8.9e-4, 1.3e-3. The default k = 1 weight kinks at r_I and is not checked here: quick
    # 7.7e-3 (Gauss 5 x 8), 5.0e-3 (8 x 16), midpoint 10 x 32 2.3e-3 (docs/theory.md, MLPG1)
    g = study["seed/gauss/8x16"]["quadrature_error"]
    mp = study["seed/midpoint/10x32"]["quadrature_error"]
    rep.check("quadrature_error gauss/8x16 (seed weight k = 2)", g, "<=", 6e-5)
    rep.check("quadrature_error midpoint/10x32 over gauss/8x16 (seed weight k = 2)", mp / g, ">=", 3.0)
    return rep.write(out_dir)


if __name__ == "__main__":
    import json

    r = main()
    print(json.dumps({k: r["metrics"][k] for k in ("rate_energy", "quadrature_study")}, indent=1))
