"""Writing scene-file tables: the inverse maps of :mod:`efgkit.scenefile.schema`, for round
trips and saving."""

from __future__ import annotations

import numpy as np

from ..methods.efg import EFG
from ..problem.exact.fields import Field
from ..problem.geometry import Loop
from ..problem.history import HISTORIES
from ..problem.scene import Scene
from ..problem.supports import Pressure
from .schema import SCHEMA, join_path

__all__ = ["efg_to_dict", "scene_to_dict"]


def _out(v, path: str):
    """A dataclass attribute as a scene-file value (TypeError for callables)."""
    if isinstance(v, Field):
        f = v.as_dict()
        return {"field": f.pop("name"), **f}
    if isinstance(v, Loop):
        return _loop_out(v)
    if isinstance(v, Pressure):
        return {"pressure": v.p}
    if isinstance(v, tuple(HISTORIES.values())):  # a load or support history
        return v.as_dict()
    tables = [t for t, (cls, _, _) in SCHEMA.items() if type(v) is cls]
    if tables:
        return _record(v, tables[0], path)
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (list, tuple)):
        return [_out(x, f"{path}[{i}]") for i, x in enumerate(v)]
    if isinstance(v, np.generic):
        return v.item()
    if callable(v) and not isinstance(v, str):  # an Expression is its formula
        raise TypeError(f"{path} is a Python callable; a scene file holds only numbers, "
                        "edge names and named fields ({ field = ... })")
    return v


def _record(obj, table: str, path: str) -> dict:
    values = {k: getattr(obj, k) for k, read in SCHEMA[table][2].items() if read}
    # () is left out, except EFG zones, where () (none) differs from None (automatic)
    return {k: _out(v, join_path(path, k)) for k, v in values.items()
            if v is not None and not (isinstance(v, tuple) and not v and k != "zones")}


def _loop_out(loop: Loop) -> dict:
    out = {"vertices": loop.vertices.tolist(), "edges": list(loop.names)}
    arcs = {str(k): {"centre": loop.centres[k].tolist(), "sweep": float(loop.sweeps[k])}
            for k in range(len(loop.vertices)) if loop.sweeps[k] != 0}
    return {**out, "arcs": arcs} if arcs else out


def scene_to_dict(scene: Scene) -> dict:
    """The scene-file table of ``scene`` (inverse of :func:`scene_from_dict`).

    Loops are written in the vertices form, as the domain stores them (outer
    counter-clockwise, holes clockwise). Raises TypeError for callables.
    """
    return _record(scene, "", "")


def efg_to_dict(efg: EFG) -> dict:
    """The ``[efg]`` table of ``efg`` (inverse of :func:`efg_from_dict`); None and () omitted."""
    return _record(efg, "efg", "efg")
