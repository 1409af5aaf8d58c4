"""MLPG1 on the singular patch of ``singular_patch`` (seed 003 Sect. 5.6.1: the exact Williams
field prescribed on the whole boundary of [-1, 1]^2 with an edge crack to the centre,
K = 1): seed 002's plain variant (visibility, no enrichment) and the enriched variants
(extrinsic MLS, extrinsic PU with the diffraction rule; the radial sqrt(r) basis with
visibility), beside EFG with the same enrichments (the settings of ``singular_patch``).
K from :meth:`Solution.sifs` (interaction integral over the field quadrature, discs of
radii 0.3, 0.5, 0.7), as the mean over the discs.

Not done here: the clamped SENT of seed 001 with MLPG.
"""

from __future__ import annotations

import warnings

from _report import Report
from singular_patch import MODES, RADII, VARIANTS, A, scene
from singular_patch import method as efg_method

from efgkit import MLPG
from efgkit.static import solve

NAME = "mlpg_fracture"
MLPG_VARIANTS = {
    "plain": dict(),  # seed 002: visibility, quadratic basis, no enrichment
    "extrinsic_mls": dict(enrichment="extrinsic_mls", crack_rule="diffraction", rule_power=1.0),
    "pu": dict(enrichment="pu", crack_rule="diffraction", rule_power=1.0),
    "radial": dict(enrichment="radial", enrich_radius=0.9 * A, ramp_inner=0.6 * A),
}
EFG_VARIANTS = {"plain": "linear", "extrinsic_mls": "extrinsic_mls", "pu": "pu", "radial": "radial"}

TITLE = 'MLPG1 singular patch (K = 1)'


def markdown(r: dict) -> list[str]:
    """The section of docs/verification.md for a full-mode record."""
    rows = ["| case / method / variant / grid | K error | energy error |", "|---|---|---|"]
    rows += [f"| {k} | {v:.2e} | {r['metrics']['energy_error'][k]:.2e} |"
             for k, v in r["metrics"]["K_error"].items()]
    return ["Singular patch of ``singular_patch`` (K_I = 1 or K_II = 1, suffix /II), K as the "
            "mean over the interaction-integral discs 0.3, 0.5, 0.7. MLPG plain: seed 002's "
            "visibility rule without enrichment; EFG plain: the linear basis of "
            "``singular_patch``.", "", *rows]


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
    rep.metrics["K_error"] = K_error
    rep.metrics["energy_error"] = energy
    rep.ref("K", 1.0, "prescribed Williams field (seed 003 Sect. 5.6.1)")
    if quick:  # 9 x 9: extrinsic MLS measured 6e-5
        rep.check("K_error mlpg/extrinsic_mls 9x9", K_error["singular_patch/mlpg/extrinsic_mls/9x9"],
                  "<=", 2e-4)
    else:
        rep.check("K_error mlpg/extrinsic_mls 17x17 (target 0.1 %)",
                  K_error["singular_patch/mlpg/extrinsic_mls/17x17"], "<=", 1e-3)
        rep.check("K_error mlpg/extrinsic_mls 17x17 mode II (target 0.1 %)",
                  K_error["singular_patch/mlpg/extrinsic_mls/17x17/II"], "<=", 1e-3)
    return rep.write(out_dir)


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"]["K_error"], indent=1))
