"""Verification reports: the JSON record every verification script writes.

Format of ``verification/out/<name>.json``::

    {"name": str, "passed": bool, "quick": bool,
     "metrics": {key: value, ...},
     "reference": {key: {"value": ..., "source": "seed file / equation / table"}},
     "checks": [{"what": str, "value": float, "bound": float, "passed": bool}, ...],
     "figures": [paths]}
"""

from __future__ import annotations

import json
import math
from pathlib import Path

__all__ = ["Report", "VERIFICATION_OUT", "growth_figures"]

VERIFICATION_OUT = Path(__file__).resolve().parent / "out"


def _clean(obj):
    """JSON-safe copy: tuples and arrays to lists, numpy scalars to floats, non-finite to
    strings."""
    if getattr(obj, "ndim", 0):  # a numpy array (not a scalar): its elements, recursively
        obj = obj.tolist()
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if hasattr(obj, "item") and not isinstance(obj, (str, bytes)):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return str(obj)
    return obj


class Report:
    """Collects metrics, references and pass/fail checks of one verification script.

    Examples
    --------
    >>> r = Report("demo", quick=True)
    >>> r.check("error", 1e-8, "<=", 1e-6)
    True
    >>> r.result()["passed"]
    True
    """

    def __init__(self, name: str, quick: bool):
        self.name, self.quick = name, quick
        self.metrics: dict = {}
        self.reference: dict = {}
        self.checks: list = []
        self.figures: list = []

    def ref(self, key: str, value, source: str) -> None:
        self.reference[key] = {"value": value, "source": source}

    def check(self, what: str, value: float, op: str, bound: float) -> bool:
        """Record ``value op bound`` (op in "<=", ">=")."""
        ok = bool(value <= bound) if op == "<=" else bool(value >= bound)
        ok = ok and math.isfinite(value)
        self.checks.append({"what": what, "value": value, "op": op, "bound": bound, "passed": ok})
        return ok

    def result(self) -> dict:
        return _clean({"name": self.name, "passed": all(c["passed"] for c in self.checks),
                       "quick": self.quick, "metrics": self.metrics,
                       "reference": self.reference, "checks": self.checks,
                       "figures": self.figures})

    def write(self, out_dir: Path | None = None) -> dict:
        """Write ``<out_dir>/<name>.json`` (quick runs: ``<name>_quick.json``) and return it."""
        out = Path(out_dir) if out_dir is not None else VERIFICATION_OUT
        out.mkdir(parents=True, exist_ok=True)
        res = self.result()
        suffix = "_quick" if self.quick else ""
        (out / f"{self.name}{suffix}.json").write_text(json.dumps(res, indent=1) + "\n")
        return res


def growth_figures(steps, fig_dir, stem: str, path_name: str = "path") -> list[str]:
    """The crack-path and K-history figures of growth ``steps`` as
    ``fig_dir/<stem>_<path_name>.png`` and ``fig_dir/<stem>_K.png``; their paths."""
    import matplotlib.pyplot as plt

    from efgkit.growth.figures import plot_k, plot_path

    fig_dir = Path(fig_dir)
    fig_dir.mkdir(parents=True, exist_ok=True)
    out = []
    for what, plot in ((path_name, plot_path), ("K", plot_k)):
        fig = plot(steps)
        p = fig_dir / f"{stem}_{what}.png"
        fig.savefig(p, dpi=110, bbox_inches="tight")
        plt.close(fig)
        out.append(str(p))
    return out
