"""The single-edge-notched tension (SENT) specimen of seed 001 Sect. 4, FEM beside EFG.

Specimen 50 mm long (x) and W = 10 mm wide (y), edge crack of a = W/2 at mid-length from
the mouth (25, 0) to the tip (25, 5); both ends clamped (u_y = 0) and pulled apart by
0.0253882 mm each (u_x = -/+ 0.0253882); E = 210 GPa = 210e3 MPa, nu = 0.3, plane strain.
Units N, mm, MPa: forces per mm of thickness, J in N/mm (= kJ/m^2; seed: J/m^2 / 1000).

* FEM: scikit-fem P2 graded toward the tip with quarter-point tip elements (the seed's
  focused meshes F), and uniform 8-node serendipity quadrilaterals with n elements
  across W (the seed's not-focused Abaqus CPE8 meshes NF, 3 x 3 Gauss); J from the domain
  integral (Wendland C2 q) at the element quadrature points, the energy release rate
  -dU/da at fixed grips from remeshed specimens, CMOD, reactions.
* EFG at n = 20, 40, 80, 160 nodes across W (spacing W / n), variants: linear basis,
  linear + tip rosette, intrinsic radial (visibility rule: the sqrt(r) basis needs no
  smoothing, seed 003 Sect. 5.3.2) and full enrichment, extrinsic MLS and PU enrichment;
  the grips by Nitsche's method (bc="variational"), SuperLU or, above 20k unknowns, CG
  with the auxiliary-space preconditioner. J at the quadrature points and point-wise at
  the nodes (Voronoi volumes, seed 001 Eq. 8), with the seed's cubic-spline (Eq. 10) and
  Wendland C2 (Eq. 13) q-functions, on the seed's domain radii (Tables 4, 5).
* Which J is right (Abaqus 6.786 N/mm, seed 001 Table 5, or ~6.871): grips, plane,
  half model, energy release, modulus (see ``markdown``).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _report import Report

from efgkit import EFG, Domain, Elastic, Loop, Rosette, Scene, Support, solve
from efgkit.fem.model import FEM, solve_fem
from efgkit.fracture.integrals import contract, domain_integrands
from efgkit.fracture.qfunctions import QFunction
from efgkit.fracture.sif import tip_result
from efgkit.fracture.volumes import nodal_volumes
from efgkit.gallery import sent_seed001
from efgkit.problem.material import strain_from_gradient

NAME = "sent"
TITLE = "Single-edge-notched tension specimen (seed 001 Sect. 4)"
ROOT = Path(__file__).resolve().parents[1]
L, W, A, D = 50.0, 10.0, 5.0, 0.0253882  # mm; D = grip displacement of each end
E, NU = 210e3, 0.3  # MPa
TIP = np.array([L / 2, A])
RADII = (1.0, 2.0, 3.0, 4.0)  # J domains for the headline values (mm)

# seed 001 (J in J/m^2 = 1e-3 N/mm, CMOD in mm)
J_F160, J_NF160, J_SPH160, J_JR = 6786.0, 6785.0, 6862.0, 6686.0  # Sect. 4.1, 6, Table 5
CMOD_F160, CMOD_SPH160 = 0.04252, 0.04248  # Table 3
SEED_T4 = {  # Table 4: SPH J against domain radius (mm), per particles across W
    20: {0.8: 4325, 1.6: 5573, 2.4: 6299, 3.2: 6643, 4.0: 6806, 4.8: 6900},
    40: {0.4: 4801, 0.8: 5787, 1.2: 6339, 1.6: 6613, 2.0: 6741, 2.4: 6815, 2.8: 6861, 3.2: 6891,
         3.6: 6913, 4.0: 6929},
    80: {0.2: 6113, 0.4: 6366, 0.6: 6589, 0.8: 6734, 1.0: 6797, 1.2: 6833, 1.4: 6855, 1.6: 6869,
         1.8: 6880, 2.0: 6888, 2.2: 6893, 2.4: 6898, 2.6: 6901, 2.8: 6904},
    160: {0.1: 7133, 0.2: 7285, 0.3: 6971, 0.4: 6950, 0.5: 6914, 0.6: 6900, 0.7: 6889, 0.8: 6881,
          0.9: 6877, 1.0: 6874, 1.1: 6871, 1.2: 6873, 1.3: 6869, 1.4: 6867, 1.5: 6865, 1.6: 6864,
          1.7: 6863, 1.8: 6863, 1.9: 6862, 2.0: 6862}}
SEED_T5 = {  # Table 5: Abaqus J (focused F, not focused NF) against contour radius (mm); the
    # extraction lost the "|" (= same as above) cells, given here as None
    20: {0.5: (6789, 6789), 1.0: (6781, 6783), 1.5: (6780, 6786), 4.0: (6780, 6786)},
    40: {0.25: (6792, 6789), 0.5: (6784, 6783), 0.75: (6783, 6786), 2.5: (6783, 6786)},
    80: {0.125: (6793, 6789), 0.25: (6786, 6783), 0.375: (6786, 6786), 2.5: (6786, 6786)},
    160: {0.0625: (6794, 6789), 0.125: (6787, 6783), 0.1875: (6786, 6786), 0.25: (6785, None),
          2.5: (6785, 6786)}}
VARIANTS = {  # EFG options beyond spacing and bc="variational"
    "linear": lambda h: {"enrichment": "none"},  # the default would enrich
    "linear + rosette": lambda h: {"rosette": Rosette(h), "enrichment": "none"},
    "radial": lambda h: {"enrichment": "radial", "crack_rule": "visibility"},  # seed 003 5.3.2
    "full": lambda h: {"enrichment": "full", "d_max": 3.0},
    "extrinsic_mls": lambda h: {"enrichment": "extrinsic_mls"},
    "pu": lambda h: {"enrichment": "pu"},
}
ENRICHED = ("radial", "full", "extrinsic_mls", "pu")


def efg_runs(quick: bool) -> dict:
    """nodes across W -> variants run."""
    if quick:
        return {20: ("linear", "extrinsic_mls", "pu")}
    allv = tuple(VARIANTS)
    return {20: allv, 40: allv, 80: allv, 160: allv}


def scene(a: float = A, plane: str = "strain", modulus: float = E, nu: float = NU,
          grips: str = "clamped", pin: float = 0.0) -> Scene:
    """The SENT. ``grips="axial"`` prescribes only u_x at the ends, and u_y = 0 at the point
    (0, 0) (``pin = 0``; FEM) or on the piece |y - W/2| <= pin / 2 of the left end (EFG, whose
    supports are Gauss rules on edges: a point gets none)."""
    sc = sent_seed001(a, Elastic(modulus, nu, plane))  # efgkit.gallery: the clamped SENT
    if grips == "clamped":
        return sc

    def where(x):
        if pin == 0.0:
            return np.hypot(x[:, 0], x[:, 1]) < 1e-9
        return (x[:, 0] < 1e-9) & (np.abs(x[:, 1] - W / 2) <= pin / 2)
    return sc.with_supports((Support("left", ux=-D), Support("right", ux=D), Support(where, uy=0.0)))


def half_scene() -> Scene:
    """The right half x >= L/2 with u_x = 0 on the ligament (mode-I symmetry), crack face free."""
    loop = Loop.polygon([[L / 2, 0], [L, 0], [L, W], [L / 2, W], [L / 2, A]],
                        ["bottom", "right", "top", "ligament", "face"])
    return Scene(Domain(loop), Elastic(E, NU, "strain"), name="SENT half",
                 supports=(Support("ligament", ux=0.0), Support("right", ux=D, uy=0.0)))


def mirrored(x, w, stress, grad):
    """Fields of the half model and their mirror images about x = L/2 (mode I)."""
    xm = np.column_stack([L - x[:, 0], x[:, 1]])
    return (np.vstack([x, xm]), np.concatenate([w, w]), np.vstack([stress, stress * [1, 1, -1]]),
            np.concatenate([grad, grad * np.array([[1, -1], [-1, 1]])]))


def j_table(sc, x, w, stress, grad, radii, q: str) -> dict:
    """J per radius (one domain each, no averaging), from one pass over the largest disc."""
    terms = domain_integrands(x, w, stress, grad, sc.tips[0], sc.material, max(radii))
    return {float(r): contract(terms, QFunction(q, float(r))).J for r in radii}


# ------------------------------------------------------------------------------------ FEM


def fem_run(sc, fem: FEM, radii=RADII, tables=None) -> dict:
    t0 = time.perf_counter()
    sol = solve_fem(sc, fem)
    sec = time.perf_counter() - t0
    res = sol.sifs(radii=radii, error=False)[0]
    out = {"h": fem.h, "tip_h": fem.tip_h, "quarter_point": fem.quarter_point, "n_dofs": sol.n_dofs,
           "seconds": sec, "J": res.J, "J_domains": [d.J for d in res.domains], "KI": res.KI,
           "KII": res.KII, "T": res.T, "cmod": sol.cmod("crack"),
           "reaction": float(sol.reaction("right")[0]), "reaction_left": float(sol.reaction("left")[0]),
           "energy": sol.strain_energy()}
    if tables is not None:
        out["table"] = j_table(sc, *sol.quadrature_fields(), tables, "wendland_c2")
    return out, sol


def quad_model(n: int, sc: Scene | None = None) -> dict:
    """The seed's not-focused Abaqus model: n x 5n uniform 8-node quadrilaterals (CPE8, 3 x 3
    Gauss points), crack nodes duplicated on x = L/2 below the tip."""
    from skfem import Basis, ElementQuadS2, ElementVector, MeshQuad1, asm
    from skfem.models.elasticity import linear_elasticity

    from efgkit.fem.model import _rigid_modes
    from efgkit.system.linalg import solve as lsolve
    from efgkit.system.linear_system import LinearSystem

    sc = sc or scene()
    t0 = time.perf_counter()
    h, nx = W / n, 5 * n
    I, J_ = (a.ravel() for a in np.meshgrid(np.arange(nx + 1), np.arange(n + 1), indexing="ij"))
    p = np.column_stack([I * h, J_ * h])
    ii, jj = (a.ravel() for a in np.meshgrid(np.arange(nx), np.arange(n), indexing="ij"))

    def node(i, j):
        return i * (n + 1) + j

    t = np.column_stack([node(ii, jj), node(ii + 1, jj), node(ii + 1, jj + 1), node(ii, jj + 1)])
    split = node(nx // 2, np.arange(n // 2))  # crack nodes below the tip
    remap = np.arange(len(p) + len(split))
    remap[split] = len(p) + np.arange(len(split))
    right = ii >= nx // 2
    t[right] = remap[t[right]]
    p = np.vstack([p, p[split]])
    mesh = MeshQuad1(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T))
    basis = Basis(mesh, ElementVector(ElementQuadS2()), intorder=4)
    K = asm(linear_elasticity(*sc.material.lame), basis).tocsr()
    loc = basis.with_element(ElementQuadS2()).doflocs
    u = np.zeros(basis.N)
    fixed = []
    for s in sc.supports:
        at = np.flatnonzero(np.isclose(loc[0], 0.0 if s.edge == "left" else L))
        for c, v in ((0, s.ux), (1, s.uy)):
            u[2 * at + c] = v
            fixed.append(2 * at + c)
    Dd = np.concatenate(fixed)
    free = np.setdiff1d(np.arange(basis.N), Dd)
    z, _ = lsolve(LinearSystem(K[free][:, free], -K[free][:, Dd] @ u[Dd], True, len(free)),
                  near_nullspace=_rigid_modes(loc.T)[free])
    u[free] = z
    sec = time.perf_counter() - t0
    qp = basis.interpolate(u)
    g = qp.grad.reshape(2, 2, -1).transpose(2, 0, 1)
    x = np.asarray(basis.global_coordinates()).reshape(2, -1).T
    args = (x, basis.dx.ravel(), strain_from_gradient(g) @ sc.material.D.T, g)
    mouth = (node(nx // 2, 0), len(p) - len(split))
    res = tip_result(sc, sc.tips[0], *args, RADII)
    r = K @ u
    return {"n": n, "n_dofs": int(basis.N), "seconds": sec, "J": res.J,
            "J_domains": [d.J for d in res.domains], "cmod": float(u[2 * mouth[1]] - u[2 * mouth[0]]),
            "reaction": float(r[2 * np.flatnonzero(np.isclose(loc[0], L))].sum()),
            "table": j_table(sc, *args, sorted(SEED_T5[n]) if n in SEED_T5 else RADII, "wendland_c2")}


def energy_release(fem: FEM, da: float, five_point: bool) -> float:
    """G = -dU/da at fixed grips from specimens remeshed with the tip moved (per mm thickness)."""
    ks = (-2, -1, 1, 2) if five_point else (-1, 1)
    U = {k: solve_fem(scene(A + k * da), fem).strain_energy() for k in ks}
    if five_point:
        return -(8 * (U[1] - U[-1]) - (U[2] - U[-2])) / (12 * da)
    return -(U[1] - U[-1]) / (2 * da)


def investigation(fem: FEM, efg_n: int, efg_clamped: dict) -> dict:
    """J, CMOD and reaction of the specimen variants that could explain a different J;
    ``efg_clamped`` is the main study's EFG run of the specimen as specified (``efg_n``
    nodes across, extrinsic MLS)."""
    out = {}
    sc = scene()
    base = fem_run(sc, fem)[0]
    e_abaqus = E * (J_F160 / 1e3) / base["J"]  # the modulus that gives 6.786
    cases = {"as specified (clamped: u_x, u_y prescribed)": sc,
             "grips: only u_x prescribed (u_y free)": scene(grips="axial"),
             "one end clamped, the other only u_x": sc.with_supports(
                 (Support("left", ux=-D, uy=0.0), Support("right", ux=D))),
             "plane stress": scene(plane="stress"),
             "nu = 0.29": scene(nu=0.29), "nu = 0.31": scene(nu=0.31),
             f"E = {e_abaqus / 1e3:.1f} GPa": scene(modulus=e_abaqus), "a = 4.95 mm": scene(a=4.95)}
    for name, case in cases.items():
        r = base if case is sc else fem_run(case, fem)[0]
        out[name] = {k: r[k] for k in ("J", "cmod", "reaction", "KI", "n_dofs")}
    hfem = FEM(fem.h, tip_h=fem.tip_h, refine=((L / 2, A),))
    full_p2 = FEM(fem.h, tip_h=fem.tip_h, quarter_point=False)  # as the half (which has no tip)
    for name, case, f in (("half model + symmetry (P2, no quarter points)", half_scene(), hfem),
                          ("full model (P2, no quarter points)", sc, full_p2)):
        sol = solve_fem(case, f)
        fields = sol.quadrature_fields()
        if case.name == "SENT half":
            fields = mirrored(*fields)
            cmod = 2 * float(sol.displacement([[L / 2, 0.0]])[0, 0])
        else:
            cmod = sol.cmod("crack")
        res = tip_result(sc, sc.tips[0], *fields, RADII)
        out[name] = {"J": res.J, "cmod": cmod, "reaction": float(sol.reaction("right")[0]),
                     "KI": res.KI, "n_dofs": sol.n_dofs}
    axial, _ = efg_run(scene(grips="axial", pin=W / efg_n), efg_n, "extrinsic_mls", tables=False)
    for grips, r in (("clamped", efg_clamped), ("axial", axial)):  # an independent discretisation
        out[f"EFG{efg_n} extrinsic MLS, grips {grips}"] = {
            "J": r["J"], "cmod": r["cmod"], "reaction": r["reaction_energy"], "KI": r["KI"],
            "n_dofs": 2 * r["n_nodes"]}
    return out


# ------------------------------------------------------------------------------------ EFG


def efg_method(n: int, variant: str) -> EFG:
    h = W / n
    return EFG(spacing=h, bc="variational", **VARIANTS[variant](h))


def _nodal_points(sol, sc, rmax: float):
    """Nodes within ``rmax`` of the tip (tip node excluded, split crack nodes moved 1e-3 h onto
    their face) with their Voronoi volumes: the point set of seed 001 Eq. 8."""
    nodes, h = sol.nodes, sol.method.spacing
    x = nodes.x.copy()
    if nodes.face is not None:  # the crack runs +y: its left face is at x < L/2
        x[:, 0] -= 1e-3 * h * nodes.face
    V = nodal_volumes(x, sc.domain)
    r = np.hypot(*(x - TIP).T)
    near = (r < rmax * 1.01) & (r > 1e-9 * h)
    return x[near], V[near]


def efg_run(sc, n: int, variant: str, keep: bool = False, tables: bool = True):
    """One EFG solution: J (domains of RADII, seed radii with two q's at quadrature points and
    at the nodes), CMOD, reactions, the stress ahead of the tip."""
    t0 = time.perf_counter()
    sol = solve(sc, efg_method(n, variant))
    sec = time.perf_counter() - t0
    res = sol.sifs(radii=RADII, error=False)[0]
    h = W / n
    out = {"n": n, "variant": variant, "n_nodes": sol.nodes.n, "seconds": sec, "J": res.J,
           "J_domains": [d.J for d in res.domains], "spread": res.spread, "KI": res.KI,
           "KI_enriched": res.enriched[0] if res.enriched else None}
    u = sol.displacement([[L / 2 + 1e-6 * h, 0.0], [L / 2 - 1e-6 * h, 0.0]])
    out["cmod"] = float(u[0, 0] - u[1, 0])
    out["reaction_energy"] = sol.strain_energy() / D  # U = R D at fixed grips
    if not tables:
        return out, (sol if keep else None)
    radii = sorted(SEED_T4.get(n, {1.0: 0, 2.0: 0, 3.0: 0}))
    pts = sol.disc.points
    fields = (pts.x, pts.w, sol.stress(), sol.gradient())
    xn, V = _nodal_points(sol, sc, max(radii))
    nodal = (xn, V, sol.stress(xn), sol.gradient(xn))
    out["tables"] = {f"{where}/{q}": j_table(sc, *f, radii, q)
                     for where, f in (("quadrature", fields), ("nodes", nodal))
                     for q in ("cubic_spline", "wendland_c2")}
    r = np.geomspace(0.01, 4.9, 40)
    out["ahead"] = {"r": r.tolist(), "sxx": sol.stress(TIP + np.column_stack([0 * r, r]))[:, 0].tolist()}
    return out, (sol if keep else None)


# ---------------------------------------------------------------------------------- figures


def _save(fig, name: str, quick: bool, out_dir) -> str | None:
    import matplotlib.pyplot as plt

    from efgkit.io import write_figure

    if not quick:
        return str(write_figure(fig, ROOT / "docs" / "figures" / f"{NAME}_{name}.png", dpi=100))
    if out_dir is not None:
        return str(write_figure(fig, Path(out_dir) / f"{NAME}_{name}.png", dpi=100))
    plt.close(fig)
    return None


def fig_contours(fem_sol, efg_sol, label: str):
    """sigma_xx, von Mises and u_x of FEM and EFG on one sample grid, one colour scale per row
    (seed 001 Figs. 10-12)."""
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    from efgkit.io import sample_grid, von_mises

    sc = fem_sol.scene
    x, tri = sample_grid(sc.domain, 30000, sc.cracks)
    mat = sc.material
    vals = {}
    for key, sol in (("FEM", fem_sol), ("EFG", efg_sol)):
        s = sol.stress(x)
        vals[key] = {"sigma_xx (MPa)": s[:, 0], "von Mises (MPa)": von_mises(s, mat),
                     "u_x (mm)": sol.displacement(x)[:, 0]}
    fig, axes = plt.subplots(3, 2, figsize=(13, 6.5))
    T = Triangulation(x[:, 0], x[:, 1], tri)
    for row, comp in enumerate(vals["FEM"]):
        lo, hi = np.percentile(vals["FEM"][comp], [0.5, 99.5])
        levels = np.linspace(lo, hi, 31)
        for col, key in enumerate(("FEM", "EFG")):
            ax = axes[row, col]
            cs = ax.tricontourf(T, vals[key][comp], levels=levels, cmap="viridis", extend="both")
            ax.plot([L / 2, L / 2], [0, A], color="tab:red", lw=1.2)
            ax.set_aspect("equal")
            ax.set_title(f"{key if key == 'FEM' else label}: {comp}", fontsize=9)
            ax.set_xticks([]), ax.set_yticks([])
        fig.colorbar(cs, ax=axes[row].tolist(), shrink=0.9)
    return fig


def fig_ahead(fem_ahead: dict, efg: dict, KI: float):
    """sigma_xx ahead of the tip (seed 001 Fig. 13), linear and log axes."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    r = np.asarray(fem_ahead["r"])
    for ax, log in zip(axes, (False, True), strict=True):
        ax.plot(r, fem_ahead["sxx"], "k-", lw=2, label="FEM P2 (graded, quarter-point)")
        for key, rec in efg.items():
            ax.plot(rec["ahead"]["r"], rec["ahead"]["sxx"], "--", label=f"EFG {key}")
        ax.plot(r, KI / np.sqrt(2 * np.pi * r), ":", color="0.4", label="K_I / sqrt(2 pi r)")
        ax.set(xlabel="distance ahead of the tip r (mm)", ylabel="sigma_xx (MPa)")
        if log:
            ax.set(xscale="log", yscale="log")
        else:
            ax.set_ylim(0, 2500)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def fig_j_radius(efg: dict, J_fem: float):
    """J against domain radius (seed 001 Fig. 15): the seed's SPH beside EFG point-wise (the
    seed's algorithm on EFG fields) and EFG with enrichment at quadrature points."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    colours = dict(zip((20, 40, 80, 160), ("tab:blue", "tab:orange", "tab:green", "tab:red"), strict=True))
    for n, tab in SEED_T4.items():
        axes[0].plot(list(tab), [v / 1e3 for v in tab.values()], "x:", color=colours[n], label=f"seed SPH{n}")
    for rec in efg.values():
        n, c = rec["n"], colours[rec["n"]]
        t = rec["tables"]["nodes/cubic_spline"]
        if rec["variant"] == "linear":
            axes[0].plot([float(k) for k in t], list(t.values()), "o-", color=c, ms=3,
                         label=f"EFG{n} linear, point-wise, cubic spline q")
        if rec["variant"] in ("extrinsic_mls", "pu"):
            t = rec["tables"]["quadrature/wendland_c2"]
            axes[1].plot([float(k) for k in t], list(t.values()), "o-" if rec["variant"] == "pu" else "s--",
                         color=c, ms=3, label=f"EFG{n} {rec['variant']}")
    for ax in axes:
        ax.axhline(J_fem, color="k", lw=1.5, label=f"FEM P2 converged {J_fem:.4f}")
        ax.axhline(J_F160 / 1e3, color="0.5", ls="--", lw=1, label="seed Abaqus 6.786")
        ax.axhline(J_JR / 1e3, color="0.5", ls=":", lw=1, label="seed John & Rigling 6.686")
        ax.set(xlabel="J domain radius (mm)", ylabel="J (N/mm)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
    axes[0].set_ylim(6.0, 7.4)
    axes[1].set_ylim(6.77, 6.89)
    axes[1].set_title("enriched EFG, quadrature points, Wendland C2 q", fontsize=9)
    axes[0].set_title("seed SPH (Table 4) and EFG linear, point-wise (seed Eq. 8)", fontsize=9)
    fig.tight_layout()
    return fig


def fig_convergence(efg: dict, conv: list, nf: dict, J_fem: float):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for v in VARIANTS:
        recs = sorted((r for r in efg.values() if r["variant"] == v), key=lambda r: r["n"])
        if recs:
            axes[0].loglog([r["n"] for r in recs], [abs(r["J"] / J_fem - 1) for r in recs], "o-", label=v)
    axes[0].axhline(3e-3, color="k", ls=":", lw=1, label="0.3 % target")
    axes[0].set(xlabel="EFG nodes across W", ylabel="|J / J_FEM - 1|")
    axes[1].semilogx([c["n_dofs"] for c in conv], [c["J"] for c in conv], "ko-",
                     label="P2 graded, quarter-point")
    if nf:
        axes[1].semilogx([r["n_dofs"] for r in nf.values()], [r["J"] for r in nf.values()], "s--",
                         label="Q8 uniform (seed NF)")
    axes[1].axhline(J_F160 / 1e3, color="0.5", ls="--", label="seed Abaqus 6.786")
    axes[1].set(xlabel="FEM DOFs", ylabel="J (N/mm)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------------------------- main


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    t_start = time.perf_counter()
    sc = scene()
    graded = ((1.0, 0.05), (0.5, 0.02)) if quick else ((1.0, 0.05), (0.5, 0.02), (0.25, 0.01),
                                                       (0.125, 0.005))
    conv, fem_sol = [], None
    for h, th in graded:
        r, fem_sol = fem_run(sc, FEM(h, tip_h=th, quarter_point=True))
        conv.append(r)
    J_fem, cmod_fem, reaction_fem = conv[-1]["J"], conv[-1]["cmod"], conv[-1]["reaction"]
    r = np.geomspace(0.01, 4.9, 40)
    fem_ahead = {"r": r.tolist(), "sxx": fem_sol.stress(TIP + np.column_stack([0 * r, r]))[:, 0].tolist()}
    ns = (20,) if quick else (20, 40, 80, 160)
    focused = {n: fem_run(sc, FEM(min(2.0, 4 * W / n), tip_h=W / n / 2, quarter_point=True),
                          tables=sorted(SEED_T5[n]))[0] for n in ns}
    nf = {n: quad_model(n) for n in ((20,) if quick else (20, 40, 80))}
    t_fem = time.perf_counter()
    g_fem = FEM(1.0, tip_h=0.05, quarter_point=True) if quick else FEM(0.5, tip_h=0.02, quarter_point=True)
    da = 0.1 if quick else 0.05
    G = energy_release(g_fem, da, five_point=not quick)
    t_g = time.perf_counter()
    efg, keep = {}, None
    fig_key = (20 if quick else 80, "extrinsic_mls")
    for n, variants in efg_runs(quick).items():
        for v in variants:
            rec, sol = efg_run(sc, n, v, keep=(n, v) == fig_key)
            efg[f"{n}/{v}"] = rec
            keep = sol if sol is not None else keep
    t_efg = time.perf_counter()
    n_inv = 20 if quick else 40
    inv = investigation(g_fem, n_inv, efg[f"{n_inv}/extrinsic_mls"])
    t_inv = time.perf_counter()
    rep.metrics.update({
        "J_fem": J_fem, "cmod_fem": cmod_fem, "reaction_fem": reaction_fem,
        "J_efg": {k: v["J"] for k, v in efg.items()}, "cmod_efg": {k: v["cmod"] for k, v in efg.items()},
        "reaction_efg": {k: v["reaction_energy"] for k, v in efg.items()},
        "fem_convergence": conv, "fem_focused": focused, "fem_nf_quads": nf,
        "energy_release": {"G": G, "da": da, "five_point": not quick, "h": g_fem.h, "tip_h": g_fem.tip_h},
        "investigation": inv, "efg": efg, "fem_ahead": fem_ahead,
        "seconds": {"fem": t_fem - t_start,
                    "energy_release_and_variants": (t_g - t_fem) + (t_inv - t_efg),
                    "efg": t_efg - t_g}})
    rep.ref("J_abaqus_F160", J_F160 / 1e3, "seed 001 Sect. 4.1 and Table 5 (6786 J/m^2, focused CPE8)")
    rep.ref("J_abaqus_NF160", J_NF160 / 1e3, "seed 001 Sect. 6 (6785 J/m^2, not focused)")
    rep.ref("J_sph160", J_SPH160 / 1e3, "seed 001 Sect. 6 (SPH160 converged, 6862 J/m^2)")
    rep.ref("J_john_rigling", J_JR / 1e3, "seed 001 Sect. 4.1, ref. [38] at a force of 8595 N")
    rep.ref("cmod_abaqus_F160", CMOD_F160, "seed 001 Table 3 (FEM F160)")
    rep.ref("cmod_sph160", CMOD_SPH160, "seed 001 Table 3 (SPH160)")
    rep.ref("J_tables", "Tables 4 and 5", "seed 001 Tables 4 (SPH) and 5 (FEM): J against radius")
    rep.check("FEM J converged: relative change over the last two graded meshes",
              abs(conv[-1]["J"] / conv[-2]["J"] - 1), "<=", 5e-4)
    rep.check("FEM CMOD against Abaqus F160 (relative)", abs(cmod_fem / CMOD_F160 - 1), "<=", 2e-3)
    rep.check("energy release -dU/da against the domain J (relative)", abs(G / J_fem - 1), "<=", 5e-4)
    half = inv["half model + symmetry (P2, no quarter points)"]["J"]
    rep.check("half model with symmetry support against the full model (J, relative)",
              abs(half / inv["full model (P2, no quarter points)"]["J"] - 1), "<=", 1e-4)
    rep.check("end reactions balance (relative)",
              abs(conv[-1]["reaction"] + conv[-1]["reaction_left"]) / reaction_fem, "<=", 1e-6)
    for v in ENRICHED:
        runs = [rec for rec in efg.values() if rec["variant"] == v and rec["n"] <= 80]
        if runs:
            best = max(runs, key=lambda rec: rec["n"])
            rep.check(f"EFG {v} at {best['n']} nodes across: |J / J_fem - 1|", abs(best["J"] / J_fem - 1),
                      "<=", 3e-3)
            rep.check(f"EFG {v} at {best['n']} nodes across: |CMOD / CMOD_fem - 1|",
                      abs(best["cmod"] / cmod_fem - 1), "<=", 2e-3)
    figs = [("convergence", fig_convergence(efg, conv, nf, J_fem)),
            ("j_radius", fig_j_radius(efg, J_fem)),
            ("stress_ahead", fig_ahead(fem_ahead, {k: v for k, v in efg.items()
                                                   if v["n"] == fig_key[0]}, conv[-1]["KI"]))]
    if keep is not None:
        figs.append(("contours", fig_contours(fem_sol, keep, f"EFG{fig_key[0]} {fig_key[1]}")))
    for name, fig in figs:
        path = _save(fig, name, quick, out_dir)
        if path:
            rep.figures.append(path)
    return rep.write(out_dir)


# --------------------------------------------------------------------------------- markdown


def _pct(x: float) -> str:
    return f"{100 * x:+.3f} %"


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    Jf, cf, rf = m["J_fem"], m["cmod_fem"], m["reaction_fem"]
    conv, inv = m["fem_convergence"], m["investigation"]
    lines = [
        "Seed 001 Sect. 4: 50 x 10 mm, a/W = 0.5 edge crack at mid-length, plane strain, "
        "E = 210 GPa, nu = 0.3, both ends clamped (u_x = -/+ 0.0253882 mm, u_y = 0). N, mm, "
        "MPa; J in N/mm (= kJ/m^2). FEM: scikit-fem P2 triangles graded toward the tip "
        "(size tip h + 0.25 r, 12 quarter-point elements around it); J from the domain integral "
        f"with Wendland C2 q over discs of radii {RADII} mm, averaged. EFG: spacing W / n, the "
        "grips by Nitsche's method (bc='variational'), SuperLU or CG with the auxiliary-space "
        "preconditioner above 20k unknowns.", "",
        "| quantity | efgkit FEM | seed Abaqus F160 | difference | seed SPH160 |", "|---|---|---|---|---|",
        f"| J (N/mm) | **{Jf:.5f}** | 6.786 | {_pct(Jf / 6.786 - 1)} | 6.862 "
        f"({_pct(6.862 / Jf - 1)} from ours) |",
        f"| -dU/da (N/mm) | {m['energy_release']['G']:.5f} | | "
        f"{_pct(m['energy_release']['G'] / 6.786 - 1)} | |",
        f"| CMOD (mm) | {cf:.6f} | 0.04252 | {_pct(cf / 0.04252 - 1)} | 0.04248 |",
        f"| reaction (N/mm) | {rf:.2f} | not given | | |", "",
        "**FEM convergence** (P2, graded, quarter-point):", "",
        "| h | tip h | DOFs | J (N/mm) | J per domain | K_I (MPa mm^0.5) | CMOD (mm) | reaction (N/mm) | s |",
        "|---|---|---|---|---|---|---|---|---|"]
    for c in conv:
        lines.append(f"| {c['h']:g} | {c['tip_h']:g} | {c['n_dofs']} | {c['J']:.5f} | "
                     f"{', '.join(f'{j:.5f}' for j in c['J_domains'])} | {c['KI']:.2f} | {c['cmod']:.6f} | "
                     f"{c['reaction']:.2f} | {c['seconds']:.1f} |")
    lines += ["", f"Last two meshes differ by {_pct(conv[-1]['J'] / conv[-2]['J'] - 1)} in J (target "
              "0.05 %). The energy release rate at fixed grips, -dU/da from specimens remeshed with "
              f"the tip moved by +-{m['energy_release']['da']} mm (h = {m['energy_release']['h']}, "
              f"tip h = {m['energy_release']['tip_h']}), is {m['energy_release']['G']:.5f} N/mm: "
              "it needs no J integral and agrees with the domain J.", "",
              "**J against contour radius, FEM** (seed Table 5 beside ours; J in J/m^2 as in the "
              "seed). F: seed focused CPE8 / ours P2 graded with quarter points (tip h = W / 2n); "
              "NF: seed uniform CPE8 / ours uniform 8-node quadrilaterals with n across W, 3 x 3 "
              "Gauss points (the same element and mesh); Wendland C2 disc domains:", "",
              "| n | radius (mm) | seed F | ours F | seed NF | ours NF |", "|---|---|---|---|---|---|"]
    for n, tab in SEED_T5.items():
        F = m["fem_focused"].get(str(n), {}).get("table", {})
        NF = m["fem_nf_quads"].get(str(n), {}).get("table", {})
        for rad, (sf, snf) in tab.items():
            f_ = F.get(str(float(rad)))
            nf_ = NF.get(str(float(rad)))
            ours_nf = "-" if nf_ is None else f"{1e3 * nf_:.0f}"
            lines.append(f"| {n} | {rad:g} | {sf} | {'-' if f_ is None else f'{1e3 * f_:.0f}'} | "
                         f"{'= above' if snf is None else snf} | {ours_nf} |")
    nfq = m["fem_nf_quads"]
    lines += ["", "Uniform 8-node quadrilaterals (the seed's NF meshes), J over the four standard "
              "domains: " + ", ".join(f"NF{n}: {r['J']:.4f} N/mm, CMOD {r['cmod']:.6f} mm"
                                      for n, r in nfq.items()) + ". Ours have no quarter-point "
              "nodes, so J converges like h (the singularity), from below"]
    if len(nfq) >= 2:
        a, b = list(nfq.values())[-2:]
        lines[-1] += (f"; extrapolated as error ~ h from the last two: {2 * b['J'] - a['J']:.4f} N/mm, "
                      f"CMOD {2 * b['cmod'] - a['cmod']:.6f} mm")
    lines[-1] += (". The seed's NF20 already gives 6786 at every contour, so its not-focused "
                  "meshes presumably carry quarter-point nodes at the tip too (Sect. 4.1 describes "
                  "them for the model without saying which meshes).")
    lines.append("")
    lines += _efg_tables(m, Jf, cf)
    lines += _investigation(m, inv, Jf, cf)
    lines += ["", "![J error against nodes across (EFG) and FEM J against DOFs]"
              "(figures/sent_convergence.png)",
              "", "![J against domain radius, seed Fig. 15](figures/sent_j_radius.png)", "",
              "![sigma_xx ahead of the tip, seed Fig. 13](figures/sent_stress_ahead.png)", "",
              "![sigma_xx, von Mises and u_x of FEM and EFG, one colour scale per row, seed Figs. "
              "10-12](figures/sent_contours.png)", "",
              f"Run time of the full study: FEM {m['seconds']['fem']:.0f} s, energy release and "
              f"variants {m['seconds']['energy_release_and_variants']:.0f} s, EFG "
              f"{m['seconds']['efg']:.0f} s (a shared 2-core machine)."]
    return lines


def _efg_tables(m: dict, Jf: float, cf: float) -> list[str]:
    efg = m["efg"]
    ns = sorted({r["n"] for r in efg.values()})
    lines = ["**EFG**: J (mean over the four domains, quadrature points, Wendland C2 q), its "
             "difference to the converged FEM J, CMOD, reaction (U / D, U the strain energy; "
             "the FEM reaction is the nodal force sum), nodes and solve seconds:", "",
             "| variant | n | nodes | J (N/mm) | J - J_FEM | CMOD (mm) | CMOD - FEM | reaction (N/mm) | s |",
             "|---|---|---|---|---|---|---|---|---|"]
    for v in VARIANTS:
        for n in ns:
            r = efg.get(f"{n}/{v}")
            if r:
                lines.append(f"| {v} | {n} | {r['n_nodes']} | {r['J']:.4f} | {_pct(r['J'] / Jf - 1)} | "
                             f"{r['cmod']:.6f} | {_pct(r['cmod'] / cf - 1)} | {r['reaction_energy']:.2f} | "
                             f"{r['seconds']:.1f} |")
    lines += ["", f"FEM reaction {m['reaction_fem']:.2f} N/mm. Target: enriched EFG within 0.3 % of "
              "the FEM J at <= 80 nodes across, CMOD within 0.2 %.", "",
              "**J against domain radius, EFG beside the seed's SPH (Table 4)**, J in J/m^2. The "
              "seed's algorithm is point-wise (particles with volumes, Eq. 8) with the cubic-spline "
              "q (Eq. 10); 'nodes' is that algorithm on the EFG fields at the nodes (Voronoi "
              "volumes), 'quadrature' the same integral at the EFG quadrature points:", ""]
    for n in ns:
        if n not in SEED_T4:
            continue
        cols = [(v, w, q) for v in ("linear", "extrinsic_mls") if f"{n}/{v}" in efg
                for w, q in (("nodes", "cubic_spline"), ("quadrature", "cubic_spline"),
                             ("quadrature", "wendland_c2"))]
        lines += [f"n = {n} ({W / n:g} mm spacing):", "",
                  "| radius (mm) | seed SPH | " + " | ".join(f"{v}, {w}, {q}" for v, w, q in cols) + " |",
                  "|---" * (2 + len(cols)) + "|"]
        for rad, s in SEED_T4[n].items():
            vals = [efg[f"{n}/{v}"]["tables"][f"{w}/{q}"].get(str(float(rad))) for v, w, q in cols]
            lines.append(f"| {rad:g} | {s} | " + " | ".join(f"{1e3 * x:.0f}" for x in vals) + " |")
        lines.append("")
    return lines


def _investigation(m: dict, inv: dict, Jf: float, cf: float) -> list[str]:
    names = list(inv)
    base, axial = inv[names[0]], inv[names[1]]
    e_name = next(k for k in names if k.startswith("E = "))
    half, full = inv[names[-4]], inv[names[-3]]
    efg_c, efg_a = inv[names[-2]], inv[names[-1]]
    g, conv = m["energy_release"]["G"], m["fem_convergence"]
    enr = [r for r in m["efg"].values() if r["variant"] in ENRICHED]
    n_top = max((r["n"] for r in enr), default=0)
    efg_txt = ", ".join(f"{r['variant']} {r['J']:.4f}" for r in enr
                        if r["n"] == n_top and r["variant"] != "radial")
    lines = ["### Which J is right: 6.786 (Abaqus, seed Table 5) or 6.871 N/mm?", "",
             f"Variants of the model (FEM: one graded quarter-point P2 mesh, h = {m['energy_release']['h']}, "
             f"tip h = {m['energy_release']['tip_h']}; the half-model pair without quarter points, "
             "the half mirrored for the integrals; the EFG rows with extrinsic MLS enrichment). "
             "Differences are to the first row; 'force, B = 5 mm' is the reaction times a 5 mm "
             "thickness, for the seed's 'total applied force measured as 8595 N':", "",
             "| model | J (N/mm) | dJ | CMOD (mm) | dCMOD | reaction (N/mm) | force, B = 5 mm (N) |",
             "|---|---|---|---|---|---|---|"]
    for name, r in inv.items():
        lines.append(f"| {name} | {r['J']:.4f} | {_pct(r['J'] / base['J'] - 1)} | {r['cmod']:.6f} | "
                     f"{_pct(r['cmod'] / base['cmod'] - 1)} | {r['reaction']:.1f} | "
                     f"{5 * r['reaction']:.0f} |")
    lines += [f"| seed Abaqus (F160) | 6.786 | {_pct(6.786 / base['J'] - 1)} | 0.04252 | "
              f"{_pct(0.04252 / base['cmod'] - 1)} | | 8595 |", "", "Reasoning:", "",
              f"1. *Discretisation.* The last two graded P2 meshes agree to "
              f"{_pct(conv[-1]['J'] / conv[-2]['J'] - 1)} "
              "in J; uniform 8-node quadrilaterals (the seed's NF element and meshes) converge to the "
              "same J from below (tables above). The seed's Abaqus J is itself mesh-independent "
              "to 0.02 % "
              "(Table 5). A 1.2 % gap is not a mesh or element effect.",
              f"2. *The J integral and units.* -dU/da at fixed grips from remeshed specimens ({g:.4f}) "
              f"needs no J integral and agrees with the domain J ({Jf:.4f}) to {_pct(g / Jf - 1)}; so "
              "do K_I^2 / E' and J over every domain from 1 to 4 mm. Units give powers of ten, not "
              "1.2 %; geometric nonlinearity is of the order of the strain, 1e-3.",
              f"3. *Symmetry and plane.* The half model with a symmetry support gives the full "
              f"model's J ({_pct(half['J'] / full['J'] - 1)}); plane stress changes J by "
              f"{_pct(inv['plane stress']['J'] / base['J'] - 1)}.",
              "4. *The grips.* With only the axial displacement prescribed at the ends (u_y free, the "
              f"ends free to contract), J = {axial['J']:.4f} N/mm: the seed's Abaqus 6.786 "
              f"({_pct(6.786 / axial['J'] - 1)}), and the reaction times a 5 mm thickness is "
              f"{5 * axial['reaction']:.0f} N, the seed's 8595 N "
              f"({_pct(8595 / (5 * axial['reaction']) - 1)}). "
              "No other variant matches both: a lower modulus can reproduce J (E = "
              f"{e_name[4:]}) but then gives {5 * inv[e_name]['reaction']:.0f} N; the independent EFG "
              f"reproduces both grip conditions ({efg_c['J']:.4f} clamped, {efg_a['J']:.4f} axial).",
              f"5. *The CMOD.* The seed's Abaqus CMOD 0.04252 mm matches the clamped model "
              f"({_pct(cf / 0.04252 - 1)}) better than the axial-only one "
              f"({_pct(axial['cmod'] / 0.04252 - 1)}). The seed does not say where or how it "
              "measured the CMOD; this is the one Abaqus number that does not fit the axial-only "
              "grips.",
              f"6. *An independent method.* Enriched EFG at {n_top} nodes across: {efg_txt} N/mm, "
              "i.e. the clamped FEM value. The seed's SPH (particle layers with prescribed "
              f"displacement at both ends) converges to 6.862 ({_pct(6.862 / Jf - 1)} from ours), "
              f"with CMOD 0.04248 ({_pct(0.04248 / cf - 1)}).",
              "", f"**Conclusion.** For the specimen as specified here (both displacement components "
              f"prescribed at the grips), J = {Jf:.3f} N/mm ({1e3 * Jf:.0f} J/m^2), converged to "
              "better than 0.05 % and confirmed by the energy release rate and by EFG. The seed's "
              f"Abaqus J = 6.786 is, to 0.01 %, the J of the same specimen with the transverse "
              f"displacement of the grips free ({axial['J']:.4f}), and its reported force is that "
              "model's reaction for a 5 mm thick specimen; its reference J was evidently computed "
              "without transverse clamping. The 1.1 % the seed reports between its SPH (clamped by "
              "particle layers) and Abaqus is this boundary-condition difference, not an SPH error: "
              f"against the clamped model the SPH J is {_pct(6.862 / Jf - 1)} off."]
    return lines


if __name__ == "__main__":
    import json

    print(json.dumps({k: v for k, v in main()["metrics"].items() if k.startswith(("J_", "cmod", "reaction"))},
                     indent=1))
