"""MLPG1 on the singular patch of ``singular_patch`` (seed 003 Sect. 5.6.1: the exact Williams
field prescribed on the whole boundary of [-1, 1]^2 with an edge crack to the centre,
K = 1): seed 002's plain variant (visibility, no enrichment) and the enriched variants
(extrinsic MLS, extrinsic PU with the diffraction rule; the radial sqrt(r) basis with
visibility), beside EFG with the same enrichments (the settings of ``singular_patch``).
K from :meth:`Solution.sifs` (interaction integral over the field quadrature, discs of
radii 0.3, 0.5, 0.7), as the mean over the discs.

The SENT of seed 001 Sect. 4 (``sent``: 50 x 10 mm, a = 5 mm, plane strain) with both grip
conditions of docs/verification.md: clamped (u_x, u_y prescribed at the ends; the specimen as
specified) and axial-only (u_x at the ends, u_y = 0 on a piece W/n long at the middle of the
left end). MLPG plain (seed 002: visibility, quadratic basis, d_max 2.5; d_max 3, the remedy
for singular moment matrices elsewhere, gave J errors of 8-150 % here with the seed's weight
k = 2, r_s = 1.1 h; every MLPG row uses MLPG's default weight, k = 1, r_s = 1.5 h, the seed's
is compared in docs/theory.md, MLPG1 "Default weight") and MLPG with extrinsic
MLS enrichment and the diffraction rule, at n nodes across W; EFG's defaults (enriched,
Nitsche grips) beside. J from :meth:`Solution.sifs` (domain integral, radii 1, 2, 3, 4 mm, the
radii of ``sent``), against efgkit's FEM reference of the ``sent`` record: clamped J = 6.87072
N/mm (graded P2 with quarter-point tip elements, h = 0.125 mm, converged to 4e-6 over the last
two meshes), axial-only J = 6.78600 N/mm (the same FEM at h = 0.5 mm, the ``sent``
investigation; clamped at that mesh differs from the converged value by 2e-5). K_error of a
SENT row is |K_I / K_ref - 1| with K_ref = sqrt(J_ref E / (1 - nu^2)); J_error is
|J / J_ref - 1|. Beside them EFG's plain visibility variants (linear basis; MLPG's quadratic
trial space), the J error of every single domain of radius 0.5 ... 4.5 mm (``J_radius``) and
of the mean over the large domains 3-4.5 mm (``J_error_large``): what limits plain MLPG's J
(docs/theory.md, MLPG1, "The plain SENT and the J domain"). Plain MLPG's discs near the tip
split their rays at the shadow rays and support circles (MLPG ``split_radial`` x
``split_angular``, methods.local_tips.split_tip_discs): without that its J moved by ~1 % with
the disc rule.
"""

from __future__ import annotations

import warnings

import numpy as np
from _report import Report
from sent import NU, E, W
from sent import scene as sent_scene
from singular_patch import MODES, RADII, VARIANTS, A, scene
from singular_patch import method as efg_method

from efgkit import EFG, MLPG
from efgkit.static import solve

NAME = "mlpg_fracture"
MLPG_VARIANTS = {
    "plain": dict(),  # seed 002: visibility, quadratic basis, no enrichment
    "extrinsic_mls": dict(enrichment="extrinsic_mls", crack_rule="diffraction", rule_power=1.0),
    "pu": dict(enrichment="pu", crack_rule="diffraction", rule_power=1.0),
    "radial": dict(enrichment="radial", enrich_radius=0.9 * A, ramp_inner=0.6 * A),
}
EFG_VARIANTS = {"plain": "linear", "extrinsic_mls": "extrinsic_mls", "pu": "pu", "radial": "radial"}

TITLE = 'MLPG1 singular patch (K = 1) and SENT of seed 001'
# efgkit's FEM reference J (N/mm), verification/out/sent.json: metrics.J_fem (clamped; graded
# P2, quarter-point tip, h = 0.125) and metrics.investigation["grips: only u_x prescribed
# (u_y free)"].J (axial-only; the same FEM at h = 0.5, tip_h = 0.02)
SENT_J_FEM = {"clamped": 6.870723715163173, "axial": 6.786000814357646}
SENT_SIZES = (20, 40, 80)  # nodes across W in full mode
SENT_RADII = (1.0, 2.0, 3.0, 4.0)  # mm, the J domains of ``sent``
SENT_MLPG = {
    "plain": dict(),  # seed 002 (d_max 2.5); d_max 3 gave J errors of 8-150 % here
    "extrinsic_mls": dict(enrichment="extrinsic_mls", crack_rule="diffraction"),
}
# EFG's plain visibility variants, the reference for what a plain basis gives: EFG's linear
# basis (d_max 2, quartic weight), and MLPG's trial space (quadratic basis, d_max 2.5, Gaussian
# k = 1 with c = 0.5 r_I, i.e. alpha = 0.5 d_max) in EFG's global Galerkin form
SENT_EFG_PLAIN = {
    "plain": dict(enrichment="none", crack_rule="visibility"),
    "plain_quadratic": dict(enrichment="none", crack_rule="visibility", basis="quadratic",
                            d_max=2.5, weight="gaussian", alpha=1.25),
}
SENT_TABLE = (0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5)  # mm: J per single domain
# Large domains, 0.6-0.9 of a = W - a = 5 mm: the plain quadratic variants' J falls with the
# domain radius (near-tip error), which these leave out; reported, not checked (see main)
SENT_LARGE = (3.0, 3.5, 4.0, 4.5)


def sent_rows(n: int, grips: str, variants) -> dict:
    """SENT at n nodes across W for each MLPG variant, EFG's defaults and EFG's plain variants:
    {metric: {key: value}} with K_error, J_error, J_sent (domains ``SENT_RADII``), J_error_large
    (domains ``SENT_LARGE``) and J_radius ({radius: J error} of single domains ``SENT_TABLE``)."""
    sc = sent_scene(grips=grips, pin=W / n) if grips == "axial" else sent_scene()
    J_ref = SENT_J_FEM[grips]
    K_ref = (J_ref * E / (1 - NU**2)) ** 0.5
    methods = {f"mlpg/{v}": MLPG(spacing=W / n, **SENT_MLPG[v]) for v in variants}
    methods["efg/default"] = EFG(spacing=W / n, bc="variational")
    methods.update({f"efg/{v}": EFG(spacing=W / n, bc="variational", **kw)
                    for v, kw in SENT_EFG_PLAIN.items()})
    out = {k: {} for k in ("K_error", "J_error", "J_sent", "J_error_large", "J_radius")}
    for name, m in methods.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            doms = {d.radius: d for d in solve(sc, m).sifs(radii=SENT_TABLE, error=False)[0].domains}
        # TipResult.J and KI are the means over the domains (efgkit.fracture.sif.tip_result)
        J, KI = np.mean([doms[r].J for r in SENT_RADII]), np.mean([doms[r].KI for r in SENT_RADII])
        key = f"sent_{grips}/{name}/{n}"
        out["K_error"][key], out["J_error"][key] = abs(KI / K_ref - 1), abs(J / J_ref - 1)
        out["J_sent"][key] = J
        out["J_error_large"][key] = abs(np.mean([doms[r].J for r in SENT_LARGE]) / J_ref - 1)
        out["J_radius"][key] = {r: d.J / J_ref - 1 for r, d in doms.items()}
    return out


def markdown(r: dict) -> list[str]:
    """The section of docs/verification.md for a full-mode record."""
    m = r["metrics"]
    rows = ["| case / method / variant / grid | K error | energy error |", "|---|---|---|"]
    rows += [f"| {k} | {v:.2e} | {m['energy_error'][k]:.2e} |"
             for k, v in m["K_error"].items() if k.startswith("singular_patch")]
    out = ["Singular patch of ``singular_patch`` (K_I = 1 or K_II = 1, suffix /II), K as the "
           "mean over the interaction-integral discs 0.3, 0.5, 0.7. MLPG: the default weight "
           "(Gaussian k = 1, test discs 1.5 h); MLPG plain: seed 002's "
           "visibility rule without enrichment; EFG plain: the linear basis of "
           "``singular_patch``.", "", *rows]
    if "J_sent" not in m:
        return out
    large = m.get("J_error_large", {})
    rows = ["| grips / method / variant / nodes across W | J (N/mm) | J error | K_I error | "
            "J error, domains 3-4.5 mm |", "|---|---|---|---|---|"]
    rows += [f"| {k.removeprefix('sent_')} | {J:.4f} | {m['J_error'][k]:.2e} | {m['K_error'][k]:.2e} | "
             f"{_e(large.get(k))} |" for k, J in m["J_sent"].items()]
    plain = [f"{100 * m['J_error'][k]:.2g} %" for k in m["J_error"] if k.startswith("sent_axial/mlpg/plain/")]
    return out + ["", "SENT of seed 001 (``sent``), both grip conditions, J (domains 1-4 mm) against "
                  f"efgkit's FEM reference: clamped {SENT_J_FEM['clamped']:.5f} N/mm, axial-only "
                  f"{SENT_J_FEM['axial']:.5f} N/mm (``sent`` record); K_I error against "
                  "sqrt(J_FEM E / (1 - nu^2)). MLPG plain: seed 002's visibility rule, quadratic "
                  "basis, d_max 2.5; MLPG extrinsic_mls: diffraction rule; EFG default: "
                  "EFG(spacing=W/n, bc='variational'). Target: J within 0.3 % at <= 80 nodes "
                  f"across. MLPG plain, axial-only, at {', '.join(str(n) for n in SENT_SIZES[:len(plain)])} "
                  f"across: {', '.join(plain)} (with seed 002's weight k = 2, r_s = 1.1 h, before "
                  "the split rule: 2.0 %, 41 %, 0.26 %: erratic in n; docs/theory.md, MLPG1).", "",
                  *rows, *radius_table(m)]


def _e(v) -> str:
    return "" if v is None else f"{v:.2e}"


def radius_table(m: dict) -> list[str]:
    """J error (%) of single domains against their radius, every SENT row at the largest size."""
    if "J_radius" not in m:
        return []
    n = max(SENT_SIZES)
    keys = [k for k in m["J_radius"] if k.endswith(f"/{n}")]
    head = "| grips / method / variant | " + " | ".join(f"{r:g} mm" for r in SENT_TABLE) + " |"
    rows = [head, "|---" * (len(SENT_TABLE) + 1) + "|"]
    rows += [f"| {k.removeprefix('sent_').removesuffix(f'/{n}')} | "
             + " | ".join(f"{100 * m['J_radius'][k][str(r)]:+.3f}" for r in SENT_TABLE) + " |"
             for k in keys]
    return ["", f"J error (%) of single domains (Wendland C2 q, radius r) at {n} nodes across: the "
            "plain variants (no enrichment, visibility) overshoot most on small domains and less "
            "on large ones (near-tip error); EFG plain (linear basis, d_max 2) is nearly flat "
            "(its error is global); EFG plain_quadratic has MLPG's trial space (quadratic, "
            "d_max 2.5, Gaussian k = 1) in EFG's Galerkin form. Domains 3-4.5 mm are 0.6-0.9 "
            "of a = W - a = 5 mm. Plain MLPG's discs near the tip split their rays at the shadow "
            "rays and support circles (without that its J moved by ~1 % with the disc rule; with "
            "it the 1-4 mm mean moves by <= 0.09 % (40 across) and <= 0.05 % (80 across) between "
            "3 x 48 and 12 x 96 points per piece; "
            "docs/theory.md, MLPG1, \"The plain SENT and the J domain\"). Its mean over 1-4 mm "
            "meets the 0.3 % target partly by cancellation: its single domains run from +0.7 % "
            "(1 mm) to -0.4 % (4 mm).",
            "", *rows]


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    grids = (9,) if quick else (9, 17, 25)
    variants = ("plain", "extrinsic_mls") if quick else tuple(MLPG_VARIANTS)
    modes = ("mode I",) if quick else tuple(MODES)
    K_error, energy = {}, {}
    for mode in modes:
        KI, KII = MODES[mode]
        sc = scene(KI, KII)
        for n in grids:
            for v in variants:
                for meth in ("mlpg", "efg"):
                    m = (MLPG(spacing=2 * A / (n - 1), **MLPG_VARIANTS[v]) if meth == "mlpg"
                         else efg_method(EFG_VARIANTS[v], n))
                    if meth == "efg" and EFG_VARIANTS[v] not in VARIANTS:
                        continue
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", UserWarning)
                        sol = solve(sc, m)
                        r = sol.sifs(radii=tuple(x * A for x in RADII), error=False)[0]
                    k = r.KI if KI else r.KII
                    key = f"singular_patch/{meth}/{v}/{n}x{n}" + ("" if mode == "mode I" else "/II")
                    K_error[key] = abs(k - 1.0)
                    energy[key] = sol.errors()["energy"]
    J_error, J_sent, J_large, J_radius = {}, {}, {}, {}
    sent_sizes = (20,) if quick else SENT_SIZES
    for grips in (("clamped",) if quick else ("clamped", "axial")):
        for n in sent_sizes:
            if quick:  # one coarse MLPG solve (EFG's rows only in full mode)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)
                    r = solve(sent_scene(), MLPG(spacing=W / n, **SENT_MLPG["extrinsic_mls"])).sifs(
                        radii=SENT_RADII, error=False)[0]
                key = f"sent_clamped/mlpg/extrinsic_mls/{n}"
                K_ref = (SENT_J_FEM["clamped"] * E / (1 - NU**2)) ** 0.5
                K_error[key] = abs(r.KI / K_ref - 1)
                J_error[key], J_sent[key] = abs(r.J / SENT_J_FEM["clamped"] - 1), r.J
                continue
            rows = sent_rows(n, grips, tuple(SENT_MLPG))
            K_error.update(rows["K_error"]), J_error.update(rows["J_error"])
            J_sent.update(rows["J_sent"]), J_large.update(rows["J_error_large"])
            J_radius.update(rows["J_radius"])
    rep.metrics["K_error"] = K_error
    rep.metrics["energy_error"] = energy
    rep.metrics["J_error"] = J_error
    rep.metrics["J_sent"] = J_sent
    if not quick:
        rep.metrics["J_error_large"] = J_large
        rep.metrics["J_radius"] = J_radius
    rep.ref("K", 1.0, "prescribed Williams field (seed 003 Sect. 5.6.1)")
    rep.ref("J_sent_clamped", SENT_J_FEM["clamped"], "efgkit FEM, verification/out/sent.json metrics.J_fem "
            "(graded P2, quarter-point tip, h = 0.125 mm)")
    rep.ref("J_sent_axial", SENT_J_FEM["axial"], "efgkit FEM, verification/out/sent.json "
            "metrics.investigation['grips: only u_x prescribed (u_y free)'] (P2, h = 0.5 mm)")
    if quick:  # 9 x 9: extrinsic MLS measured 1.9e-3 with the default weight (k = 1, r_s = 1.5 h;
        # 6e-5 with the seed's k = 2, r_s = 1.1 h, which is erratic on traction-loaded plates;
        # docs/theory.md, MLPG1 "Default weight")
        rep.check("K_error mlpg/extrinsic_mls 9x9", K_error["singular_patch/mlpg/extrinsic_mls/9x9"],
                  "<=", 5e-3)
        # SENT clamped, 20 nodes across, extrinsic MLS: measured J error 9.2e-3 (seed weight 6.7e-3)
        rep.check("SENT clamped J_error mlpg/extrinsic_mls 20", J_error["sent_clamped/mlpg/extrinsic_mls/20"],
                  "<=", 2e-2)
    else:
        rep.check("K_error mlpg/extrinsic_mls 17x17 (target 0.1 %)",
                  K_error["singular_patch/mlpg/extrinsic_mls/17x17"], "<=", 1e-3)
        rep.check("K_error mlpg/extrinsic_mls 17x17 mode II (target 0.1 %)",
                  K_error["singular_patch/mlpg/extrinsic_mls/17x17/II"], "<=", 1e-3)
        n = max(SENT_SIZES)
        for grips in ("clamped", "axial"):
            for v in SENT_MLPG:
                rep.check(f"SENT {grips} J_error mlpg/{v} {n} across (target 0.3 %)",
                          J_error[f"sent_{grips}/mlpg/{v}/{n}"], "<=", 3e-3)
            # the plain basis itself reaches the target: EFG with MLPG's trial space (quadratic,
            # d_max 2.5, Gaussian k = 1, visibility) measured 0.18 % (both grips); plain MLPG's
            # J_error_large (0.38 % / 0.39 % with the split rule) is reported, not checked
            # (docs/theory.md, MLPG1, "The plain SENT and the J domain")
            rep.check(f"SENT {grips} J_error efg/plain_quadratic {n} across (target 0.3 %)",
                      J_error[f"sent_{grips}/efg/plain_quadratic/{n}"], "<=", 3e-3)
    return rep.write(out_dir)


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"]["K_error"], indent=1))
