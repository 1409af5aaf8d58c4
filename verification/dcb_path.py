"""Crack path in a double cantilever beam: seed 003 Sect. 6.2 (Figs. 49-53).

L = 300 mm long, h = 100 mm high (the text gives L, h, a and P; Fig. 49 with the load
points is not in the extraction: the beam is taken as L x h with the crack on its centre
line from the left end), crack a = 138 mm from the left end along y = h/2, P = 100 N
(per unit thickness) pulling the arms apart, spread over the first 10 mm of the top
(up) and bottom (down) edges; the loads are self-equilibrated, and a 10 mm stretch of
the right end at mid-height is held (its reactions vanish by equilibrium). E = 200 GPa,
nu = 0.3, plane stress (N, mm, MPa). A perturbation of 12 mm at 4.8 degrees ends the
initial crack (seed: "a small kink at angle d theta"), and the crack grows by the maximum
hoop stress criterion with increments da.

Seed 003: the DCB path is unstable (positive T-stress, Cotterell and Rice 1980): after
the perturbation it curves away from the centre line towards the boundary; a step that is
too large misrepresents the path (Figs. 51, 52); with da = 5 mm linear and sqrt(r) bases
give similar paths. Checked here: the offset from the centre line grows monotonically
beyond the perturbation's own; the paths for da, da/2 and da/4 converge (the difference
of the offsets at common x falls as da halves). Metrics: offsets per step size,
``path_difference`` between successive step sizes.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
from _report import Report

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, Traction
from efgkit.growth import Growth, grow

NAME = "dcb_path"
TITLE = "Crack path in a double cantilever beam (seed 003 Sect. 6.2)"
L, HGT, A, P = 300.0, 100.0, 138.0, 100.0  # mm, mm, mm, N (seed 003 Sect. 6.2)
PERT, DTHETA = 12.0, math.radians(4.8)  # perturbation length (mm) and angle, seed 003 Sect. 6.2
GRIP = 10.0  # mm of top / bottom edge carrying P (assumed: Fig. 49 is not in the text)


def scene() -> Scene:
    y0 = HGT / 2
    tip = np.array([A + PERT * math.cos(DTHETA), y0 + PERT * math.sin(DTHETA)])
    top = lambda x: (x[:, 1] > HGT - 1e-9) & (x[:, 0] < GRIP)  # noqa: E731
    bottom = lambda x: (x[:, 1] < 1e-9) & (x[:, 0] < GRIP)  # noqa: E731
    hold = lambda x: (x[:, 0] > L - 1e-9) & (np.abs(x[:, 1] - y0) < 5.0)  # noqa: E731
    return Scene(Domain.rectangle(0.0, 0.0, L, HGT), Elastic(200e3, 0.3, "stress"),
                 supports=(Support(hold, ux=0.0, uy=0.0),),
                 tractions=(Traction(top, (0.0, P / GRIP)), Traction(bottom, (0.0, -P / GRIP))),
                 cracks=(Crack([[0.0, y0], [A, y0], tip.tolist()], tips=(False, True), name="dcb"),),
                 name="dcb")


def path(spacing: float, da: float, grow_by: float) -> dict:
    g = Growth(da=da, max_steps=round(grow_by / da), snap=0.5)
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        steps = list(grow(scene(), EFG(spacing=spacing), g))
    v = steps[-1].scene.cracks[0].vertices
    if steps[-1].state is not None:  # the last increment was computed: include it
        v = steps[-1].state.cracks[0].vertices
    return {"vertices": v.tolist(), "KI": [s.tips[0].KI for s in steps if s.tips],
            "KII": [s.tips[0].KII for s in steps if s.tips], "stop": steps[-1].stop,
            "n_solves": len(steps), "seconds": time.perf_counter() - t0}


def offset_at(vertices, x: np.ndarray) -> np.ndarray:
    """Offset y - h/2 of the path beyond the initial crack, interpolated at ``x (k,)``."""
    v = np.asarray(vertices)[2:]  # from the perturbation's start on
    return np.interp(x, v[:, 0], v[:, 1]) - HGT / 2


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    # an odd number of spacings over h keeps node rows off the centre line (the crack)
    spacing, das, grow_by = (HGT / 9, (20.0, 10.0), 40.0) if quick else (HGT / 19, (10.0, 5.0, 2.5), 80.0)
    runs = {da: path(spacing, da, grow_by) for da in das}
    x_end = min(np.asarray(r["vertices"])[:, 0].max() for r in runs.values())
    x_tip0 = A + PERT * math.cos(DTHETA)
    xs = np.linspace(x_tip0, x_end, 9)
    offsets = {da: offset_at(r["vertices"], xs) for da, r in runs.items()}
    diffs = [float(np.max(np.abs(offsets[a] - offsets[b]))) for a, b in zip(das[:-1], das[1:], strict=True)]
    fine = offsets[das[-1]]
    rep.metrics.update({
        "spacing": spacing, "das": list(das), "x": xs.tolist(),
        "offsets": {str(da): o.tolist() for da, o in offsets.items()}, "path_difference": diffs,
        "runs": {str(da): r for da, r in runs.items()}})
    rep.ref("perturbation_offset", PERT * math.sin(DTHETA), "seed 003 Sect. 6.2: 12 mm at 4.8 degrees")
    pert = PERT * math.sin(DTHETA)
    rep.check("finest path: offset at the end over the perturbation's (curves away: > 1)",
              float(abs(fine[-1]) / pert), ">=", 1.5)
    rep.check("finest path: offset grows monotonically (min step of |offset|)",
              float(np.min(np.diff(np.abs(fine)))), ">=", 0.0)
    if len(diffs) > 1:
        rep.check("paths converge: difference (da/2, da/4) over (da, da/2)", diffs[-1] / diffs[-2], "<=", 0.8)
    return rep.write(out_dir)


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    head = "| x (mm) | " + " | ".join(f"offset, da = {d:g}" for d in m["das"]) + " |"
    rows = [head, "|---" * (len(m["das"]) + 1) + "|"]
    for k, x in enumerate(m["x"]):
        rows.append(f"| {x:.1f} | " + " | ".join(f"{m['offsets'][str(d)][k]:.3f}" for d in m["das"]) + " |")
    return [f"DCB of seed 003 Sect. 6.2 (EFG spacing {m['spacing']:g} mm, automatic tip zones); "
            "offset of the crack path from the centre line (mm) at common x for each step size.",
            "", *rows, "", "Largest difference between successive step sizes: "
            + ", ".join(f"{d:.3f} mm" for d in m["path_difference"]) + "."]


if __name__ == "__main__":
    import sys

    r = main(quick="--quick" in sys.argv)
    print(r["passed"], r["metrics"]["offsets"], r["metrics"]["path_difference"])
