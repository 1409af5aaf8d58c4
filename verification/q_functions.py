"""q-functions of the domain J integral, seed 001 Sect. 8 (Figs. 16-19), on EFG fields.

J against the domain radius and against the number of points in the domain, for the
cubic B-spline (seed 001 Eq. 10), Wendland C2 (Eq. 13) and the power law 1 - z^n,
n = 2..5 (Eq. 14), evaluated

* at the background quadrature points of the EFG solution (:meth:`Solution.sifs` does
  this), and
* point-wise at the nodes with Voronoi nodal volumes (seed 001 Eq. 8: the SPH way;
  :func:`efgkit.fracture.volumes.nodal_volumes`), split nodes moved 1e-9 of their
  support radius onto their own face and given half of their position's volume each.

Two problems:

* the singular patch of seed 003 Sect. 5.6.1 (mode I Williams field on [-1, 1]^2,
  E = 1, nu = 0.3, plane strain), extrinsic MLS enrichment on a 41 x 41 grid: exact
  J = K_I^2 / E';
* the SENT specimen of seed 001 Sect. 4 (50 x 10 mm, a = 5 mm, ends clamped and pulled
  apart by 0.0253882 mm each, E = 210 GPa, nu = 0.3, plane strain), extrinsic PU
  enrichment with h = 0.25 mm: reference J = 6786 J/m^2 (seed 001, Abaqus).

Metric ``oscillation``: (max - min) / |mean| of J over the outer half of the radii, per
problem, evaluation and q-function.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
from _report import Report

from efgkit import EFG, Elastic, solve
from efgkit.fracture.integrals import domain_integrals
from efgkit.fracture.qfunctions import QFunction
from efgkit.fracture.volumes import nodal_volumes
from efgkit.gallery import sent_seed001, singular_patch
from efgkit.io import write_figure

NAME = "q_functions"
TITLE = "q-functions of the J integral (seed 001 Sect. 8)"
ROOT = Path(__file__).resolve().parents[1]
QS = {"cubic_spline": dict(), "wendland_c2": dict(), "power n=2": dict(n=2.0),
      "power n=3": dict(n=3.0), "power n=4": dict(n=4.0), "power n=5": dict(n=5.0)}
KERNELS = ("wendland_c2", "cubic_spline")
PATCH_MAT = Elastic(1.0, 0.3, "strain")
SENT_MAT = Elastic(210e3, 0.3, "strain")  # MPa (seed 001 Sect. 4: E = 210 GPa)
SENT_DISP = 0.0253882  # mm at each end, seed 001 Sect. 4
J_SENT_REF = 6.786  # N/mm = 6786 J/m^2, seed 001 Sect. 4.1 and Table 5 (Abaqus CPE8)


def patch_problem(n: int):
    """Singular patch (split left edge, as in verification/singular_patch.py), extrinsic MLS."""
    sc = singular_patch(1.0, 0.0, 1.0, PATCH_MAT, split_mouth=True)  # efgkit.gallery
    h = 2.0 / (n - 1)
    m = EFG(spacing=h, bc="lagrange", enrichment="extrinsic_mls", rule_power=1.0)
    return sc, m, h, 0.9, 1.0 / PATCH_MAT.E_prime  # exact J = K_I^2 / E'


def sent_problem(h: float):
    """SENT of seed 001 Sect. 4 (mm, N, MPa), extrinsic PU."""
    sc = sent_seed001(5.0, SENT_MAT)  # efgkit.gallery (u_x = -/+ SENT_DISP at the ends)
    m = EFG(spacing=h, bc="lagrange", enrichment="pu", rule_power=1.0)
    return sc, m, h, 4.5, J_SENT_REF


def _fields(sol):
    """Quadrature-point and point-wise (nodal) evaluation sets: (x, w, stress, grad_u)."""
    pts = sol.disc.points
    quad = (pts.x, pts.w, sol.stress(), sol.gradient())
    nodes = sol.nodes
    tip = sol.scene.tips[0].x
    xn = nodes.face_positions(sol.disc.approx.lines, 1e-9)
    keep = np.hypot(*(nodes.x - tip).T) > 1e-9 * sol.method.spacing  # the field is singular there
    uniq, inv = np.unique(np.round(nodes.x / (1e-9 * sol.method.spacing)), axis=0, return_inverse=True)
    inv = inv.ravel()
    first = np.zeros(len(uniq), int)
    first[inv[::-1]] = np.arange(len(inv))[::-1]
    V = nodal_volumes(nodes.x[first], sol.scene.domain)[inv] / np.bincount(inv)[inv]
    xn, V = xn[keep], V[keep]
    point = (xn, V, sol.stress(xn), sol.gradient(xn))
    return {"quadrature points": quad, "point-wise (nodes)": point}


def study(sc, m, h, r_max, J_ref, n_radii: int) -> dict:
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = solve(sc, m)
    t_solve = time.perf_counter() - t0
    tip = sc.tips[0]
    radii = np.linspace(2 * h, r_max, n_radii)
    out = {"h": h, "n_nodes": sol.nodes.n, "J_ref": J_ref, "radii": radii.tolist(),
           "seconds_solve": t_solve, "evaluations": {}}
    for ev, (x, w, s, g) in _fields(sol).items():
        per_q = {}
        for q, opts in QS.items():
            kind = "power" if q.startswith("power") else q
            J, npts = [], []
            for R in radii:
                d = domain_integrals(x, w, s, g, tip, sc.material, QFunction(kind, float(R), **opts))
                J.append(d.J)
                npts.append(d.n_points)
            J = np.array(J)
            outer = J[radii >= np.median(radii)]
            per_q[q] = {"J": J.tolist(), "n_points": npts,
                        "oscillation": float(np.ptp(outer) / abs(np.mean(outer))),
                        "J_outer_mean": float(np.mean(outer)),
                        "J_error_outer": float(np.mean(outer) / J_ref - 1)}
        out["evaluations"][ev] = per_q
    return out


def figure(res: dict, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    probs = list(res)
    evs = list(res[probs[0]]["evaluations"])
    fig, axes = plt.subplots(len(probs), 2 * len(evs), figsize=(4.2 * 2 * len(evs), 3.4 * len(probs)),
                             squeeze=False)
    for i, p in enumerate(probs):
        r = res[p]
        radii = np.array(r["radii"])
        for j, ev in enumerate(evs):
            for k, (q, d) in enumerate(r["evaluations"][ev].items()):
                J = np.array(d["J"]) / r["J_ref"]
                kernel = not q.startswith("power")
                style = dict(color=f"C{k}", lw=2.0 if kernel else 1.0, zorder=3 if kernel else 2, label=q)
                axes[i, 2 * j].plot(radii / r["h"], J, **style)
                axes[i, 2 * j + 1].plot(d["n_points"], J, **style)
            for c, xl in ((2 * j, "domain radius / spacing"), (2 * j + 1, "points in the domain")):
                ax = axes[i, c]
                ax.axhline(1.0, color="k", lw=0.6)
                ax.set_ylim(0.9, 1.1)
                ax.set_xlabel(xl)
                ax.set_title(f"{p}: {ev}", fontsize=9)
                ax.set_ylabel("J / J_ref")
            axes[i, 2 * j + 1].set_xscale("log")
            axes[i, 2 * j + 1].xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    return write_figure(fig, path, dpi=100)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    problems = {"singular patch": (patch_problem(25 if quick else 41), 17 if quick else 33),
                "SENT": (sent_problem(0.5 if quick else 0.25), 9 if quick else 33)}
    res = {p: study(*args, n_radii=n) for p, (args, n) in problems.items()}
    osc = {f"{p}/{ev}/{q}": d["oscillation"] for p, r in res.items()
           for ev, per_q in r["evaluations"].items() for q, d in per_q.items()}
    rep.metrics.update({"oscillation": osc, "problems": res})
    rep.ref("J_patch", 1.0 / PATCH_MAT.E_prime, "exact: J = K_I^2 / E', E' = E / (1 - nu^2), K_I = 1 "
            "prescribed (seed 003 Eq. 60)")
    rep.ref("J_SENT", J_SENT_REF, "seed 001 Sect. 4.1 and Table 5: FEM (Abaqus CPE8) 6786 J/m^2")
    for p, r in res.items():
        qp, pw = r["evaluations"]["quadrature points"], r["evaluations"]["point-wise (nodes)"]
        # seed 001 Sect. 8: the power law oscillates with the point layout, more so for larger n
        rep.check(f"{p}, point-wise: oscillation of power n=5 exceeds Wendland C2",
                  pw["power n=5"]["oscillation"] - pw["wendland_c2"]["oscillation"], ">=", 0.0)
        rep.check(f"{p}, point-wise: oscillation of power n=5 exceeds n=2",
                  pw["power n=5"]["oscillation"] - pw["power n=2"]["oscillation"], ">=", 0.0)
        rep.check(f"{p}, quadrature points: Wendland C2 oscillation", qp["wendland_c2"]["oscillation"],
                  "<=", 2e-3)
    pq = res["singular patch"]["evaluations"]["quadrature points"]
    rep.check("singular patch, quadrature points: |J error| of Wendland C2 and cubic spline "
              "(outer half)", max(abs(pq[q]["J_error_outer"]) for q in KERNELS), "<=", 1e-4)
    pw = res["singular patch"]["evaluations"]["point-wise (nodes)"]
    if not quick:  # seed 001 Sect. 10: within 2.5 % of the FEM reference with >= 500 particles
        rep.check("singular patch, point-wise: |J error| of Wendland C2 and cubic spline (outer "
                  "half, >= 500 points)", max(abs(pw[q]["J_error_outer"]) for q in KERNELS), "<=", 0.025)
    if not quick:
        rep.figures.append(str(figure(res, ROOT / "docs" / "figures" / f"{NAME}_J.png")))
    elif out_dir is not None:
        rep.figures.append(str(figure(res, Path(out_dir) / f"{NAME}_J.png")))
    return rep.write(out_dir)


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    probs = m["problems"]
    lines = [
        "Seed 001 Sect. 8 on EFG fields: J against the domain radius for the q-functions of seed "
        "001 (cubic B-spline Eq. 10, Wendland C2 Eq. 13, power law 1 - z^n Eq. 14), at the "
        "quadrature points and point-wise at the nodes (Voronoi volumes, seed 001 Eq. 8). "
        "Problems: the singular patch (mode I, exact J = K^2 / E'; extrinsic MLS on "
        f"{probs['singular patch']['n_nodes']} nodes, h = {probs['singular patch']['h']:.4g}) and "
        f"the SENT of seed 001 (extrinsic PU, h = {probs['SENT']['h']:g} mm, "
        f"{probs['SENT']['n_nodes']} nodes; reference J = 6.786 N/mm from seed 001's Abaqus model). "
        "Radii from 2 h to 0.9 a (patch) and 4.5 mm (SENT).", "",
        "Oscillation = (max - min) / |mean| of J over the outer half of the radii; J error = mean "
        "over the outer half against the reference:", "",
        "| problem | evaluation | " + " | ".join(QS) + " |", "|---|---|" + "---|" * len(QS)]
    for p, r in probs.items():
        for ev, per_q in r["evaluations"].items():
            lines.append(f"| {p} | {ev} oscillation | "
                         + " | ".join(f"{per_q[q]['oscillation']:.1e}" for q in QS) + " |")
            lines.append(f"| {p} | {ev} J error | "
                         + " | ".join(f"{per_q[q]['J_error_outer']:+.2%}" for q in QS) + " |")
    lines += ["", "![J against radius and points](figures/q_functions_J.png)", "",
              "As in seed 001 (Figs. 16, 19), the power law oscillates with the point layout, "
              "more for larger n: its gradient is largest at the outer edge and jumps from "
              "-n / r_out to 0 there, so the sum over points depends on which points fall just "
              "inside the circle. It does so at the quadrature points too (the circle cuts the "
              "background cells, whose Gauss rules assume a smooth integrand), with a bias that "
              "grows with n. The kernel-shaped Wendland C2 and cubic B-spline, whose gradient "
              "vanishes at r_out, are smooth: at the quadrature points J is domain independent "
              "to ~1e-5 (the library default is Wendland C2). Point-wise with nodal volumes "
              "every q is less accurate (errors up to 2 %, within seed 001's ~2.5 % at ~500 "
              "particles): one point per node is a low-order rule for a singular integrand. The "
              "SENT errors are against seed 001's Abaqus J; efgkit's P2 model of the SENT "
              "(verification/sent.py) also lies about 1.3 % above it."]
    return lines


if __name__ == "__main__":
    import json

    res = main()
    print(json.dumps(res["metrics"]["oscillation"], indent=1))
    print([c for c in res["checks"] if not c["passed"]])
