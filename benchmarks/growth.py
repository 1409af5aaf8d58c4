"""Crack growth: time of an incremental system update against a full rebuild.

An edge crack in the unit square (tension on the top edge), EFG with fixed zones (none),
extrinsic MLS enrichment ramped over ``enrich_radius = 2 h`` (the growth loop's default
enrichment), cells of one spacing with 4 x 4 Gauss points. Each step extends the crack by
``da = 2 h`` at a kink angle, then times, interleaved in the same process,

* the incremental update (:func:`efgkit.growth.incremental.update`: nodes and points
  regenerated and matched, shape rows of the affected points, K -= old + new rows, f), and
* the full rebuild (:func:`efgkit.growth.incremental.assemble`: ``discretize``, the
  stiffness of all points, the loads),

both ending with the same K and f before the constraints and the linear solve (which is the
same in both and not timed). ``step_time_ratio`` is the median over steps of the ratio of
the two times; the max-norm relative difference of the two K is reported too.

Run:  python benchmarks/growth.py                   (20k and 100k nodes)
      python benchmarks/growth.py --sides 141 224   (20k and 50k nodes)
      python benchmarks/growth.py --quick           (small, a smoke run)
"""

from __future__ import annotations

import argparse
import gc
import json
import platform
import statistics
import time
from pathlib import Path

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, Traction
from efgkit.growth.incremental import assemble, update
from efgkit.io import write_json

ROOT = Path(__file__).resolve().parents[1]
ANGLES = (0.3, -0.2, 0.25, -0.3, 0.1, -0.15)


def scene_and_method(n_side: int, enrichment: str = "auto"):
    """The benchmark scene (n_side^2 grid nodes) and its EFG ("auto": ramped extrinsic MLS
    over 2 h; "pu": PU nodes within 1.5 h of the tip)."""
    h = 1.0 / (n_side - 1)
    sc = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3, "strain"),
               supports=(Support("bottom", uy=0.0), Support("left", ux=0.0)),
               tractions=(Traction("top", (0.0, 1.0)),),
               cracks=(Crack([[0.0, 0.5 + h / 3], [0.3, 0.5 + h / 3]], tips=(False, True)),))
    radius = 1.5 * h if enrichment == "pu" else 2 * h
    return sc, EFG(spacing=h, zones=(), enrichment=enrichment, enrich_radius=radius), h


def ratio_run(n_side: int, steps: int, enrichment: str = "auto") -> dict:
    """Interleaved incremental / full timings over ``steps`` growth steps."""
    sc, m, h = scene_and_method(n_side, enrichment)
    prev = assemble(sc, m)  # also compiles the kernels
    inc, full, diffs, frac = [], [], [], []
    for k in range(steps):
        sc = sc.with_cracks((sc.cracks[0].extended(2 * h, ANGLES[k % len(ANGLES)]),))
        gc.collect()  # both timings start from the same heap state
        t0 = time.perf_counter()
        new = update(prev, sc, m)
        t1 = time.perf_counter()
        gc.collect()
        t1b = time.perf_counter()
        ref = assemble(sc, m)
        t2 = time.perf_counter()
        if new.reason is not None:
            raise RuntimeError(f"the update fell back to a full rebuild: {new.reason}")
        inc.append(t1 - t0)
        full.append(t2 - t1b)
        diffs.append(float(abs(new.K - ref.K).max() / abs(ref.K).max()))
        frac.append(new.recomputed / len(ref.disc.points.w))
        prev = new
        del ref
    return {"n_nodes": int(prev.disc.nodes.n), "n_points": int(len(prev.disc.points.w)),
            "n_dofs": int(prev.disc.n_dofs), "steps": steps,
            "incremental_s": [round(t, 4) for t in inc], "full_s": [round(t, 4) for t in full],
            "step_time_ratio": statistics.median(a / b for a, b in zip(inc, full, strict=True)),
            "recomputed_fraction": statistics.median(frac),
            "max_rel_K_difference": max(diffs)}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sides", type=int, nargs="+", default=[141, 317],
                    help="grid nodes per side (141: ~20k nodes, 224: ~50k, 317: ~100k)")
    ap.add_argument("--steps", type=int, default=4)
    ap.add_argument("--enrichment", choices=("auto", "pu"), default="auto")
    ap.add_argument("--no-write", action="store_true", help="do not write benchmarks/out")
    args = ap.parse_args(argv)
    sides = [41] if args.quick else args.sides
    res = {"machine": f"{platform.machine()}, {platform.python_implementation()} "
                      f"{platform.python_version()}",
           "date": time.strftime("%Y-%m-%d"), "command": "python benchmarks/growth.py"
           + (" --quick" if args.quick else f" --sides {' '.join(map(str, sides))}"
              f" --steps {args.steps}") + ("" if args.enrichment == "auto"
                                            else f" --enrichment {args.enrichment}")}
    runs = [ratio_run(s, args.steps, args.enrichment) for s in sides]
    res["runs"] = runs
    res["step_time_ratio"] = {str(r["n_nodes"]): r["step_time_ratio"] for r in runs}
    if not args.no_write:
        name = "growth.json" if args.enrichment == "auto" else f"growth_{args.enrichment}.json"
        write_json(res, ROOT / "benchmarks" / "out" / name)
    return res


if __name__ == "__main__":
    print(json.dumps(main(), indent=1, default=str))
