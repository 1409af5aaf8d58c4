"""The tungsten plate of seed 000 Sect. 5.2.1: a central crack pulled at nominal strain
rates of 200/s and 1000/s, propagation by nodal release on a principal-stress criterion.

Material (seed): E = 400 GPa, nu = 0.29, rho = 19300 kg/m^3, plane strain (the seed's
c_R = 2624.1 m/s is the plane-strain value; plane stress gives 2594 m/s), critical maximum
principal stress sigma_c = 4.5 GPa. Units mm, MPa, tonne/mm^3, s.

Dimensions the seed omits (its Fig. 14 is not in the text), chosen here:

* the quarter model is 10 x 10 mm (plate 20 x 20 mm, "square"): the four zones of the
  seed stacked over the crack line, 0.3 + 0.5 + 1 + 8.2 mm, make 10 mm, and zones of
  uniform grids spanning 10 mm across (13 rows of 401, 10 of 201, 10 of 101 and 41 of 51
  nodes) hold exactly the seed's 10,324 particles (``nodes(1)`` builds that grid);
* the initial crack: the seed gives no length for it; its Sect. 5.2.2 compares the
  central one of three "0.8 mm long" cracks with this crack, so it is taken 0.8 mm long,
  in the seed's own sense of "crack length" in Figs. 16 and 18 (lengths up to 5 mm in a
  10 mm quarter: the tip's distance from the centre), i.e. a0 = 0.8 mm in the quarter
  model (``A_SEED_READING``). The other reading, 0.8 mm for the whole crack (a0 = 0.4 mm,
  ``A0``), is run in full mode beside it: at 200/s it does not initiate within 16 us on
  the seed's grid (the peak sigma_1 on the line stays below 4.5 GPa), against the seed's
  9.6 us; this is why the first reading is the one checked (it was chosen after both had
  been run: the record shows both);
* the nominal strain rate is the velocity difference of the pulled edges over the plate
  height: each edge moves at ``v0 = rate * 10 mm`` (2 m/s at 200/s, 10 m/s at 1000/s),
  ``u_y = v0 t`` on the top edge of the quarter (a moving support, Lagrange projection),
  ``u_x`` free there (the seed states only the pulled direction).

Symmetry: ``u_x = 0`` on x = 0, ``u_y = 0`` on the ligament of y = 0 (seed: "normal
velocities and tangential tractions equal to zero on the planes of symmetry"); the crack
faces are the free part of y = 0 and grow by releasing the line's nodes
(:mod:`efgkit.growth.release`). "Crack length" is the half-length, the tip's distance from
the plate centre (the quarter model's crack). The seed's face gap (2e-3 mm) has no
counterpart on a symmetry line (module docstring of release.py).

Three cracks (seed 000 Sect. 5.2.2, full mode; the seed's Fig. 19 is missing, so its
dimensions are chosen): three cracks on the crack line, the central one 0.8 mm long
(a0 = 0.4 mm in the quarter) and side cracks 0.8 mm long centred at +-2 mm (``XC``); the
plate, grid and settings of the single crack. The start of each tip (tip 1 the central
crack's, 2 and 3 the side crack's inner and outer tips) beside the seed's (at 200/s tip 3
starts 0.4 us after tip 1, tip 2 a little later; at 1000/s all together). Measured, with
either release (the criterion decides the starts): at 200/s tips 1, 2, 3 start at 13.74,
13.82 and 13.84 us (tip 3 0.11 us after tip 1, tip 2 before tip 3); the cracks join at
17.6 us (energy release; 14.2 us released at once); at 1000/s all three start at 2.06 us.
Checked at 200/s: the order efgkit can claim, tip 1 first, tips 2 and 3 after it (not the
seed's 0.4 us: nothing is fitted to it; the delay depends on the side cracks' place,
which the seed does not give).

"At high rates the central crack's speed is unaffected by the others" (seed): at 1000/s
the central crack's length and speed before the cracks join against the single crack's,
same rate, grid and settings (:func:`central_vs_single`), for a0 = 0.8 mm (the checked
single crack; side cracks as above, a gap of 0.8 mm) and a0 = 0.4 mm (a single crack of
that length run for it). Measured: with a0 = 0.8 mm, 13 growth points before the join
(2.06-2.34 us, 0.825-1.175 mm; 3 distinct 11-point windows), the speeds agree within 0.6 %
until the gap to tip 2 has closed to 0.5 mm, then the central crack speeds up as the tips
close: largest difference 13.3 % (lengths at equal times 4.6 %, instants at equal lengths
0.035 us); with a0 = 0.4 mm (23 points, 0.425-0.975 mm) within 1.1 % until the gap has
closed to 0.55 mm, then up to 17.6 % (lengths 4.2 %). The 11-point fit's relative standard
error over these windows is 0.3-5.7 % (median 2.2 % with a0 = 0.8 mm, 1.0 % with 0.4 mm:
``single_fit_rel_se``). Against the rate: at equal lengths the single crack at 200/s is
45-96 % slower than at 1000/s. Checked: "unaffected" in that sense, the neighbours' effect
(0.133) is 0.29 of the smallest rate effect (0.45); not in the stricter sense: near the
join it is well above the fit's scatter. The two runs added for this (the three cracks
with a0 = 0.8 mm, the single crack with a0 = 0.4 mm) take about 6 s each, 8 % of full
mode.

Release and speed against c_R (2624 m/s). Growth instants are the interpolated crossings
of sigma_c (:mod:`efgkit.growth.release`); the crack length is the released node's x (the
end of the opened segment). Checked: the energy release (:mod:`efgkit.growth.cohesive`):
the released support softens and dissipates the fracture energy of the toughness the
criterion implies, ``G_c = 2 pi h sigma_c^2 / E'`` = 7.28 N/mm (h = 0.025 mm; physics, not
the seed, nothing fitted to its speeds). Measured: 200/s max 0.966 c_R, 1354 m/s at 2 mm
(the crack first creeps 0.25 mm in 3.9 us, then runs); 1000/s max 0.951 c_R, 2162 m/s at
2 mm; the model absorbs 0.97 of ``G_c da / 2`` (the last segments still soften); the
traction-free tip (``Released.free``, the crack tip of the cohesive model) trails the
released nodes: 1398 m/s at 2 mm and max 0.846 c_R at 200/s, 2109 m/s and 0.953 c_R at
1000/s (both checked). Side by
side, the seed's release at once (``cohesive=False``): the same initiation, 200/s 1758 m/s
at 2 mm (seed 1.9 km/s, checked within 20 %), max 0.951 c_R; 1000/s, overdriven, 1.00-1.03
c_R from 2 to 4 mm (max 1.031 c_R; 1.059 with instants on whole steps; half the step
1.026): docs/theory.md, "Nodal release", says why. Sensitivity (energy release): half the
step 0.952 c_R at 1000/s; half the fracture energy at 200/s: new cracks open ahead of the
tip (11) and the main tip is at 813 m/s at 2 mm; the grid twice as coarse doubles G_c (it
scales with h) and slows the 1000/s crack to 1421 m/s at 2 mm, at 200/s it starts at 14.1
us and has not run by 17 us.

Grids: ``nodes(f)`` scales the seed's spacings 0.025 / 0.05 / 0.1 / 0.2 mm by ``f``. Full
mode (2.5 to 10 minutes on the shared machine, with its load) runs the seed's grid
(``f = 1``, 10,324 nodes, 5-110 s per run) for both rates and both releases, and as sensitivity (not
checked) the other crack length, the grid twice as coarse, half the step and half the
fracture energy; quick mode ``f = 4`` (688 nodes) at 1000/s to 2.6 us.
EFG: linear basis, quartic weight, d_max = 2 (seed: smoothing length 1.5 spacings; d_max
is the support radius over the distance to the 2nd neighbour), quadrature on the Delaunay
triangles of the nodes (the graded cloud has no single cell size).
"""

from __future__ import annotations

import math
import time

import numpy as np
from _report import Report

from efgkit import EFG, Domain, Elastic, Linear, Scene, Support
from efgkit.growth.cohesive import criterion_energy
from efgkit.growth.release import LineRelease, run_release
from efgkit.growth.running_tip import speed_fit
from efgkit.problem.history import Stepping

NAME = "tungsten"
TITLE = "Tungsten plate: crack growth by nodal release at 200/s and 1000/s (seed 000 Sect. 5.2.1)"
US = 1e-6
W = 10.0  # quarter model width and height (mm)
A0 = 0.4  # initial half-length (mm) if the seed's 0.8 mm is the full length
A_SEED_READING = 0.8  # initial half-length (mm) if 0.8 mm is the quarter model's crack length
XC = 2.0  # centre of the side cracks of the three-crack plate (mm; the seed's Fig. 19 is missing)
MAT = Elastic(400e3, 0.29, "strain", rho=19300e-12)
SIGMA_C = 4500.0  # MPa
ZONES = ((0.0, 0.3, 0.025), (0.3, 0.8, 0.05), (0.8, 1.8, 0.1), (1.8, 10.0, 0.2))  # y0, y1, spacing
SEED = {"initiation_us": {200: 9.6, 1000: 2.0}, "speed_at_2mm_m_s": 1900.0, "c_R_m_s": 2624.1,
        "particles": 10324}


def nodes(f: float = 1.0) -> np.ndarray:
    """The zoned grid of the seed with spacings scaled by ``f``, shape (n, 2): each zone a
    uniform grid over the full width (``f = 1``: 10,324 nodes)."""
    pts = []
    for i, (y0, y1, h) in enumerate(ZONES):
        h = h * f
        ny = max(1, round((y1 - y0) / h))
        ys = np.linspace(y0, y1, ny + 1)[(0 if i == 0 else 1):]
        xs = np.linspace(0.0, W, max(1, round(W / h)) + 1)
        X, Y = np.meshgrid(xs, ys)
        pts.append(np.column_stack([X.ravel(), Y.ravel()]))
    return np.vstack(pts)


def scene(rate: float, duration: float) -> Scene:
    v0 = rate * W  # mm/s: the edge velocity of a nominal strain rate over the 2W plate
    dom = Domain.rectangle(0.0, 0.0, W, W)
    return Scene(dom, MAT, supports=(Support("left", ux=0.0), Support("top", uy=v0, history=Linear())),
                 duration=duration)


def run(rate: float, f: float, duration: float, a0: float = A0, max_length: float = 5.0,
        dt_factor: float = 1.0, cohesive: bool = True, energy_factor: float = 1.0) -> dict:
    """One run: strain ``rate`` (1/s), spacings scaled by ``f``, initial half-length ``a0``;
    ``dt_factor`` scales the default step (``Stepping().safety`` times the critical step of
    the system without the line's constraint); ``cohesive``: the released support softens
    and dissipates ``energy_factor`` times the fracture energy the criterion implies,
    ``G_c = 2 pi h sigma_c^2 / E'`` (:mod:`efgkit.growth.cohesive`); False: it vanishes at
    once (the seed's release)."""
    x = nodes(f)
    h = ZONES[0][2] * f
    gc = energy_factor * float(criterion_energy(SIGMA_C, h, MAT.E / (1 - MAT.nu**2))) if cohesive else 0.0
    m = EFG(spacing=ZONES[0][2] * f, coordinates=x, d_max=2.0, zones=(), enrichment="none",
            quadrature="triangles", bc="lagrange")
    st = Stepping(output_interval=0.05 * US, safety=dt_factor * Stepping().safety)
    t0 = time.perf_counter()
    r = run_release(scene(rate, duration), m, LineRelease(SIGMA_C, a0, fracture_energy=gc), st,
                    max_length=max_length)
    sec = time.perf_counter() - t0
    t, a, v = r.t / US, r.length, r.speed / 1e3  # us, mm, m/s
    grow = np.isfinite(v)
    at2 = float(np.interp(2.0, a[grow], v[grow])) if grow.sum() >= 2 and a[grow].max() >= 2.0 else math.nan
    new = r.releases["new_crack"].astype(bool) if len(r.releases["t"]) else np.zeros(0, bool)
    fa, fv = r.free["length"], r.free["speed"] / 1e3  # the traction-free tip
    fg = np.isfinite(fv)
    f2 = float(np.interp(2.0, fa[fg], fv[fg])) if fg.sum() >= 2 and fa[fg].max() >= 2.0 else math.nan
    return {"rate": rate, "f": f, "a0_mm": a0, "nodes": len(x), "h_line_mm": h,
            "release": "cohesive" if cohesive else "at once", "G_c_N_mm": gc,
            "dissipated_N": r.info["dissipated"],
            "t_us": t, "length_mm": a, "speed_m_s": v,
            "initiation_us": float(t[1]) if len(t) > 1 else math.nan,
            "speed_at_2mm_m_s": at2, "max_speed_m_s": float(np.nanmax(v)) if grow.any() else 0.0,
            "free_t_us": r.free["t"] / US, "free_length_mm": fa, "free_speed_m_s": fv,
            "free_speed_at_2mm_m_s": f2, "free_max_speed_m_s": float(np.nanmax(fv)) if fg.any() else 0.0,
            "releases": len(r.releases["t"]), "new_cracks": int(new.sum()),
            "new_crack_x_mm": r.releases["x"][new] if new.any() else np.zeros(0),
            "history_t_us": r.history["t"] / US, "history_length_mm": r.history["length"],
            "sigma1_max_MPa": r.history["sigma1_max"],
            "sigma1_peak_MPa": float(np.nanmax(r.history["sigma1_max"])),
            "stop": r.stop, "dt_us": r.info["dt"] / US, "steps": r.info["steps"], "seconds": sec,
            "timings": r.timings}


def three_cracks(rate: float, f: float, duration: float, cohesive: bool = True, a0: float = A0) -> dict:
    """Seed 000 Sect. 5.2.2: three cracks on the crack line, the central one of half-length
    ``a0`` (0.4 mm: 0.8 mm long; ``A_SEED_READING``: the single crack's 0.8 mm) and side
    cracks 0.8 mm long centred at +-XC, the quarter model holding the central crack's half
    and one side crack. Tip 1: the central crack's; tip 2: the side crack's inner tip; tip
    3: its outer tip. ``cohesive`` as :func:`run`. The central crack's length and speed
    (``central_*``, the released nodes as :func:`run`) hold until the cracks join, when the
    length jumps to tip 3."""
    x = nodes(f)
    gc = float(criterion_energy(SIGMA_C, ZONES[0][2] * f, MAT.E / (1 - MAT.nu**2))) if cohesive else 0.0
    m = EFG(spacing=ZONES[0][2] * f, coordinates=x, d_max=2.0, zones=(), enrichment="none",
            quadrature="triangles", bc="lagrange")
    t0 = time.perf_counter()
    r = run_release(scene(rate, duration), m,
                    LineRelease(SIGMA_C, a0, cracks=((XC - 0.4, XC + 0.4),), fracture_energy=gc),
                    Stepping(output_interval=0.05 * US), max_length=5.0)
    t, e = r.tips["t"] / US, r.tips["x"]
    start = {}
    for name, moved in (("tip 1", e[:, 0, 1] > e[0, 0, 1]), ("tip 2", e[:, 1, 0] < e[0, 1, 0]),
                        ("tip 3", e[:, 1, 1] > e[0, 1, 1])):
        start[name] = float(t[np.argmax(moved)]) if moved.any() else math.nan
    joined = np.flatnonzero(np.isclose(e[:, 0, 1], e[:, 1, 1]))
    return {"rate": rate, "f": f, "a0_mm": a0, "release": "cohesive" if cohesive else "at once",
            "start_us": start,
            "tip3_after_tip1_us": start["tip 3"] - start["tip 1"],
            "joined_us": float(t[joined[0]]) if len(joined) else math.nan,
            "t_us": t, "tips_mm": e, "central_t_us": r.t / US, "central_length_mm": r.length,
            "stop": r.stop, "dt_us": r.info["dt"] / US, "seconds": time.perf_counter() - t0}


def central_vs_single(x3: dict, x1: dict, slow: dict | None = None) -> dict:
    """The central crack of the three-crack run ``x3`` (:func:`three_cracks`) against the
    single crack ``x1`` (:func:`run`: same rate, a0, grid and settings) at the central
    crack's growth instants before the cracks join, within the single run's span: its
    speed (the 11-point least-squares fit over those points, :func:`speed_fit`) over the
    single crack's (its own fit, interpolated in time), its length over the single crack's
    at equal times, the instants at equal lengths, the gap tip 2 - tip 1; ``slow``: the
    single crack at another rate, its speed over ``x1``'s at equal lengths (the rate
    effect), where it has grown that far; ``single_fit_rel_se``: the standard error of the
    single crack's 11-point slope over the slope (min, median, max over the window)."""
    t3, a3 = x3["central_t_us"], x3["central_length_mm"]
    t1, a1, v1 = x1["t_us"][1:], x1["length_mm"][1:], x1["speed_m_s"][1:]
    pre = (t3 < x3["joined_us"]) if math.isfinite(x3["joined_us"]) else np.ones(len(t3), bool)
    pre[0] = False  # the initial length
    pre &= (t3 >= t1[0]) & (t3 <= t1[-1]) if len(t1) else False
    t, a = t3[pre], a3[pre]
    if len(t) < 2:
        return {"points": len(t), "max_rel_speed_diff": math.nan, "max_rel_length_diff": math.nan}
    v = speed_fit(t, a) * 1e3  # mm/us -> m/s
    dv = v / np.interp(t, t1, v1) - 1
    gap = x3["tips_mm"][np.searchsorted(x3["t_us"], t, side="right") - 1, 1, 0] - a
    off = np.flatnonzero(np.abs(dv) > 0.02)
    out = {"points": len(t), "t_us": [float(t[0]), float(t[-1])], "length_mm": [float(a[0]), float(a[-1])],
           "rel_speed_diff": dv, "gap_mm": gap, "max_rel_speed_diff": float(np.abs(dv).max()),
           "max_rel_length_diff": float(np.abs(a / np.interp(t, t1, a1) - 1).max()),
           "max_time_diff_us": float(np.abs(t - np.interp(a, a1, t1)).max()),
           "within_2pct_until_mm": float(a[off[0] - 1]) if len(off) and off[0] > 0 else
           (float(a[-1]) if not len(off) else math.nan),
           "gap_at_first_2pct_mm": float(gap[off[0]]) if len(off) else math.nan}
    # the fit's scatter: the standard error of the single crack's 11-point slope (the
    # windows of speed_fit) over its speed, at its points within the window's lengths
    n, k = len(t1), min(11, len(t1))
    idx = np.clip(np.arange(n) - 5, 0, n - k)[:, None] + np.arange(k)[None, :]
    Tc, Ac = t1[idx] - t1[idx].mean(1, keepdims=True), a1[idx] - a1[idx].mean(1, keepdims=True)
    slope = (Tc * Ac).sum(1) / (Tc**2).sum(1)
    se = np.sqrt(((Ac - slope[:, None] * Tc) ** 2).sum(1) / max(k - 2, 1) / (Tc**2).sum(1)) / slope
    inside = (a1 >= a[0] - 1e-9) & (a1 <= a[-1] + 1e-9)
    out["single_fit_rel_se"] = [float(se[inside].min()), float(np.median(se[inside])),
                                float(se[inside].max())] if inside.any() and k > 2 else [math.nan] * 3
    if slow is not None:
        as_, vs = slow["length_mm"][1:], slow["speed_m_s"][1:]
        far = a <= as_.max() if len(as_) >= 2 else np.zeros(len(a), bool)
        rate = np.abs(np.interp(a[far], as_, vs) / np.interp(a[far], a1, v1) - 1)
        out["rate_rel_speed_diff"] = [float(rate.min()), float(rate.max())] if far.any() else [math.nan] * 2
    return out


def _brief(r: dict) -> dict:
    keys = ("rate", "f", "a0_mm", "release", "G_c_N_mm", "nodes", "initiation_us", "speed_at_2mm_m_s",
            "max_speed_m_s",
            "releases", "new_cracks", "sigma1_peak_MPa", "stop", "dt_us", "seconds")
    return {k: r[k] for k in keys}


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    c_r = MAT.c_rayleigh / 1e3  # m/s
    arrival = W / MAT.c_dilatational / US  # the P wave from the pulled edge reaches the line
    if quick:
        runs = {1000: run(1000.0, 4.0, 2.6 * US, A_SEED_READING, max_length=1.6)}
        seed_runs = {}
    else:  # the energy release (checked) and the seed's release at once, side by side
        runs = {rate: run(float(rate), 1.0, dur * US, A_SEED_READING)
                for rate, dur in ((200, 17.0), (1000, 6.0))}
        seed_runs = {rate: run(float(rate), 1.0, dur * US, A_SEED_READING, cohesive=False)
                     for rate, dur in ((200, 14.0), (1000, 6.0))}
    sens = []
    if not quick:  # the other reading of the crack length, a grid twice as coarse, dt / 2,
        # half the fracture energy (rate, f, duration, a0, dt factor, energy factor)
        for rate, f, dur, a0, dtf, ef in ((200, 1.0, 16.0, 0.4, 1.0, 1.0),
                                          (200, 2.0, 17.0, A_SEED_READING, 1.0, 1.0),
                                          (1000, 2.0, 6.0, A_SEED_READING, 1.0, 1.0),
                                          (1000, 1.0, 6.0, A_SEED_READING, 0.5, 1.0),
                                          (200, 1.0, 17.0, A_SEED_READING, 1.0, 0.5)):
            r = run(float(rate), f, dur * US, a0, dt_factor=dtf, energy_factor=ef)
            sens.append({**_brief(r), "dt_factor": dtf, "energy_factor": ef})
    three = {} if quick else {
        f"{rate}{'' if coh else ' at once'}": three_cracks(float(rate), 1.0, dur * US, coh)
        for rate, dur, coh in ((200, 20.0, True), (1000, 5.0, True), (200, 18.0, False))}
    vs_single = {}
    if not quick:  # the central crack against the single crack at 1000/s, both readings of a0
        three["1000 a0=0.8"] = three_cracks(1000.0, 1.0, 6.0 * US, True, a0=A_SEED_READING)
        single_04 = run(1000.0, 1.0, 6.0 * US, A0)
        vs_single = {"0.8": central_vs_single(three["1000 a0=0.8"], runs[1000], slow=runs[200]),
                     "0.4": {**central_vs_single(three["1000"], single_04), "single": _brief(single_04)}}
    rep.metrics.update({"runs": {str(k): v for k, v in runs.items()},
                        "runs_at_once": {str(k): v for k, v in seed_runs.items()}, "sensitivity": sens,
                        "three_cracks": three, "three_cracks_vs_single": vs_single,
                        "c_R_m_s": c_r, "arrival_us": arrival, "plate_mm": [2 * W, 2 * W]})
    if not quick:
        rep.check("seed grid: particles (the zones over a 10 x 10 mm quarter; seed: 10,324)",
                  abs(runs[200]["nodes"] - SEED["particles"]), "<=", 0)
        # seed 9.6 us; measured 9.75 us (1.5 %) on the seed's grid, 14.1 us on the grid twice
        # as coarse: the stress at the node ahead grows like 1 / sqrt(spacing)
        rep.check("200/s: |initiation / 9.6 us - 1|", abs(runs[200]["initiation_us"] / 9.6 - 1), "<=", 0.05)
        rep.check("200/s: max LSQ speed / c_R", runs[200]["max_speed_m_s"] / c_r, "<=", 1.0)
        rep.check("200/s: max LSQ speed of the traction-free tip / c_R",
                  runs[200]["free_max_speed_m_s"] / c_r, "<=", 1.0)
        # the seed's release reproduces the seed's speed: measured 1758 m/s (-7.5 %); the
        # energy release's 1354 m/s (-29 %) is reported, not checked (module docstring)
        rep.check("seed's release, 200/s: |speed at 2 mm / 1.9 km/s - 1|",
                  abs(seed_runs[200]["speed_at_2mm_m_s"] / SEED["speed_at_2mm_m_s"] - 1), "<=", 0.2)
        for rate in (200, 1000):  # the model (half the body) dissipates G_c / 2 per unit of
            # new crack once the segments are free (cohesive.py), never more; the last few may
            # still soften: measured deficits 0.034 (200/s) and 0.026 (1000/s)
            x = runs[rate]
            deficit = 1 - x["dissipated_N"] / (0.5 * x["G_c_N_mm"] * (x["length_mm"][-1] - x["length_mm"][0]))
            rep.check(f"{rate}/s: 1 - dissipated / (G_c da / 2) (energy balance of the release)",
                      deficit, ">=", -1e-9)
            rep.check(f"{rate}/s: 1 - dissipated / (G_c da / 2) (segments still softening)",
                      deficit, "<=", 0.08)
        # three cracks at 200/s (seed Sect. 5.2.2: tip 3 starts 0.4 us after tip 1, tip 2 a
        # little later; not fitted): what is claimed is the order, tip 1 first; measured tip 2
        # +0.081 us and tip 3 +0.105 us after tip 1 (tip 2 before tip 3, against the seed)
        st = three["200"]["start_us"]
        rep.check("three cracks, 200/s: tip 2 starts after tip 1 (us; measured 0.081)",
                  st["tip 2"] - st["tip 1"], ">=", 0.027)
        rep.check("three cracks, 200/s: tip 3 starts after tip 1 (us; measured 0.105, seed 0.4)",
                  st["tip 3"] - st["tip 1"], ">=", 0.035)
        # 1000/s, the central crack (a0 = 0.8 mm, the single crack's) before the cracks join:
        # measured 0.133 (speeds within 0.6 % while the gap to tip 2 exceeds 0.5 mm, then the
        # central crack speeds up as the tips close: above the fit's relative standard error,
        # 0.4-5.7 %); "unaffected" is checked against the rate effect: at equal lengths the
        # single crack at 200/s is 45-96 % slower than at 1000/s (rate_rel_speed_diff)
        c = vs_single["0.8"]
        rep.check("three cracks, 1000/s: largest |central crack's speed / single crack's - 1| "
                  "before the join (seed: unaffected; measured 0.133)", c["max_rel_speed_diff"], "<=", 0.4)
        rep.check("three cracks, 1000/s: the same / the smallest rate effect (200/s against "
                  "1000/s single crack at equal lengths; measured 0.29)",
                  c["max_rel_speed_diff"] / c["rate_rel_speed_diff"][0], "<=", 0.9)
        rep.check("three cracks, 1000/s: largest |central crack's length / single crack's - 1| "
                  "at equal times before the join (measured 0.046)", c["max_rel_length_diff"], "<=", 0.14)
    r = runs[1000]
    # seed "about 2 us"; no release can precede the P wave's arrival at the line, 1.92 us;
    # measured 2.06 us (3 %) on the seed's grid, 2.4 us on the quick grid (0.1 mm)
    rep.check("1000/s: initiation after the P wave reaches the line (us)", r["initiation_us"] - arrival,
              ">=", 0.0)
    rep.check("1000/s: |initiation / 2 us - 1|", abs(r["initiation_us"] / 2.0 - 1), "<=",
              0.25 if quick else 0.1)
    rep.check("1000/s: max LSQ speed / c_R", r["max_speed_m_s"] / c_r, "<=", 1.0)
    rep.check("1000/s: max LSQ speed of the traction-free tip / c_R", r["free_max_speed_m_s"] / c_r,
              "<=", 1.0)
    rep.ref("c_R_m_s", SEED["c_R_m_s"], "seed 000 Sect. 5.2.1 Eqs. 5.9-5.10 (2624.1 m/s; efgkit "
            f"plane strain {c_r:.1f})")
    rep.ref("initiation_200_us", 9.6, "seed 000 Sect. 5.2.1 (text, Fig. 16)")
    rep.ref("initiation_1000_us", 2.0, "seed 000 Sect. 5.2.1: 'at about 2 us' (text, Fig. 16)")
    rep.ref("speed_at_2mm_200_m_s", 1900.0, "seed 000 Sect. 5.2.1: 1.9 km/s at crack length 2 mm, "
            "200/s (Fig. 18; Batra and Love's FEM the same)")
    rep.ref("arrival_us", arrival, "closed form: W / c_d, the P wave from the pulled edge to the line")
    return rep.write(out_dir)


def _f(v, fmt: str) -> str:
    """A number formatted, '-' for what is not one (NaN is written as a string)."""
    return format(v, fmt) if isinstance(v, (int, float)) and math.isfinite(v) else "-"


def markdown(r: dict) -> list[str]:
    m = r["metrics"]
    out = [f"Quarter model 10 x 10 mm (plate {m['plate_mm'][0]:g} x {m['plate_mm'][1]:g} mm, the seed "
           "omits its dimensions: module docstring), crack half-length a0 = 0.8 mm, "
           "principal-stress criterion 4.5 GPa at the bonded nodes of the symmetry line, "
           "nodal release (efgkit.growth.release), top edge pulled at v0 = rate x 10 mm. Release: "
           "'energy' (checked) softens the released support and dissipates the fracture energy "
           "the criterion implies, G_c = 2 pi h sigma_c^2 / E' (efgkit.growth.cohesive); 'at once' "
           "is the seed's.", "",
           "| rate (1/s) | release | nodes | initiation (us) | seed | speed at 2 mm (m/s) | seed | "
           "max speed / c_R | traction-free tip: speed at 2 mm (m/s) | max / c_R | releases | "
           "new cracks | run (s) |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for rel, runs in (("energy", m["runs"]), ("at once", m.get("runs_at_once", {}))):
        for k, x in runs.items():
            out.append(f"| {k} | {rel} | {x['nodes']} | {_f(x['initiation_us'], '.2f')} | "
                       f"{SEED['initiation_us'][int(k)]:g} | {_f(x['speed_at_2mm_m_s'], '.0f')} | "
                       f"{'1900' if k == '200' else '-'} | {x['max_speed_m_s'] / m['c_R_m_s']:.3f} | "
                       f"{_f(x.get('free_speed_at_2mm_m_s'), '.0f')} | "
                       f"{_f(x.get('free_max_speed_m_s', math.nan) / m['c_R_m_s'], '.3f')} | "
                       f"{x['releases']} | {x['new_cracks']} | {x['seconds']:.0f} |")
    if m.get("sensitivity"):
        out += ["", "Sensitivity (energy release, not checked):", "",
                "| rate | spacing factor | a0 (mm) | dt factor | G_c (N/mm) | initiation (us) | "
                "speed at 2 mm (m/s) | max speed / c_R | new cracks | peak sigma_1 on the line (MPa) |",
                "|---|---|---|---|---|---|---|---|---|---|"]
        out += [f"| {s['rate']:g} | {s['f']:g} | {s['a0_mm']:g} | {s['dt_factor']:g} | "
                f"{s['G_c_N_mm']:.2f} | {_f(s['initiation_us'], '.2f')} | "
                f"{_f(s['speed_at_2mm_m_s'], '.0f')} | "
                f"{s['max_speed_m_s'] / m['c_R_m_s']:.3f} | {s['new_cracks']} | {s['sigma1_peak_MPa']:.0f} |"
                for s in m["sensitivity"]]
    if m.get("three_cracks"):
        out += ["", "Three cracks (seed 000 Sect. 5.2.2): side cracks 0.8 mm long centred at "
                f"+-{XC:g} mm (our choice: the seed's Fig. 19 is missing), seed's grid; the central "
                "crack 0.8 mm long (a0 = 0.4 mm) or, at 1000/s, also 1.6 mm (a0 = 0.8 mm, the single "
                "crack's). Tip 1 is the central crack's, tips 2 and 3 the side crack's inner and "
                "outer tips. Checked at 200/s: tips 2 and 3 start after tip 1 (the seed's 0.4 us "
                "is not fitted).", "",
                "| rate (1/s) | release | a0 (mm) | tip 1 starts (us) | tip 2 (us) | tip 3 (us) | "
                "tip 3 - tip 1 (us) | seed | cracks join (us) |", "|---|---|---|---|---|---|---|---|---|"]
        for x in m["three_cracks"].values():
            st = x["start_us"]
            out.append(f"| {x['rate']:g} | {x.get('release', 'at once')} | {x.get('a0_mm', A0):g} | "
                       f"{_f(st['tip 1'], '.2f')} | "
                       f"{_f(st['tip 2'], '.2f')} | {_f(st['tip 3'], '.2f')} | "
                       f"{_f(x['tip3_after_tip1_us'], '.2f')} | "
                       f"{'0.4 (tip 2 a little later)' if x['rate'] == 200 else 'simultaneous'} | "
                       f"{_f(x['joined_us'], '.2f')} |")
    if m.get("three_cracks_vs_single"):
        out += ["", "Central crack of the three against the single crack at 1000/s (same a0, grid and "
                "settings), at its growth instants before the cracks join (seed: 'at high rates the "
                "central crack's speed is unaffected by the others'). Speeds: 11-point least-squares "
                "fits; 'within 2 % until': the central crack's length up to which the speeds agree "
                "within 2 %, and the gap tip 2 - tip 1 when they first differ by more; fit's standard "
                "error: of the single crack's 11-point slope over the slope; rate effect: "
                "|v(200/s) / v(1000/s) - 1| of the single crack at equal lengths.", "",
                "| a0 (mm) | points | window (us) | lengths (mm) | max speed difference | "
                "max length difference (equal times) | max instant shift (us) | within 2 % until (mm) | "
                "gap then (mm) | fit's relative standard error (min-max) | rate effect |",
                "|---|---|---|---|---|---|---|---|---|---|---|"]
        for k, c in m["three_cracks_vs_single"].items():
            rate = c.get("rate_rel_speed_diff")
            out.append(f"| {k} | {c['points']} | {c['t_us'][0]:.2f}-{c['t_us'][1]:.2f} | "
                       f"{c['length_mm'][0]:.3f}-{c['length_mm'][1]:.3f} | "
                       f"{_f(c['max_rel_speed_diff'], '.1%')} | {_f(c['max_rel_length_diff'], '.1%')} | "
                       f"{_f(c['max_time_diff_us'], '.3f')} | {_f(c['within_2pct_until_mm'], '.3f')} | "
                       f"{_f(c['gap_at_first_2pct_mm'], '.2f')} | "
                       f"{_f(c['single_fit_rel_se'][0], '.1%')}-{_f(c['single_fit_rel_se'][2], '.1%')} | "
                       f"{_f(rate[0], '.0%') + '-' + _f(rate[1], '.0%') if rate else '-'} |")
    return out
