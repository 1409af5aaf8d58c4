"""Shear edge crack of seed 003 Sect. 5.6.2 and Table 1.

Plate W = 7 wide (x) and L = 16 high (y), clamped on the bottom edge, shear traction
t = (1, 0) on the top edge, edge crack of length a = W / 2 = 3.5 at mid-height from the
left edge; E = 3e7, nu = 0.25, plane strain (units psi, in). Evenly spaced grids of
5 x 11 and 11 x 29 nodes (spacings 1.75 x 1.6 and 0.7 x 0.571; the tip is a node of
both), Lagrange multipliers on the bottom edge, J domains of radius 0.8, 1.0 and 1.2
about the tip (the seed's "+-1 in. from the crack tip"; Wendland C2 q).

Variants as in Table 1 (linear basis without rings, extrinsic MLS, intrinsic full and
intrinsic sqrt(r)), plus extrinsic PU, with the settings of ``singular_patch`` scaled by
the crack length. References: Wilson (1969), quoted by seed 003: K_I = 34.0,
K_II = 4.55; and a converged reference of our own: EFG with PU enrichment on uniform
grids of h = 0.175 and 0.0875 and P2 quarter-point finite elements (scikit-fem) with
h = 0.125 / 0.0625 (tip elements 0.01 / 0.005).
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
from _report import Report

from efgkit import EFG, FEM, Elastic, Scene, solve, solve_fem
from efgkit.approx.mls import SingularMomentMatrix
from efgkit.gallery import shear_edge_crack
from efgkit.io import write_figure

NAME = "shear_edge_crack"
TITLE = "Shear edge crack (seed 003 Table 1)"
ROOT = Path(__file__).resolve().parents[1]
W, L, A = 7.0, 16.0, 3.5
MAT = Elastic(3e7, 0.25, "strain")
GRIDS = ((5, 11), (11, 29))
RADII = (0.8, 1.0, 1.2)  # J discs about the tip: seed 003 "a domain of +-1 in."
CURVE = tuple(np.round(np.linspace(0.5, 3.0, 11), 6))  # K against the radius (figure)
K_WILSON = (34.0, 4.55)  # Wilson (1969), quoted in seed 003 Sect. 5.6.2
# Measured by this script in full mode (recomputed there): EFG PU at h = 0.0875 gives
# (34.0419, 4.5370) and FEM P2 quarter-point at h = 0.0625, tip_h = 0.005 (34.0406, 4.5368).
K_CONVERGED = (34.041, 4.5369)
# Seed 003 Table 1: (k1, k2) on 5 x 11 and 11 x 29 nodes
SEED = {"linear": ((26.90, 3.43), (32.51, 4.33)), "extrinsic_mls": ((34.43, 4.58), (34.21, 4.55)),
        "full": ((32.24, 4.21), (33.87, 4.54)), "radial": ((31.86, 4.20), (33.01, 4.59))}
# Settings per variant: those of singular_patch (seed 003's default support d_max = 2.5,
# Sect. 2; diffraction lambda = 1 with the extrinsic enrichments; visibility with sqrt(r),
# Sect. 5.3.2), the intrinsic disc scaled by the crack length. The full basis with the
# settings under which it gives the seed's Table 1 values on 11 x 29 (33.87, 4.54; not those
# on 5 x 11): seed 003's default Gaussian weight (Eq. 1a, alpha = d_max / 4, Sect. 2) on
# supports enlarged to d_max = 3 for the 7-term moment matrix, and the basis at every node
# ("it must be used at all nodes", Sect. 5.3.1). singular_patch's quartic weight on a ramped
# disc gives 33.30 (studies).
D_MAX = 2.5
INTRINSIC_DISC = dict(enrich_radius=0.9 * A, ramp_inner=0.6 * A)  # r2, r1 of Eq. (54)
WHOLE_PLATE = dict(enrich_radius=20.0, ramp_inner=19.0)  # r1 beyond the farthest corner (8.7)
VARIANTS = {
    "linear": dict(d_max=D_MAX, enrichment="none"),  # the default would enrich
    "extrinsic_mls": dict(d_max=D_MAX, enrichment="extrinsic_mls", rule_power=1.0),
    "full": dict(enrichment="full", weight="gaussian", d_max=3.0, alpha=0.75, rule_power=1.0,
                 **WHOLE_PLATE),
    "radial": dict(d_max=D_MAX, enrichment="radial", crack_rule="visibility", **INTRINSIC_DISC),
    "pu": dict(d_max=D_MAX, enrichment="pu", rule_power=1.0),
}
FULL_QUARTIC_DISC = dict(weight="quartic", **INTRINSIC_DISC)  # singular_patch's full, ramped
REFERENCE_PU = dict(enrichment="pu", rule_power=1.0)  # the converged EFG reference (d_max 2)
LABELS = {"linear": "Linear (no rings)", "extrinsic_mls": "Extrinsic MLS", "full": "Intrinsic (full)",
          "radial": "Intrinsic (sqrt r)", "pu": "Extrinsic PU"}
TOL = 0.003  # issue 4: enriched variants at 11 x 29 within 0.3 % of K_I and K_II
EFG_REF = (0.175, 0.0875)  # uniform spacings of the converged EFG reference (PU, lambda = 1)
FEM_REF = ((0.125, 0.01), (0.0625, 0.005))  # (h, tip_h) of the P2 quarter-point reference


def scene() -> Scene:
    return shear_edge_crack(NAME)  # efgkit.gallery


def grid(nx: int, ny: int) -> np.ndarray:
    """Evenly spaced nodes (nx * ny, 2) on the plate."""
    g = np.meshgrid(np.linspace(0.0, W, nx), np.linspace(0.0, L, ny))
    return np.column_stack([a.ravel() for a in g])


def _sifs(sol, radii):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = sol.sifs(radii=radii, error=False)[0]
    return res, sorted({str(w.message)[:120] for w in caught})


def run(variant: str, nx: int, ny: int, curve: bool = True) -> dict:
    h = max(W / (nx - 1), L / (ny - 1))
    t0 = time.perf_counter()
    sol = solve(scene(), EFG(spacing=h, coordinates=grid(nx, ny), bc="lagrange", **VARIANTS[variant]))
    res, notes = _sifs(sol, RADII)
    out = {"KI": res.KI, "KII": res.KII, "spread": res.spread, "n_nodes": sol.nodes.n,
           "domains": [{"radius": d.radius, "KI": d.KI, "KII": d.KII, "n_points": d.n_points}
                       for d in res.domains], "warnings": notes}
    if res.enriched is not None:
        out["KI_enriched"], out["KII_enriched"] = res.enriched
    if curve:
        doms = _sifs(sol, CURVE)[0].domains
        out["curve"] = {"radius": [d.radius for d in doms], "KI": [d.KI for d in doms],
                        "KII": [d.KII for d in doms]}
    out["seconds"] = time.perf_counter() - t0
    return out


def run_with(variant: str, override: dict, uniform: bool = False) -> dict:
    """K of ``variant`` with settings changed: on the 11 x 29 grid or (``uniform``) on the
    regular grid of ``override["spacing"]``."""
    nx, ny = GRIDS[-1]
    opts = dict(spacing=max(W / (nx - 1), L / (ny - 1)), coordinates=grid(nx, ny), bc="lagrange",
                **VARIANTS[variant])
    if uniform:
        opts.pop("coordinates")
    opts.update(override)
    try:
        res, _ = _sifs(solve(scene(), EFG(**opts)), RADII)
    except SingularMomentMatrix as err:  # recorded: the 7-term basis far from the tip
        return {"error": str(err)[:160]}
    return {"KI": res.KI, "KII": res.KII, "spread": res.spread}


# Studies on the 11 x 29 grid (full mode): each variant's settings changed one at a time.
FINE_STUDIES = {
    **{f"{LABELS[v]}, d_max {d:g}": (v, dict(d_max=d)) for v in ("extrinsic_mls", "pu")
       for d in (2.0, 3.0)},
    **{f"{LABELS[v]}, lambda = 2": (v, dict(rule_power=2.0)) for v in ("extrinsic_mls", "pu")},
    "Intrinsic (full), Gaussian alpha = 1": ("full", dict(alpha=1.0)),
    "Intrinsic (full), ramped disc r1 = 0.6 a, r2 = 0.9 a": ("full", INTRINSIC_DISC),
    **{f"Intrinsic (full), quartic weight, ramped disc, d_max {d:g}": (
        "full", dict(FULL_QUARTIC_DISC, d_max=d)) for d in (2.0, 2.5, 3.0, 4.0)},
    "Intrinsic (full), quartic weight, whole plate": ("full", dict(weight="quartic")),
    "Intrinsic (sqrt r), diffraction lambda = 2": ("radial", dict(crack_rule="diffraction",
                                                                 rule_power=2.0)),
    **{f"Intrinsic (sqrt r), d_max {d:g}": ("radial", dict(d_max=d)) for d in (2.0, 3.0)},
    "Intrinsic (sqrt r), whole plate": ("radial", WHOLE_PLATE),
    **{f"{LABELS[v]}, quadratic basis, d_max 3": (v, dict(basis="quadratic", d_max=3.0))
       for v in ("extrinsic_mls", "radial", "pu")},
    "Intrinsic (full), quartic weight, ramped disc, quadratic basis": (
        "full", dict(FULL_QUARTIC_DISC, basis="quadratic")),
}


def on_fine_grid() -> dict:
    """K of the ``FINE_STUDIES`` settings on the 11 x 29 grid."""
    return {f"{name}, 11x29": run_with(v, over) for name, (v, over) in FINE_STUDIES.items()}


def efg_reference(h: float) -> dict:
    t0 = time.perf_counter()
    sol = solve(scene(), EFG(spacing=h, bc="lagrange", **REFERENCE_PU))
    res, _ = _sifs(sol, RADII)
    est = sol.near_tip_estimates(sol.scene.tips[0])  # seed 000 Eqs. 5.2-5.5 and the COD
    return {"h": h, "n_nodes": sol.nodes.n, "KI": res.KI, "KII": res.KII, "spread": res.spread,
            "seconds": time.perf_counter() - t0,
            "estimates": {k: [float(v) for v in val] for k, val in est.items()}}


def fem_reference(h: float, tip_h: float) -> dict:
    t0 = time.perf_counter()
    sol = solve_fem(scene(), FEM(h, tip_h=tip_h, quarter_point=True))
    res, _ = _sifs(sol, RADII)
    return {"h": h, "tip_h": tip_h, "n_dofs": sol.n_dofs, "KI": res.KI, "KII": res.KII,
            "spread": res.spread, "seconds": time.perf_counter() - t0}


def figure(rows: dict, ref: tuple, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10.0, 4.0))
    g = f"{GRIDS[-1][0]}x{GRIDS[-1][1]}"
    for k, (v, per_grid) in enumerate(rows.items()):
        c = per_grid[g]["curve"]
        for ax, key in zip(axes, ("KI", "KII"), strict=True):
            ax.plot(c["radius"], c[key], "o-", ms=3, color=f"C{k}", label=LABELS[v])
    for ax, key, i in zip(axes, ("K_I", "K_{II}"), (0, 1), strict=True):
        ax.axhline(K_WILSON[i], color="k", ls="--", lw=0.8, label="Wilson (1969)")
        ax.axhline(ref[i], color="k", ls=":", lw=0.8, label="converged (EFG PU / FEM)")
        ax.set_xlabel("J-domain radius (in.)")
        ax.set_ylabel(f"${key}$ (psi sqrt(in.))")
        ax.set_title(f"${key}$, {GRIDS[-1][0]} x {GRIDS[-1][1]} nodes")
    axes[0].set_ylim(K_WILSON[0] * 0.9, K_WILSON[0] * 1.05)
    axes[1].set_ylim(K_WILSON[1] * 0.9, K_WILSON[1] * 1.05)
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    return write_figure(fig, path, dpi=100)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    rows = {v: {f"{nx}x{ny}": run(v, nx, ny, curve=not quick) for nx, ny in GRIDS} for v in VARIANTS}
    extra = {}
    if quick:  # the recorded reference, cross-checked by a coarse FE model
        efg_ref, fem_ref = [], [fem_reference(0.5, 0.05)]
        ref = K_CONVERGED
    else:
        efg_ref = [efg_reference(h) for h in EFG_REF]
        fem_ref = [fem_reference(h, t) for h, t in FEM_REF]
        ref = (efg_ref[-1]["KI"], efg_ref[-1]["KII"])
        extra = on_fine_grid()
        for h in (0.7, 0.35, 0.175):  # the quartic full basis on uniform grids: its disc, and 4 h
            extra[f"full, uniform h = {h:g}"] = run_with("full", dict(FULL_QUARTIC_DISC, spacing=h),
                                                         uniform=True)
            extra[f"full (r2 = 4 h, r1 = 0), uniform h = {h:g}"] = run_with(
                "full", dict(FULL_QUARTIC_DISC, spacing=h, enrich_radius=None, ramp_inner=0.0),
                uniform=True)
    rep.metrics.update({
        "settings": {"W": W, "L": L, "a": A, "E": MAT.E, "nu": MAT.nu, "plane": MAT.plane,
                     "radii": RADII, "q": "wendland_c2", "bc": "lagrange", "variants": VARIANTS},
        "KI": {f"{v}/{g}": r["KI"] for v, d in rows.items() for g, r in d.items()},
        "KII": {f"{v}/{g}": r["KII"] for v, d in rows.items() for g, r in d.items()},
        "rows": rows, "seed_table_1": SEED, "reference_efg": efg_ref, "reference_fem": fem_ref,
        "K_converged": ref, "studies": extra})
    rep.ref("KI", K_WILSON[0], "Wilson (1969), quoted in seed 003 Sect. 5.6.2")
    rep.ref("KII", K_WILSON[1], "Wilson (1969), quoted in seed 003 Sect. 5.6.2")
    rep.ref("K_converged", list(ref), "EFG PU (lambda = 1) at h = 0.0875, this script's full mode; "
            "in quick mode the value recorded from it")
    rep.ref("seed_table_1", SEED, "seed 003 Table 1 (k1, k2 on 5 x 11 and 11 x 29 nodes)")
    rep.ref("tolerance", TOL, "issue 4: enriched variants at 11 x 29 within 0.3 % of both K")
    fine = f"{GRIDS[-1][0]}x{GRIDS[-1][1]}"
    for v in ("extrinsic_mls", "full", "radial", "pu"):
        r = rows[v][fine]
        e_conv, e_wil = _err(r, ref), _err(r, K_WILSON)
        if not quick or v == "pu":
            rep.check(f"{LABELS[v]}, {fine}: max relative K error against the converged reference",
                      e_conv, "<=", TOL)
        if not quick:
            rep.check(f"{LABELS[v]}, {fine}: max relative K error against Wilson (1969)", e_wil,
                      "<=", TOL)
    fe = fem_ref[-1]
    rep.check("FEM P2 quarter-point against the converged reference (max relative K difference)",
              _err(fe, ref), "<=",
              1e-3 if quick else 1e-4)
    if not quick:
        # the reference must be converged well below the 0.3 % target
        rep.check("EFG reference converged (max relative K change, h = 0.175 -> 0.0875)",
                  _err(efg_ref[0], ref), "<=",
                  1e-3)
        rep.figures.append(str(figure(rows, ref, ROOT / "docs" / "figures" / f"{NAME}_K.png")))
    return rep.write(out_dir)


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    ref = m["K_converged"]
    grids = list(next(iter(m["rows"].values())))
    lines = [
        "Seed 003 Sect. 5.6.2: plate 7 x 16, bottom clamped (Lagrange multipliers), shear "
        "traction 1 on the top, edge crack a = 3.5 at mid-height, E = 3e7, nu = 0.25, plane "
        "strain; evenly spaced grids of 5 x 11 and 11 x 29 nodes; K as the mean over J discs of "
        f"radius {list(m['settings']['radii'])} about the tip (Wendland C2 q). Settings as in "
        "`singular_patch`: quartic weight, d_max 2.5 (seed 003's default support); linear: "
        "diffraction lambda = 2; extrinsic MLS and PU: diffraction lambda = 1; sqrt(r): the "
        "basis within r1 = 0.6 a = 2.1, ramped to r2 = 0.9 a = 3.15, visibility rule. Full "
        "basis: seed 003's default Gaussian weight (alpha = d_max / 4), d_max 3, on every node "
        "of the plate, diffraction lambda = 1 (with these settings it gives the seed's values "
        "on 11 x 29 nodes, not on 5 x 11).", "",
        "Table 1 side by side, efgkit (seed):", "",
        "| nodes | " + " | ".join(f"{LABELS[v]} k1 | k2" for v in m["rows"]) + " |",
        "|---|" + "---|---|" * len(m["rows"])]
    for i, g in enumerate(grids):
        cells = []
        for v, d in m["rows"].items():
            seed = m["seed_table_1"].get(v)
            s1 = f" ({seed[i][0]:.2f})" if seed else ""
            s2 = f" ({seed[i][1]:.2f})" if seed else ""
            cells += [f"{d[g]['KI']:.2f}{s1}", f"{d[g]['KII']:.3f}{s2}"]
        lines.append(f"| {g.replace('x', ' x ')} | " + " | ".join(cells) + " |")
    lines += ["", f"Errors at {grids[-1]} against Wilson {K_WILSON} and against the converged "
              f"reference ({ref[0]:.4f}, {ref[1]:.4f}); target 0.3 %:", "",
              "| variant | K_I vs Wilson | K_II vs Wilson | K_I vs converged | K_II vs converged | "
              "spread |", "|---|---|---|---|---|---|"]
    for v, d in m["rows"].items():
        r = d[grids[-1]]
        lines.append(f"| {LABELS[v]} | {r['KI'] / K_WILSON[0] - 1:+.2%} | "
                     f"{r['KII'] / K_WILSON[1] - 1:+.2%} | {r['KI'] / ref[0] - 1:+.2%} | "
                     f"{r['KII'] / ref[1] - 1:+.2%} | {r['spread']:.1e} |")
    r = m["rows"]["extrinsic_mls"]
    lines += ["", "Extrinsic MLS, the solution's own K (enrichment unknowns): " + ", ".join(
        f"{g}: ({r[g]['KI_enriched']:.2f}, {r[g]['KII_enriched']:.3f})" for g in grids) + ".", "",
        "Converged reference:", "", "| model | size | K_I | K_II | spread |", "|---|---|---|---|---|"]
    for e in m["reference_efg"]:
        lines.append(f"| EFG PU, uniform grid | h = {e['h']:g} ({e['n_nodes']} nodes) | {e['KI']:.4f} | "
                     f"{e['KII']:.4f} | {e['spread']:.1e} |")
    for e in m["reference_fem"]:
        lines.append(f"| FEM P2 quarter-point | h = {e['h']:g}, tip {e['tip_h']:g} ({e['n_dofs']} DOFs) | "
                     f"{e['KI']:.4f} | {e['KII']:.4f} | {e['spread']:.1e} |")
    if m["reference_efg"] and "estimates" in m["reference_efg"][-1]:
        e = m["reference_efg"][-1]
        names = {"stress_0": "stresses on theta = 0 (seed 000 Eq. 5.2), 2 nearest points",
                 "stress_90": "stresses on theta = 90 deg (seed 000 Eq. 5.3, mixed form)",
                 "cod": "crack-opening displacement, linear fit to r = 0"}
        lines += ["", f"Near-tip estimates on the finest EFG reference (h = {e['h']:g}; samples 1 "
                  "to 6 spacings from the tip) beside its interaction integrals:", "",
                  "| estimate | K_I | K_II |", "|---|---|---|",
                  f"| interaction integrals | {e['KI']:.3f} | {e['KII']:.4f} |"]
        lines += [f"| {names[k]} | {v[0]:.3f} | {v[1]:.4f} |" for k, v in e["estimates"].items()]
        lines += ["", "The point estimates carry the O(r) terms of the near-tip expansion (and the "
                  "stress recovery right at the tip), which is why the domain integrals are the "
                  "ones reported."]
    st = m["studies"]
    fine = {k: v for k, v in st.items() if k.endswith(", 11x29") and "KI" in v}
    if fine:
        lines += ["", f"Studies on {grids[-1].replace('x', ' x ')} nodes (the errors as above):", "",
                  "| setting | K_I | K_II | K_I vs Wilson | K_II vs Wilson | K_I vs converged | "
                  "K_II vs converged |", "|---|---|---|---|---|---|---|"]
        lines += [f"| {k[:-7]} | {v['KI']:.3f} | {v['KII']:.4f} | {v['KI'] / K_WILSON[0] - 1:+.2%} | "
                  f"{v['KII'] / K_WILSON[1] - 1:+.2%} | {v['KI'] / ref[0] - 1:+.2%} | "
                  f"{v['KII'] / ref[1] - 1:+.2%} |" for k, v in fine.items()]
    fe = m["reference_fem"][-1]
    agree = _err(fe, ref)
    lines += ["", "![K against the J-domain radius, 11 x 29 nodes](figures/shear_edge_crack_K.png)", "",
              "Findings:", "", f"- EFG (PU) and the quarter-point FE model agree on K_I = {ref[0]:.3f}, "
              f"K_II = {ref[1]:.4f} to {agree:.0e}. Wilson's K_II = {K_WILSON[1]} is "
              f"{K_WILSON[1] / ref[1] - 1:.2%} above it (his value is itself approximate), so a "
              "K_II within 0.3 % of both references must lie in a narrow window."]
    if fine:
        lines += _findings(m["rows"], fine, st, ref, grids[-1])
    return lines


def _err(r: dict, ref) -> float:
    return max(abs(r["KI"] / ref[0] - 1), abs(r["KII"] / ref[1] - 1))


def _far(r: dict) -> dict:
    """Mean K of the K-radius curve over the discs of radius 2 to 3 (2 to 4 spacings)."""
    c = r["curve"]
    far = [i for i, rad in enumerate(c["radius"]) if rad >= 2.0]
    return {key: float(np.mean([c[key][i] for i in far])) for key in ("KI", "KII")}


def _row(r: dict) -> str:
    return f"({r['KI']:.3f}, {r['KII']:.4f})" if "KI" in r else "(singular moment matrix)"


def _findings(rows: dict, fine: dict, st: dict, ref: tuple, g: str) -> list[str]:
    """The findings drawn from the full-mode studies on the fine grid ``g``."""
    def k(name):
        return fine[f"{name}, 11x29"]

    pu, mls, full, rad = (rows[v][g] for v in ("pu", "extrinsic_mls", "full", "radial"))
    uni = [(key.split(", uniform ")[0], key.split("uniform ")[1], v) for key, v in st.items()
           if key.startswith("full") and "uniform" in key]
    return [
        f"- Extrinsic PU {_row(pu)} is at most {_err(pu, K_WILSON):.2%} from Wilson's K and "
        f"{_err(pu, ref):.2%} from the converged ones. At d_max 2 and 3 it is as close to the "
        f"converged K, {_row(k('Extrinsic PU, d_max 2'))} and "
        f"{_row(k('Extrinsic PU, d_max 3'))}, whose K_II are 0.3-0.4 % below Wilson's: against "
        "Wilson, passing or not is decided by the gap between the references. On a quadratic "
        f"basis: {_row(k('Extrinsic PU, quadratic basis, d_max 3'))}.",
        f"- Extrinsic MLS (global Williams fields) gives K_I = {mls['KI']:.2f}, the seed's 34.21 "
        "with the seed's support. It moves by some 0.5 % with the settings, which a 0.3 % target "
        f"cannot absorb: d_max 2 {_row(k('Extrinsic MLS, d_max 2'))}, d_max 3 "
        f"{_row(k('Extrinsic MLS, d_max 3'))}, lambda = 2 {_row(k('Extrinsic MLS, lambda = 2'))}, "
        f"quadratic basis {_row(k('Extrinsic MLS, quadratic basis, d_max 3'))}; its K spread "
        f"over the J discs is {mls['spread']:.1e} (PU {pu['spread']:.1e}). Its error stays near "
        "the tip, where the seed's +-1 in. J domain lies (1.4 spacings of this grid; seed 001 "
        "asks for 10): over the discs of radius 2 to 3 (the K-radius curve) it gives "
        f"{_row(_far(mls))}, within {_err(_far(mls), ref):.2%} of the converged K and "
        f"{_err(_far(mls), K_WILSON):.2%} of Wilson's. The full basis gives "
        f"{_row(_far(full))} there: its error is in the whole field. Its own K (the "
        "enrichment unknowns) differ from the integral values by up to 1 %; the integral values "
        "are the ones to use.",
        f"- The full basis with the seed's settings gives {_row(full)}, the seed's (33.87, 4.54): "
        "0.4 % low in K_I, as in the seed. It depends on the weight and the enriched region: "
        f"Gaussian alpha = 1 {_row(k('Intrinsic (full), Gaussian alpha = 1'))}, on the ramped "
        f"disc {_row(k('Intrinsic (full), ramped disc r1 = 0.6 a, r2 = 0.9 a'))}; with "
        "singular_patch's quartic weight on the ramped disc K_I = " + " / ".join(
            f"{k(f'Intrinsic (full), quartic weight, ramped disc, d_max {d:g}')['KI']:.2f}"
            for d in (2.0, 2.5, 3.0, 4.0)) + " at d_max 2 / 2.5 / 3 / 4, and "
        f"{k('Intrinsic (full), quartic weight, whole plate')['KI']:.2f} on the whole plate. The "
        "least-squares fit of the smooth part of the field (its curvature) loads the "
        "branch-function coefficients, the more the larger the support; a quadratic basis under "
        "them takes the curvature: "
        f"{_row(k('Intrinsic (full), quartic weight, ramped disc, quadratic basis'))} (quartic, "
        "ramped disc). No setting tried brings both K within 0.3 %.",
        f"- The sqrt(r) basis with visibility: {_row(rad)} (the seed's 33.01, 4.59); with "
        f"diffraction {_row(k('Intrinsic (sqrt r), diffraction lambda = 2'))}, d_max 2 "
        f"{_row(k('Intrinsic (sqrt r), d_max 2'))}, 3 {_row(k('Intrinsic (sqrt r), d_max 3'))}, on "
        f"the whole plate {_row(k('Intrinsic (sqrt r), whole plate'))}.",
        "- The quartic full basis on uniform grids, K_I: " + "; ".join(
            f"{name} at {h}: " + (f"{v['KI']:.2f}" if "KI" in v else "singular moment matrix")
            for name, h, v in uni) + ". The fixed disc (r2 = 3.15 = 9 h at h = 0.35) fails on "
        "the finer grids: the 7-term moment matrix turns singular some 10 spacings from the tip, "
        "where the branch functions are nearly linear over a support, so the enriched disc must "
        "shrink with h (efgkit's default r2 = 4 h does). On the singular patch, whose exact "
        "field is the pure Williams field, the full basis over the whole patch gives K to 1e-5."]


if __name__ == "__main__":
    import json

    res = main()
    print(json.dumps({k: res["metrics"][k] for k in ("KI", "KII", "K_converged")}, indent=1))
    print([c for c in res["checks"] if not c["passed"]])
