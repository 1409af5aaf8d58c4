"""Infinite plate with a circular hole under remote tension (Kirsch), seed 003 Sect. 4.5.1:
a = 1, l = 5, E = 3e7, nu = 0.3, plane strain, quarter model with symmetry supports
and the exact tractions of Eq. (35) on the outer edges. Nodes graded around the
hole up to r = 2a, 9 x 9 Gauss points there and 5 x 5 elsewhere, as in the seed.

Metrics: the stress concentration factor sigma_xx(0, a) / sigma (exact 3, Eq. 35a)
and the relative energy-norm error (Eq. 36) per refinement.
"""

from __future__ import annotations

import numpy as np
from _report import Report

from efgkit import EFG, Elastic, Scene, Zone
from efgkit.gallery import kirsch
from efgkit.static import solve

NAME = "kirsch"
A_HOLE, L_PLATE = 1.0, 5.0


def scene() -> Scene:
    return kirsch(A_HOLE, L_PLATE, 1.0, Elastic(3e7, 0.3, "strain"), NAME)  # efgkit.gallery


def method(h: float) -> EFG:
    return EFG(spacing=h, zones=(Zone((0.0, 0.0), 2 * A_HOLE, h / 2),), order=5,
               refined_order=9, bc="lagrange")


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    spacings = (0.5, 0.25) if quick else (0.5, 0.25, 0.125, 0.0625)
    sc = scene()
    scf, energy, nodes = [], [], []
    for h in spacings:
        sol = solve(sc, method(h))
        scf.append(float(sol.stress([[0.0, A_HOLE]])[0, 0]))
        energy.append(sol.errors()["energy"])
        nodes.append(sol.nodes.n)
    rate = float(np.polyfit(np.log(spacings), np.log(energy), 1)[0])
    rep.metrics.update({"spacing": list(spacings), "n_nodes": nodes, "scf": scf,
                        "energy_error": energy, "rate_energy": rate})
    rep.ref("scf", 3.0, "seed 003 Eq. (35a) at (x, y) = (0, a)")
    # measured: 3.5e-3 at h = 0.0625 (full), 7.2e-3 at h = 0.25 (quick, which cannot reach
    # the full bound); each bound within 3x of its measurement
    rep.check("finest scf relative error", abs(scf[-1] / 3.0 - 1), "<=", 0.005 if not quick
              else 0.02)
    rep.check("energy error decreases", energy[-1] / energy[0], "<=", 0.6)
    return rep.write(out_dir)


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"], indent=1))
