"""Running cracks in an explicit run: prescribed speed and a stress criterion (seed 002
Sect. 3.1 and Fig. 5, seed 000 Sect. 5.2.2).

(a) Prescribed speed. The centre-cracked plate of ``center_crack_dynamic`` (104 x 40 mm,
a0 = 12 mm, step tension 0.1 MPa on top and bottom, E = 75.6 GPa, nu = 0.286, rho = 2450
kg/m^3, plane strain; units mm, N, MPa, tonne/mm^3, s). Both tips start running at
``V = 1000 m/s`` at ``t0 = 4 us`` (seed 002 does not state its start time; 4 us lies in the
window below, 0.84 us after the wave reaches the crack) by increments ``da`` = one node
spacing, 1 mm (quick mode: the 2 mm grid, da = 1 mm)
(:class:`efgkit.growth.dynamic.PrescribedSpeed`, each advance a full rebuild and a re-fit
of the state), K_I from the moving-tip J' at speed V; the same run with a
stationary crack beside it. Seed 002 Fig. 5 (not in the text) plots both histories;
the text says only that they "agree well" with the moving-singular-element results of
Nishioka and Atluri (1980).

Reference: until waves from the other tip (``2 a0 / c_d`` after the arrival ``t_a = 20 mm
/ c_d``) or the corners reach the tip, each tip is Freund's semi-infinite crack struck by a
step wave; for a crack that starts running at constant ``V``, ``K_I(t, V) = k(V) K_I(t, 0)``
with the universal function ``k(V) ~ (1 - V / c_R) / sqrt(1 - V / c_d)`` (Freund,
*Dynamic Fracture Mechanics*, 1990, Sect. 7.4; the approximation is within a few percent
of the exact k). Measured: ``K_run / K_stat`` (the stationary history interpolated to the
running instants) over whole advance cycles from the first advance to the end of the
window: its cycle mean (``ratio_mean``) against ``k(V)`` (``k_error``). The state crosses
each rebuild by copying the coefficients node by node (the default of ``run_growing``).
Full mode also records the mean for other increments, a grid twice as fine and the
re-fit transfer (``sensitivity``, not checked; the re-fit blows up on the fine grid). The tip of the
model jumps by ``da`` at each advance and stands between (nodal release without a
gradual release of the cohesive force): K falls right after an advance and rises above
the continuous value before the next, a sawtooth whose mean is compared; its extremes
are recorded (``ratio_min``, ``ratio_max``).

(b) Criterion. A plate 20 x 10 mm with a central crack of half-length 2 mm (same
material, step tension 1 MPa, 41 x 20 nodes, spacing 0.5 mm): each tip gains a segment of
0.5 mm when the maximum principal stress 0.5 mm ahead of it reaches ``sigma_c = 3 MPa``
(:class:`efgkit.growth.dynamic.PrincipalStress`, checked every ``CHECK`` steps): the
initiation time, the crack-length and speed histories (least-squares speed over 11 advances,
seed 000 Sect. 5.2.2) and the stop reason; the speed must stay below ``c_R``.
"""

from __future__ import annotations

import math
import time

import numpy as np
from _report import Report
from center_crack_dynamic import A0, HALF_H, LOAD, METHODS, scene

from efgkit import EFG, Crack, Domain, Elastic, Scene, Traction
from efgkit.fracture.velocity import velocity_functions
from efgkit.growth.dynamic import PrescribedSpeed, PrincipalStress, run_growing
from efgkit.problem.history import Heaviside, Stepping

NAME = "running_crack"
TITLE = "Running cracks: prescribed speed (seed 002 Fig. 5) and a stress criterion (seed 000 Sect. 5.2)"
US = 1e-6
SPEED = 1.0e6  # mm/s (1000 m/s)
START = 4.0 * US
SIGMA_C, CHECK = 3.0, 2


def k_universal(v: float, mat: Elastic) -> float:
    """Freund's approximation of the universal function k(V) (module docstring)."""
    return (1 - v / mat.c_rayleigh) / math.sqrt(1 - v / mat.c_dilatational)


def prescribed(nx: int, ny: int, dt: float, duration: float, da: float = 1.0,
               transfer: str = "copy") -> dict:
    sc = scene("mode_I", duration)
    m = METHODS["efg"](nx, ny)
    h = m.spacing
    radii = tuple(r * h for r in (2.0, 2.5, 3.0, 3.5, 4.0))  # as center_crack_dynamic
    st = Stepping(dt=dt, output_interval=0.1 * US if nx > 60 else 0.2 * US)
    t0 = time.perf_counter()
    stat = run_growing(sc, m, PrescribedSpeed(SPEED, start=10 * duration, da=da), st, radii=radii)
    t1 = time.perf_counter()
    run = run_growing(sc, m, PrescribedSpeed(SPEED, start=START, da=da), st, radii=radii,
                      transfer=transfer)
    t2 = time.perf_counter()
    mat = sc.material
    norm = LOAD * math.sqrt(math.pi * A0)
    ks = stat.history["K"][:, :, 0].mean(axis=1) / norm
    kr = run.history["K"][:, :, 0].mean(axis=1) / norm
    tr = run.history["t"]
    ta = HALF_H / mat.c_dilatational
    t_end = ta + 2 * A0 / mat.c_dilatational
    per = run.info["da"] / SPEED
    first = START + 0.5 * per
    cycles = int((t_end - first) // per)
    win = (tr >= first) & (tr <= first + cycles * per + 1e-12 * per)
    ks_i = np.interp(tr, stat.history["t"], ks)
    ratio = kr[win] / ks_i[win]
    # cycle mean: trapezoid over each cycle (both rows at an advance instant kept)
    mean = float(np.trapezoid(kr[win], tr[win]) / np.trapezoid(ks_i[win], tr[win])) if cycles else math.nan
    kv = k_universal(SPEED, mat)
    # before the first advance the tip has not moved: the J' is the stationary one and only
    # the velocity function differs, K_run / K_stat = sqrt(A_I(0) / A_I(V)) (seed 002 Eq. 33)
    A0_, AV = velocity_functions(0.0, mat)[0], velocity_functions(SPEED, mat)[0]
    pre = (tr > START) & (tr < first - 0.25 * per) & (ks_i > 0.1 * ks.max())
    pre_err = float(np.max(np.abs(kr[pre] / ks_i[pre] / math.sqrt(A0_ / AV) - 1)))
    return {"t_us": tr / US, "K_running": kr, "K_stationary_t_us": stat.history["t"] / US,
            "K_stationary": ks, "extension_mm": run.history["length"][:, 0],
            "ratio_mean": mean, "k_V": kv, "pre_advance_error": pre_err,
            "velocity_factor": math.sqrt(A0_ / AV), "k_error": abs(mean / kv - 1),
            "ratio_min": float(ratio.min()) if cycles else math.nan,
            "ratio_max": float(ratio.max()) if cycles else math.nan,
            "window_us": [first / US, (first + cycles * per) / US], "cycles": cycles,
            "t_end_us": t_end / US, "advances": len(run.advances["t"]), "stop": run.stop,
            "dt_us": dt / US, "da_mm": run.info["da"], "nodes": [nx, ny], "transfer": transfer,
            "seconds": {"stationary": t1 - t0, "running": t2 - t1},
            "rebuild_seconds_per_advance": run.timings["rebuild"] / max(run.info["rebuilds"], 1),
            "transfer_seconds_per_advance": run.timings["transfer"] / max(run.info["rebuilds"], 1),
            "integrate_seconds": run.timings["integrate"]}


def criterion(duration: float) -> dict:
    mat = Elastic(75600.0, 0.286, "strain", rho=2450e-12)
    W, H, a0, nx, ny = 10.0, 5.0, 2.0, 41, 20
    X, Y = np.meshgrid(np.linspace(-W, W, nx), np.linspace(-H, H, ny))
    m = EFG(spacing=2 * W / (nx - 1), coordinates=np.column_stack([X.ravel(), Y.ravel()]),
            d_max=2.5, zones=(), enrichment="none")
    sc = Scene(Domain.rectangle(-W, -H, W, H), mat, cracks=(Crack([[-a0, 0.0], [a0, 0.0]]),),
               duration=duration, tractions=(Traction("top", (0.0, 1.0), history=Heaviside()),
                                             Traction("bottom", (0.0, -1.0), history=Heaviside())))
    t0 = time.perf_counter()
    r = run_growing(sc, m, PrincipalStress(SIGMA_C, check_every=CHECK),
                    Stepping(output_interval=0.1 * US), radii=(1.0, 1.25, 1.5))
    tip = r.tips[1]
    sp = r.speeds.get(tip)
    adv = r.advances
    mine = np.array([k == tip for k in adv["tip"]], bool)
    return {"t_us": r.history["t"] / US, "K_I": r.history["K"][:, 1, 0],
            "extension_mm": r.history["length"][:, 1],
            "advance_t_us": adv["t"][mine] / US, "advance_extension_mm": adv["extension"][mine],
            "speed_m_s": [] if sp is None else sp["speed"] / 1e3,
            "max_speed_over_c_R": 0.0 if sp is None else float(np.max(sp["speed"]) / mat.c_rayleigh),
            "initiation_us": float(adv["t"][mine][0] / US) if mine.any() else None,
            "c_R_m_s": mat.c_rayleigh / 1e3, "stop": r.stop, "seconds": time.perf_counter() - t0,
            "plate_mm": [2 * W, 2 * H], "a0_mm": a0, "nodes": [nx, ny], "sigma_c_MPa": SIGMA_C,
            "check_every": CHECK, "dt_us": r.info["dt"] / US}


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    a = prescribed(53, 21, 0.2 * US, 6.6 * US) if quick else prescribed(105, 42, 0.1 * US, 8.0 * US)
    b = criterion(6.0 * US if quick else 18.0 * US)
    sens = []
    if not quick:  # the cycle mean against the increment and the grid (not checked)
        for nx, ny, dt, da, tr in ((105, 42, 0.1 * US, 0.5, "copy"), (209, 83, 0.05 * US, 1.0, "copy"),
                                   (209, 83, 0.05 * US, 0.5, "copy"), (105, 42, 0.1 * US, 1.0, "refit"),
                                   (209, 83, 0.05 * US, 0.5, "refit")):
            s = prescribed(nx, ny, dt, 7.5 * US, da=da, transfer=tr)
            sens.append({k: s[k] for k in ("nodes", "da_mm", "transfer", "cycles", "ratio_mean",
                                           "k_error", "ratio_min", "ratio_max")})
    a["sensitivity"] = sens
    rep.metrics.update({"prescribed": a, "criterion": b})
    # k(V): measured 9.0 % (quick, 2 mm grid) and 6.1 % (full, the seed's 1 mm grid)
    rep.check("prescribed speed: |cycle mean of K_run/K_stat / k(V) - 1|", a["k_error"], "<=",
              0.25 if quick else 0.15)
    rep.check("prescribed speed, before the first advance: |K_run/K_stat / sqrt(A_I(0)/A_I(V)) - 1|",
              a["pre_advance_error"], "<=", 2e-4)  # measured 6e-5 (quick and full)
    rep.check("criterion: advances (initiation and a speed history)", len(b["advance_t_us"]), ">=", 2)
    rep.check("criterion: max fitted speed / c_R", b["max_speed_over_c_R"], "<=", 1.0)
    rep.ref("velocity_factor", a["velocity_factor"], "seed 002 Eqs. 33-34: sqrt(A_I(0) / A_I(V))")
    rep.ref("k_V", a["k_V"], "Freund 1990 Sect. 7.4: k(V) ~ (1 - V/c_R)/sqrt(1 - V/c_d), the "
            "running/stationary K ratio for a crack starting to run under step-wave loading")
    rep.ref("c_R_m_s", b["c_R_m_s"],
            "Rayleigh speed of the material (Elastic.c_rayleigh; seed 000 Eqs. 5.9-5.10)")
    return rep.write(out_dir)


def markdown(r: dict) -> list[str]:
    a, b = r["metrics"]["prescribed"], r["metrics"]["criterion"]
    sp = b["speed_m_s"]
    return [f"(a) Centre-cracked plate, {a['nodes'][0]} x {a['nodes'][1]} nodes, dt = {a['dt_us']:g} us, "
            f"both tips run at 1000 m/s from {START / US:g} us by da = {a['da_mm']:g} mm "
            f"({a['advances']} advances, full rebuild {a['rebuild_seconds_per_advance']:.2f} s "
            f"and state transfer ({a['transfer']}) {a['transfer_seconds_per_advance']:.2f} s per "
            "advance). Over "
            f"{a['cycles']} advance cycles ({a['window_us'][0]:.2f}-{a['window_us'][1]:.2f} us, "
            f"before the other tip's waves at {a['t_end_us']:.2f} us) the cycle mean of K_run / "
            f"K_stat is {a['ratio_mean']:.3f} against Freund's k(V) = {a['k_V']:.3f} (error "
            f"{a['k_error']:.1%}); within a cycle the ratio runs from {a['ratio_min']:.2f} right "
            f"after an advance to {a['ratio_max']:.2f} before the next: the tip jumps by a node "
            "spacing and stands between jumps. Seed 002 Fig. 5 is not in the text: its caption "
            "says it plots the stationary and the running histories, and the text that they "
            "agree with Nishioka and Atluri's moving singular elements; Freund's k(V) < 1 is "
            "the drop of K when the crack starts to run.",
            *([""] + ["| nodes | da (mm) | state transfer | cycles | cycle mean K_run/K_stat | "
                      "error vs k(V) | min | max |", "|---|---|---|---|---|---|---|---|"]
              + [f"| {s['nodes'][0]} x {s['nodes'][1]} | {s['da_mm']:g} | {s['transfer']} | {s['cycles']} | "
                 f"{s['ratio_mean']:.3f} | {s['k_error']:.1%} | {s['ratio_min']:.2f} | "
                 f"{s['ratio_max']:.2f} |" for s in a.get("sensitivity", [])]
              if a.get("sensitivity") else []),
            "", f"(b) Plate {b['plate_mm'][0]:g} x {b['plate_mm'][1]:g} mm, a0 = {b['a0_mm']:g} mm, "
            f"{b['nodes'][0]} x {b['nodes'][1]} nodes, sigma_c = {b['sigma_c_MPa']:g} MPa at 0.5 mm "
            f"ahead, checked every {b['check_every']} steps: initiation at "
            f"{b['initiation_us'] if b['initiation_us'] is None else round(b['initiation_us'], 2)} us, "
            f"{len(b['advance_t_us'])} advances, fitted speeds "
            f"{', '.join(f'{s:.0f}' for s in sp) or '-'} m/s (c_R = {b['c_R_m_s']:.0f} m/s, "
            f"max / c_R = {b['max_speed_over_c_R']:.2f}); stop: {b['stop']}."]
