"""Singular patch test of seed 003 Sect. 5.6.1 and Fig. 42: K against the J-domain size.

Square [-a, a]^2 (a = 1) with an edge crack from (-a, 0) to the tip at the centre; the
exact Williams displacement (seed 003 Eq. 60 for mode I, Anderson Table 2.2 for mode II)
is prescribed on the whole boundary by Lagrange multipliers, K_I = 1 and K_II = 1 in two
separate runs; plane strain, E = 1, nu = 0.3. Regular grids of 9 x 9, 17 x 17 and 25 x 25
nodes; six discretisations (``VARIANTS``): linear basis, linear basis with a star-shaped
tip array, radial sqrt(r) and full intrinsic enrichment, extrinsic MLS and extrinsic PU
enrichment. K from :meth:`Solution.sifs` (interaction integrals at the quadrature points,
Wendland C2 q) as the mean over the discs of radii 0.3, 0.5 and 0.7 a, and K against the
disc radius from 0.1 a to 0.9 a for the figure (seed 003 Fig. 42).

The left edge is one edge through the crack mouth: efgkit's Lagrange multipliers jump at a
mouth (the mode-II traction does), and the sensitivity table compares two edges meeting there.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
from _report import Report

from efgkit import EFG, Domain, Elastic, Loop, Rosette, Scene, discretize
from efgkit.gallery import singular_patch
from efgkit.io import write_figure
from efgkit.static import solve

NAME = "singular_patch"
TITLE = "Singular patch: K against domain size (seed 003 Fig. 42)"
ROOT = Path(__file__).resolve().parents[1]
A = 1.0
MAT = Elastic(1.0, 0.3, "strain")
MODES = {"mode I": (1.0, 0.0), "mode II": (0.0, 1.0)}
GRIDS = (9, 17, 25)
RADII = (0.3, 0.5, 0.7)  # J discs of the reported K (of a)
CURVE = tuple(np.round(np.linspace(0.1, 0.9, 17), 6))  # K against the radius (Fig. 42)
ROSETTE = Rosette(0.18 * A, rings=3, per_ring=9)  # seed 003 Fig. 34: outer ring 0.18 a, 3 rings
# Settings per variant (the same on every grid). Supports d_max = 2.5, seed 003's default
# ("used unless otherwise stated", Sect. 2), with efgkit's quartic weight; the full basis
# enlarges them to 3 for its 7-term moment matrix (Sect. 5.3.1). Seed 003 Sect. 5.6.1 uses the
# diffraction rule with lambda = 1 for the enriched approximations ("unless otherwise
# specified"); the sqrt(r) basis needs no smoothing (Sect. 5.3.2) and takes visibility.
D_MAX = 2.5
INTRINSIC_DISC = dict(enrich_radius=0.9 * A, ramp_inner=0.6 * A)  # r2, r1 of Eq. (54)
# Full intrinsic enrichment on the whole patch (r1 = 1.5 a > sqrt(2) a, the farthest corner):
# "the exact solution is contained in the trial function" (seed 003 Sect. 5.6.1), so what is
# left is quadrature and boundary discretisation; the fan rules (tip_order 12) and the 2 x 2
# sub-cells (refined_order 8, the whole patch) make the quadrature part small.
FULL_PATCH = dict(enrich_radius=1.6 * A, ramp_inner=1.5 * A, tip_order=12, refined_order=8)
VARIANTS = {
    "linear": dict(d_max=D_MAX, enrichment="none"),  # the default would enrich
    "rosette": dict(d_max=D_MAX, rosette=ROSETTE, enrichment="none"),
    "radial": dict(enrichment="radial", d_max=D_MAX, crack_rule="visibility", **INTRINSIC_DISC),
    "full": dict(enrichment="full", d_max=3.0, rule_power=1.0, **FULL_PATCH),
    "extrinsic_mls": dict(d_max=D_MAX, enrichment="extrinsic_mls", rule_power=1.0),
    "pu": dict(d_max=D_MAX, enrichment="pu", rule_power=1.0),
}
LABELS = {"linear": "linear", "rosette": "linear + rosette",
          "radial": "intrinsic sqrt(r)", "full": "intrinsic full", "extrinsic_mls": "extrinsic MLS",
          "pu": "extrinsic PU"}
# Alternatives run on the two coarse grids for the sensitivity table.
SENSITIVITY = {
    "extrinsic_mls, lambda = 2": ("extrinsic_mls", dict(rule_power=2.0), False),
    "pu, lambda = 2": ("pu", dict(rule_power=2.0), False),
    "full, lambda = 2": ("full", dict(rule_power=2.0), False),
    "full, ramped disc r1 = 0.6 a, r2 = 0.9 a, lambda = 2, orders 8 / 6": (
        "full", dict(INTRINSIC_DISC, rule_power=2.0, tip_order=8, refined_order=6), False),
    "full, ramped disc r1 = 0.6 a, r2 = 0.9 a, lambda = 2, orders 16 / 10": (
        "full", dict(INTRINSIC_DISC, rule_power=2.0, tip_order=16, refined_order=10), False),
    **{f"radial, d_max {d:g}": ("radial", dict(d_max=d), False) for d in (2.0, 2.25, 2.75)},
    "radial, diffraction lambda = 2": ("radial", dict(crack_rule="diffraction"), False),
    "radial, diffraction lambda = 2, d_max 2 (the default rule and support)": (
        "radial", dict(crack_rule="diffraction", d_max=2.0), False),
    "radial, efgkit default disc (r2 = 4h, r1 = 0)": (
        "radial", dict(enrich_radius=None, ramp_inner=0.0), False),
    "extrinsic_mls, two left edges meeting at the mouth": ("extrinsic_mls", {}, True),
    "pu, two left edges meeting at the mouth": ("pu", {}, True),
    "full, two left edges meeting at the mouth": ("full", {}, True),
}
TOL_ENRICHED = 5e-4  # issue 4: full intrinsic, extrinsic MLS and PU within 0.05 % on every grid
TOL_RADIAL = 0.01  # issue 4: radial within 1 % at 17 x 17
TOL_ROSETTE = 0.02  # issue 4: linear + rosette within 2 % at 25 x 25


def domain(split_mouth: bool = False) -> Domain:
    """[-a, a]^2; with ``split_mouth`` the left edge is two edges "left" meeting at the mouth."""
    if not split_mouth:
        return Domain.rectangle(-A, -A, A, A)
    v = [[-A, -A], [A, -A], [A, A], [-A, A], [-A, 0.0]]
    return Domain(Loop.polygon(v, ["bottom", "right", "top", "left", "left"]))


def scene(KI: float, KII: float, split_mouth: bool = False) -> Scene:
    return singular_patch(KI, KII, A, MAT, split_mouth, name=NAME)  # efgkit.gallery


def method(variant: str, n: int, **override) -> EFG:
    return EFG(spacing=2 * A / (n - 1), bc="lagrange", **dict(VARIANTS[variant], **override))


def run(variant: str, n: int, mode: str, split_mouth: bool = False, curve: bool = True,
        **override) -> dict:
    KI, KII = MODES[mode]
    sc = scene(KI, KII, split_mouth)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = solve(sc, method(variant, n, **override))
        res = sol.sifs(radii=RADII, error=False)[0]
        doms = sol.sifs(radii=CURVE, error=False)[0].domains if curve else ()
    out = {"KI": res.KI, "KII": res.KII, "J": res.J, "spread": res.spread,
           "K": res.KI if KI else res.KII, "other": res.KII if KI else res.KI,
           "n_nodes": sol.nodes.n, "energy_error": sol.errors()["energy"],
           "seconds": time.perf_counter() - t0,
           "warnings": sorted({str(w.message)[:120] for w in caught})}
    if res.enriched is not None:
        out["K_enriched"] = res.enriched[0] if KI else res.enriched[1]
    if curve:
        out["curve"] = {"radius": [d.radius for d in doms],
                        "K": [d.KI if KI else d.KII for d in doms]}
    return out


def reproduction(n: int = 17) -> dict:
    """Max error of the MLS reproduction ``sum_I phi_I f(x_I)`` of near-tip functions f at
    random points (seeded) with 1e-3 < r < 0.55 a (inside r1), radial and full intrinsic bases."""
    sc = scene(1.0, 0.0)
    x = np.random.default_rng(0).uniform(-0.5, 0.5, (2000, 2))
    x = x[(np.hypot(*x.T) > 1e-3) & (np.hypot(*x.T) < 0.55 * A)]
    rx, tx = np.hypot(*x.T), np.arctan2(x[:, 1], x[:, 0])
    out = {}
    for v in ("radial", "full"):
        disc = discretize(sc, method(v, n))
        nodes = disc.nodes
        r, th = np.hypot(*nodes.x.T), np.arctan2(nodes.x[:, 1], nodes.x[:, 0])
        on_face = (nodes.face != 0) & (nodes.x[:, 0] < 0)  # split nodes carry their face
        th = np.where(on_face, np.where(nodes.face > 0, np.pi, -np.pi), th)
        phi = disc.shape_at(x, derivatives=False).phi
        for name, f in (("sqrt(r)", lambda r, t: np.sqrt(r)),
                        ("sqrt(r) sin(theta/2)", lambda r, t: np.sqrt(r) * np.sin(t / 2))):
            out[f"{v} basis, {name}"] = float(np.abs(phi @ f(r, th) - f(rx, tx)).max())
    return out


def figure(rows: dict, variants, grids, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(variants), figsize=(2.6 * len(variants), 5.6), sharex=True,
                             squeeze=False)
    for i, mode in enumerate(MODES):
        for j, v in enumerate(variants):
            ax = axes[i, j]
            for k, n in enumerate(grids):
                c = rows[mode][v].get(f"{n}x{n}", {}).get("curve")
                if c:
                    ax.plot(c["radius"], c["K"], "o-", ms=3, color=f"C{k}", label=f"{n} x {n}")
            ax.axhline(1.0, color="k", lw=0.6)
            lo, hi = ax.get_ylim()
            ax.set_ylim(min(lo, 0.99), max(hi, 1.01))
            ax.set_title(f"{LABELS[v]}\n{mode}", fontsize=9)
            if i == 1:
                ax.set_xlabel("J-domain radius / a")
            if j == 0:
                ax.set_ylabel("K / K_exact")
            ax.tick_params(labelsize=7)
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    return write_figure(fig, path, dpi=100)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    grids = GRIDS[:2] if quick else GRIDS
    variants = [v for v in VARIANTS if not (quick and v == "radial")]
    rows = {mode: {v: {} for v in variants} for mode in MODES}
    for mode in MODES:
        for v in variants:
            for n in grids:
                rows[mode][v][f"{n}x{n}"] = run(v, n, mode)
    KI = {f"{mode}/{v}/{g}": r["KI"] for mode in MODES for v in variants for g, r in rows[mode][v].items()}
    KII = {f"{mode}/{v}/{g}": r["KII"] for mode in MODES for v in variants
           for g, r in rows[mode][v].items()}
    spread = {f"{mode}/{v}/{g}": r["spread"] for mode in MODES for v in variants
              for g, r in rows[mode][v].items()}
    own = {f"{mode}/{g}": r["K_enriched"] for mode in MODES
           for g, r in rows[mode]["extrinsic_mls"].items()}
    sens = {}
    if not quick:
        for label, (v, override, split) in SENSITIVITY.items():
            sens[label] = {mode: {f"{n}x{n}": run(v, n, mode, split_mouth=split, curve=False,
                                                  **override)["K"]
                                  for n in GRIDS[:2]} for mode in MODES}
    rep.metrics.update({
        "settings": {"a": A, "E": MAT.E, "nu": MAT.nu, "plane": MAT.plane, "radii": RADII,
                     "q": "wendland_c2", "bc": "lagrange",
                     "rosette": {"radius": ROSETTE.radius, "rings": ROSETTE.rings,
                                 "per_ring": ROSETTE.per_ring},
                     "variants": {v: {k: val for k, val in o.items() if k != "rosette"}
                                  for v, o in VARIANTS.items()}},
        "grids": [f"{n}x{n}" for n in grids], "variants": variants,
        "KI": KI, "KII": KII, "spread": spread, "K_enriched_extrinsic": own,
        "rows": rows, "sensitivity": sens, "reproduction": reproduction()})
    rep.ref("KI", 1.0, "prescribed Williams field, mode I run (seed 003 Eq. 60, k_1 = 1)")
    rep.ref("KII", 1.0, "prescribed Williams field, mode II run (Anderson, Fracture Mechanics, "
            "Table 2.2)")
    rep.ref("tolerances", {"enriched": TOL_ENRICHED, "radial_17": TOL_RADIAL, "rosette_25": TOL_ROSETTE},
            "issue 4 targets for singular_patch")

    def err(v, n):
        return max(abs(rows[mode][v][f"{n}x{n}"]["K"] - 1.0) for mode in MODES)

    for v in ("full", "extrinsic_mls", "pu"):
        for n in grids:
            rep.check(f"{LABELS[v]}, {n} x {n}: max |K - 1| over both modes", err(v, n), "<=",
                      TOL_ENRICHED)
    if not quick:
        rep.check(f"{LABELS['radial']}, 17 x 17: max |K - 1|", err("radial", 17), "<=", TOL_RADIAL)
        rep.check(f"{LABELS['rosette']}, 25 x 25: max |K - 1|", err("rosette", 25), "<=", TOL_ROSETTE)
    else:  # the rosette target grid is not run in quick mode: the finest one run instead
        rep.check(f"{LABELS['rosette']}, {grids[-1]} x {grids[-1]}: max |K - 1|",
                  err("rosette", grids[-1]), "<=", TOL_ROSETTE)
    other = max(abs(r["other"]) for mode in MODES for v in ("full", "extrinsic_mls", "pu")
                for r in rows[mode][v].values())
    rep.check("spurious other-mode K (symmetric patch), enriched variants, every grid", other, "<=",
              1e-4)
    lin = [err("linear", n) for n in grids]
    rep.check("linear basis: K error decreases with refinement (finest / coarsest)", lin[-1] / lin[0], "<=",
              0.75)
    if not quick:
        rep.figures.append(str(figure(rows, variants, grids, ROOT / "docs" / "figures" / f"{NAME}_K.png")))
    elif out_dir is not None:
        rep.figures.append(str(figure(rows, variants, grids, Path(out_dir) / f"{NAME}_K.png")))
    return rep.write(out_dir)


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    s = m["settings"]
    grids = m["grids"]
    other = max(abs(r["other"]) for mode in MODES for v in ("full", "extrinsic_mls", "pu")
                for r in m["rows"][mode][v].values())
    lin = [abs(r["K"] - 1) for mode in MODES for r in m["rows"][mode]["linear"].values()]
    lin_lo, lin_hi = min(lin), max(lin)
    radial17 = max(abs(m["rows"][mode]["radial"]["17x17"]["K"] - 1) for mode in MODES) \
        if "radial" in m["variants"] and "17x17" in grids else float("nan")
    lines = [
        "Seed 003 Sect. 5.6.1: square [-a, a]^2 (a = 1), edge crack from (-a, 0) to the tip at the "
        "centre, the exact Williams displacement prescribed on the whole boundary (Lagrange "
        f"multipliers), plane strain, E = {s['E']:g}, nu = {s['nu']:g}; K_I = 1 and K_II = 1 in "
        "separate runs. K is the mean of the interaction integrals (quadrature points, Wendland "
        f"C2 q) over the discs of radii {list(s['radii'])} a; \"spread\" is max - min over "
        "them. Settings (the same on every grid): quartic weight, d_max 2.5 (seed 003's default "
        "support, Sect. 2) except for the full basis; linear: diffraction lambda = 2 (efgkit's "
        "default rule); rosette: seed 003 Fig. 34's tip array, outer ring 0.18 a, 3 rings "
        "(efgkit spaces them evenly: 0.06, 0.12, 0.18 a; 8 angles, background nodes inside "
        "switched off); intrinsic sqrt(r): the enriched basis within r1 = 0.6 a, "
        "ramped (quintic) to the linear one at r2 = 0.9 a, visibility rule (the sqrt(r) basis "
        "needs no smoothing, seed 003 Sect. 5.3.2); intrinsic full: the near-tip basis "
        "on the whole patch (r1 = 1.5 a, beyond the corners; the seed's 'exact solution "
        "contained in the trial function'), d_max 3 (7-term moment matrix), tip fan rules of "
        "order 12 and 2 x 2 sub-cells of order 8 everywhere, diffraction lambda = 1; extrinsic "
        "MLS (global Williams fields, K_I and K_II unknowns) and PU (nodes "
        "within 2 h of the tip enriched by the four branch functions) with the diffraction "
        "rule at lambda = 1, as seed 003 uses with enrichment.", "",
        "| mode | variant | " + " | ".join(grids) + " | spread (finest) |",
        "|---|---|" + "---|" * (len(grids) + 1)]
    for mode in ("mode I", "mode II"):
        for v in m["variants"]:
            r = m["rows"][mode][v]
            lines.append(f"| {mode} | {LABELS[v]} | " + " | ".join(f"{r[g]['K']:.6f}" for g in grids)
                         + f" | {r[grids[-1]]['spread']:.1e} |")
    lines += ["", "Extrinsic MLS: the solution's own K (the enrichment unknowns, seed 003 Eq. 46) "
              "beside the integral values:", "", "| mode | " + " | ".join(grids) + " |",
              "|---|" + "---|" * len(grids)]
    for mode in ("mode I", "mode II"):
        lines.append(f"| {mode} | " + " | ".join(f"{m['K_enriched_extrinsic'][f'{mode}/{g}']:.5f}"
                                                 for g in grids) + " |")
    lines += ["", "![K against the J-domain radius](figures/singular_patch_K.png)", "",
              "Findings:", "",
              "- Full intrinsic, extrinsic MLS and PU enrichment reach K within 0.05 % on every "
              "grid in both modes (the target); their K is flat in the domain radius, as in the "
              "seed's Fig. 42(a).",
              "- Full intrinsic enrichment needs the near-tip basis on the whole patch for that: "
              "with the ramped disc (r1 = 0.6 a, r2 = 0.9 a) the linear basis outside r2 cannot "
              "represent the prescribed Williams field and mode II at 9 x 9 stays ~1e-3 off once "
              "the quadrature is converged (sensitivity table, orders 16 / 10; the 8 / 6-order "
              "value is closer by luck).",
              "- The radial sqrt(r) basis with the visibility rule is within "
              f"{radial17:.1%} at 17 x 17 (target 1 %); on 17 x 17 and 25 x 25 it underestimates "
              "K slightly, as the seed says it underestimates the stress (Fig. 39). Both choices "
              "matter (sensitivity "
              "table): with the diffraction rule it overestimates K by about 3 % and is less "
              "accurate than the plain linear basis, and with visibility K falls from above 1 to "
              "below it as d_max grows from 2 to 2.75; d_max 2.5 is the seed's default, used for "
              "every variant here, and at 2.25 mode II is 1.5 % off. sqrt(r) times locally linear "
              "MLS coefficients carries the radial but not the angular variation of the "
              "near-tip field: reproduction on 17 x 17 (max error of sum_I phi_I f(x_I) - f(x) "
              "at random points with r < 0.55 a): "
              + ", ".join(f"{k}: {v:.1e}" for k, v in m["reproduction"].items())
              + ". The seed reports < 3 % variation on the coarsest grid for its sqrt(r) basis and "
              "does not give its K.",
              f"- The linear basis (diffraction) overestimates K by {lin_lo:.0%}-{lin_hi:.0%} (the "
              "seed, with the visibility rule, finds it 5-15 % low); the rosette of Fig. 34 brings "
              "it within about 1.5 %.",
              "- Mode II is the harder case on the boundary: its traction on the left edge jumps "
              "at the crack mouth (sigma_xx = -+2 K_II / sqrt(2 pi a) on the two faces). efgkit's "
              "Lagrange multipliers have one hat node per side of a mouth, so they jump there "
              "too; the sensitivity table shows the same K with the left edge split into two "
              "edges meeting at the mouth.",
              "- The other-mode K (zero by symmetry) stays below 1e-4 with enrichment: "
              + f"{other:.1e} at most.", "",
              "Sensitivity (K on the two coarse grids; the chosen settings above):", "",
              "| alternative | mode | " + " | ".join(grids[:2]) + " |", "|---|---|---|---|"]
    for label, per_mode in m["sensitivity"].items():
        for mode, vals in per_mode.items():
            lines.append(f"| {label} | {mode} | " + " | ".join(f"{vals[g]:.6f}" for g in grids[:2])
                         + " |")
    return lines


if __name__ == "__main__":
    import json

    res = main()
    print(json.dumps({k: res["metrics"][k] for k in ("KI", "KII")}, indent=1))
    print([c for c in res["checks"] if not c["passed"]])
