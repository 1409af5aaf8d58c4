"""The EFG deciding runs of the interleaved work-precision benchmark, this tree against an
earlier revision, and the FEM deciding runs, timed in turns in one process.

Run:  git -C <repo> archive <rev> | tar -x -C /tmp/base
      PYTHONPATH=. python benchmarks/work_before_after.py --base /tmp/base --rounds 41

The earlier revision's package is copied to a temporary folder as ``efgkit_base`` (its
absolute ``efgkit`` imports renamed) and imported beside this tree's ``efgkit``. For each
problem (the settings of :data:`SETTINGS`, the deciding runs of the interleaved benchmark
in docs/performance.md) the whole pipeline, ``solve(scene, EFG(...))`` then ``sifs``, runs
as new, base, FEM, new, base, FEM, ... after three warm-up rounds, each call on a scene
built once by that package's own gallery. Prints K_I and J of new and base (their relative
difference) and the median times with the ratios of each round (median and a bootstrap
90 % interval of the median, np.random.default_rng(0), 2000 resamples). ``--candidates``:
instead, K_I, K_II and J of every EFG candidate of :mod:`work_interleaved` and of its
refinement, new against base.
"""

from __future__ import annotations

import argparse
import re
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

SETTINGS = {  # problem: (EFG spacing, (FEM h, tip h)); EFG extrinsic MLS, Nitsche, orders 3/4, tip 6
    "singular patch": (1.0, (1.0, 0.3)),
    "SENT": (2.0, (2.0, 0.5)),
}
EFG_OPTIONS = dict(enrichment="extrinsic_mls", bc="variational", order=3, refined_order=4, tip_order=6)


def import_base(tree: Path):
    """The package of the exported revision ``tree`` imported as ``efgkit_base``."""
    tmp = Path(tempfile.mkdtemp(prefix="efgkit_base_"))
    dst = tmp / "efgkit_base"
    shutil.copytree(tree / "efgkit", dst)
    for f in dst.rglob("*.py"):
        text = f.read_text()
        new = re.sub(r"\b(from|import) efgkit\b", r"\1 efgkit_base", text)
        if new != text:
            f.write_text(new)
    sys.path.insert(0, str(tmp))
    import efgkit_base

    return efgkit_base


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", type=Path, required=True, help="an exported tree of the earlier revision")
    ap.add_argument("--rounds", type=int, default=41)
    ap.add_argument("--candidates", action="store_true",
                    help="instead: K_I, K_II and J of every EFG candidate of work_interleaved (and "
                         "its refinement, half the spacing), new against base")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import work_precision as wp

    import efgkit
    from efgkit.fem.model import FEM, solve_fem

    base = import_base(args.base)
    import efgkit_base.gallery as base_gallery

    base_scenes = {"singular patch": lambda: base_gallery.singular_patch(1.0, 0.0, name="singular patch"),
                   "SENT": base_gallery.sent_seed001}
    if args.candidates:
        return same_results(wp, efgkit, base, base_scenes)
    rng = np.random.default_rng(0)
    for problem, setting in SETTINGS.items():
        compare(problem, setting, wp, efgkit, base, base_scenes[problem](), FEM, solve_fem, args.rounds, rng)


def same_results(wp, efgkit, base, base_scenes) -> None:
    """The largest relative difference of K_I, K_II and J (over |K_I|, |J|) of every EFG candidate."""
    import work_interleaved as wi

    worst, n = 0.0, 0
    for problem, spec in wi.EFG_CANDIDATES.items():
        radii = wp.PROBLEMS[problem]["radii"]
        sc_new, sc_old = wp.PROBLEMS[problem]["scene"](), base_scenes[problem]()
        for variant, options in spec["variants"].items():
            for h in sorted({float(h) for h in spec["spacing"]} | {float(h) / 2 for h in spec["spacing"]}):
                a = efgkit.solve(sc_new, efgkit.EFG(spacing=h, **options)).sifs(radii=radii, error=False)[0]
                b = base.solve(sc_old, base.EFG(spacing=h, **options)).sifs(radii=radii, error=False)[0]
                d = max(abs(a.KI - b.KI) / abs(b.KI), abs(a.KII - b.KII) / abs(b.KI), abs(a.J / b.J - 1))
                worst, n = max(worst, d), n + 1
                print(f"{problem}, {variant}, h = {h:.4g}: {d:.1e}")
    print(f"{n} runs: largest relative difference {worst:.1e}")


def compare(problem, setting, wp, efgkit, base, sc_old, FEM, solve_fem, rounds, rng) -> None:  # noqa: N803
    """Time new, base and FEM of ``problem`` in turns and print the medians and ratios."""
    h, (fh, fth) = setting
    radii = wp.PROBLEMS[problem]["radii"]
    sc_new = wp.PROBLEMS[problem]["scene"]()
    m_new, m_old = efgkit.EFG(spacing=h, **EFG_OPTIONS), base.EFG(spacing=h, **EFG_OPTIONS)
    fem = FEM(fh, tip_h=fth, quarter_point=True)
    runs = {"new": lambda: efgkit.solve(sc_new, m_new).sifs(radii=radii, error=False)[0],
            "base": lambda: base.solve(sc_old, m_old).sifs(radii=radii, error=False)[0],
            "fem": lambda: solve_fem(sc_new, fem).sifs(radii=radii, error=False)[0]}
    a, b = runs["new"](), runs["base"]()
    print(f"{problem}: K_I new {a.KI:.15g} base {b.KI:.15g} (relative difference "
          f"{abs(a.KI / b.KI - 1):.1e}), J relative difference {abs(a.J / b.J - 1):.1e}")
    for _ in range(3):
        for f in runs.values():
            f()
    from turns import median_interval, take_turns

    t = take_turns(runs, rounds)

    def ratio(x, y):
        r = np.array(t[x]) / np.array(t[y])
        lo, hi = median_interval(r, rng)
        return f"{np.median(r):.3f} ({lo:.3f} - {hi:.3f})"

    print(f"  median s: new {statistics.median(t['new']):.4f}, base {statistics.median(t['base']):.4f}, "
          f"FEM {statistics.median(t['fem']):.4f}; new / base {ratio('new', 'base')}, "
          f"new / FEM {ratio('new', 'fem')}, base / FEM {ratio('base', 'fem')}")

if __name__ == "__main__":
    main()
