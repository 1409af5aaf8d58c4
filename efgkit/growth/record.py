"""Files of a growth loop: the JSON event log, the restart file, VTU per step, figures.

* ``<out>/growth_log.jsonl``: one JSON object per step (:func:`step_record`), appended as
  the loop runs, so a long loop that is stopped keeps its history;
* ``<out>/growth_restart.json``: the :class:`~efgkit.growth.loop.GrowthState` after the
  last step (:func:`save_state`); :func:`load_state` reads it and ``grow(..., start=...)``
  goes on from there, reaching the same result as an uninterrupted loop;
* ``<out>/growth_<k>.vtu`` per step (optional) and ``growth_path.png``, ``growth_K.png``
  (``growth_life.png`` for Paris loops) at the end.

Floats are written with ``repr`` (JSON), which reads back to the same bits: a restart
continues from exactly the saved cracks.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..io import jsonable, write_figure, write_json
from ..problem.crack import Crack
from .loop import GrowthState, GrowthStep, grow

__all__ = ["LOG_NAME", "RESTART_NAME", "load_state", "run", "save_state", "step_record"]

LOG_NAME = "growth_log.jsonl"
RESTART_NAME = "growth_restart.json"
_VERSION = 1


def step_record(step: GrowthStep) -> dict:
    """JSON-ready summary of a step: index, crack lengths and vertices, per tip id, x, y,
    KI, KII, kink angle (radians and degrees), K_eq, closed, da, the load factor, cycles,
    events, stop and timings."""
    tips = []
    for t, a, k, c in zip(step.tips, step.kink, step.K_eq, step.closed, strict=True):
        tips.append({"id": t.tip.id, "x": float(t.tip.x[0]), "y": float(t.tip.x[1]), "KI": t.KI,
                     "KII": t.KII, "kink": float(a), "kink_deg": float(np.degrees(a)),
                     "K_eq": float(k), "closed": bool(c), "spread": t.spread, "error": t.error,
                     "da": step.da.get(t.tip.id, 0.0), "warnings": list(t.warnings)})
    return jsonable({"step": step.index, "lengths": step.lengths,
                     "cracks": {c.name: c.vertices.tolist() for c in step.scene.cracks},
                     "tips": tips, "load_factor": step.load_factor, "cycles": step.cycles,
                     "events": list(step.events), "stop": step.stop, "seconds": step.seconds})


def save_state(state: GrowthState, path) -> Path:
    """Write a restart file (JSON) of ``state``; returns the path."""
    if not isinstance(state, GrowthState):
        raise TypeError(f"state must be a GrowthState, got {type(state).__name__}")
    obj = {"version": _VERSION, "index": state.index, "cycles": state.cycles,
           "cracks": [{"name": c.name, "vertices": c.vertices.tolist(), "tips": list(c.tips),
                       "pressure": c.pressure} for c in state.cracks],
           "previous": state.previous, "events": list(state.events)}
    return write_json(jsonable(obj), path)


def load_state(path) -> GrowthState:
    """Read a restart file written by :func:`save_state` (or :func:`run`).

    Raises
    ------
    ValueError
        The file is not a growth restart file (or of another version).
    """
    path = Path(path)
    try:
        obj = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as err:
        raise ValueError(f"restart file {str(path)!r} cannot be read as JSON ({err}); give the "
                         f"{RESTART_NAME} that a growth run wrote") from err
    if not isinstance(obj, dict) or obj.get("version") != _VERSION or "cracks" not in obj:
        raise ValueError(f"{str(path)!r} is not a growth restart file (version {_VERSION}); give "
                         f"the {RESTART_NAME} that a growth run wrote")
    cracks = tuple(Crack(np.array(c["vertices"], dtype=float), tuple(c["tips"]), c["name"],
                         c["pressure"]) for c in obj["cracks"])
    return GrowthState(int(obj["index"]), cracks, float(obj["cycles"]), obj["previous"],
                       tuple(obj["events"]))


def run(scene, method, settings, out, start: GrowthState | None = None, vtu: bool = False,
        figures: bool = True, on_step: Callable[[GrowthStep], None] | None = None) -> dict:
    """Run :func:`~efgkit.growth.loop.grow` writing its files into the directory ``out``.

    Parameters
    ----------
    scene, method, settings, start
        As for :func:`~efgkit.growth.loop.grow`.
    out : path
        Directory (created); the log is started afresh unless ``start`` is given, when the
        steps are appended to it.
    vtu : bool
        Write the fields of every step (``growth_<k>.vtu``).
    figures : bool
        Write the path and K figures at the end.
    on_step : callable ``step -> None``, optional
        Called after each step (the CLI's progress bar).

    Returns
    -------
    dict
        ``steps`` (the step records), ``stop``, ``outputs`` (paths).
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    log = out / LOG_NAME
    if start is None and log.exists():
        log.unlink()
    records, steps, outputs = [], [], [log]
    for step in grow(scene, method, settings, start):
        rec = step_record(step)
        if vtu:
            p = step.solution.write_vtu(out / f"growth_{step.index:04d}.vtu")
            rec["vtu"] = str(p)
            outputs.append(p)
        with log.open("a") as f:
            f.write(json.dumps(rec) + "\n")
        if step.state is not None:
            save_state(step.state, out / RESTART_NAME)
        records.append(rec)
        steps.append(step)
        if on_step is not None:
            on_step(step)
    if (out / RESTART_NAME).exists():
        outputs.append(out / RESTART_NAME)
    if figures:
        from .figures import plot_k, plot_life, plot_path

        outputs.append(write_figure(plot_path(steps, n_target=5000), out / "growth_path.png"))
        outputs.append(write_figure(plot_k(steps), out / "growth_K.png"))
        if steps[-1].cycles is not None:
            outputs.append(write_figure(plot_life(steps), out / "growth_life.png"))
    return {"steps": records, "stop": steps[-1].stop, "outputs": [str(p) for p in outputs]}
