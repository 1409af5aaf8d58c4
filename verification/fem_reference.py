"""The FEM reference model verified on the singular patch (seed 003 Sect. 5.6.1).

Square [-a, a]^2 (a = 1) with an edge crack from (-a, 0) to the tip at the origin; the
exact Williams displacement (K_I = 1 or K_II = 1, plane strain, E = 1, nu = 0.3) is
prescribed on the whole boundary, crack mouth included. scikit-fem P2 triangles graded
toward the tip (size ``tip_h + 0.25 r``, a fan of 12 elements at the tip), with and
without quarter-point tip elements, and uniform meshes for contrast. K_I, K_II and J come
from :meth:`FEMSolution.sifs` (interaction and J domain integrals at the element
quadrature points, Wendland C2 q on discs of radii 0.3-0.75 a). A third case puts a
pressure p = 0.7 on the faces and prescribes the Williams field (K_I = 1, K_II = 0.3)
plus the uniform field sigma_yy = -p, which carries exactly that face pressure: it checks
the pressure loads of the FEM and the crack-face terms of the integrals.

Metrics: K errors, J error and J spread over the domains per mesh and mode; K with the
q-functions of seed 001 (Eqs. 10, 13, 14) and the FE plateau; the tip-fan comparison.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _report import Report

from efgkit import Crack, Domain, Elastic, Field, Scene, Support
from efgkit.fem.model import FEM, solve_fem

NAME = "fem_reference"
TITLE = "FEM reference model on the singular patch"
ROOT = Path(__file__).resolve().parents[1]
A = 1.0
MAT = Elastic(1.0, 0.3, "strain")
RADII = (0.3, 0.45, 0.6, 0.75)  # J domains (of a), four: path independence
PRESSURE = 0.7
MODES = {"mode I": (1.0, 0.0), "mode II": (0.0, 1.0), "pressurised": (1.0, 0.3)}
GRADED = ((0.25, 0.02), (0.25, 0.005), (0.125, 0.002), (0.0625, 0.0005))  # (h, tip_h)
UNIFORM = (0.1, 0.05, 0.025)
TOL_K = 5e-4  # issue 5: K within 0.05 % on a graded mesh


def exact_displacement(KI: float, KII: float, pressure: float = 0.0):
    """``x (n, 2) -> u (n, 2)``: Williams field plus the uniform field sigma_yy = -pressure."""
    W = Field.named("williams", KI=KI, KII=KII)
    C = MAT.compliance()

    def u(x):
        return W.displacement(x, MAT) + np.column_stack([-pressure * C[0, 1] * x[:, 0],
                                                         -pressure * C[1, 1] * x[:, 1]])
    return u


def scene(KI: float, KII: float, pressure: float = 0.0) -> Scene:
    u = exact_displacement(KI, KII, pressure)
    sup = tuple(Support(e, ux=lambda x: u(x)[:, 0], uy=lambda x: u(x)[:, 1])
                for e in ("left", "bottom", "right", "top"))
    crack = Crack([[-A, 0.0], [0.0, 0.0]], tips=(False, True), name="crack", pressure=pressure)
    return Scene(Domain.rectangle(-A, -A, A, A), MAT, supports=sup, cracks=(crack,),
                 name="singular_patch")


def run(mode: str, fem: FEM, qs=("wendland_c2",)) -> list[dict]:
    """One solve; its K and J with each q-function of ``qs`` (one record per q)."""
    KI, KII = MODES[mode]
    p = PRESSURE if mode == "pressurised" else 0.0
    t0 = time.perf_counter()
    sol = solve_fem(scene(KI, KII, p), fem)
    t1 = time.perf_counter()
    energy = sol.errors(Field.named("williams", KI=KI, KII=KII))["energy"] if p == 0.0 else None
    J_exact = (KI**2 + KII**2) / MAT.E_prime
    out = []
    for q in qs:
        res = sol.sifs(radii=RADII, q=q, error=False)[0]
        J = np.array([d.J for d in res.domains])
        rec = {"h": fem.h, "tip_h": fem.tip_h, "quarter_point": fem.quarter_point,
               "fan": fem.tip_fan, "n_dofs": sol.n_dofs, "seconds": t1 - t0, "KI": res.KI,
               "KII": res.KII, "KI_error": res.KI - KI, "KII_error": res.KII - KII, "J": res.J,
               "J_error": res.J / J_exact - 1, "J_spread": float(np.ptp(J) / J_exact),
               "J_domains": J.tolist(), "K_spread": res.spread}
        if energy is not None:
            rec["energy_error"] = energy
        out.append(rec)
    return out


def families(quick: bool) -> dict:
    """Mesh families: name -> list of FEM."""
    graded = GRADED[:3:2] if quick else GRADED
    out = {"graded, quarter-point": [FEM(h, tip_h=t, quarter_point=True) for h, t in graded]}
    if not quick:
        out["graded"] = [FEM(h, tip_h=t, quarter_point=False) for h, t in graded]
        out["uniform"] = [FEM(h, tip_h=h, quarter_point=False) for h in UNIFORM]  # not the default
    return out


def figure(rows: dict, path: Path) -> Path:
    import matplotlib.pyplot as plt

    from efgkit.io import write_figure

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, (mode, key) in zip(axes, (("mode I", "KI_error"), ("mode II", "KII_error")), strict=True):
        for fam, marker in zip(rows[mode], "osd", strict=False):
            r = rows[mode][fam]
            ax.loglog([x["n_dofs"] for x in r], [max(abs(x[key]), 1e-9) for x in r], marker + "-",
                      label=fam)
        ax.axhline(TOL_K, color="k", ls=":", lw=1, label="0.05 %")
        ax.set(xlabel="DOFs", ylabel=f"|{key.split('_')[0]} error| (K = 1)", title=mode)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return write_figure(fig, path, dpi=100)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    fams = families(quick)
    # the finest graded quarter-point mesh also gives K with the other q-functions
    finest = fams["graded, quarter-point"][-1]
    others = ("cubic_spline", "plateau")
    rows, q_kinds = {}, {q: {} for q in ("wendland_c2", *others)}
    for mode in ("mode I", "mode II"):
        rows[mode] = {}
        for f, fems in fams.items():
            runs = [run(mode, fem, ("wendland_c2", *others) if fem is finest else ("wendland_c2",))
                    for fem in fems]
            rows[mode][f] = [r[0] for r in runs]
            if f == "graded, quarter-point":
                for q, rec in zip(q_kinds, runs[-1], strict=True):
                    q_kinds[q][mode] = rec
    rows["pressurised"] = {"graded, quarter-point": [run("pressurised", fem)[0]
                                                     for fem in fams["graded, quarter-point"]]}
    fan_fem = fams["graded, quarter-point"][0]  # its tip fan is the default, 12 elements
    fan = {str(n): run("mode I", FEM(fan_fem.h, tip_h=fan_fem.tip_h, quarter_point=True,
                                     tip_fan=n))[0] for n in (0, 8)}
    fan[str(fan_fem.tip_fan)] = rows["mode I"]["graded, quarter-point"][0]
    rep.metrics.update({"material": {"E": MAT.E, "nu": MAT.nu, "plane": MAT.plane},
                        "radii": list(RADII), "pressure": PRESSURE, "rows": rows,
                        "q_kinds": q_kinds, "tip_fan": fan})
    rep.ref("KI", 1.0, "prescribed Williams field (seed 003 Sect. 5.6.1, Eq. 60)")
    rep.ref("KII", 1.0, "prescribed Williams field, mode II run")
    rep.ref("J", 1 / MAT.E_prime, "J = (K_I^2 + K_II^2) / E', E' = E / (1 - nu^2) (plane strain)")
    rep.ref("K_tolerance", TOL_K, "issue 5: K within 0.05 % on a graded mesh")
    for mode, key in (("mode I", "KI_error"), ("mode II", "KII_error"), ("pressurised", "KI_error")):
        best = rows[mode]["graded, quarter-point"][-1]
        rep.check(f"{mode}: |K error| on the finest graded quarter-point mesh", abs(best[key]), "<=",
                  TOL_K)
    best = rows["pressurised"]["graded, quarter-point"][-1]
    rep.check("pressurised: |J error| (crack-face term)", abs(best["J_error"]), "<=", TOL_K)
    for mode in ("mode I", "mode II"):
        best = rows[mode]["graded, quarter-point"][-1]
        other = "KII_error" if mode == "mode I" else "KI_error"
        rep.check(f"{mode}: spurious other-mode K", abs(best[other]), "<=", 1e-4)
        rep.check(f"{mode}: |J error|", abs(best["J_error"]), "<=", TOL_K)
        rep.check(f"{mode}: J spread over {len(RADII)} domains (relative)", best["J_spread"], "<=",
                  TOL_K)
    for q in others:  # Wendland C2: the checks above
        rep.check(f"|K_I error| with q = {q}", abs(q_kinds[q]["mode I"]["KI_error"]), "<=", TOL_K)
    if not quick:
        rep.figures.append(str(figure(rows, ROOT / "docs" / "figures" / f"{NAME}_convergence.png")))
    elif out_dir is not None:
        rep.figures.append(str(figure(rows, Path(out_dir) / f"{NAME}_convergence.png")))
    return rep.write(out_dir)


def _table(rows: list, key: str) -> list[str]:
    out = ["| h | tip h | DOFs | K error | J error | J spread | energy error | s |",
           "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        e = r.get("energy_error")
        out.append(f"| {r['h']:g} | {r['tip_h'] if r['tip_h'] is not None else '-'} | {r['n_dofs']} | "
                   f"{r[key]:+.1e} | {r['J_error']:+.1e} | {r['J_spread']:.1e} | "
                   f"{'-' if e is None else f'{e:.4f}'} | {r['seconds']:.2f} |")
    return out


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    lines = ["Singular patch of seed 003 Sect. 5.6.1: square [-1, 1]^2, edge crack from (-1, 0) to "
             "the tip at (0, 0), the exact Williams displacement prescribed on the whole boundary; "
             f"plane strain, E = {m['material']['E']:g}, nu = {m['material']['nu']:g}. scikit-fem P2 "
             "triangles (Triangle meshes, size tip h + 0.25 r toward the tip, 12 elements around "
             "it). K from the interaction integrals and J from the domain integral at the element "
             f"quadrature points, Wendland C2 q, domain radii {m['radii']} (J spread = "
             "max - min over the four domains / exact J). K = 1 in the mode run; K errors are "
             "absolute = relative.", ""]
    for mode, key in (("mode I", "KI_error"), ("mode II", "KII_error")):
        for fam, rows in m["rows"][mode].items():
            lines += [f"**{mode}, {fam}**", "", *_table(rows, key), ""]
    lines += [f"**Pressurised faces** (p = {m['pressure']}, K_I = 1, K_II = 0.3 plus the uniform "
              "sigma_yy = -p: the faces carry exactly p), graded quarter-point:", "",
              *_table(m["rows"]["pressurised"]["graded, quarter-point"], "KI_error"), "",
              "The face terms are summed facet by facet (Gauss points of each loaded facet, "
              "through its quarter-point map, with the gradient of its own element): a single "
              "Gauss rule along the faces, across the jumps of the FE gradient between facets, "
              "left J errors of 4e-4 to 4e-3 on these meshes, not decreasing with them.", "",
              "q-functions on the finest graded quarter-point mesh (K errors):", "",
              "| q | K_I error (mode I) | K_II error (mode II) | J error (mode I) |",
              "|---|---|---|---|"]
    for q, r in m["q_kinds"].items():
        lines.append(f"| {q} | {r['mode I']['KI_error']:+.1e} | {r['mode II']['KII_error']:+.1e} | "
                     f"{r['mode I']['J_error']:+.1e} |")
    lines += ["", "Elements around the tip (first graded quarter-point mesh, mode I): Triangle "
              "alone leaves 5-6, the fan option puts n vertices at tip h from the tip:", "",
              "| fan | DOFs | K_I error | energy error |", "|---|---|---|---|"]
    for n, r in m["tip_fan"].items():
        lines.append(f"| {n if n != '0' else 'none'} | {r['n_dofs']} | {r['KI_error']:+.1e} | "
                     f"{r['energy_error']:.4f} |")
    lines += ["", f"![K errors against DOFs](figures/{NAME}_convergence.png)"]
    return lines


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"]["rows"]["mode I"], indent=1))
