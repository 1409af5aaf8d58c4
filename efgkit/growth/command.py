"""``efgkit run`` on a scene file with a ``[growth]`` table: the loop, its files, a report.

The CLI stays thin (one call): this builds the :class:`~efgkit.growth.settings.Growth`
from the table, runs :func:`~efgkit.growth.record.run` into the output directory and
returns the JSON-ready report that ``efgkit run`` prints.
"""

from __future__ import annotations

import math
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from ..io import jsonable
from .record import run
from .settings import Growth

__all__ = ["growth_table", "run_table", "summary"]


def growth_table(path) -> dict | None:
    """The ``[growth]`` table of a scene file (checked to be a table of finite numbers,
    strings and booleans), or None without one; :meth:`Growth.from_dict` reads its keys
    (docs/scenes.md). Call it on a file :func:`efgkit.load_study` has read."""
    path = Path(path)
    with open(path, "rb") as f:
        d = tomllib.load(f)
    if "growth" not in d:
        return None
    g = d["growth"]
    if not isinstance(g, dict):
        raise TypeError(f"{path}: growth must be a table ([growth]), got {g!r}")
    for k, v in g.items():
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"{path}: growth.{k} must be finite, got {v!r}")
    return g


def run_table(scene, method, table: dict, out, vtu: bool = False, on_step=None) -> dict:
    """Run the growth loop of ``table`` (a ``[growth]`` table) on ``scene`` with ``method``
    (EFG), writing into ``out``; returns the report: ``scene``, ``growth`` (the settings),
    ``stop``, ``n_steps``, ``steps`` (per-step records) and ``outputs``.

    Raises
    ------
    ValueError, TypeError
        A bad ``[growth]`` table (naming ``growth.<key>``).
    """
    settings = Growth.from_dict(table)
    res = run(scene, method, settings, out, vtu=vtu, on_step=on_step)
    rep = {"scene": scene.name, "growth": {k: getattr(settings, k) for k in Growth.keys()},
           "stop": res["stop"], "n_steps": len(res["steps"]) - 1, "steps": res["steps"],
           "outputs": res["outputs"]}
    return jsonable(rep)


def summary(rep: dict) -> str:
    """Text summary of a growth report: one line per step (tips, K, kink) and the stop."""
    lines = [f"scene {rep['scene']}: {rep['n_steps']} growth steps"]
    for s in rep["steps"]:
        tips = "; ".join(f"{t['id']} K_I {t['KI']:.5g} K_II {t['KII']:.5g} kink {t['kink_deg']:.3g} deg"
                         for t in s["tips"])
        extra = f", N = {s['cycles']:.6g}" if s.get("cycles") is not None else ""
        lines.append(f"  step {s['step']}: {tips}{extra}")
    lines.append(f"stopped: {rep['stop']}")
    lines += [f"wrote {p}" for p in rep["outputs"]]
    return "\n".join(lines)
