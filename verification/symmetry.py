"""Half and quarter models against the full model of the same specimen.

A crack on a symmetry line is boundary in the half (and quarter) model: its face is a free
edge, its ligament carries u_n = 0, and ``Solution.sifs`` takes K_I, J and T of the modelled
tip from the fields mirrored onto the whole body (``efgkit.problem.symmetry``,
``efgkit.fracture.symmetric``; K_II = 0 by symmetry). Specimens (``efgkit.gallery``):

* ``cct``: centre-cracked plate, a/b = 0.5, h/b = 1.5, traction sigma = 1 on the ends
  (full model held by a pin and a roller), half (y >= 0) and quarter (x, y >= 0) models;
* ``sent``: the clamped SENT of seed 001 (50 x 10 mm, a/W = 0.5, 0.0253882 mm at each
  end), half model x >= 25 mm.

Each model is solved with the same discretisation settings (FEM: P2 graded to the same tip
size, no quarter points, since the part's tip is a boundary point without a tip fan; EFG: the
same spacing, linear basis without enrichment, which the part's boundary tip does not get),
and K_I and T are taken over the same J domains. Metric ``rel_diff``: for each
``specimen/method/model``, max over the modelled tips of |K_I / K_I,full - 1| and
|T / T_full - 1|.
"""

from __future__ import annotations

import time
import warnings

from _report import Report

from efgkit import EFG, FEM, solve, solve_fem
from efgkit.gallery import cct, sent_seed001

NAME = "symmetry"
TITLE = "Half and quarter models (symmetry) against the full model"
SPECIMENS = {  # name -> (model -> scene builder, J-domain radii, FEM (quick, full), EFG spacings)
    "cct": ({m: (lambda m=m: cct(0.5, 1.5, model=m)) for m in ("full", "half", "quarter")},
            (0.2, 0.3, 0.4), ((0.1, 0.01), (0.05, 0.002)), (0.1, 0.05)),
    "sent": ({m: (lambda m=m: sent_seed001(model=m)) for m in ("full", "half")},
             (1.0, 2.0, 3.0), ((2.0, 0.1), (1.0, 0.02)), (1.0, 0.5)),
}
TARGET = 1e-4  # issue 17: K_I and T of the part equal to the full model's to 1e-4


def _solve(method: str, sc, quick: bool, spec):
    _, _, fems, spacings = spec
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if method == "fem":
            h, tip_h = fems[0 if quick else 1]
            return solve_fem(sc, FEM(h, tip_h=tip_h, quarter_point=False))
        return solve(sc, EFG(spacing=spacings[0 if quick else 1], bc="lagrange", enrichment="none"))


def run(specimen: str, method: str, quick: bool) -> dict:
    spec = SPECIMENS[specimen]
    out = {}
    for model, build in spec[0].items():
        t0 = time.perf_counter()
        sol = _solve(method, build(), quick, spec)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = sol.sifs(radii=spec[1], error=False)
        out[model] = {r.tip.id: {"KI": r.KI, "KII": r.KII, "T": r.T, "J": r.J,
                                 "T_domains": [d.T for d in r.domains]} for r in res}
        out[model]["seconds"] = time.perf_counter() - t0
    return out


def rel_diff(rows: dict, model: str, keys=("KI", "T")) -> float:
    full, part = rows["full"], rows[model]
    return max(abs(part[t][k] / full[t][k] - 1) for t in part if t != "seconds" for k in keys)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    methods = ("fem",) if quick else ("fem", "efg")
    results, diffs, by_key = {}, {}, {"KI": {}, "T": {}}
    for specimen in SPECIMENS:
        for method in methods:
            rows = results[f"{specimen}/{method}"] = run(specimen, method, quick)
            for model in rows:
                if model != "full":
                    diffs[f"{specimen}/{method}/{model}"] = rel_diff(rows, model)
                    for k in by_key:
                        by_key[k][f"{specimen}/{method}/{model}"] = rel_diff(rows, model, (k,))
    rep.metrics.update({"rel_diff": diffs, "rel_diff_KI": by_key["KI"], "rel_diff_T": by_key["T"],
                        "results": results})
    rep.ref("rel_diff", TARGET, "issue 17: half and quarter models equal to the full model to 1e-4")
    for key in diffs:
        specimen, method, model = key.split("/")
        kII = max(abs(r["KII"]) for t, r in results[f"{specimen}/{method}"][model].items() if t != "seconds")
        rep.check(f"{key}: K_II reported 0 by symmetry", kII, "<=", 0.0)
    for key in [k for k in diffs if "/fem/" in k]:
        # K_I meets the 1e-4 target (measured <= 7e-5); T does not: measured 1.4e-4 to 4e-3
        # (quick and full), of the order of T's scatter over the full model's own J domains
        # (2e-4 to 3e-3, metric T_scatter_full): the two models are meshed independently
        specimen, method, model = key.split("/")
        full = results[f"{specimen}/{method}"]["full"]
        scatter = max(max(abs(t / r["T"] - 1) for t in r["T_domains"])
                      for k, r in full.items() if k != "seconds")
        rep.metrics.setdefault("T_scatter_full", {})[key] = scatter
        rep.check(f"{key}: K_I relative difference", by_key["KI"][key], "<=", TARGET)
        rep.check(f"{key}: T relative difference (target 1e-4 not reached)", by_key["T"][key], "<=", 1.2e-2)
    for key in [k for k in diffs if "/efg/" in k]:
        # half and quarter share the boundary tip: they agree to rounding; against the full model
        # (a crack with node splitting and the diffraction rule, no enrichment) the difference is
        # the discretisation error of the full model's unenriched tip (measured 7e-3 at h = 0.05)
        rep.check(f"{key}: relative difference", diffs[key], "<=", 2e-2)
    if not quick:
        q = results["cct/efg"]
        rep.check("cct/efg: quarter equals half", max(
            abs(q["quarter"]["crack:1"][k] / q["half"]["crack:1"][k] - 1) for k in ("KI", "T")), "<=", 1e-5)
    return rep.write(out_dir)


def markdown(r: dict) -> list[str]:
    m = r["metrics"]
    lines = ["Each part (half, quarter) against the full model of the same specimen, solved with "
             "the same settings (FEM P2 graded to the same tip size without quarter points; EFG "
             "linear basis, no enrichment, Lagrange multipliers), K_I and T over the same J "
             "domains; `rel_diff` = max(|dK_I / K_I|, |dT / T|) over the modelled tips. Target "
             f"(issue 17): {TARGET:g}.", "",
             "| specimen / method / model | K_I (part) | K_I (full) | dK_I | T (part) | T (full) | dT | "
             "rel_diff |", "|---|---|---|---|---|---|---|---|"]
    for key, d in m["rel_diff"].items():
        specimen, method, model = key.split("/")
        rows = m["results"][f"{specimen}/{method}"]
        tip = next(t for t in rows[model] if t != "seconds")
        p, f = rows[model][tip], rows["full"][tip]
        lines.append(f"| {key} | {p['KI']:.6g} | {f['KI']:.6g} | {m['rel_diff_KI'][key]:.1e} | "
                     f"{p['T']:.5g} | {f['T']:.5g} | {m['rel_diff_T'][key]:.1e} | {d:.2e} |")
    sc = m.get("T_scatter_full", {})
    return lines + ["", "K_I of every FEM part is within the 1e-4 target of the full model's. T is not: "
                    "the difference is of the order of T's own scatter between meshes and domains (the "
                    "models are meshed independently), the largest relative deviation of the full "
                    "model's T over its J domains being " + ", ".join(f"{k}: {v:.1e}" for k, v in sc.items())
                    + ". The EFG parts and the full EFG model differ by the discretisation error "
                    "of the full model's unenriched crack (the part's tip is a boundary point, with "
                    "no node splitting or crack rule), not by the symmetry: half and quarter agree "
                    "to 1e-5 or better."]


if __name__ == "__main__":
    import json

    print(json.dumps(main()["metrics"]["rel_diff"], indent=1))
