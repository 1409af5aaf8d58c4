"""MLPG1 patch test (seed 002 Eqs. 20-24): the linear field of ``patch`` prescribed on the
whole boundary of the unit square must be reproduced inside, on regular and perturbed
clouds, for every essential-BC method (penalty in the local weak form, the modified MLS
of seed 002 with row cross-out, collocation) and disc rule (the seed's 5 x 8 piecewise
midpoint, a finer midpoint, Gauss). The local symmetric weak form is consistent for each
of them, so the error measures the quadrature (and the modified MLS's discontinuity).
"""

from __future__ import annotations

import numpy as np
from _report import Report
from patch import errors, scene

from efgkit import MLPG
from efgkit.static import solve

NAME = "mlpg_patch"
CLOUDS = {"regular": dict(perturb=0.0), "perturbed": dict(perturb=0.3, seed=7)}
BCS = ("penalty", "collocation", "modified_mls")
RULES = {"midpoint5x8": dict(quadrature="midpoint", radial=5, angular=8),
         "midpoint10x32": dict(quadrature="midpoint", radial=10, angular=32),
         "gauss5x8/cut8": dict(quadrature="gauss", radial=5, angular=8, cut_angular=8),
         "gauss5x8": dict(quadrature="gauss", radial=5, angular=8, cut_angular=16)}
RECOMMENDED = "gauss5x8"  # the default: 16 Gauss points per angular piece of a cut disc

TITLE = 'MLPG1 patch test per BC method and disc rule'


def _e(v) -> str:
    return f"{v:.2e}" if isinstance(v, float) else str(v)


def markdown(r: dict) -> list[str]:
    """The section of docs/verification.md for a full-mode record."""
    rows = ["| cloud / bc / rule | max rel. displacement error | max rel. stress error |",
            "|---|---|---|"]
    for k, v in r["metrics"]["errors"].items():
        if "failed" in v:
            rows.append(f"| {k} | failed: {v['failed']} | |")
        else:
            rows.append(f"| {k} | {_e(v['max_rel_disp_error'])} | {_e(v['max_rel_stress_error'])} |")
    return [f"Unit square, the linear field of ``patch`` prescribed on every edge, spacing "
            f"{r['metrics']['settings']['spacing']}, perturbed clouds 0.3 h (seed 7); MLPG "
            "defaults (quadratic basis; linear for the modified MLS). Rules: the seed's 5 x 8 "
            "piecewise midpoint (Eq. 39), 10 x 32 midpoint, Gauss 5 x 8 with 8 or (default) 16 "
            "Gauss points per angular piece of a cut disc. Errors are maxima over 400 random "
            "interior points, relative to the largest exact value.", "", *rows]


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    h = 0.25 if quick else 0.1
    x = np.random.default_rng(0).uniform(0.02, 0.98, (400, 2))
    sc = scene()
    table = {}
    rules = {RECOMMENDED: RULES[RECOMMENDED], "midpoint5x8": RULES["midpoint5x8"]} if quick else RULES
    for cloud, opts in CLOUDS.items():
        for bc in BCS:
            for rule, ropts in rules.items():
                basis = "linear" if bc == "modified_mls" else "quadratic"  # modified MLS: at
                # most 2 interpolation nodes per support with the shrunk supports
                try:
                    eu, es = errors(solve(sc, MLPG(spacing=h, bc=bc, basis=basis, **ropts, **opts)), x)
                except ValueError as err:  # reported, e.g. a singular modified-MLS moment matrix
                    table[f"{cloud}/{bc}/{rule}"] = {"failed": str(err)[:200]}
                    continue
                table[f"{cloud}/{bc}/{rule}"] = {"max_rel_disp_error": eu, "max_rel_stress_error": es}
    rep.metrics["errors"] = table
    rep.metrics["settings"] = {"spacing": h, "recommended": RECOMMENDED}
    rep.ref("max_rel_disp_error", 0.0, "exact linear field (consistency of the local weak form)")
    for key, val in table.items():
        if key.endswith(RECOMMENDED) and "modified_mls" not in key:
            rep.check(f"{key} displacement", val.get("max_rel_disp_error", np.inf), "<=", 1e-6)
            rep.check(f"{key} stress", val.get("max_rel_stress_error", np.inf), "<=", 1e-5)
    return rep.write(out_dir)


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"], indent=1))
