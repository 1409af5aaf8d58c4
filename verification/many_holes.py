"""Cracks growing in a plate with 31 randomly placed holes: seed 003 Sect. 6.5 (Figs. 60-62).

The seed (after Al-Ostaz and Jasiuk 1995): a plate with thirty-one randomly spaced holes,
2396 EFG nodes; a stress analysis without cracks finds the highest stresses, and small
cracks are seeded at the seven highest stress locations; the bottom edge is fixed and the
top edge displaced vertically, the displacement "incremented each step by 0.02 %"; the
enriched basis (Eq. 50) near each crack, ramped to linear. After 12 steps: "after a few
steps of growth, a few dominant cracks developed and the other cracks arrested. Some cracks
grew into other holes, but in general the cracks seemed to deflect away from the holes".

The seed gives no dimensions, no material and no toughness; chosen and stated here (N, mm,
MPa):

* plate 50 x 50 mm; 31 holes of radius R = 1.5 mm placed by random sequential addition
  (``np.random.default_rng(HOLE_SEED)``) with centres at least 2 R + 2.5 mm apart (ligaments
  of 2.5 mm or more) and at least R + 2 mm from the edges;
* a brittle polymer (Al-Ostaz and Jasiuk tested brittle polymer sheets): E = 3 GPa,
  nu = 0.35, plane stress, K_Ic = 0.8 MPa sqrt(m) = 25.3 MPa sqrt(mm);
* bottom edge fixed (ux = uy = 0), top edge uy = u, ux free;
* EFG h = ``FULL["h"]`` (0.75 mm: 4534 nodes with the seeded cracks, metric ``n_nodes``
  beside the seed's 2396, ``n_nodes_seed``; the seed's with enrichment; here no enrichment,
  as in verification/two_holes.py, so a finer grid), d_max = 2.5, diffraction, K from the
  interaction integral; growth direction by the maximum hoop stress (Erdogan and Sih 1963;
  the seed names none);
* crack seeding: the crack-free solve's von Mises stress (seed Fig. 61) sampled on circles
  of radius R + h/4 around every hole (96 angles); the seven holes with the highest peaks
  each get one radial crack of a0 = 1.5 mm (2 h) at their peak (one per hole: the hoop
  stress peaks twice per hole, on opposite sides, and the seed's seven cracks sit at seven
  different holes in Fig. 62a);
* loading by a toughness criterion (:func:`~efgkit.fracture.criteria.critical_load_factor`):
  step 0 is the strain eps_0 at which the most critical seeded tip reaches K_Ic; step n
  applies eps_n = eps_0 + n 0.02 % ("0.02 %" read as a strain increment of 2e-4, i.e. 0.02 %
  of the plate height per step; a 0.02 % relative increase would keep the load constant
  within 0.24 % over the 12 steps); every tip whose K_eq (at eps_n) reaches K_Ic grows by
  da = 1 mm (the others arrest for that step), by :func:`efgkit.growth.advance`: a tip
  reaching a hole or the edge becomes a mouth, one reaching another crack joins it; 12
  steps (13 solves) unless the cracks cut a piece off. The strain grows faster than the
  fixed da relieves a growing tip, so the tips that keep growing run above K_Ic (K_eq up to
  2.6 K_Ic after 12 steps): under displacement control they would run unstably; the seed's
  fixed increments per step do the same.

Quick mode: a 20 x 20 mm plate with 5 holes (the same rules, HOLE_SEED), 2 seeded cracks,
h = 1 mm, 2 steps.
"""

from __future__ import annotations

import math
import time
import warnings
from pathlib import Path

import numpy as np
from _report import Report

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, solve
from efgkit.fracture.criteria import critical_load_factor, hoop_stress
from efgkit.growth import advance
from efgkit.growth.extend import ray_hits
from efgkit.problem.geometry import Loop, segments_intersect

NAME = "many_holes"
TITLE = "Cracks growing in a plate with 31 random holes (seed 003 Sect. 6.5)"
ROOT = Path(__file__).resolve().parents[1]
HOLE_SEED = 7  # random hole layout, assumed
R = 1.5  # hole radius (mm), assumed
LIGAMENT, EDGE_GAP = 2.5, 2.0  # smallest hole-hole ligament, smallest hole-edge gap (mm), assumed
E, NU = 3000.0, 0.35  # brittle polymer (MPa), assumed; plane stress (sheet)
K_IC = 0.8 * math.sqrt(1000.0)  # 0.8 MPa sqrt(m) in MPa sqrt(mm), assumed
STRAIN_STEP = 2e-4  # seed 003 Sect. 6.5: "incremented each step by 0.02%" (read as strain)
EPS_REF = 1e-3  # reference strain of the solves (K scales linearly with it)
D_MAX = 2.5
FULL = {"size": 50.0, "holes": 31, "cracks": 7, "h": 0.75, "a0": 1.5, "da": 1.0, "steps": 12}
QUICK = {"size": 24.0, "holes": 4, "cracks": 2, "h": 1.5, "a0": 3.0, "da": 1.5, "steps": 1}


def hole_centres(size: float, n: int, seed: int = HOLE_SEED) -> np.ndarray:
    """``n`` hole centres ``(n, 2)`` in the plate ``[0, size]^2`` by random sequential addition:
    uniform candidates, kept when at least ``2 R + LIGAMENT`` from every kept centre."""
    rng = np.random.default_rng(seed)
    lo, hi = R + EDGE_GAP, size - R - EDGE_GAP
    out = np.zeros((0, 2))
    for _ in range(200 * n):  # candidates, drawn 64 at a time
        for c in rng.uniform(lo, hi, (64, 2)):
            if len(out) == 0 or np.hypot(*(out - c).T).min() >= 2 * R + LIGAMENT:
                out = np.vstack([out, c])
                if len(out) == n:
                    return out
    raise ValueError(f"could not place {n} holes of radius {R} in a {size} mm plate")


def plate(size: float, centres: np.ndarray, cracks=(), strain: float = EPS_REF) -> Scene:
    """The plate with holes at ``centres``: bottom fixed, top displaced by ``strain * size``."""
    dom = Domain.rectangle(0.0, 0.0, size, size,
                           holes=[Loop.circle(c, R, f"hole{k}") for k, c in enumerate(centres)])
    return Scene(dom, Elastic(E, NU, "stress"),
                 supports=(Support("bottom", ux=0.0, uy=0.0), Support("top", uy=strain * size)),
                 cracks=tuple(cracks), name="many_holes")


def method(h: float) -> EFG:
    return EFG(spacing=h, d_max=D_MAX, enrichment="none")


def seed_cracks(size, centres, n_cracks, h, a0):
    """Crack-free solve, von Mises on circles of radius R + h/4 around the holes, one radial
    crack of length ``a0`` at the peak of each of the ``n_cracks`` highest holes.
    Returns the cracks and the peaks (hole index, angle, von Mises over the nominal stress:
    the top edge's reaction over the width), and the nominal stress."""
    sol = solve(plate(size, centres), method(h))
    nominal = float(sol.reaction("top")[1]) / size
    th = np.linspace(0.0, 2 * np.pi, 96, endpoint=False)
    ring = np.column_stack([np.cos(th), np.sin(th)])
    pts = (centres[:, None, :] + (R + 0.25 * h) * ring[None]).reshape(-1, 2)
    s = sol.stress(pts)
    vm = np.sqrt(s[:, 0] ** 2 - s[:, 0] * s[:, 1] + s[:, 1] ** 2 + 3 * s[:, 2] ** 2).reshape(len(centres), -1)
    k = np.argmax(vm, axis=1)
    peak = vm[np.arange(len(centres)), k] / nominal
    top = np.argsort(-peak)[:n_cracks]
    cracks, info = [], []
    for j, i in enumerate(top):
        d = ring[k[i]]
        poly, _ = Loop.circle(centres[i], R).polyline()  # the mouth on the hole's polyline
        p0 = centres[i] + ray_hits(centres[i], d, np.stack([poly, np.roll(poly, -1, 0)], 1)).min() * d
        cracks.append(Crack([p0.tolist(), (p0 + a0 * d).tolist()], (False, True), f"c{j}"))
        info.append({"hole": int(i), "angle_deg": float(np.degrees(th[k[i]])),
                     "von_mises_over_nominal": float(peak[i])})
    return cracks, info, nominal


def kirsch_von_mises(h: float) -> float:
    """Von Mises stress over the remote stress S at r = R + h/4 beside an isolated hole in
    an infinite plate under uniaxial tension, across the load (Kirsch 1898):
    sigma_rr = 1.5 S (rho^2 - rho^4), sigma_tt = S (2 + rho^2 + 3 rho^4) / 2, rho = R / r."""
    rho = R / (R + 0.25 * h)
    srr, stt = 1.5 * (rho**2 - rho**4), 0.5 * (2 + rho**2 + 3 * rho**4)
    return math.sqrt(srr**2 - srr * stt + stt**2)


def run(cfg: dict) -> dict:
    """Seed the cracks, then grow them over ``cfg["steps"]`` load steps."""
    t0 = time.perf_counter()
    size, h, da = cfg["size"], cfg["h"], cfg["da"]
    centres = hole_centres(size, cfg["holes"])
    cracks, seeds, nominal = seed_cracks(size, centres, cfg["cracks"], h, cfg["a0"])
    scene = plate(size, centres, cracks)
    names = [c.name for c in cracks]
    hist = {"strain": [], "K_eq": [], "KI": [], "KII": [], "spread": [], "grows": [], "events": [],
            "n_nodes": [], "hole_gap": []}
    eps0, stop = None, None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the J-domain notes are kept in the spreads
        for n in range(cfg["steps"] + 1):
            sol = solve(scene, method(h))
            tips = sol.sifs(error=False)
            ids = [t.tip.crack for t in tips]
            hs = hoop_stress(np.array([t.KI for t in tips]), np.array([t.KII for t in tips]))
            if eps0 is None:
                eps0 = EPS_REF * critical_load_factor(hs.K_eq, K_IC)
            f = (eps0 + n * STRAIN_STEP) / EPS_REF
            K = f * hs.K_eq
            grows = [i for i, k, c in zip(ids, K, hs.closed, strict=True)
                     if not c and k >= K_IC * (1 - 1e-9)]  # K_Ic reached (to rounding at step 0)
            hist["strain"].append(eps0 + n * STRAIN_STEP)
            for key, v in (("K_eq", K), ("KI", f * np.array([t.KI for t in tips])),
                           ("KII", f * np.array([t.KII for t in tips])),
                           ("spread", [t.spread for t in tips])):
                hist[key].append({i: float(x) for i, x in zip(ids, v, strict=True)})
            hist["grows"].append(grows)
            hist["hole_gap"].append({t.tip.crack: float(np.hypot(*(centres - t.tip.x).T).min() - R)
                                     for t in tips})
            hist["n_nodes"].append(int(sol.nodes.n) if hasattr(sol.nodes, "n") else None)
            if n == cfg["steps"]:
                stop = f"{cfg['steps']} steps done"
                break
            if not grows:
                hist["events"].append([])
                continue
            moves = {f"{i}:1": (da, float(hs.angle[ids.index(i)])) for i in grows}
            adv = advance(scene, moves, snap=0.5)
            hist["events"].append(list(adv.events))
            if adv.scene is None:
                stop = adv.stop
                break
            scene = adv.scene
            if not scene.tips:
                stop = "every tip has joined a hole, the edge or another crack"
                break
    return {"centres": centres.tolist(), "seeds": seeds, "nominal_stress_ref": nominal,
            "names": names, "eps0": eps0,
            "stop": stop, "vertices": {c.name: c.vertices.tolist() for c in scene.cracks},
            "tips": {c.name: list(c.tips) for c in scene.cracks}, "history": hist,
            "n_solves": len(hist["strain"]), "seconds": time.perf_counter() - t0,
            "scene": scene}


def where_ends(scene: Scene, centres: np.ndarray) -> list[str]:
    """Where the grown ends that are no longer tips lie: "edge", "hole" or "crack" (the
    seeded ends, vertex 0, are on their holes)."""
    out = []
    size = scene.domain.bbox[2]
    for c in scene.cracks:
        if c.tips[1]:
            continue
        p = c.vertices[-1]
        if min(p.min(), size - p.max()) <= 1e-9 * size:
            out.append("edge")
        elif np.hypot(*(centres - p).T).min() <= R * (1 + 1e-3):  # on the hole's polyline
            out.append("hole")
        else:
            out.append("crack")
    return out


def crossings(scene: Scene) -> int:
    """Crack segments that cross the boundary (holes, edges) anywhere but at a mouth vertex,
    counted independently of the Scene's own check."""
    bnd = scene.domain.boundary_segments()
    bad = 0
    for c in scene.cracks:
        for k, (a, b) in enumerate(c.segments):
            a = a + 1e-7 * (b - a) if k == 0 and not c.tips[0] else a
            b = b + 1e-7 * (a - b) if k == len(c.segments) - 1 and not c.tips[1] else b
            bad += int(segments_intersect(np.broadcast_to(a, (len(bnd), 2)),
                                          np.broadcast_to(b, (len(bnd), 2)), bnd[:, 0], bnd[:, 1]).any())
    return bad


def figure(r: dict, cfg: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 6))
    for c in r["centres"]:
        ax.add_patch(plt.Circle(c, R, fc="0.85", ec="k", lw=0.6))
    grown = {i for g in r["history"]["grows"] for i in g}
    for k, (name, v) in enumerate(r["vertices"].items()):
        v = np.asarray(v)
        ax.plot(v[:, 0], v[:, 1], "-", lw=2.0 if name in grown else 1.2,
                color=f"C{k}", label=f"{name} ({len(v) - 2} segments grown)")
        ax.plot(*v[1], "k.", ms=3)  # the seeded crack's tip
    ax.set(xlim=(0, cfg["size"]), ylim=(0, cfg["size"]), aspect="equal", xlabel="x (mm)",
           ylabel="y (mm)", title=f"{len(r['centres'])} holes, {len(r['names'])} seeded cracks, "
           f"{r['n_solves'] - 1} load steps")
    ax.legend(fontsize=7, loc="upper right")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main(quick: bool = False, out_dir=None) -> dict:
    rep = Report(NAME, quick)
    cfg = QUICK if quick else FULL
    r = run(cfg)
    scene = r.pop("scene")
    hist = r["history"]
    steps = cfg["steps"]
    done = hist["grows"][:len(hist["events"])]  # the last solve's growers are not advanced
    n_grow = {i: sum(i in g for g in done) for i in r["names"]}
    late = {i for g in done[steps // 2:] for i in g}  # grew in the second half
    ends = where_ends(scene, np.asarray(r["centres"]))
    joined_hole, joined_edge = ends.count("hole"), ends.count("edge")
    joined_crack = sum(1 for ev in hist["events"] for e in ev if "joined crack" in e)
    # J-domain spread at the growing tips, apart for tips within h of a hole (their J
    # domains cross the hole, whose boundary term the domain integral leaves out)
    spreads = [(s[i], gap[i]) for s, gap, grows in zip(hist["spread"], hist["hole_gap"], done,
                                                       strict=False) for i in grows]
    far = [s for s, gap in spreads if gap > cfg["h"]]
    near = [s for s, gap in spreads if gap <= cfg["h"]]
    r.update({"n_nodes": hist["n_nodes"][0], "n_nodes_seed": 2396,  # reported, not checked
              "n_grow": n_grow, "late_growers": sorted(late), "joined_hole": joined_hole,
              "joined_edge": joined_edge, "joined_crack": joined_crack,
              "max_spread_growing_far": max(far, default=None),
              "max_spread_growing_near_hole": max(near, default=None), "config": cfg,
              "plate": {"size": cfg["size"], "hole_radius": R, "ligament": LIGAMENT,
                        "edge_gap": EDGE_GAP, "E": E, "nu": NU, "K_Ic": K_IC,
                        "strain_step": STRAIN_STEP, "hole_seed": HOLE_SEED}})
    rep.metrics.update(r)
    rep.ref("n_holes", 31, "seed 003 Sect. 6.5")
    rep.ref("n_cracks", 7, "seed 003 Sect. 6.5: cracks seeded at the seven highest stress locations")
    rep.ref("steps", 12, "seed 003 Sect. 6.5, Fig. 62b: 12 steps of crack growth")
    rep.ref("strain_step", STRAIN_STEP, "seed 003 Sect. 6.5: displacement incremented by 0.02 % "
            "per step (read here as 0.02 % of the height)")
    rep.ref("nodes", 2396, "seed 003 Sect. 6.5 (enriched basis near the cracks)")
    kirsch = kirsch_von_mises(cfg["h"])
    rep.ref("kirsch_von_mises", kirsch, "Kirsch (1898): von Mises / S at r = R + h/4 beside "
            "an isolated hole, across the load")
    rep.check("seeded holes: smallest von Mises peak (over the nominal stress) / Kirsch's "
              "isolated hole at the same radius (the seven highest of the random holes: their "
              "neighbours raise the peak)",
              min(s["von_mises_over_nominal"] for s in r["seeds"]) / kirsch, ">=", 1.0)
    rep.check("crack segments crossing a hole or an edge (paths stay in the body; a path "
              "reaching a hole stops there)", float(crossings(scene)), "<=", 0.0)
    if quick:
        rep.check("the most critical seeded crack grows at step 0 (it is at K_Ic by the load "
                  "factor)", float(len(hist["grows"][0])), ">=", 1.0)
    else:
        # seed 003 Sect. 6.5: "a few dominant cracks developed and the other cracks arrested"
        rep.check("dominant cracks: cracks growing in the second half of the steps (seed: a "
                  "few of the 7)", float(len(late)), "<=", 3.0)
        rep.check("dominant cracks: at least one crack still grows in the second half",
                  float(len(late)), ">=", 1.0)
        rep.check("arrested cracks: seeded cracks that grow in the second half of the steps "
                  "no more (seed: the other cracks arrested)",
                  float(len(r["names"]) - len(late)), ">=", 4.0)
        rep.check("cracks that grew into another hole (seed: some cracks grew into other "
                  "holes)", float(joined_hole), ">=", 1.0)
        if far:
            rep.check("largest J-domain spread of K at a growing tip more than h from every "
                      "hole (domain independence)", float(max(far)), "<=", 0.1)
        fig_dir = ROOT / "docs" / "figures"
        fig_dir.mkdir(parents=True, exist_ok=True)
        path = fig_dir / f"{NAME}_paths.png"
        figure(r, cfg, path)
        rep.figures = [str(path)]
    return rep.write(out_dir)


def markdown(record: dict) -> list[str]:
    m = record["metrics"]
    p, cfg, hist = m["plate"], m["config"], m["history"]
    rows = ["| crack | hole | seeded at (deg) | von Mises / nominal | steps grown | K_eq / K_Ic at "
            "step 0 -> last solve (ended: on a hole, the edge or a crack) |", "|---|---|---|---|---|---|"]
    for name, s in zip(m["names"], m["seeds"], strict=True):
        k0 = hist["K_eq"][0].get(name)
        k1 = hist["K_eq"][-1].get(name)
        ks = "-" if k0 is None else f"{k0 / p['K_Ic']:.2f} -> " + ("ended" if k1 is None
                                                                 else f"{k1 / p['K_Ic']:.2f}")
        rows.append(f"| {name} | {s['hole']} | {s['angle_deg']:.0f} | "
                    f"{s['von_mises_over_nominal']:.2f} | {m['n_grow'][name]} | {ks} |")
    return [f"Plate {p['size']:g} x {p['size']:g} mm with {len(m['centres'])} holes of radius "
            f"{p['hole_radius']:g} mm (random sequential addition, seed {p['hole_seed']}, "
            f"ligaments >= {p['ligament']:g} mm), E = {p['E']:g} MPa, nu = {p['nu']:g}, "
            f"K_Ic = {p['K_Ic']:.1f} MPa sqrt(mm) (all assumed: the seed gives no dimensions); "
            f"EFG h = {cfg['h']:g} mm ({m.get('n_nodes', hist['n_nodes'][0])} nodes at step 0; "
            f"seed: {m.get('n_nodes_seed', 2396)} with enrichment), a0 = {cfg['a0']:g} mm, "
            f"da = {cfg['da']:g} mm; strain eps_0 = "
            f"{m['eps0']:.4%} (the most critical tip at K_Ic), then + {p['strain_step']:.2%} per "
            f"step. {m['n_solves']} solves with cracks (and the crack-free one) in {m['seconds']:.0f} s; "
            f"stop: {m['stop']}.", "",
            *rows, "",
            f"Cracks growing in the second half of the steps: {', '.join(m['late_growers']) or 'none'}; "
            f"tips that reached another hole: {m['joined_hole']}, the outer edge: "
            f"{m['joined_edge']}, joined another crack: {m['joined_crack']}. Largest J-domain "
            f"spread of K at a growing tip: {_e(m['max_spread_growing_far'])} more than h from "
            f"every hole, {_e(m['max_spread_growing_near_hole'])} within h of a hole (its J "
            "domains cross the hole).", "", f"![paths](figures/{NAME}_paths.png)"]


def _e(v) -> str:
    return "-" if v is None else f"{v:.3f}"


if __name__ == "__main__":
    import sys

    res = main(quick="--quick" in sys.argv)
    print(res["passed"], [(c["what"][:60], c["value"], c["passed"]) for c in res["checks"]])
