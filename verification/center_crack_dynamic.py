"""Centre-cracked plate under step tension and step shear: dynamic K(t) (seed 002 Sect. 4.1,
seed 000 Sect. 5.1).

Plate 104 x 40 mm (seed 000: 2 x 52 by 2 x 20 mm) with a central crack of half-length
``a0 = 12 mm``, Heaviside tractions on the top and bottom edges: tension ``sigma0`` (mode I,
E = 75.6 GPa, nu = 0.286) or shear ``tau0`` (mode II, E = 73.5 GPa, nu = 0.25), both
rho = 2450 kg/m^3, ``sigma0 = tau0 = 0.1 MPa``, plane strain (seed 002 Table 1; seed 000:
mu = 29.4 GPa, the same mode-I material). Units: mm, N, MPa, tonne/mm^3, s (E = 75600 MPa,
rho = 2.45e-9 tonne/mm^3, speeds in mm/s). No supports: the tensile load is
self-equilibrated; the shear one carries a couple, which turns the plate slowly as a rigid
body (a rotation does not enter K).

Discretisation (seed 002): 105 x 42 regular nodes (spacing 1 mm in x, 40/41 mm in y, so no
node lies on the crack line), support radius ``r_I = 2.5 dx`` (``d_max = 2.5``), no tip
enrichment and no refinement zones (the seed's grid), diffraction rule, 4 x 4 Gauss points
on 1 mm cells, ``dt = 0.1 us``. Full mode adds a grid twice as fine (209 x 83, dt = 0.05 us).
The MLPG test radius ``r_s = 1.1 dx`` and the seed's 8 x 8 area / 16 line points of its
J' quadrature belong to MLPG (its rows come when MLPG is merged); EFG integrates J' over
its own Gauss points in discs of radii ``R = 2, 2.5, 3, 3.5, 4 mm`` (the seed's path
radius 3 mm in the middle), with the crack-face terms.

Reported: ``K / (sigma0 sqrt(pi a0))`` against time (J', interaction with inertia,
near-tip stresses at 0 and 90 degrees, mean of both tips), its peaks, the instant the tip
first feels the load against the P-wave travel time ``20 mm / c_d`` = 3.16 us (c_d = 6327
m/s): that is the physical arrival. Seed 000's "about 2.5 us" matches what a meshless
model shows instead: a small precursor ahead of the front (supports of several spacings,
coupled within one explicit step) makes K non-zero before 3.16 us, at 2.6 us on the
seed's grid and 2.8 us at 0.5 mm (full record), moving towards 3.16 us as the grid is
refined. Also the path dependence of J' over the
radii (metric ``path_dependence``, ``max_r J'(R) - min_r J'(R)`` over ``|J'(3 mm)|``, largest
over the instants where K is above a quarter of its peak; target 1 %; seed 002: 2.4 % and
1.8 %). Early-time check, mode I: the step waves from the top and bottom edges (``sigma_yy =
sigma0`` behind each front) meet on the crack plane at ``t_a = 20 mm / c_d``, where the
uncracked stress doubles to ``2 sigma0``; by superposition the crack then sees a suddenly
applied face pressure ``2 sigma0``, and until waves from the other tip (``2 a0 / c_d``
after ``t_a``) or from the plate's corners (44.7 mm from the tip: 7.07 us) arrive, Freund's
semi-infinite crack holds: ``K_I = 4 sigma0 sqrt(c_d (t - t_a) (1 - 2 nu) / pi) / (1 - nu)``.
Checked over the second half of that window.

Full mode also runs the seed's grid with PU crack-tip enrichment (``efg_pu``; nodes within
two spacings of a tip, their enrichment unknowns lumped by the absolute row sum so the
stable step stays that of the plain grid, 16 Jacobi steps of the acceleration recovery,
which then move the enrichment unknowns too: the settings that bring the path dependence
within 1 % on that grid, docs/theory.md), records the static floor of the path
dependence (:func:`static_path_dependence`, plain and PU) and compares the near-tip
estimates with ``K`` from ``J'`` (``near_tip_vs_J``): the seed's mean of the two points
nearest the tip (``stress_0``) and the line fitted on ``r = h..4h`` and extrapolated to the
tip (``stress_0_fit``, :mod:`efgkit.explicit.near_tip`).

Full mode also runs what users get by default at the seed's spacing (``efg_default``,
:data:`DEFAULT_ROWS`): ``EFG(spacing=1 mm)`` with every other setting at its default (its own
105 x 41 grid, the automatic tip zones h/2 within 6 h and h/4 within 3 h, PU enrichment of
the nodes whose support comes within h of a tip, d_max 2, the diagonal enrichment mass of
``dynamics``, the 4 Jacobi steps of ``DynamicDSIF`` and the default step, 0.9 of the
critical one), and the same on the seed's 105 x 42 nodes (``efg_default_seed_grid``: user
coordinates, so no zones); the same J' radii; and one factor off the defaults, the
abs-row-sum enrichment mass (``efg_default_abs_row_sum``), which sets the critical step.

Full mode also runs the slanted crack of seed 002 Sect. 4.2 (:func:`run_slanted`; mixed
mode, E = 75.6 GPa, nu = 0.286, dt = 0.1 us, 20 us): the path dependence of J'_1 and J'_2
(seed: 0.6 % and 3.1 %) and the K_I, K_II histories of every estimate, among them
``J_decomposed`` (K_I, K_II from J'_1 of the symmetric and antisymmetric parts of the field,
:mod:`efgkit.fracture.decomposition`, which needs no J'_2), on the seed's 45 x 33 nodes and
on 89 x 65 (0.5 mm, dt = 0.05 us). Its J' discs are R = 6-12 mm with the near-tip face W of
J'_2 from the fitted face displacement and the plateau q (:mod:`efgkit.fracture.face_fit`,
``DynamicDSIF(q="plateau_fit")``); the raw face W, no face term and the seed's radii
(2-4 mm, Wendland q) run beside them on the same states (:data:`SLANT_HOOKS`).
"""

from __future__ import annotations

import math
import time

import numpy as np
from _report import Report

from efgkit import EFG, Crack, Domain, Elastic, Scene, Traction
from efgkit.explicit import DynamicDSIF, dynamics, integrate, stable_step
from efgkit.problem.history import Heaviside, Stepping

NAME = "center_crack_dynamic"
TITLE = "Centre-cracked plate under step tension and shear: dynamic K(t) (seed 002 Sect. 4.1)"
HALF_W, HALF_H, A0, LOAD = 52.0, 20.0, 12.0, 0.1  # mm, mm, mm, MPa
RHO = 2450e-12  # tonne/mm^3 (2450 kg/m^3)
CASES = {"mode_I": (Elastic(75600.0, 0.286, "strain", rho=RHO), (0.0, LOAD)),
         "mode_II": (Elastic(73500.0, 0.25, "strain", rho=RHO), (LOAD, 0.0))}
RADII = (2.0, 2.5, 3.0, 3.5, 4.0)  # mm; the seed's path radius 3 mm in the middle
US = 1e-6  # s
TARGET = 0.01  # issue [dynamics]: path dependence within 1 %
ESTIMATES = ("J", "interaction", "stress_0", "stress_0_fit", "stress_90")
SLANT_ESTIMATES = ESTIMATES + ("J_decomposed",)  # the slanted crack: also the decomposition


def grid(nx: int, ny: int) -> np.ndarray:
    """Regular nodes (nx * ny, 2) over the plate, row by row."""
    X, Y = np.meshgrid(np.linspace(-HALF_W, HALF_W, nx), np.linspace(-HALF_H, HALF_H, ny))
    return np.column_stack([X.ravel(), Y.ravel()])


# discretisations: name -> (nx, ny) -> method (MLPG: one more entry); "efg_pu": the same
# grid with PU crack-tip enrichment (nodes within 2 spacings of a tip), whose enrichment
# unknowns take the absolute row sum of the consistent mass (the unenriched stable step)
METHODS = {"efg": lambda nx, ny: EFG(spacing=2 * HALF_W / (nx - 1), coordinates=grid(nx, ny),
                                     d_max=2.5, zones=(), enrichment="none"),
           "efg_pu": lambda nx, ny: EFG(spacing=2 * HALF_W / (nx - 1), coordinates=grid(nx, ny),
                                        d_max=2.5, zones=(), enrichment="pu"),
           # what users get: EFG(spacing=h) alone (its own grid, the automatic tip zones and
           # enrichment, d_max 2), and the same on the seed's nodes (coordinates: no zones)
           "efg_default": lambda nx, ny: EFG(spacing=2 * HALF_W / (nx - 1)),
           "efg_default_seed_grid": lambda nx, ny: EFG(spacing=2 * HALF_W / (nx - 1),
                                                       coordinates=grid(nx, ny)),
           # one factor off the defaults: the enrichment mass (the critical step)
           "efg_default_abs_row_sum": lambda nx, ny: EFG(spacing=2 * HALF_W / (nx - 1))}
ENRICHMENT_MASS = {"efg_pu": "abs_row_sum", "efg_default_abs_row_sum": "abs_row_sum"}
# Jacobi steps of the acceleration recovery (DynamicDSIF.mass_iterations): with the
# abs-row-sum mass the enrichment unknowns take them too; 16 (4 in mode I: 1.31 %)
MASS_ITERATIONS = {"efg_pu": 16}
# every other setting at its default too: dynamics() enrichment mass, DynamicDSIF()
# mass_iterations, Stepping() step (safety x the critical step)
DEFAULT_ROWS = ("efg_default", "efg_default_seed_grid")
STEP_RULE = (*DEFAULT_ROWS, "efg_default_abs_row_sum")  # dt: 0.9 of the critical step
SEED_GRID_ONLY = ("efg_pu", *STEP_RULE)  # full mode: at the seed's 1 mm spacing only


def scene(case: str, duration: float) -> Scene:
    mat, t = CASES[case]
    return Scene(Domain.rectangle(-HALF_W, -HALF_H, HALF_W, HALF_H), mat, name=case,
                 cracks=(Crack([[-A0, 0.0], [A0, 0.0]]),), duration=duration,
                 tractions=(Traction("top", t, history=Heaviside()),
                            Traction("bottom", (-t[0], -t[1]), history=Heaviside())))


def freund_k(t: np.ndarray, mat: Elastic) -> np.ndarray:
    """K_I of the two plane step waves striking the crack (module docstring), (n,)."""
    ta = HALF_H / mat.c_dilatational
    return 4 * LOAD * np.sqrt(mat.c_dilatational * np.clip(t - ta, 0, None) * (1 - 2 * mat.nu)
                              / math.pi) / (1 - mat.nu)


def run(case: str, method: str, nx: int, ny: int, dt: float, duration: float,
        every: float, radii=RADII) -> dict:
    """One run; ``radii`` of the J' discs (mm), the path dependence against the middle one;
    ``dt`` None: the default step rule (``Stepping``); :data:`DEFAULT_ROWS`: the defaults of
    ``dynamics`` and ``DynamicDSIF`` (no keyword given)."""
    sc = scene(case, duration)
    m = METHODS[method](nx, ny)
    t0 = time.perf_counter()
    default = method in DEFAULT_ROWS
    dyn = dynamics(sc, m) if default else dynamics(
        sc, m, enrichment_mass=ENRICHMENT_MASS.get(method, "diagonal"))
    dtc, lam = stable_step(dyn)
    hook = DynamicDSIF(radii=radii, domains=True) if default else DynamicDSIF(  # inertia with
        radii=radii, domains=True, mass_iterations=MASS_ITERATIONS.get(method, 4))  # recovered a
    lumped, lumped_J = DynamicDSIF(radii=radii, domains=True, mass_iterations=0), []

    def both(dyn, u, v, a, t):  # the lumped-mass acceleration on the same states, J' only
        lumped_J.append(lumped(dyn, u, v, a, t)["J_prime_domains"][0, :, 0])
        return hook(dyn, u, v, a, t)

    sol = integrate(sc, m, Stepping(dt=dt, output_interval=every), dyn=dyn, critical=(dtc, lam),
                    dsif=both)
    t = sol.t
    mat = sc.material
    norm = LOAD * math.sqrt(math.pi * A0)
    comp = 0 if case == "mode_I" else 1
    s = sol.history["sifs"]
    out = {"t_us": t / US, "dt_critical_us": dtc / US, "dt_us": sol.info["dt"] / US,
           "n_dofs": dyn.n_dofs, "n_nodes": dyn.disc.nodes.n, "mass_iterations": hook.mass_iterations,
           "steps": sol.info["steps"], "seconds": time.perf_counter() - t0, "K": {}, "peaks": {}}
    for key in ESTIMATES:  # mean of the two tips (equal by symmetry), normalised
        k = np.abs(s[key][:, :, comp]).mean(axis=1) / norm
        out["K"][key] = {"K_I": s[key][:, :, 0].mean(axis=1) / norm,
                         "K_II": s[key][:, :, 1].mean(axis=1) / norm}
        j = int(np.argmax(k))
        out["peaks"][key] = {"value": float(k[j]), "t_us": float(t[j] / US)}
    kJ = np.abs(s["J"][:, :, comp]).mean(axis=1) / norm
    near = np.abs(s["stress_0"][:, :, comp]).mean(axis=1) / norm
    out["first_felt_us"] = {key: float(t[np.argmax(v > 0.01)] / US) if np.any(v > 0.01) else None
                            for key, v in (("J", kJ), ("stress_0", near))}
    out["travel_time_us"] = HALF_H / (mat.c_dilatational if case == "mode_I" else mat.c_shear) / US
    # path dependence of J'_1 (the only non-zero component in a pure mode) over the radii
    Jd = sol.history["sifs"]["J_prime_domains"][:, 0, :, 0]  # (n_out, n_radii), tip 1
    big = kJ >= 0.25 * kJ.max()
    dep = (Jd[big].max(axis=1) - Jd[big].min(axis=1)) / np.abs(Jd[big, len(radii) // 2])
    out["path_dependence"] = float(dep.max())
    # near-tip estimates against K from J': the ratio of the peaks and the median deviation
    out["near_tip_vs_J"] = {key: {"peak_ratio": out["peaks"][key]["value"] / out["peaks"]["J"]["value"],
                                  "median_deviation": float(np.median(np.abs(
                                      np.abs(s[key][big, :, comp]).mean(axis=1) / norm / kJ[big] - 1)))}
                            for key in ("stress_0", "stress_0_fit", "stress_90")}
    out["J1_domains"] = Jd
    Jl = np.array(lumped_J)[big]
    out["path_dependence_lumped"] = float(np.max(np.ptp(Jl, axis=1) / np.abs(Jl[:, len(radii) // 2])))
    if case == "mode_I":
        ta = HALF_H / mat.c_dilatational
        win = (t > ta + 0.5 * 2 * A0 / mat.c_dilatational) & (t < ta + 2 * A0 / mat.c_dilatational)
        ref = freund_k(t, mat)
        out["early_time_error"] = {key: float(np.max(np.abs(
            np.abs(s[key][win, :, 0]).mean(axis=1) / ref[win] - 1))) if np.any(win) else None
            for key in ESTIMATES}
        out["K_freund"] = ref / norm
    return out


# Sect. 4.2: the slanted crack. Figure 7 is missing from the text: the plate is taken as
# 44 x 32 mm, so that the 45 x 33 regular nodes are 1 mm apart; the crack runs from the
# bottom edge at (6.5, 0) to the tip (22.5, 16) (a0 = 22.63 mm, 45 degrees); hinged supports
# (u = 0) on the bottom, right and top edges, the step tension on the left edge.
SLANT = dict(size=(44.0, 32.0), nodes=(45, 33), crack=((6.5, 0.0), (22.5, 16.0)))
# J' discs of the slanted crack: 6-12 mm (the tip is 16 mm from the top and bottom edges),
# with the plateau q of the face fit (efgkit.explicit.dsif.PLATEAU_FIT: q = 1 within 1.5
# spacings, where the face W comes from the fitted face displacement); the seed's radii
# (RADII, 2-4 mm about its 3 mm path, Wendland q) are run beside them on the same states.
SLANT_RADII = (6.0, 7.5, 9.0, 10.5, 12.0)
# hook name -> (radii, DynamicDSIF options): "full" is the recorded setting; the others show
# what the face fit, the face term and the radii do (same states)
SLANT_HOOKS = {"full": (SLANT_RADII, dict(q="plateau_fit", decomposition=True)),
               "raw_face": (SLANT_RADII, dict(q="plateau_fit", face_fit=False)),
               "no_face_term": (SLANT_RADII, dict(q="plateau_fit", face_terms=False)),
               "seed_radii": (RADII, {}),
               "seed_radii_raw_face": (RADII, dict(face_fit=False))}


def _path_dependence(J: np.ndarray) -> dict:
    """``max_t ptp_R J'_k / |J'_k(R_mid)|`` over the instants where ``|J'_k(R_mid)|`` is above a
    quarter of its peak, for ``J (n_out, n_radii, 2)``: ``{"J1": .., "J2": ..}``."""
    out = {}
    for c, name in ((0, "J1"), (1, "J2")):
        ref = J[:, J.shape[1] // 2, c]
        big = np.abs(ref) >= 0.25 * np.abs(ref).max()
        out[name] = float(np.max(np.ptp(J[big, :, c], axis=1) / np.abs(ref[big])))
    return out


def run_slanted(method: str, dt: float, duration: float, every: float, nodes=None) -> dict:
    """The mixed-mode slanted crack (seed 002 Sect. 4.2): K_I, K_II histories and the path
    dependence of J'_1 and J'_2 (each hook of :data:`SLANT_HOOKS`) and of J'_1 of the
    symmetric and antisymmetric parts; ``nodes`` ``(nx, ny)`` (default the seed's 45 x 33)."""
    from efgkit import Support

    (w, h), (nx, ny), (a, b) = SLANT["size"], nodes or SLANT["nodes"], SLANT["crack"]
    mat = CASES["mode_I"][0]
    sc = Scene(Domain.rectangle(0.0, 0.0, w, h), mat, name="slanted", duration=duration,
               cracks=(Crack([a, b], tips=(False, True)),),
               supports=tuple(Support(e, ux=0.0, uy=0.0) for e in ("bottom", "right", "top")),
               tractions=(Traction("left", (-LOAD, 0.0), history=Heaviside()),))
    X, Y = np.meshgrid(np.linspace(0, w, nx), np.linspace(0, h, ny))
    m = EFG(spacing=w / (nx - 1), coordinates=np.column_stack([X.ravel(), Y.ravel()]),
            d_max=2.5, zones=(), enrichment="none") if method == "efg" else None
    t0 = time.perf_counter()
    dyn = dynamics(sc, m)
    dtc, lam = stable_step(dyn)
    hooks = {k: DynamicDSIF(radii=r, domains=True, **o) for k, (r, o) in SLANT_HOOKS.items()}
    got = {k: [] for k in hooks}
    states = []

    def every_hook(dyn, u, v, a, t):  # every hook on the same states
        for k, hook in hooks.items():
            got[k].append(hook(dyn, u, v, a, t))
        states.append((u.copy(), a.copy()))
        return {}

    sol = integrate(sc, m, Stepping(dt=dt, output_interval=every), dyn=dyn, critical=(dtc, lam),
                    dsif=every_hook)
    t = sol.t
    s = {key: np.array([g[key] for g in got["full"]]) for key in got["full"][0]}
    a0 = math.dist(a, b)
    norm = LOAD * math.sqrt(math.pi * a0)
    out = {"t_us": t / US, "dt_us": dt / US, "dt_critical_us": dtc / US, "a0_mm": a0, "nodes": [nx, ny],
           "n_dofs": dyn.n_dofs, "radii_mm": list(SLANT_RADII), "seed_radii_mm": list(RADII),
           "seconds": time.perf_counter() - t0,
           "K": {key: {"K_I": s[key][:, 0, 0] / norm, "K_II": s[key][:, 0, 1] / norm}
                 for key in ESTIMATES}}
    Jd = s["J_prime_domains"][:, 0]  # (n_out, n_radii, 2)
    out["J_domains"] = Jd
    out["path_dependence"] = _path_dependence(Jd)
    out["path_dependence_by_hook"] = {}
    for k in hooks:
        Jk = np.array([g["J_prime_domains"][0] for g in got[k]])
        out["path_dependence_by_hook"][k] = _path_dependence(Jk)
        out["K"][f"J_{k}"] = {"K_I": np.array([g["J"][0, 0] for g in got[k]]) / norm,
                              "K_II": np.array([g["J"][0, 1] for g in got[k]]) / norm}
        out[f"J2_mid_{k}"] = Jk[:, Jk.shape[1] // 2, 1] * mat.E_prime / norm**2
    # the decomposition method: J'_1 of the symmetric (mode I) and antisymmetric (mode II) parts
    Jdec = s["J_decomposed_domains"][:, 0]  # (n_out, n_radii, 2)
    out["J_decomposed_domains"] = Jdec
    out["K"]["J_decomposed"] = {"K_I": s["J_decomposed"][:, 0, 0] / norm,
                                "K_II": s["J_decomposed"][:, 0, 1] / norm}
    for c, name in ((0, "J1_I"), (1, "J1_II")):
        ref = Jdec[:, len(SLANT_RADII) // 2, c]
        big = np.abs(ref) >= 0.25 * np.abs(ref).max()
        out["path_dependence"][name] = float(np.max(np.ptp(Jdec[big, :, c], axis=1) / np.abs(ref[big])))
    # agreement with the interaction K (a different integrand) where |K| >= 1/4 of its peak
    Ki = s["interaction"][:, 0]
    size = np.hypot(Ki[:, 0], Ki[:, 1])
    big = size >= 0.25 * size.max()
    # J'_2 against -2 K_I K_II / E' of the interaction K (seed 002 Eq. 33, V = 0), both in
    # (sigma0^2 pi a0 / E'): the bias of J'_2, not only its spread; at the peak of |K| and
    # the largest deviation (share of the peak of -2 K_I K_II) where |K| is large
    j = int(np.argmax(size))
    j2i = -2 * Ki[:, 0] * Ki[:, 1] / norm**2
    out["J2_at_peak"] = {"t_us": float(t[j] / US), "J2": Jd[j, :, 1] * mat.E_prime / norm**2,
                         "from_interaction": float(j2i[j])}
    out["J2_vs_interaction"] = {k: float(np.max(np.abs(out[f"J2_mid_{k}"][big] - j2i[big]))
                                         / np.abs(j2i[big]).max()) for k in hooks}
    out["J2_from_interaction"] = j2i
    deltas = (0.0, 0.25, 0.5, 1.0, 2.0)
    out["J2_face_exclusion"] = {"delta_h": list(deltas), "radii_mm": list(RADII), "J2": j2_face_exclusion(
        dyn, *states[j], RADII, deltas) * mat.E_prime / norm**2}
    for name, key in (("decomposed_vs_interaction", "J_decomposed"), ("J_vs_interaction", "J")):
        out[name] = {c: float(np.max(np.abs(s[key][big, 0, i] - Ki[big, i]) / size[big]))
                     for i, c in enumerate(("K_I", "K_II"))}
    return out


def static_path_dependence(case: str, method: str, nx: int, ny: int, radii=RADII) -> float:
    """Path dependence of the static ``J_1`` over ``radii`` on the plate under the step's
    final load (mode II: the shear ``tau0`` on all four edges, which balances the couple),
    solved with the run's stiffness ``K u = f`` (the three rigid modes taken out by the
    shift ``K + 1e-8 k M``, ``k`` the mean diagonal ratio): the floor the dynamic runs
    cannot go below on that discretisation."""
    from scipy.sparse import diags_array
    from scipy.sparse.linalg import spsolve

    mat, t = CASES[case]
    tr = [Traction("top", t), Traction("bottom", (-t[0], -t[1]))]
    if case == "mode_II":
        tr += [Traction("right", (0.0, t[0])), Traction("left", (0.0, -t[0]))]
    sc = Scene(Domain.rectangle(-HALF_W, -HALF_H, HALF_W, HALF_H), mat, name=case, duration=1e-6,
               cracks=(Crack([[-A0, 0.0], [A0, 0.0]]),), tractions=tuple(tr))
    dyn = dynamics(sc, METHODS[method](nx, ny), enrichment_mass=ENRICHMENT_MASS.get(method, "diagonal"))
    shift = 1e-8 * dyn.K.diagonal().mean() / dyn.m.mean()
    u = spsolve((dyn.K + shift * diags_array(dyn.m)).tocsc(), dyn.F.sum(axis=1))
    J = DynamicDSIF(radii=radii, domains=True, inertia=False)(dyn, u, 0 * u, 0 * u, 0.0)
    J = J["J_prime_domains"][0, :, 0]
    return float(np.ptp(J) / abs(J[len(radii) // 2]))


def j2_face_exclusion(dyn, u, a, radii, deltas) -> np.ndarray:
    """J'_2 of the first tip at one state (coefficients ``u``, ``a``) with the crack-face
    points closer than ``delta h`` to the tip left out of its face term, for each ``delta``
    of ``deltas``: ndarray (n_deltas, n_radii). A diagnostic of where the face term's error
    sits (the hook's own operators, acceleration recovery and q-function)."""
    from efgkit.explicit.dsif import TipOperators
    from efgkit.fracture.dynamic import contract_dynamic, dynamic_integrands
    from efgkit.fracture.integrals import FaceLoad
    from efgkit.fracture.qfunctions import QFunction
    from efgkit.problem.material import strain_from_gradient

    ops = TipOperators(dyn, radii)
    d, mat = ops.tips[0], dyn.disc.scene.material

    def grad(op):
        return (op @ u).reshape(2, 2, -1).transpose(2, 0, 1)

    g, m = grad(d["op"]), len(d["x"])
    acc = (d["val"] @ ops.recovered_acceleration(a, 4)).reshape(2, m).T
    it = dynamic_integrands(d["x"], d["w"], strain_from_gradient(g) @ mat.D.T, g,
                            np.zeros((m, 2)), acc, None, d["tip"], mat, max(radii))
    f = d["face0"]
    fg = np.concatenate([grad(d["faces"][side]) for side in (1.0, -1.0)])
    r = np.hypot(*(f.x - d["tip"].x).T)
    out = []
    for delta in deltas:
        k = r > delta * d["h"]
        fk = FaceLoad(f.x[k], f.w[k], f.traction[k], fg[k], f.side[k])
        out.append([contract_dynamic(it, QFunction("wendland_c2", R), fk).J2 for R in radii])
    return np.array(out)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    if quick:  # coarse (2 mm) and short: mode I until the early-time window closes
        grids = {"53x21": (53, 21, 0.2 * US)}  # the radii scale with the spacing (x 2)
        duration, every, cases, radii = 7.0 * US, 0.4 * US, ("mode_I",), tuple(2 * r for r in RADII)
    else:
        grids = {"105x42": (105, 42, 0.1 * US), "209x83": (209, 83, 0.05 * US)}
        duration, every, cases, radii = 14.0 * US, 0.2 * US, tuple(CASES), RADII
    m = {"path_dependence": {}, "runs": {}}
    for case in cases:
        for method in METHODS if not quick else ("efg",):
            for gname, (nx, ny, dt) in grids.items():
                if method in SEED_GRID_ONLY and gname != "105x42":
                    continue
                r = run(case, method, nx, ny, None if method in STEP_RULE else dt,
                        duration, every, radii)
                key = f"{case}/{method}/{gname}"
                m["runs"][key] = r
                m["path_dependence"][f"{key}/J1"] = r["path_dependence"]
    if not quick:
        m["static_path_dependence"] = {f"{case}/{method}/105x42": static_path_dependence(
            case, method, 105, 42) for case in cases for method in METHODS}
        for nodes, dt in (((45, 33), 0.1 * US), ((89, 65), 0.05 * US)):  # the seed's, and 0.5 mm
            key = f"slanted/efg/{nodes[0]}x{nodes[1]}"
            r = m["runs"][key] = run_slanted("efg", dt, 20.0 * US, every, nodes=nodes)
            for c, v in r["path_dependence"].items():
                m["path_dependence"][f"{key}/{c}"] = v
            # two different integrands on the same states: decomposed J'_1 and interaction K
            rep.check(f"{key}: K from the decomposed J'_1 against the interaction K (share of |K|)",
                      max(r["decomposed_vs_interaction"].values()), "<=", 0.05)  # 3.9 %, 1.6 %
            # against the issue's 1 %: J'_2 with the face fit and the plateau q, 6-12 mm
            # (measured 0.50 % and 0.45 %; raw face W 2.5 % on 45 x 33; seed 002: 3.1 %), the
            # J'_1 of the same discs 0.68 % and 0.11 % (seed 002: 0.6 %)
            for c in ("J1", "J2"):
                rep.check(f"{key}: path dependence of {c} over 6-12 mm (face fit, plateau q)",
                          r["path_dependence"][c], "<=", TARGET)
    finest = list(grids)[-1]
    for key, v in m["path_dependence"].items():
        # plain EFG: the finest grid (seed's grid: 2.07 %, 1.98 %); PU: the seed's grid
        # (measured 0.89 % and 0.69 %); the defaults at 1 mm (0.22 % and 0.18 %; on the
        # seed's nodes 0.63 % and 0.50 %; with the abs-row-sum mass 0.04 % and 0.03 %)
        if finest in key or quick or "/efg_pu/" in key or "/efg_default" in key:
            # quick: 2 mm spacing, radii 4-8 mm; measured 2.0 % (lumped acceleration: 4.8 %)
            rep.check(f"{key}: path dependence of J' over the radii", v, "<=",
                      0.06 if quick else TARGET)
    for key, r in m["runs"].items():
        if "early_time_error" in r:
            rep.check(f"{key}: K_J against Freund's step-wave K_I (early-time window)",
                      r["early_time_error"]["J"], "<=", 0.12 if quick else 0.05)  # quick: 7.4 %
    m["settings"] = {"plate_mm": [2 * HALF_W, 2 * HALF_H], "a0_mm": A0, "load_MPa": LOAD,
                     "rho": RHO, "units": "mm, N, MPa, tonne/mm^3, s", "radii_mm": radii,
                     "d_max": 2.5, "enrichment_mass": ENRICHMENT_MASS,
                     "mass_iterations": MASS_ITERATIONS,
                     "grids": {g: list(v[:2]) + [v[2] / US] for g, v in grids.items()},
                     "duration_us": duration / US, "output_us": every / US,
                     "c_d_mode_I": CASES["mode_I"][0].c_dilatational,
                     "c_s_mode_II": CASES["mode_II"][0].c_shear}
    rep.metrics.update(m)
    rep.ref("path_dependence", TARGET, "issue [dynamics] target 1 %; seed 002 Sect. 4.1: 2.4 % "
            "(mode I) and 1.8 % (mode II) against tipR = 3 mm")
    rep.ref("travel_time_us", 20.0 / 6.327, "20 mm / c_d, c_d = 6327 m/s (seed 000 quotes ~2.5 us)")
    rep.ref("K_I early", "2 sigma0 sqrt(c_d (t - t_a) (1 - 2 nu) / pi) / (1 - nu)",
            "Freund, Dynamic Fracture Mechanics (1990): a step wave on a semi-infinite crack")
    return rep.write(out_dir)


def markdown(r: dict) -> list[str]:
    m = r["metrics"]
    s = m["settings"]
    rows = ["| run | dt (us) | dt_c (us) | peak K/(s0 sqrt(pi a0)): J' / interaction / stress 0 / "
            "stress 0 fit / stress 90 (t us) | first felt (J', stress 0) / travel time (us) | "
            "path dependence (lumped acceleration) | early-time error (J', interaction) |",
            "|---|---|---|---|---|---|---|"]
    for key, v in m["runs"].items():
        if key.startswith("slanted"):
            continue
        pk = " / ".join(f"{v['peaks'][e]['value']:.3f} ({v['peaks'][e]['t_us']:.1f})"
                        for e in ESTIMATES if e in v["peaks"])
        ff = {k: "-" if x is None else f"{x:.2f}" for k, x in v["first_felt_us"].items()}
        et = v.get("early_time_error")
        early = "-" if not et else f"{et['J']:.1%}, {et['interaction']:.1%}"
        rows.append(f"| {key} | {v['dt_us']:.3g} | {v['dt_critical_us']:.3g} | {pk} | "
                    f"{ff['J']}, {ff['stress_0']} / {v['travel_time_us']:.2f} | "
                    f"{v['path_dependence']:.2%} ({v['path_dependence_lumped']:.2%}) | {early} |")
    return [f"Plate {s['plate_mm'][0]:g} x {s['plate_mm'][1]:g} mm, a0 = {s['a0_mm']:g} mm, step "
            f"load {s['load_MPa']} MPa on top and bottom; units {s['units']}; d_max "
            f"{s['d_max']}, no zones; rows efg: no enrichment, rows efg_pu: PU crack-tip "
            "enrichment (nodes within 2 spacings of a tip) with the abs-row-sum enrichment mass "
            "(the plain critical step) and 16 Jacobi steps of the acceleration recovery (4 for "
            "efg); rows efg_default: EFG(spacing=1 mm) with every other setting at its "
            "default (its own 105 x 41 grid with the automatic tip zones, h/2 within 6 h and h/4 "
            "within 3 h; PU enrichment of the nodes whose support comes within h of a tip, d_max "
            "2, the diagonal enrichment mass, 4 Jacobi steps, dt = 0.9 of the critical step), "
            "rows efg_default_seed_grid: the same on the seed's 105 x 42 nodes (user "
            "coordinates: no zones), rows efg_default_abs_row_sum: efg_default with the "
            "abs-row-sum enrichment mass (one factor off the defaults); J' discs R = "
            f"{s['radii_mm']} mm; histories "
            f"to {s['duration_us']:g} us. First felt: the first output where the normalised K "
            "exceeds 0.01 (the meshless supports and the explicit step let a small precursor "
            "run ahead of the front, so it comes before the travel time, 20 mm / c_d in mode I "
            "and 20 mm / c_s in mode II, and moves towards it as the grid is refined). "
            "Path dependence: J'_1 with the inertia term on the recovered acceleration (4 "
            "Jacobi steps towards the consistent-mass one, efgkit.explicit.dsif), in brackets "
            "with the driver's lumped-mass acceleration on the same states. "
            "Early-time error: against Freund's K_I for the doubled step stress "
            "(module docstring), second half of the window before the other tip's wave.",
            "", *rows, *_near_tip_lines(m), *_slanted_lines(m)]


def _near_tip_lines(m: dict) -> list[str]:
    """The near-tip estimates against K from J' and the static floor of the path dependence."""
    runs = {k: v for k, v in m["runs"].items() if "near_tip_vs_J" in v}
    if not runs:
        return []
    rows = ["", "Near-tip estimates against K from J' (peak of the estimate over peak of K_J; "
            "median of |K / K_J - 1| over the instants with K_J above a quarter of its peak): "
            "stress 0 is the seed's mean of the two points nearest the tip (r = h, 2h), "
            "stress 0 fit the line K + b r fitted on r = h..4h and taken at r = 0 "
            "(efgkit.explicit.near_tip).", "",
            "| run | stress 0 | stress 0 fit | stress 90 |", "|---|---|---|---|"]
    for key, v in runs.items():
        c = v["near_tip_vs_J"]
        rows.append(f"| {key} | " + " | ".join(
            f"{c[e]['peak_ratio']:.3f}, {c[e]['median_deviation']:.1%}"
            for e in ("stress_0", "stress_0_fit", "stress_90")) + " |")
    st = m.get("static_path_dependence")
    if st:
        rows += ["", "Static floor: path dependence of J_1 over the same radii under the final "
                 "load, solved with the run's stiffness (mode II: shear on all four edges): "
                 + ", ".join(f"{k} {x:.2%}" for k, x in st.items()) + "."]
    return rows


def _slanted_lines(m: dict) -> list[str]:
    v = m["runs"].get("slanted/efg/45x33")
    if v is None:
        return []
    est = [e for e in SLANT_ESTIMATES if e in v["K"]]
    K = {e: (np.array(v["K"][e]["K_I"]), np.array(v["K"][e]["K_II"])) for e in est}
    j = int(np.argmax(np.abs(K["interaction"][0])))
    at = ", ".join(f"{e} ({K[e][0][j]:.3f}, {K[e][1][j]:.3f})" for e in est)
    pd = v["path_dependence"]
    rows = ["", f"Slanted crack (Sect. 4.2; plate 44 x 32 mm, 45 x 33 nodes, crack (6.5, 0)-"
            f"(22.5, 16), a0 = {v['a0_mm']:.2f} mm, hinged bottom, right and top edges, step "
            f"tension on the left, dt = {v['dt_us']:g} us; J' discs R = "
            f"{', '.join(f'{r:g}' for r in v['radii_mm'])} mm, the tip being 16 mm from the "
            "top and bottom edges): path dependence of J'_1 "
            f"{pd['J1']:.1%}, of J'_2 {pd['J2']:.1%} (seed: 0.6 % and 3.1 %). At the peak of "
            f"the interaction K_I (t = {v['t_us'][j]:.1f} us), (K_I, K_II) / (sigma0 sqrt(pi "
            f"a0)): {at}. J'_2 holds W on both crack faces; without enrichment the discrete "
            "stresses within about two spacings of the tip differ between the faces by "
            "O(K / sqrt(h)), an O(K^2 / E') error in the face term that refinement does not "
            "remove (the raw face W rows below). "
            "J'_2 here takes the face W within 1.5 spacings of the tip from the face "
            "displacement fitted to its near-tip expansion on 1.5-6 spacings, and q = 1 "
            "there (efgkit.fracture.face_fit, DynamicDSIF(q=\"plateau_fit\"), docs/theory.md). "
            "Path dependence of J'_1 / J'_2 and the largest deviation of J'_2 from -2 K_I K_II"
            " / E' of the interaction K (share of its peak, where |K| is above a quarter of its "
            "peak), per setting on the same states:", "",
            "| grid | setting | radii (mm) | J'_1 | J'_2 | J'_2 against the interaction K |",
            "|---|---|---|---|---|---|"]
    label = {"full": "face fit, plateau q", "raw_face": "raw face W, plateau q",
             "no_face_term": "no face term, plateau q", "seed_radii": "face fit, Wendland q",
             "seed_radii_raw_face": "raw face W, Wendland q"}
    for g in ("45x33", "89x65"):
        w = m["runs"].get(f"slanted/efg/{g}")
        if w is None:
            continue
        for k, p in w["path_dependence_by_hook"].items():
            radii = w["seed_radii_mm"] if k.startswith("seed") else w["radii_mm"]
            rows.append(f"| {g} | {label.get(k, k)} | {radii[0]:g}-{radii[-1]:g} | {p['J1']:.2%} | "
                        f"{p['J2']:.2%} | {w['J2_vs_interaction'][k]:.1%} |")
    return rows + [*_decomposed_lines(v), *_decomposed_lines(m["runs"].get("slanted/efg/89x65"))]


def _decomposed_lines(v: dict) -> list[str]:
    if v is None or "J1_I" not in v["path_dependence"]:
        return []
    pd, agree, kj = v["path_dependence"], v["decomposed_vs_interaction"], v["J_vs_interaction"]
    fe = v["J2_face_exclusion"]
    return ["", f"J_decomposed ({v['nodes'][0]} x {v['nodes'][1]} nodes): K_I, K_II from J'_1 "
            "of the symmetric and antisymmetric parts of the field about the crack line "
            "(decomposition method, efgkit.fracture.decomposition; no J'_2): path dependence "
            f"of J'_1(u^I) {pd['J1_I']:.1%}, of J'_1(u^II) {pd['J1_II']:.1%} (J'_1 of the whole "
            f"field {pd['J1']:.1%}, J'_2 {pd['J2']:.1%} on the same discs), and K within "
            f"{agree['K_I']:.1%} (K_I) and {agree['K_II']:.1%} (K_II) of the interaction K, "
            "relative to |K|, wherever |K| is above a quarter of its peak; K from J'_1, J'_2 by "
            f"Eq. 38 within {kj['K_I']:.1%} and {kj['K_II']:.1%} (K_I close to -K_II here, "
            "where Eq. 38 splits J'_1 into K_I and K_II badly: J'_2 close to J'_1). "
            f"J'_2 E' / (sigma0^2 pi a0) at t = {v['J2_at_peak']['t_us']:.1f} us over the radii: "
            f"{', '.join(f'{x:.3f}' for x in v['J2_at_peak']['J2'])}, against "
            f"{v['J2_at_peak']['from_interaction']:.3f} from the interaction K. The raw face "
            f"W (no fit, Wendland q, R = {fe['radii_mm'][0]:g}-{fe['radii_mm'][-1]:g} mm) with "
            "the face points closer than delta h to the tip left out of the face term: "
            + "; ".join(f"delta = {dl:g}: " + ", ".join(f"{x:.3f}" for x in row) for dl, row in
                        zip(fe["delta_h"], fe["J2"], strict=True)) + "."]
