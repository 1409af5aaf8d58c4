"""Waves from an impact pulse in a square plate: P, S and Rayleigh front speeds (seed 002
Sect. 4.3, the uncracked plate).

Seed 002 Sect. 4.3: a 200 mm square plate, 201 x 201 nodes (1 mm; full mode also 0.5 mm), an impact pressure
``p0 g(t)`` over 8 mm at the centre of the top edge with the pulse of Eq. 40, steel with
nu = 0.3, rho = 7800 kg/m^3 and E printed as 210 MPa, which would make the P wave travel
2.9 mm in 15 us: the figures need E = 210 GPa (seed README), used here (plane strain:
c_1 = 6020 m/s, c_2 = 3218 m/s, c_R = 2984 m/s). The printed pulse is -0.0041 p0 at t = 0,
a jump from rest: :class:`efgkit.problem.history.ImpactPulse` shifts and rescales it so
that it starts from 0 and peaks at 1 (at most 0.4 % of the peak from the printed shape).
Units: mm, N, MPa, tonne/mm^3, s; p0 = 1 MPa; no supports (the pulse is over before the
momentum it gives matters for the fronts).

Each wave is picked where only it carries the measured quantity, and its front speed is the
slope of distance against the time of the pulse's peak (a parabola through the largest
sample and its neighbours) at several distances from the load:

* P: the dilatation ``eps_xx + eps_yy`` on the vertical axis below the load (S waves carry
  no dilatation), depths 30-70 mm (quick: 15-35 mm, on a 100 mm plate at 2 mm);
* S: the rotation ``(u_y,x - u_x,y) / 2`` on the ray 30 degrees off the vertical (P waves
  carry no rotation; inside the critical angle asin(c_2 / c_1) = 32 degrees, so no head
  wave, and far from the P wave reflected by the side edge, which on a 45 degree ray
  outgrows the direct S wave at 70 mm), distances 30-70 mm (quick: 15-35 mm);
* Rayleigh: the horizontal velocity on the top edge, 40-75 mm (quick: 15-35 mm) from the
  load's centre (the surface wave dominates there; for a vertical line load the Rayleigh
  part of the horizontal surface velocity has the shape of the load history, Lamb 1904,
  while the vertical displacement has its Hilbert transform, whose peak is not at the
  arrival).

The peak (of the lobe with the sign of the largest one at the nearest distance) is sought
within +-25 % of the expected travel time after the pulse's peak
(2.5 us), which keeps reflections from the edges out and does not bias a speed that is off
by less than that.

Metric ``front_speed_error`` ``{wave: |c_measured / c - 1|}``, target 2 %. The cracked
plates of the seed (horizontal and vertical 40 mm cracks, sigma_y snapshots at 15-30 us)
and the head wave are not done here.
"""

from __future__ import annotations

import math
import time

import numpy as np
from _report import Report
from scipy.sparse import csr_array, vstack

from efgkit import EFG, Domain, Elastic, Scene, Traction
from efgkit.explicit import dynamics, integrate, stable_step
from efgkit.problem.history import ImpactPulse, Stepping

NAME = "wave_diffraction"
TITLE = "Impact pulse in a square plate: P, S and Rayleigh front speeds (seed 002 Sect. 4.3)"
MAT = Elastic(210000.0, 0.3, "strain", rho=7800e-12)  # MPa, tonne/mm^3 (E in GPa: seed README)
P0, HALF_LOAD = 1.0, 4.0  # MPa, mm (8 mm loaded)
US = 1e-6
TARGET = 0.02
METHODS = {"efg": lambda h: EFG(spacing=h, enrichment="none")}


def scene(size: float, duration: float) -> Scene:
    c = size / 2

    def pressure(x):  # downward traction on the loaded stretch of the top edge
        return np.column_stack([np.zeros(len(x)), np.where(np.abs(x[:, 0] - c) <= HALF_LOAD, -P0, 0.0)])

    return Scene(Domain.rectangle(0.0, 0.0, size, size), MAT, name="wave_diffraction",
                 tractions=(Traction("top", pressure, history=ImpactPulse()),), duration=duration)


def _peak_time(t: np.ndarray, f: np.ndarray, gate: tuple[float, float]) -> float:
    """Time of the largest ``f`` within ``gate`` (t0, t1) by a parabola through it and its
    neighbours (pass ``-f`` for the largest negative lobe)."""
    inside = np.flatnonzero((t >= gate[0]) & (t <= gate[1]))
    k = int(inside[np.argmax(f[inside])])
    k = min(max(k, 1), len(t) - 2)
    y = f[k - 1:k + 2]
    den = y[0] - 2 * y[1] + y[2]
    s = 0.0 if den >= 0 else float(np.clip(0.5 * (y[0] - y[2]) / den, -1.0, 1.0))
    return float(t[k] + s * (t[k + 1] - t[k]))


def run(method: str, size: float, h: float, distances: dict, duration: float,
        every: float) -> dict:
    """One run; ``distances`` {wave: (n,)} from the load's centre (mm)."""
    sc = scene(size, duration)
    m = METHODS[method](h)
    t0 = time.perf_counter()
    dyn = dynamics(sc, m)
    crit = stable_step(dyn)
    c = size / 2
    d = {k: np.asarray(v, float) for k, v in distances.items()}
    s3 = math.sqrt(0.75)  # the S ray 30 degrees off the vertical
    pts = {"P": np.column_stack([np.full(len(d["P"]), c), size - d["P"]]),
           "S": np.column_stack([c + 0.5 * d["S"], size - s3 * d["S"]]),
           "R": np.column_stack([c + d["R"], np.full(len(d["R"]), size)])}
    ops = {}
    for k, x in pts.items():
        sh = dyn.disc.shape_at(sc.domain.field_points(x), derivatives=True)
        ops[k] = csr_array(vstack(list(sh.u_operators()) + list(sh.grad_operators()), format="csr"))
    hist = {k: [] for k in pts}
    times = []
    state = None
    dt = None
    step = Stepping(output_interval=1e30)
    while True:
        sol = integrate(sc, m, step, dyn=dyn, critical=crit, state=state,
                        steps=max(1, round(every / (dt or 0.9 * crit[0]))),
                        dsif=None, progress=False)
        state, dt = sol.state, sol.info["dt"]
        u = state.u
        times.append(state.t)
        for k, A in ops.items():
            if k == "R":  # horizontal velocity v^{n-1/2}: at t - dt/2
                hist[k].append((A[: 2 * len(d[k])] @ state.v)[: len(d[k])])
                continue
            v = (A @ u).reshape(6, len(d[k]))  # ux, uy, gxx, gxy, gyx, gyy
            hist[k].append({"P": v[2] + v[5], "S": 0.5 * (v[4] - v[3])}[k])
        if state.t >= duration:
            break
    t = np.array(times)
    speeds = {"P": MAT.c_dilatational, "S": MAT.c_shear, "R": MAT.c_rayleigh}
    out = {"t_us": t / US, "distances": d, "dt_us": dt / US, "dt_critical_us": crit[0] / US,
           "n_dofs": dyn.n_dofs, "steps": state.step, "seconds": time.perf_counter() - t0,
           "peak_times_us": {}, "speed": {}, "speed_exact": speeds, "error": {}}
    centre = ImpactPulse().centre
    for k in pts:
        f = np.array(hist[k])  # (n_t, n)
        # gate: +-25 % of the travel time about the expected peak (keeps reflections out)
        tk = t - 0.5 * dt if k == "R" else t
        # the same lobe at every distance: the sign of the largest one at the nearest point
        # (cylindrical spreading reshapes the pulse, and the largest |f| can change lobes)
        sign = np.sign(f[np.argmax(np.abs(f[:, 0])), 0]) or 1.0
        tp = np.array([_peak_time(tk, sign * f[:, j], (centre + 0.75 * dj / speeds[k],
                                                       centre + 1.25 * dj / speeds[k]))
                       for j, dj in enumerate(d[k])])
        slope = np.polyfit(tp, d[k], 1)[0]
        out["peak_times_us"][k] = tp / US
        out["speed"][k] = float(slope)
        out["error"][k] = abs(slope / speeds[k] - 1)
    return out


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    if quick:
        size, spacings = 100.0, (2.0,)
        dist = {k: np.linspace(15.0, 35.0, 5) for k in "PSR"}
    else:  # the seed's 1 mm grid (201 x 201) and 0.5 mm (401 x 401)
        size, spacings = 200.0, (1.0, 0.5)
        dist = {"P": np.linspace(30.0, 70.0, 9), "S": np.linspace(30.0, 70.0, 9),
                "R": np.linspace(40.0, 75.0, 8)}  # the corner (100 mm) disturbs beyond
    duration = 1.25 * max(dist["R"]) / MAT.c_rayleigh + 6 * US
    m = {"front_speed_error": {}, "front_speed_error_by_spacing": {}, "runs": {}}
    names = {"P": "P", "S": "S", "R": "Rayleigh"}
    for method in METHODS:
        for h in spacings:  # the finest spacing last: it gives front_speed_error
            r = run(method, size, h, dist, duration, 0.1 * US)
            m["runs"][f"{method}/{h:g}mm"] = r
            for k, v in r["error"].items():
                m["front_speed_error"][f"{method}/{names[k]}"] = v
                m["front_speed_error_by_spacing"][f"{method}/{h:g}mm/{names[k]}"] = v
    # quick (2 mm, 4-8 nodes a wavelength): measured P 2.1 %, S 2.9 %; the 7 mm surface
    # pulse is not resolved at 2 mm (its peak times are not monotone in the distance), so
    # quick mode reports the Rayleigh speed without checking it
    quick_bound = {"P": 0.06, "S": 0.08}
    for key, v in m["front_speed_error"].items():
        wave = key.split("/")[1]
        if quick and wave not in quick_bound:
            continue
        rep.check(f"{key} (spacing {spacings[-1]:g} mm): front speed error", v, "<=",
                  quick_bound[wave] if quick else TARGET)
    m["settings"] = {"size_mm": size, "spacings_mm": spacings, "distances_mm": dist,
                     "E_MPa": MAT.E, "nu": MAT.nu, "rho": MAT.rho, "p0_MPa": P0,
                     "loaded_mm": 2 * HALF_LOAD, "units": "mm, N, MPa, tonne/mm^3, s",
                     "duration_us": duration / US}
    rep.metrics.update(_lists(m))
    rep.ref("c_1, c_2, c_R (m/s)", [6020, 3218, 2984], "seed README: seed 002 Sect. 4.3 with "
            "E = 210 GPa, plane strain; efgkit.Elastic wave speeds")
    rep.ref("front_speed_error", TARGET, "issue [dynamics]: target 2 %")
    return rep.write(out_dir)


def _lists(obj):
    if isinstance(obj, dict):
        return {k: _lists(v) for k, v in obj.items()}
    return obj.tolist() if isinstance(obj, np.ndarray) else obj


def markdown(r: dict) -> list[str]:
    m = r["metrics"]
    s = m["settings"]
    names = {"P": "P", "S": "S", "R": "Rayleigh"}
    rows = ["| method / wave | measured (m/s) | theory (m/s) | error |", "|---|---|---|---|"]
    for meth, v in m["runs"].items():
        rows += [f"| {meth} / {names[k]} | {v['speed'][k] / 1e3:.0f} | "
                 f"{v['speed_exact'][k] / 1e3:.0f} | {v['error'][k]:.2%} |" for k in v["speed"]]
        rows.append(f"| {meth}: dt / dt_c (us) | {v['dt_us']:.4g} / {v['dt_critical_us']:.4g} | | |")
    return [f"Plate {s['size_mm']:g} mm square, spacings {s['spacings_mm']} mm, E = "
            f"{s['E_MPa']:g} MPa (the seed's 210 MPa read as GPa), nu = {s['nu']}, rho = "
            f"{s['rho']:g} tonne/mm^3, plane strain; impact pulse (seed 002 Eq. 40, started "
            f"from rest) of {s['p0_MPa']:g} MPa over {s['loaded_mm']:g} mm at the top centre. "
            "Speeds: slope of distance against the peak time of the dilatation (P, on the "
            "axis), the rotation (S, 30 degrees off the axis) and the horizontal surface "
            "velocity (Rayleigh).", "", *rows]
