"""The functionally graded single-edge-notch plate of seed 000 Sect. 5.2.3 (after Shukla
and Jain): a crack grows along the gradient under impact, nodal release when the dynamic
SIF at the next node reaches twice the static toughness there.

Seed data: ``rho(x) = 1200 e^{-1.52 x}`` kg/m^3, ``mu(x) = 1.345 e^{1.76 x}`` GPa,
``K_Ic(x) = 2.18 x + 0.71`` MPa m^1/2, nu = 0.34, an edge crack a = 0.125 W on the left
edge, the top and bottom edges pulled apart at 2.1 m/s each, half model (symmetry about
the crack line), 360 particles across x near the tip; "a particle fails when the DSIF there
equals twice the SSIF". Seed results: the crack starts at about 90 us and runs at 822 m/s
(the slope of a least-squares line through its length history), against 600-700 m/s
measured by Shukla and Jain.

Choices where the seed is silent (the units of x, the plate's size, Fig. 22 is missing):

* x in metres (``XU``): the seed states every other quantity in SI units (kg/m^3, GPa, MPa
  m^1/2), and over a 0.1 m plate the properties stay those of one polymer family: rho
  1200 -> 1031 kg/m^3, mu 1.345 -> 1.60 GPa, K_Ic 0.71 -> 0.93 MPa m^1/2, the local c_R 974
  -> 1148 m/s. The reading of the previous version, x in units of W, makes rho fall to 262
  kg/m^3 at the far edge (lighter than any solid polymer) while mu grows 5.8-fold; it is
  kept as a variant (full mode). The choice was made on these grounds, and it also brings
  the mean speed to the seed's (below);
* W = 100 mm and a square plate (height 100 mm: the half model 100 x 50 mm); plane stress
  (thin photoelastic plates). No public source found states the specimen's size (a search
  for Shukla and Jain's and Rousseau and Tippur's specimens); the plate's height sets the
  start (below);
* the DSIF at a node: ``K = sigma_1 sqrt(2 pi r)`` with sigma_1 at the node next to the tip
  and r its distance to the tip (seed 000 Eq. 5.4, sigma_22 on theta = 0, where sigma_1 =
  sigma_22 on the symmetry line in mode I), so the criterion is the position-dependent
  critical stress ``sigma_c(x) = 2 K_Ic(x) / sqrt(2 pi h)`` of
  :class:`~efgkit.growth.release.LineRelease` (h the line's node spacing);
* the release: the released support softens and dissipates ``G_c(x) = (2 K_Ic(x))^2 /
  E(x)``, the energy of the toughness the criterion fires at (:mod:`efgkit.growth.cohesive`);
  the seed's release at once and ``G_c = K_Ic^2 / E`` are variants;
* E(x) = 2 mu(x) (1 + nu); the grading of :mod:`efgkit.problem.graded`.

Results (full mode, 5,664 nodes, ``verification/out/fgm_plate.json``): the crack starts at
37.4 us (seed about 90 us) and runs at a least-squares mean of 813 m/s (seed 822 m/s,
experiment 600-700 m/s), accelerating from about 230 m/s to 0.96-0.98 local c_R over the
last third of the plate. The traction-free tip (``Released.free``, the crack tip of the
cohesive model; :mod:`efgkit.growth.cohesive`) stays below 0.956 local c_R (checked); the
11-point fit of the released nodes (the front of the cohesive zone, the seed's measure)
fluctuates by +-4 % and reaches 1.019 local c_R at 66 mm (not checked; docs/theory.md,
"Nodal release"). Variants (not checked): the seed's release, the same start, 975 m/s, 1.054
c_R; ``G_c = K_Ic^2 / E`` (a quarter of the criterion's energy), 907 m/s, tip 1.007 c_R; x in
units of W, 1285 m/s (1589 released at once); the finest band 8 mm thick instead of 2, the
same speeds (tip 0.996 c_R: the margin is small in this overdriven plate). The start is set
by the plate's height, not by the release: the P wave from the pulled edge reaches the
crack at H / c_d(0) = 27 us (H = 50 mm) and the crack starts 10 us later; plates 100 x 200
and 100 x 300 mm start at 62.7 and 88.9 us (arrivals 54 and 81 us; the seed's "about 90
us") and run at 700 and 639 m/s (the experiment's range), below 0.98 and 0.89 local c_R.
Those variants were run after the seed's start time was known: they show what sets the
start, they do not fix the plate.

Grid: zones over the crack line like the tungsten plate's (``tungsten.py``): spacings h0,
2 h0, 4 h0, 8 h0 in bands 0-2, 2-6, 6-16, 16-50 mm, h0 = W / 360 (the seed's 360 particles
across x) scaled by f (full mode f = 1, quick f = 8). Units mm, MPa, tonne/mm^3, s.
"""

from __future__ import annotations

import math
import time

import numpy as np
from _report import Report

from efgkit import EFG, Domain, Elastic, Linear, Scene, Support
from efgkit.growth.release import LineRelease, run_release
from efgkit.problem.expression import Expression
from efgkit.problem.graded import Grading
from efgkit.problem.history import Stepping

NAME = "fgm_plate"
TITLE = "Functionally graded edge-notch plate under impact (seed 000 Sect. 5.2.3)"
US = 1e-6
W, H = 100.0, 50.0  # plate width, half height (mm)
A = 0.125 * W
NU = 0.34
MU0, RHO0 = 1345.0, 1200e-12  # MPa, tonne/mm^3 at x = 0
V0 = 2100.0  # mm/s: 2.1 m/s
H0 = W / 360
XU = 1000.0  # mm per unit of the seed's x: metres (module docstring)
BANDS = ((0.0, 2.0, 1), (2.0, 6.0, 2), (6.0, 16.0, 4), (16.0, H, 8))  # y0, y1, spacing / h0
SQRT_M = math.sqrt(1000.0)  # MPa m^1/2 -> MPa mm^1/2
SEED = {"initiation_us": 90.0, "speed_m_s": 822.0, "measured_m_s": (600.0, 700.0)}


def material() -> Elastic:
    return Elastic(2 * MU0 * (1 + NU), NU, "stress", rho=RHO0)


def grading(xu: float = XU) -> Grading:
    """The seed's mu(x) / mu(0) and rho(x) / rho(0), x in units of ``xu`` mm."""
    return Grading(modulus=Expression(f"exp(1.76 * x / {xu})"), density=Expression(f"exp(-1.52 * x / {xu})"))


def toughness(x: np.ndarray, xu: float = XU) -> np.ndarray:
    """K_Ic at points (n, 2) in MPa mm^1/2 (seed: 2.18 x + 0.71 MPa m^1/2, x in units of
    ``xu`` mm)."""
    return (2.18 * x[:, 0] / xu + 0.71) * SQRT_M


def fracture_energy(x: np.ndarray, xu: float = XU) -> np.ndarray:
    """The material's fracture energy G_c = K_Ic(x)^2 / E(x) (plane stress), N/mm."""
    return toughness(x, xu) ** 2 / (material().E * np.exp(1.76 * x[:, 0] / xu))


def nodes(f: float, half_height: float = H, bands: tuple = BANDS) -> np.ndarray:
    pts = []
    for i, (y0, y1, k) in enumerate(bands[:-1] + ((bands[-1][0], half_height, bands[-1][2]),)):
        h = H0 * k * f
        ys = np.linspace(y0, y1, max(1, round((y1 - y0) / h)) + 1)[(0 if i == 0 else 1):]
        xs = np.linspace(0.0, W, max(1, round(W / h)) + 1)
        X, Y = np.meshgrid(xs, ys)
        pts.append(np.column_stack([X.ravel(), Y.ravel()]))
    return np.vstack(pts)


def c_rayleigh(x: np.ndarray, xu: float = XU) -> np.ndarray:
    """The local Rayleigh speed (m/s) at x (mm): c_R(0) sqrt(mu(x) / rho(x) / (mu0 / rho0))."""
    return material().c_rayleigh / 1e3 * np.exp(0.5 * (1.76 + 1.52) * np.asarray(x) / xu)


def run(f: float, duration: float, cohesive: bool = True, xu: float = XU, energy_factor: float = 4.0,
        half_height: float = H, bands: tuple = BANDS) -> dict:
    """One run on the grid scaled by ``f``, x of the seed's formulas in units of ``xu`` mm;
    ``cohesive``: the released support softens and dissipates ``energy_factor`` times the
    static fracture energy ``K_Ic(x)^2 / E(x)`` (:mod:`efgkit.growth.cohesive`; 4: the energy
    ``(2 K_Ic)^2 / E`` of the seed's criterion); False: it vanishes at once (the seed's
    release); ``half_height``: the half model's height (mm); ``bands``: the node zones."""
    x = nodes(f, half_height, bands)
    h = H0 * f
    m = EFG(spacing=h, coordinates=x, d_max=2.0, zones=(), enrichment="none",
            quadrature="triangles", bc="lagrange")
    sc = Scene(Domain.rectangle(0.0, 0.0, W, half_height), material(), grading=grading(xu), duration=duration,
               supports=(Support("top", uy=V0, history=Linear()),))

    def sigma_c(p):
        return 2 * toughness(p, xu) / math.sqrt(2 * math.pi * h)

    def g_c(p):
        return energy_factor * fracture_energy(p, xu)

    rule = LineRelease(sigma_c, A, fracture_energy=g_c if cohesive else 0.0)
    t0 = time.perf_counter()
    r = run_release(sc, m, rule, Stepping(output_interval=1.0 * US), max_length=0.95 * W)
    t, a, v = r.t / US, r.length, r.speed / 1e3
    grow = np.isfinite(v)
    fit = float(np.polyfit(t[grow], a[grow], 1)[0] * 1e3) if grow.sum() >= 2 else math.nan  # mm/us -> m/s
    over = v[grow] / c_rayleigh(a[grow], xu) if grow.any() else np.zeros(0)
    fr = r.free  # the traction-free crack (the tip of the cohesive model)
    fg = np.isfinite(fr["speed"])
    f_over = fr["speed"][fg] / 1e3 / c_rayleigh(fr["length"][fg], xu) if fg.any() else np.zeros(0)
    return {"f": f, "nodes": len(x), "h_mm": h, "x_unit_mm": xu,
            "release": "cohesive" if cohesive else "at once",
            "energy_factor": energy_factor if cohesive else 0.0, "half_height_mm": half_height,
            "t_us": t, "length_mm": a, "speed_m_s": v,
            "initiation_us": float(t[1]) if len(t) > 1 else math.nan,
            "mean_speed_m_s": fit, "max_speed_over_local_c_R": float(over.max()) if len(over) else 0.0,
            "max_speed_m_s": float(v[grow].max()) if grow.any() else 0.0,
            "releases": len(r.releases["t"]), "new_cracks": int(r.releases["new_crack"].sum()),
            "new_crack_x_mm": r.releases["x"][r.releases["new_crack"].astype(bool)],
            "new_crack_t_us": r.releases["t"][r.releases["new_crack"].astype(bool)] / US,
            "at_max_mm": float(a[grow][np.argmax(over)]) if len(over) else math.nan,
            "history_t_us": r.history["t"] / US,
            "ratio_max": r.history["ratio_max"], "ratio_ahead": r.history["ratio_ahead"],
            "stop": r.stop, "dt_us": r.info["dt"] / US,
            "free_t_us": fr["t"] / US, "free_length_mm": fr["length"], "free_speed_m_s": fr["speed"] / 1e3,
            "free_max_speed_over_local_c_R": float(f_over.max()) if len(f_over) else 0.0,
            "free_mean_speed_m_s": float(np.polyfit(fr["t"][fg], fr["length"][fg], 1)[0] / 1e3)
            if fg.sum() >= 2 else math.nan,
            "dissipated_N": r.info["dissipated"], "seconds": time.perf_counter() - t0}


VARIANTS = (  # label, run() keywords (full mode, not checked)
    ("seed's release (at once)", {"cohesive": False}),
    ("G_c = K_Ic^2 / E (static toughness)", {"energy_factor": 1.0}),
    ("x in units of W", {"xu": W}),
    ("x in units of W, seed's release", {"xu": W, "cohesive": False}),
    ("finest band 8 mm thick", {"bands": ((0.0, 8.0, 1), (8.0, 16.0, 2), (16.0, 30.0, 4), (30.0, H, 8))}),
    ("plate 100 x 200 mm", {"half_height": 100.0, "duration": 300 * US}),
    ("plate 100 x 300 mm", {"half_height": 150.0, "duration": 350 * US}),
)


def _brief(r: dict) -> dict:
    """The numbers of a run without its histories (the variants' record)."""
    return {k: v for k, v in r.items() if not isinstance(v, np.ndarray) or k.startswith("new_crack")}


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    r = run(8.0, 150 * US) if quick else run(1.0, 250 * US)
    var = [] if quick else [{"label": lab, **_brief(run(1.0, kw.pop("duration", 250 * US), **kw))}
                            for lab, kw in ((lab, dict(kw)) for lab, kw in VARIANTS)]
    rep.metrics.update({"run": r, "variants": var, "plate_mm": [W, 2 * H], "a_mm": A,
                        "c_R0_m_s": float(c_rayleigh(0.0))})
    arrival = H / material().c_dilatational / US  # us: the P wave at x = 0, the slowest
    rep.check("initiation after the P wave from the pulled edge reaches the crack (us)",
              r["initiation_us"] - arrival, ">=", 0.0)
    rep.check("the crack runs: releases", r["releases"], ">=", 10)
    if not quick:  # on the quick grid (2.2 mm on the line) the speed means little
        # the crack tip of the cohesive model, where the traction vanishes; measured 0.956. The
        # release front (the nodes' release instants, the seed's measure) reaches 1.019 local
        # c_R: reported, not checked (module docstring)
        rep.check("max LSQ speed of the traction-free tip / local c_R", r["free_max_speed_over_local_c_R"],
                  "<=", 1.0)
    rep.ref("initiation_us", SEED["initiation_us"], "seed 000 Sect. 5.2.3 (Fig. 23): about 90 us")
    rep.ref("speed_m_s", SEED["speed_m_s"], "seed 000 Sect. 5.2.3: 822 m/s (LSQ slope of Fig. 23)")
    rep.ref("measured_m_s", list(SEED["measured_m_s"]), "Shukla and Jain, as quoted by seed 000 Sect. 5.2.3")
    rep.ref("arrival_us", arrival, "closed form: H / c_d(x = 0) (the slowest P wave)")
    return rep.write(out_dir)


def _f(v, fmt: str) -> str:
    return format(v, fmt) if isinstance(v, (int, float)) and math.isfinite(v) else "-"


def markdown(r: dict) -> list[str]:
    x = r["metrics"]["run"]

    def row(label, v):
        return (f"| {label} | {_f(v['initiation_us'], '.1f')} | {_f(v['mean_speed_m_s'], '.0f')} | "
                f"{_f(v['max_speed_over_local_c_R'], '.3f')} | {_f(v.get('free_mean_speed_m_s'), '.0f')} | "
                f"{_f(v.get('free_max_speed_over_local_c_R'), '.3f')} | {v['releases']} | "
                f"{v.get('new_cracks', '-')} | {v['stop']} |")

    return [f"Plate {W:g} x {2 * H:g} mm (half model; our choice, module docstring), a = {A:g} mm, "
            f"x of the seed's formulas in metres, plane stress, {x['nodes']} nodes (line spacing "
            f"{x['h_mm']:.3f} mm), top pulled at 2.1 m/s, release when sigma_1 sqrt(2 pi h) at the "
            "node next to the tip reaches 2 K_Ic(x); the released support softens and dissipates "
            "G_c = (2 K_Ic)^2 / E (efgkit.growth.cohesive).", "",
            "| | initiation (us) | mean speed (m/s, LSQ over the history) | max speed / local c_R "
            "| traction-free tip: mean speed (m/s) | max / local c_R | releases | new cracks | stop |",
            "|---|---|---|---|---|---|---|---|---|",
            row("efgkit", x), *(row(f"efgkit, {v['label']}", v) for v in r["metrics"].get("variants", [])),
            "| seed 000 (MSPH) | about 90 | 822 | - | - | - | - | - | - |",
            "| Shukla and Jain (experiment) | - | 600-700 | - | - | - | - | - | - |"]
