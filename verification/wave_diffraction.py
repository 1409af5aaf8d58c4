"""Waves from an impact pulse in a square plate: P, S and Rayleigh front speeds (seed 002
Sect. 4.3, the uncracked plate).

Seed 002 Sect. 4.3: a 200 mm square plate, 201 x 201 nodes (1 mm), an impact pressure
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
  no dilatation), depths 30-70 mm (quick: 15-35 mm);
* S: the rotation ``(u_y,x - u_x,y) / 2`` on the ray 45 degrees below the surface (P waves
  carry no rotation), distances 30-70 mm (quick: 15-35 mm);
* Rayleigh: the vertical displacement on the top edge, 30-70 mm (quick: 15-35 mm) from
  the load's centre (the surface wave dominates there).

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


def _peak_time(t: np.ndarray, f: np.ndarray) -> float:
    """Time of the largest |f| by a parabola through it and its neighbours."""
    k = int(np.argmax(np.abs(f)))
    k = min(max(k, 1), len(t) - 2)
    y = np.abs(f[k - 1:k + 2])
    den = y[0] - 2 * y[1] + y[2]
    s = 0.0 if den == 0 else 0.5 * (y[0] - y[2]) / den
    return float(t[k] + s * (t[1] - t[0]))


def run(method: str, size: float, h: float, distances: np.ndarray, duration: float,
        every: float) -> dict:
    sc = scene(size, duration)
    m = METHODS[method](h)
    t0 = time.perf_counter()
    dyn = dynamics(sc, m)
    crit = stable_step(dyn)
    c = size / 2
    d = np.asarray(distances, float)
    s2 = math.sqrt(0.5)
    pts = {"P": np.column_stack([np.full(len(d), c), size - d]),
           "S": np.column_stack([c + s2 * d, size - s2 * d]),
           "R": np.column_stack([c + d, np.full(len(d), size)])}
    ops = {}
    for k, x in pts.items():
        sh = dyn.disc.shape_at(sc.domain.field_points(x), derivatives=True)
        ops[k] = csr_array(vstack(list(sh.u_operators()) + list(sh.grad_operators()), format="csr"))
    n = len(d)
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
            v = (A @ u).reshape(6, n)  # ux, uy, gxx, gxy, gyx, gyy
            hist[k].append({"P": v[2] + v[5], "S": 0.5 * (v[4] - v[3]), "R": v[1]}[k])
        if state.t >= duration:
            break
    t = np.array(times)
    speeds = {"P": MAT.c_dilatational, "S": MAT.c_shear, "R": MAT.c_rayleigh}
    out = {"t_us": t / US, "distances": d, "dt_us": dt / US, "dt_critical_us": crit[0] / US,
           "n_dofs": dyn.n_dofs, "steps": state.step, "seconds": time.perf_counter() - t0,
           "peak_times_us": {}, "speed": {}, "speed_exact": speeds, "error": {}}
    for k in pts:
        f = np.array(hist[k])  # (n_t, n)
        tp = np.array([_peak_time(t, f[:, j]) for j in range(n)])
        slope = np.polyfit(tp, d, 1)[0]
        out["peak_times_us"][k] = tp / US
        out["speed"][k] = float(slope)
        out["error"][k] = abs(slope / speeds[k] - 1)
    return out


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    if quick:
        size, h, dist = 100.0, 2.0, np.linspace(15.0, 35.0, 5)
    else:
        size, h, dist = 200.0, 1.0, np.linspace(30.0, 70.0, 9)
    duration = (max(dist) / MAT.c_rayleigh + 6 * US)
    m = {"front_speed_error": {}, "runs": {}}
    for method in METHODS:
        r = run(method, size, h, dist, duration, 0.1 * US)
        m["runs"][method] = r
        names = {"P": "P", "S": "S", "R": "Rayleigh"}
        for k, v in r["error"].items():
            m["front_speed_error"][f"{method}/{names[k]}"] = v
    # quick (2 mm, 4-8 nodes a wavelength; R and S fronts not yet apart): measured P 2.1 %,
    # S 3.1 %, Rayleigh 10 % (numerical dispersion slows the short surface pulse)
    quick_bound = {"P": 0.06, "S": 0.08, "Rayleigh": 0.25}
    for key, v in m["front_speed_error"].items():
        rep.check(f"{key}: front speed error", v, "<=",
                  quick_bound[key.split("/")[1]] if quick else TARGET)
    m["settings"] = {"size_mm": size, "spacing_mm": h, "E_MPa": MAT.E, "nu": MAT.nu,
                     "rho": MAT.rho, "p0_MPa": P0, "loaded_mm": 2 * HALF_LOAD,
                     "units": "mm, N, MPa, tonne/mm^3, s", "duration_us": duration / US}
    rep.metrics.update(_lists(m))
    rep.ref("c_1, c_2, c_R (m/s)", [6020, 3218, 2984], "seed README: seed 002 Sect. 4.3 with "
            "E = 210 GPa, plane strain; efgkit.Elastic wave speeds")
    rep.ref("front_speed_error", TARGET, "issue [dynamics]: target 2 %")
    return rep.write(out_dir)


def _lists(obj):
    if isinstance(obj, dict):
        return {k: _lists(v) for k, v in obj.items()}
    return obj.tolist() if isinstance(obj, np.ndarray) else obj
