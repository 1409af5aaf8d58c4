"""Maximum hoop stress kink angle against the closed form in 50-digit arithmetic.

Erdogan and Sih (1963): theta_c = 2 atan((K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)), the
criterion efgkit uses for growth (seed 003 Sect. 6 states none; seed README). The closed
form is evaluated with mpmath at 50 digits, where its 0/0 and cancellation at small
K_II / K_I are harmless; efgkit evaluates the cancellation-free equal form
-2 atan(2 K_II / (K_I + S)) in float64 (:func:`efgkit.fracture.criteria.kink_angle`).
Cases: K_II / K_I in {0, 1e-12, 0.1, 0.5, 1, 5} of both signs and pure mode II
(K_I = 0: -/+ acos(1/3) = -/+ 70.5288 degrees). Metric ``max_abs_error_deg``; the
textbook form in float64 is recorded beside it (it is NaN at K_II = 0 and loses digits
at 1e-12).
"""

from __future__ import annotations

import math
import warnings

import mpmath
import numpy as np
from _report import Report

from efgkit.fracture.criteria import hoop_stress

NAME = "kink_angle"
TITLE = "Maximum hoop stress kink angle (Erdogan and Sih 1963)"
RATIOS = (0.0, 1e-12, 0.1, 0.5, 1.0, 5.0)


def exact_deg(KI: float, KII: float) -> float:
    """theta_c in degrees from the closed form at 50 digits (K_II = 0: 0)."""
    mpmath.mp.dps = 50
    if KII == 0:
        return 0.0
    ki, kii = mpmath.mpf(KI), mpmath.mpf(KII)
    return float(mpmath.degrees(2 * mpmath.atan((ki - mpmath.sqrt(ki**2 + 8 * kii**2)) / (4 * kii))))


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    cases = [(1.0, s * r) for r in RATIOS for s in ((1.0,) if r == 0 else (1.0, -1.0))]
    cases += [(0.0, 1.0), (0.0, -1.0)]
    KI, KII = np.array(cases).T
    got = np.degrees(hoop_stress(KI, KII).angle)
    ref = np.array([exact_deg(a, b) for a, b in cases])
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        textbook = np.degrees(2 * np.arctan((KI - np.sqrt(KI**2 + 8 * KII**2)) / (4 * KII)))
    err = np.abs(got - ref)
    rel_small = float(abs(got[1] / ref[1] - 1))  # K_II / K_I = 1e-12: relative error
    rep.metrics.update({
        "max_abs_error_deg": float(err.max()), "rel_error_at_1e-12": rel_small,
        "cases": [{"KI": a, "KII": b, "efgkit_deg": g, "exact_deg": r, "textbook_float64_deg": t}
                  for (a, b), g, r, t in zip(cases, got, ref, textbook, strict=True)]})
    rep.ref("pure_mode_II_deg", -math.degrees(math.acos(1 / 3)),
            "Erdogan and Sih 1963: K_I sin t + K_II (3 cos t - 1) = 0 with K_I = 0 gives cos t = 1/3")
    # measured 1.4e-14 degrees (one ulp of 66.76 degrees is 1.4e-14)
    rep.check("max |theta - closed form| over the cases (degrees)", float(err.max()), "<=", 5e-14)
    rep.check("relative error at K_II / K_I = 1e-12", rel_small, "<=", 1e-15)  # measured 0
    rep.check("pure mode II equals -acos(1/3) (degrees)",
              float(abs(got[-2] + math.degrees(math.acos(1 / 3)))), "<=", 1e-12)
    return rep.write(out_dir)


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    rows = ["| K_I | K_II | efgkit (deg) | closed form, 50 digits (deg) | textbook form in float64 |",
            "|---|---|---|---|---|"]
    rows += [f"| {c['KI']:g} | {c['KII']:g} | {c['efgkit_deg']:.15g} | {c['exact_deg']:.15g} | "
             f"{c['textbook_float64_deg']} |" for c in m["cases"]]
    return ["The kink angle of efgkit (cancellation-free form) against the Erdogan-Sih closed "
            "form evaluated with mpmath at 50 digits; the textbook form in float64 is shown "
            "for contrast (NaN at K_II = 0, digits lost at 1e-12).", "", *rows, "",
            f"Largest error {m['max_abs_error_deg']:.2e} degrees; relative error at "
            f"K_II / K_I = 1e-12: {m['rel_error_at_1e-12']:.2e}."]


if __name__ == "__main__":
    print(main()["metrics"]["max_abs_error_deg"])
