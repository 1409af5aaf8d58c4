"""What the defaults give: ``EFG(spacing=h)`` and ``FEM(h=h)`` alone, on specimens with
independent references.

A user who sets nothing else gets, on a scene with crack tips, two graded zones at
every tip, extrinsic enrichment and Lagrange multipliers (``EFG.for_scene``). This
script measures K and T with those defaults at W/10 and W/20 (W the specimen width)
against references that efgkit did not produce:

* ``singular_patch`` (mode I and mode II): the Williams field prescribed around an edge
  crack in [-1, 1]^2 (seed 003 Sect. 5.6.1): K exact, T = 0;
* ``griffith`` (beta = 0) and ``inclined`` (beta = 45 degrees): a crack of half-length 1
  in [-2, 2]^2 with the exact Westergaard field on the boundary, remote tension 1
  (Tada, Paris & Irwin p. 5.11): K_I = sqrt(pi) cos^2 beta, K_II = sqrt(pi) sin beta
  cos beta, T = -cos 2 beta;
* ``shear_edge_crack`` (seed 003 Sect. 5.6.2): Wilson's K_I = 34.0, K_II = 4.55 (1969),
  3 digits; the errors are against the converged reference of
  ``verification/shear_edge_crack.py`` (34.042, 4.5371), which agrees with Wilson and
  with quarter-point P2 FEM;
* ``sent``: the clamped SENT of seed 001 (J = 6870.7 J/m^2 from the converged
  quarter-point FEM of ``verification/sent.py``, whose u_y-free variant reproduces the
  seed's Abaqus J = 6786 J/m^2 to 1e-6);
* handbook specimens of :mod:`efgkit.gallery` (plane strain, nu = 0.3, remote tension
  sigma = 1 on free ends): ``cct_a03`` and ``cct_a05`` (centre crack, a/b = 0.3 and 0.5,
  h/b = 3, W = 2b), ``sent_free`` (single edge crack, a/w = 0.5, h/w = 2, ends free to
  rotate, W = w) and ``dent`` (double edge crack, a/b = 0.5, h/b = 3, W = 2b). Their
  handbook fits (Tada, Paris & Irwin; :func:`efgkit.gallery.reference_k`) are stated
  accurate to 0.1 % (CCT, p. 2.2) and 0.5 % (SENT p. 2.11, DENT p. 2.6): a 0.1 % target
  cannot be measured against a 0.5 % fit. So K is measured against a converged reference,
  :func:`converged`: quarter-point P2 FEM (``FEM(h)``, tips graded to h/8) at W/40 and
  W/80, Richardson-extrapolated with the rate observed from W/20, W/40, W/80. That value
  is efgkit's own, so it is a reference only because it is cross-checked against the
  handbook within the handbook's stated accuracy (a check of this script; measured:
  CCT +0.020 % and +0.037 %, SENT -0.071 %). The extrapolation moves K by 5e-6 to 3e-5
  (observed rates 1.0 to 1.5; the DENT's 0.61, where K changes by only 2.8e-5 and
  1.9e-5 between levels, is clipped to 1 and its uncertainty taken at 0.61: 2.4e-5).
  The DENT is not anchored: its converged K is 0.56 % above the gallery's fit
  ``(1 + 0.122 cos^4 c) sqrt(tan c / c)``, c = pi a / 2b (stated 0.5 %), and 1.25 %
  below the other fit usually quoted from the same handbook for this plate,
  ``(1.122 - 0.561 al - 0.205 al^2 + 0.471 al^3 - 0.190 al^4) / sqrt(1 - al)`` (also
  quoted as 0.5 %); the two fits differ by 1.8 % at a/b = 0.5, so neither could be
  confirmed without the handbook at hand. The DENT rows are recorded (``K_error``
  against the converged FEM, ``K_error_handbook`` against the gallery's fit) but not
  checked. No handbook T was at hand for these plates (Leevers & Radon, Sherry et al.
  tabulate the biaxiality ratio, but their tables were not available to check), so
  their ``T_error`` is against the same converged FEM: a cross-check of EFG against FEM
  and of FEM against itself, not a verification, and not checked against ``T_TOL``.

``FEM(h=h)`` grades the mesh to h/8 at the tips with quarter-point P2 elements
(``FEM.for_scene``) and takes its J domains in lengths of the geometry (10, 12.5, 15 h);
``fem_uniform`` (P2 of size h everywhere, the FEM default before) is recorded beside.

Targets (issue [trust]): within 0.1 % on K (``max(|dK_I|, |dK_II|) / |K|``) and 0.005
sigma on T at W/20 or coarser, for the EFG and the FEM defaults.
"""

from __future__ import annotations

import math
import time
import warnings

from _report import Report

from efgkit import EFG, FEM, gallery, solve, solve_fem

NAME = "defaults"
TITLE = "Defaults: EFG(spacing=h) and FEM(h=h) against independent references"
K_TOL, T_TOL = 1e-3, 5e-3  # issue [trust]: 0.1 % on K, 0.005 sigma on T at W/20
# name -> (gallery builder, its parameters, width W); the reference_k parameters are the same
HANDBOOK = {"cct_a03": ("cct", dict(a_over_b=0.3, h_over_b=3.0), 2.0),
            "cct_a05": ("cct", dict(a_over_b=0.5, h_over_b=3.0), 2.0),
            "sent_free": ("sent", dict(a_over_w=0.5, h_over_w=2.0), 1.0),
            "dent": ("dent", dict(a_over_b=0.5, h_over_b=3.0), 2.0)}
# (K_I, T) of the converged FEM reference (converged(), full mode of this script, 2026-11-26;
# the full mode recomputes them and checks them to CONVERGED_TOL)
CONVERGED = {"cct_a03": (1.026868, -1.07137), "cct_a05": (1.487267, -1.25698),
             "sent_free": (3.540075, -0.42139), "dent": (1.465443, -0.55223)}
CONVERGED_TOL = 2e-5
# specimens whose converged K is anchored by its handbook fit (checked in full mode); the
# DENT is not: see the module docstring
ANCHORED = ("cct_a03", "cct_a05", "sent_free")


def specimens() -> dict:
    """name -> (scene, (K_I, K_II), T or None, width W, stress scale sigma)."""
    import error_estimate as ee
    import inclined as inc

    out = {}
    for mode, K in (("I", (1.0, 0.0)), ("II", (0.0, 1.0))):
        sc, K, W = ee.singular_patch(*K)
        out[f"singular_patch_{mode}"] = (sc, K, 0.0, W, 1.0)
    for name, beta_deg in (("griffith", 0.0), ("inclined", 45.0)):
        sc, K, W = ee.inclined(beta_deg)
        T = -inc.SIGMA * math.cos(2 * math.radians(beta_deg))
        out[name] = (sc, K, T, W, inc.SIGMA)
    sc, K, W = ee.shear_edge_crack()
    out["shear_edge_crack"] = (sc, K, None, W, 1.0)
    sc, K, W = ee.sent()
    out["sent"] = (sc, K, None, W, None)
    for name, (builder, kw, W) in HANDBOOK.items():
        KI, T = CONVERGED[name]
        out[name] = (gallery.SPECIMENS[builder](**kw), (KI, 0.0), T, W, 1.0)
    return out


def converged(name: str) -> dict:
    """Richardson-extrapolated quarter-point FEM K_I and T of a HANDBOOK specimen.

    ``FEM(h=W/n)`` for n = 20, 40, 80; the observed rate ``p = log2(d1 / d2)`` (d the
    changes of K_I between levels, clipped to [1, 2]) extrapolates
    ``K = K_80 + (K_80 - K_40) / (2^p - 1)``; ``K_uncertainty`` is the larger of that
    correction and the one at the unclipped observed rate (relative to K). T is
    the W/80 value (it changes by < 1.3e-4 sigma from W/40). Both tips of a two-tip
    specimen are averaged (they agree to 1e-6 by symmetry).
    """
    builder, kw, W = HANDBOOK[name]
    sc = gallery.SPECIMENS[builder](**kw)
    K, T = [], []
    for n in (20, 40, 80):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            tips = solve_fem(sc, FEM(h=W / n)).sifs(error=False)
        K.append(sum(t.KI for t in tips) / len(tips))
        T.append(sum(t.T for t in tips) / len(tips))
    d1, d2 = K[1] - K[0], K[2] - K[1]
    observed = math.log2(abs(d1 / d2)) if d1 * d2 > 0 else 0.0
    p = min(max(observed, 1.0), 2.0)
    corr = d2 / (2**p - 1)
    worst = abs(d2) / (2 ** min(max(observed, 0.25), p) - 1)
    hb = gallery.reference_k(builder, **kw)
    return {"K_I": K[2] + corr, "K_uncertainty": worst / abs(K[2]), "rate": p,
            "rate_observed": observed, "T": T[2],
            "T_change": abs(T[2] - T[1]), "levels": K, "handbook": hb["KI"],
            "handbook_accuracy": hb["accuracy"], "handbook_source": hb["source"],
            "handbook_error": (K[2] + corr) / hb["KI"] - 1}


def run(sc, K, T, method) -> dict:
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        sol = solve(sc, method) if isinstance(method, EFG) else solve_fem(sc, method)
        tips = sol.sifs(error=False)
    sec = time.perf_counter() - t0
    k = math.hypot(*K)
    out = {"K_error": max(max(abs(t.KI - K[0]), abs(t.KII - K[1])) for t in tips) / k,
           "KI": [t.KI for t in tips], "KII": [t.KII for t in tips], "T": [t.T for t in tips],
           "spread": max(t.spread for t in tips), "seconds": sec,
           "n_dofs": sol.sizes()["n_dofs"]}
    if T is not None:
        out["T_error"] = max(abs(t.T - T) for t in tips)
    return out


# The choices behind the EFG defaults, each changed alone from EFG(spacing=W/20) (full mode).
STUDY = {
    "default": {},
    "bc='penalty'": dict(bc="penalty"),
    "bc='variational'": dict(bc="variational"),
    "no zones (zones=())": dict(zones=()),
    "one zone (6h, h/2)": "one_zone",
    "PU (radius h) instead of extrinsic MLS": dict(enrichment="pu", enrich_radius=None),
    "no enrichment": dict(enrichment="none"),
}
STUDY_SPECIMENS = ("singular_patch_I", "shear_edge_crack", "sent")


def study(specs: dict) -> dict:
    """K error and seconds of each STUDY variant on the single-tip specimens at W/20."""
    from efgkit import Zone

    out = {}
    for name in STUDY_SPECIMENS:
        sc, K, T, W, _ = specs[name]
        h = W / 20
        for label, kw in STUDY.items():
            if kw == "one_zone":
                kw = dict(zones=tuple(Zone(tuple(t.x), 6 * h, h / 2) for t in sc.tips),
                          enrichment="extrinsic_mls", bc="lagrange")
            elif kw.get("enrichment") == "pu":
                kw = dict(kw, enrich_radius=h, zones=EFG(spacing=h).for_scene(sc).zones)
            elif "enrichment" in kw or "zones" in kw:  # an explicit choice switches zones off
                kw = dict(dict(zones=EFG(spacing=h).for_scene(sc).zones), **kw)
            r = run(sc, K, None, EFG(spacing=h, **kw))
            out[f"{name}/{label}"] = {"K_error": r["K_error"], "seconds": r["seconds"],
                                      "n_dofs": r["n_dofs"]}
    return out


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    specs = specimens()
    names = ("singular_patch_I", "inclined", "sent_free") if quick else tuple(specs)
    sizes = (10,) if quick else (10, 20)
    conv = {} if quick else {name: converged(name) for name in HANDBOOK}
    rows = {}
    for name in names:
        sc, K, T, W, sigma = specs[name]
        for n in sizes:
            for label, method in (("efg", EFG(spacing=W / n)), ("fem", FEM(h=W / n)),
                                  ("fem_uniform", FEM(h=W / n, tip_h=W / n, quarter_point=False))):
                r = run(sc, K, T, method)
                if "T_error" in r:
                    r["T_error"] /= sigma
                if name in HANDBOOK:
                    r["K_error_handbook"] = max(abs(k / conv_handbook(name) - 1) for k in r["KI"])
                rows[f"{name}/{label}/W{n}"] = r
    rep.metrics.update({
        "study": {} if quick else study(specs),
        "converged": conv,
        "runs": rows,
        "K_error": {k: r["K_error"] for k, r in rows.items()},
        "T_error": {k: r["T_error"] for k, r in rows.items() if "T_error" in r}})
    rep.ref("singular_patch", "K exact, T = 0", "the prescribed Williams field (seed 003 5.6.1)")
    rep.ref("griffith/inclined", "K_I = sqrt(pi) cos^2 b, K_II = sqrt(pi) sin b cos b, "
            "T = -cos 2b", "Tada, Paris & Irwin, Stress Analysis of Cracks Handbook, p. 5.11")
    rep.ref("shear_edge_crack", [34.042, 4.5371], "converged reference of shear_edge_crack "
            "(EFG PU, agrees with quarter-point P2 FEM and Wilson 1969: 34.0, 4.55)")
    rep.ref("sent_J", 6870.7, "converged quarter-point P2 FEM of sent (J/m^2); its u_y-free "
            "variant gives seed 001's Abaqus 6786 J/m^2 to 1e-6")
    for name, (builder, kw, _) in HANDBOOK.items():
        hb = gallery.reference_k(builder, **kw)
        rep.ref(f"{name}_handbook", hb["KI"], f"{hb['source']}, stated accuracy {hb['accuracy']:g}")
        rep.ref(f"{name}_converged", list(CONVERGED[name]), "K_I, T: Richardson-extrapolated "
                "quarter-point P2 FEM at W/40, W/80 (converged(); efgkit's own, checked against "
                "the handbook K within its stated accuracy; T is a cross-check only)")
    for name, c in conv.items():
        K0, T0 = CONVERGED[name]
        rep.check(f"{name}: recomputed converged K_I against the recorded one (rel.)",
                  abs(c["K_I"] / K0 - 1), "<=", CONVERGED_TOL)
        rep.check(f"{name}: recomputed converged T against the recorded one", abs(c["T"] - T0),
                  "<=", 1e-3)
        rep.check(f"{name}: converged K_I uncertainty (Richardson correction, rel.)",
                  c["K_uncertainty"], "<=", K_TOL / 10)
        if name in ANCHORED:
            rep.check(f"{name}: converged K_I against {c['handbook_source']} (rel.), within its "
                      "stated accuracy", abs(c["handbook_error"]), "<=", c["handbook_accuracy"])
    for key, r in rows.items():
        name = key.split("/")[0]
        if "/fem_uniform/" in key or (name in HANDBOOK and name not in ANCHORED):
            continue
        rep.check(f"{key}: K error (max |dK| / |K|)", r["K_error"], "<=", K_TOL)
        if "T_error" in r and name not in HANDBOOK:  # handbook specimens: T is a cross-check
            rep.check(f"{key}: T error / sigma", r["T_error"], "<=", T_TOL)
    return rep.write(out_dir)


def conv_handbook(name: str) -> float:
    builder, kw, _ = HANDBOOK[name]
    return gallery.reference_k(builder, **kw)["KI"]


def markdown(record: dict) -> list[str]:
    runs = record["metrics"]["runs"]
    lines = ["| specimen / method / size | K error | K error against the handbook fit | "
             "T error / sigma | spread | dofs | s |", "|---|---|---|---|---|---|---|"]
    for k, r in runs.items():
        t = f"{r['T_error']:.1e}" if "T_error" in r else "-"
        hb = f"{r['K_error_handbook']:.2e}" if "K_error_handbook" in r else "-"
        lines.append(f"| {k} | {r['K_error']:.2e} | {hb} | {t} | {r['spread']:.1e} | "
                     f"{r['n_dofs']} | {r['seconds']:.1f} |")
    conv = record["metrics"].get("converged") or {}
    if conv:
        lines += ["", "Converged references of the handbook specimens (quarter-point P2 FEM at "
                  "W/20, W/40, W/80, Richardson-extrapolated) against the handbook fits:", "",
                  "| specimen | K_I converged | Richardson correction | rate | T (W/80) | "
                  "handbook K_I | converged / handbook - 1 | stated accuracy |",
                  "|---|---|---|---|---|---|---|---|"]
        lines += [f"| {k} | {c['K_I']:.6f} | {c['K_uncertainty']:.1e} | {c['rate']:.2f} | "
                  f"{c['T']:.4f} | {c['handbook']:.6f} ({c['handbook_source']}) | "
                  f"{c['handbook_error']:+.2e} | {c['handbook_accuracy']:g} |"
                  for k, c in conv.items()]
    st = record["metrics"].get("study") or {}
    if st:
        lines += ["", "Each EFG choice changed alone from the default at W/20 (the defaults are the "
                  "first row of each specimen; seconds: solve and integrals on a shared 2-core "
                  "machine):", "", "| specimen / variant | K error | dofs | s |", "|---|---|---|---|"]
        lines += [f"| {k} | {r['K_error']:.2e} | {r['n_dofs']} | {r['seconds']:.1f} |"
                  for k, r in st.items()]
    return lines


if __name__ == "__main__":
    import json

    res = main()
    print(json.dumps({"K_error": res["metrics"]["K_error"], "T_error": res["metrics"]["T_error"]},
                     indent=1))
