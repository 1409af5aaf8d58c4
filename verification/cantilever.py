"""Timoshenko cantilever with a parabolic end shear (Timoshenko & Goodier; the meshless
benchmark of Dolbow & Belytschko 1998): energy-norm convergence rates of EFG for the
linear and quadratic bases and each weight, over four uniform refinements.

The exact field is prescribed at x = 0 and its traction applied at x = L, so the
only error is the discretisation (and quadrature) error. Expected rates: h^1
(linear basis) and h^2 (quadratic basis) in the energy norm.

The essential-BC methods side by side (quartic weight): the table above uses Lagrange
multipliers; ``bc_rates`` adds penalty (default beta), Nitsche ("variational"), the
modified collocation method of Zhu and Atluri 1998 ("collocation") and seed 002's
modified MLS.
"""

from __future__ import annotations

import numpy as np
from _report import Report

from efgkit import EFG, Domain, Elastic, Scene, Support, Traction
from efgkit.problem.exact.fields import Field
from efgkit.static import solve

NAME = "cantilever"
L, D, P = 48.0, 12.0, 1000.0
BASES = {"linear": dict(d_max=2.0, order=4), "quadratic": dict(d_max=3.0, order=8)}
WEIGHTS = ("quartic", "gaussian", "cubic")
BCS = ("penalty", "lagrange", "variational", "collocation", "modified_mls")
CHECKED_BCS = ("collocation",)  # the others' rates: Lagrange above, the rest reported


def scene() -> Scene:
    f = Field.named("cantilever", L=L, D=D, P=P)
    return Scene(Domain.rectangle(0.0, -D / 2, L, D / 2), Elastic(3e7, 0.3, "stress"),
                 supports=(Support("left", ux=f, uy=f),), tractions=(Traction("right", f),),
                 exact=f, name=NAME)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    spacings = (3.0, 2.0, 1.5) if quick else (2.0, 1.0, 0.5, 0.25)
    sc = scene()
    results, rates = {}, {}
    for basis, opts in BASES.items():
        for weight in WEIGHTS:
            errs = []
            for h in spacings:
                m = EFG(spacing=h, basis=basis, weight=weight, alpha=opts["d_max"] / 4,
                        bc="lagrange", **opts)
                sol = solve(sc, m)
                e = sol.errors()
                errs.append(e["energy"])
                results[f"{basis}/{weight}/h={h:g}"] = {"energy": e["energy"], "l2": e["l2"],
                                                        "n_nodes": sol.nodes.n}
            rate = float(np.polyfit(np.log(spacings), np.log(errs), 1)[0])
            rates[f"{basis}/{weight}"] = rate
            bound = 0.95 if basis == "linear" else 1.9
            rep.check(f"rate_energy {basis}/{weight}", rate, ">=", bound)
    bc_rates, bc_errors = {}, {}
    for basis, opts in BASES.items():
        for bc in ("lagrange", *CHECKED_BCS) if quick else BCS:  # quick: only what is checked
            errs = []
            for h in spacings:
                if bc == "lagrange":  # solved above
                    errs.append(results[f"{basis}/quartic/h={h:g}"]["energy"])
                    continue
                m = EFG(spacing=h, basis=basis, alpha=opts["d_max"] / 4, bc=bc, **opts)
                errs.append(solve(sc, m).errors()["energy"])
                bc_errors[f"{basis}/{bc}/h={h:g}"] = errs[-1]
            bc_rates[f"{basis}/{bc}"] = rate = float(np.polyfit(np.log(spacings), np.log(errs), 1)[0])
            if bc in CHECKED_BCS:
                rep.check(f"rate_energy {basis}/{bc}", rate, ">=", 0.95 if basis == "linear" else 1.9)
    rep.metrics["bc_rates"] = bc_rates
    rep.metrics["bc_errors"] = bc_errors
    rep.metrics["rate_energy"] = rates
    rep.metrics["errors"] = results
    rep.metrics["spacings"] = list(spacings)
    rep.ref("rate_energy/linear", 1.0, "energy-norm rate h^p of a degree-p basis (issue [core])")
    rep.ref("rate_energy/quadratic", 2.0, "energy-norm rate h^p of a degree-p basis (issue [core])")
    return rep.write(out_dir)


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"]["rate_energy"], indent=1))
