"""One study point on a worker: scene document in, result row out.

:func:`run_point` is the dask task. It receives the point as JSON text (the scene
document and the parameter values: kilobytes), builds the :class:`~efgkit.Scene` and
:class:`~efgkit.EFG` from it with :mod:`efgkit.scenefile`, runs the point's kind
(:data:`RUNNERS`) and returns one row, a JSON-ready dict (kilobytes): matrices, shape
functions and fields never leave the worker.

Every exception of the run is caught and becomes a row with ``status = "failed"``,
its ``error_type`` and ``error_message``: one bad point does not stop a study. Only
the death of the worker process itself (out of memory killed, node lost) reaches
the client, which then leaves the point to the next run.

Row keys: ``key``, ``kind``, ``params`` (name -> value), ``status`` (``"ok"`` |
``"failed"``), ``error_type``, ``error_message``, ``tips`` (one dict per crack tip:
``id, x, y, KI, KII, J, T, spread, error``), ``values`` (scalar results:
``n_nodes, n_dofs, energy, residual``), ``timings`` (seconds per stage and
``total``), ``warnings``, ``worker`` (host:pid), ``started``, ``finished`` (UTC, ISO
8601) and ``efgkit`` (version).
"""

from __future__ import annotations

import json
import math
import os
import socket
import time
import warnings
from contextlib import contextmanager
from datetime import datetime, timezone

from ..io import jsonable
from ..scenefile import efg_from_dict, scene_from_dict

__all__ = ["RUNNERS", "TIP_KEYS", "run_point", "solve_point"]

TIP_KEYS = ("KI", "KII", "J", "T", "spread", "error")  # per tip, in the table


def solve_point(doc: dict, options: dict) -> dict:
    """The ``"static"`` kind: solve the scene once and take K_I, K_II, J, T of every tip.

    Parameters
    ----------
    doc : dict
        A scene-file document with an ``[efg]`` table.
    options : dict
        ``error_estimate`` (bool): Richardson's error estimate of K from a solve at
        twice the spacing (:meth:`efgkit.Solution.sifs`).

    Returns
    -------
    dict
        ``tips``, ``values`` and ``timings`` of the row (module docstring).
    """
    from ..static import solve

    t0 = time.perf_counter()
    scene = scene_from_dict(doc)
    method = efg_from_dict(doc["efg"]) if "efg" in doc else None
    if method is None:
        raise ValueError("the point's scene has no [efg] table")
    timings = {"build": time.perf_counter() - t0}
    sol = solve(scene, method)
    timings.update({k: float(v) for k, v in sol.timings.items() if k != "total"})
    tips = ()
    if scene.tips:
        t0 = time.perf_counter()
        tips = sol.sifs(error=bool(options.get("error_estimate", True)))
        timings["sifs"] = time.perf_counter() - t0
    energy = sol.strain_energy()
    if not math.isfinite(energy):
        raise ArithmeticError(f"the solution is not finite (strain energy {energy!r}); a load, "
                              "modulus or length of the scene overflows: rescale its units")
    res = sol.info.get("residual")
    values = {**sol.sizes(), "energy": energy,
              "residual": float(res) if isinstance(res, (int, float)) else None}
    rows = [{"id": t.tip.id, "x": float(t.tip.x[0]), "y": float(t.tip.x[1]),
             **{k: getattr(t, k) for k in TIP_KEYS}} for t in tips]
    return {"tips": rows, "values": values, "timings": timings,
            "warnings": [w for t in tips for w in t.warnings]}


# kind -> runner(doc, options) -> {"tips", "values", "timings", "warnings"}; a growth
# path joins as another kind whose tips are those of its last step and whose values
# hold its step count and crack lengths.
RUNNERS = {"static": solve_point}


@contextmanager
def _numba_threads(n: int | None):
    """At most ``n`` numba threads inside (one per worker process: no oversubscription)."""
    if n is None:
        yield
        return
    import numba

    old = numba.get_num_threads()
    numba.set_num_threads(max(1, min(int(n), numba.config.NUMBA_NUM_THREADS)))
    try:
        yield
    finally:
        numba.set_num_threads(old)


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


def run_point(task, threads: int | None = None) -> dict:
    """Run one point and return its row (module docstring); never raises for the point's
    own failures.

    Parameters
    ----------
    task : str or dict
        :meth:`Point.task <efgkit.study.spec.Point.task>`: ``key``, ``kind``,
        ``params``, ``doc``, ``options``.
    threads : int, optional
        Numba threads for this point (None: leave as they are). BLAS threads are set by
        the worker's environment (``OMP_NUM_THREADS``; dask's nanny sets 1).
    """
    from .. import __version__

    if isinstance(task, str):
        task = json.loads(task)
    t_start = time.perf_counter()
    row = {"key": task["key"], "kind": task["kind"], "params": task["params"], "status": "ok",
           "error_type": None, "error_message": None, "tips": [], "values": {}, "timings": {},
           "warnings": [], "worker": f"{socket.gethostname()}:{os.getpid()}", "started": _now(),
           "efgkit": __version__}
    try:
        run = RUNNERS[task["kind"]]
        with _numba_threads(threads), warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out = run(task["doc"], task.get("options", {}))
        row.update(out)
        row["warnings"] = list(dict.fromkeys([*out.get("warnings", ()),
                                              *(str(w.message) for w in caught)]))
    except Exception as err:  # the point failed; the study goes on (module docstring)
        msg = str(err.args[0]) if isinstance(err, KeyError) and err.args else str(err)
        if isinstance(err, MemoryError):
            msg = msg or "out of memory: use a coarser spacing, or fewer workers per machine"
        row.update(status="failed", error_type=type(err).__name__,
                   error_message=" ".join(msg.split()) or type(err).__name__)
    row["timings"]["total"] = time.perf_counter() - t_start
    row["finished"] = _now()
    return jsonable(row)
