"""Scene files: TOML documents that map one to one onto :class:`Scene` and :class:`EFG`.

A scene file holds the physical problem (top-level keys, ``[material]``,
``[domain]``, ``[[supports]]``, ``[[tractions]]``, ``[[cracks]]``, ``[exact]``)
and optionally the discretisation (``[efg]``). Every key is documented in
``docs/scenes.md``. Values are in the user's consistent units and are never
converted. Where a Python scene takes a callable, a file takes a named
analytic field, written as a table ``{ field = "kirsch", a = 1.0 }``
(:class:`~efgkit.problem.exact.fields.Field`).

The reader is strict: an unknown key is an error that names the key, its
table and the nearest valid key; a missing required key, a wrong type or a
NaN/inf value is an error naming the key path (``supports[1].ux``). Errors of
the dataclasses themselves (``nu`` out of range, a support on an edge the
domain does not have) propagate with their message, prefixed with the key
path and, from :func:`load_scene` / :func:`load_study`, the file path.

Examples
--------
>>> scene = scene_from_dict({
...     "material": {"E": 1000.0, "nu": 0.3, "plane": "stress"},
...     "domain": {"outer": {"rectangle": [0.0, 0.0, 1.0, 1.0]}},
...     "supports": [{"edge": "left", "ux": 0.0}, {"edge": "bottom", "uy": 0.0}],
...     "tractions": [{"edge": "right", "t": [1.0, 0.0]}],
... })
>>> sorted(scene.domain.edge_names), scene.tractions[0].t
(['bottom', 'left', 'right', 'top'], (1.0, 0.0))
>>> scene_from_dict({"material": {"E": 1.0, "nu": 0.3}, "domain": {}, "suports": []})
Traceback (most recent call last):
...
ValueError: unknown key 'suports' in scene file (top level); did you mean 'supports'?
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .methods.efg import EFG, Rosette, Zone
from .methods.mlpg_file import study_method
from .problem.crack import Crack
from .problem.exact.fields import Field
from .problem.geometry import Domain, Loop
from .problem.material import Elastic
from .problem.scene import Scene, Support, Traction

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["efg_from_dict", "efg_to_dict", "load_scene", "load_study", "scene_from_dict",
           "scene_to_dict"]

_RECTANGLE_EDGES = ("bottom", "right", "top", "left")
_LOOP_FORMS = ("vertices", "rectangle", "circle")


# --- checking helpers: each names the key path ------------------------------------------

def _join(path: str, key) -> str:
    return f"{path}.{key}" if path else str(key)


def _where(path: str) -> str:
    return f"table '{path}'" if path else "scene file (top level)"


def _keys(d, path: str, required=(), optional=()) -> dict:
    """Check that ``d`` is a table with all ``required`` keys and no others."""
    if not isinstance(d, dict):
        raise TypeError(f"{path or 'the scene file'} must be a table, got {d!r}")
    valid = (*required, *optional)
    for k in d:
        if k not in valid:
            near = difflib.get_close_matches(str(k), valid, n=1)
            hint = f"did you mean {near[0]!r}?" if near else f"valid keys: {', '.join(valid)}"
            raise ValueError(f"unknown key {k!r} in {_where(path)}; {hint}")
    for k in required:
        if k not in d:
            raise ValueError(f"missing required key {k!r} in {_where(path)}")
    return d


def _check_finite(v, path: str) -> None:
    """Reject NaN and inf anywhere in a nested table (TOML has nan/inf literals)."""
    if isinstance(v, dict):
        for k, x in v.items():
            _check_finite(x, _join(path, k))
    elif isinstance(v, (list, tuple)):
        for i, x in enumerate(v):
            _check_finite(x, f"{path}[{i}]")
    elif isinstance(v, np.ndarray) and v.dtype.kind in "fc":
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{path} holds NaN or inf; every number must be finite")
    elif isinstance(v, (float, np.floating)) and not math.isfinite(v):
        raise ValueError(f"{path} = {v!r}; every number in a scene file must be finite")


@contextmanager
def _at(path: str):
    """Prefix ValueError/TypeError messages raised inside with ``path: `` (if any)."""
    if not path:
        yield
        return
    try:
        yield
    except (ValueError, TypeError) as e:
        cls = TypeError if isinstance(e, TypeError) else ValueError
        raise cls(f"{path}: {e}") from e


def _typed(v, path: str, types: tuple, what: str):
    if not isinstance(v, types) or (isinstance(v, bool) and bool not in types):
        raise TypeError(f"{path} must be {what}, got {v!r}")
    return v


def _num(v, path: str) -> float:
    return float(_typed(v, path, (int, float, np.integer, np.floating), "a number"))


def _int(v, path: str) -> int:
    return int(_typed(v, path, (int, np.integer), "an integer"))


def _str(v, path: str) -> str:
    return _typed(v, path, (str,), "a string")


def _list(v, path: str, n: int | None = None) -> list:
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if not isinstance(v, (list, tuple)):
        raise TypeError(f"{path} must be an array, got {v!r}")
    if n is not None and len(v) != n:
        raise ValueError(f"{path} must have {n} entries, got {len(v)}: {v!r}")
    return list(v)


def _floats(v, path: str, n: int | None = None) -> tuple[float, ...]:
    return tuple(_num(x, f"{path}[{i}]") for i, x in enumerate(_list(v, path, n)))


def _points(v, path: str) -> np.ndarray:
    """An array of [x, y] pairs -> ndarray (n, 2)."""
    rows = [_floats(p, f"{path}[{i}]", 2) for i, p in enumerate(_list(v, path))]
    return np.array(rows, dtype=float).reshape(-1, 2)


def _strs(v, path: str) -> tuple[str, ...]:
    return tuple(_str(x, f"{path}[{i}]") for i, x in enumerate(_list(v, path)))


# --- values: numbers or named analytic fields -------------------------------------------

def _field(d: dict, path: str) -> Field:
    """``{ field = name, param = value, ... }`` -> Field (parameters checked by Field)."""
    if not isinstance(d, dict):
        raise TypeError(f"{path} must be a table {{ field = name, ... }}, got {d!r}")
    if "field" not in d:
        raise ValueError(f"missing required key 'field' in {_where(path)} "
                         "(a field value is { field = \"name\", parameter = value, ... })")
    name = _str(d["field"], _join(path, "field"))
    params = tuple((k, tuple(v) if isinstance(v, list) else v)
                   for k, v in d.items() if k != "field")
    with _at(path):
        return Field(name, params)


def _scalar(v, path: str) -> float | Field:
    return _field(v, path) if isinstance(v, dict) else _num(v, path)


def _vector(v, path: str) -> tuple[float, float] | Field:
    return _field(v, path) if isinstance(v, dict) else _floats(v, path, 2)


# --- geometry ---------------------------------------------------------------------------

def _loop(d, path: str) -> Loop:
    """A loop table in one of three forms: vertices (+ edges, arcs), rectangle, circle."""
    if not isinstance(d, dict):
        raise TypeError(f"{path} must be a table, got {d!r}")
    forms = [k for k in _LOOP_FORMS if k in d]
    if len(forms) != 1:
        raise ValueError(f"{_where(path)} needs exactly one of the keys 'vertices', "
                         f"'rectangle', 'circle'; got {forms or 'none of them'}")
    if forms == ["circle"]:
        _keys(d, path, ("circle",), ("name",))
        c = _keys(d["circle"], _join(path, "circle"), ("centre", "radius"))
        centre = _floats(c["centre"], _join(path, "circle.centre"), 2)
        radius = _num(c["radius"], _join(path, "circle.radius"))
        name = _str(d.get("name", "hole"), _join(path, "name"))
        with _at(path):
            return Loop.circle(centre, radius, name)
    if forms == ["rectangle"]:
        _keys(d, path, ("rectangle",), ("edges",))
        x0, y0, x1, y1 = _floats(d["rectangle"], _join(path, "rectangle"), 4)
        if not (x1 > x0 and y1 > y0):
            raise ValueError(f"{_join(path, 'rectangle')} = [x0, y0, x1, y1] needs x1 > x0 "
                             f"and y1 > y0, got {[x0, y0, x1, y1]}")
        names = _strs(d.get("edges", _RECTANGLE_EDGES), _join(path, "edges"))
        with _at(path):
            return Loop.polygon([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], names)
    _keys(d, path, ("vertices",), ("edges", "arcs"))
    v = _points(d["vertices"], _join(path, "vertices"))
    n = len(v)
    names = (_strs(d["edges"], _join(path, "edges")) if "edges" in d
             else tuple(f"edge{k}" for k in range(n)))
    centres, sweeps = np.full((n, 2), np.nan), np.zeros(n)
    arcs = d.get("arcs", {})
    if not isinstance(arcs, dict):
        raise TypeError(f"{_join(path, 'arcs')} must be a table {{ edge index = {{ centre, "
                        f"sweep }} }}, got {arcs!r}")
    for key, arc in arcs.items():
        p = _join(path, f"arcs.{key}")
        if not (str(key).isdigit() and int(key) < n):
            raise ValueError(f"{_join(path, 'arcs')}: key {key!r} is not an edge index; a loop "
                             f"of {n} vertices has edges 0 to {n - 1} (edge k runs from "
                             "vertices[k] to vertices[k + 1])")
        _keys(arc, p, ("centre", "sweep"))
        k = int(key)
        centres[k] = _floats(arc["centre"], _join(p, "centre"), 2)
        sweeps[k] = _num(arc["sweep"], _join(p, "sweep"))
        if sweeps[k] == 0:
            raise ValueError(f"{p}.sweep is 0 (a straight edge); remove the arc entry")
    with _at(path):
        return Loop(v, names, centres, sweeps)


def _tips(v, path: str) -> tuple[bool, bool]:
    return tuple(_typed(t, f"{path}[{i}]", (bool,), "true or false")
                 for i, t in enumerate(_list(v, path, 2)))


def _pair(v, path: str) -> tuple[float, float]:
    return _floats(v, path, 2)


def _one(table: str) -> Callable:
    """Reader of a sub-table ``[table]``."""
    return lambda v, path: _table(v, table, path)


def _many(table: str, read: Callable | None = None) -> Callable:
    """Reader of an array of tables ``[[table]]`` (each read by ``read``)."""
    def reader(v, path):
        if isinstance(v, dict):
            raise TypeError(f"{path} must be an array of tables ([[{path}]]), got one table")
        return tuple((read or _one(table))(t, f"{path}[{i}]") for i, t in enumerate(_list(v, path)))
    return reader


# Table name -> (dataclass, required keys, {key: reader}): the schema, one to one with the
# dataclass fields (a test checks this). Readers take (value, key path); "efg" at the top
# level is read by efg_from_dict, not by Scene.
_SCHEMA: dict[str, tuple[type, tuple[str, ...], dict[str, Callable | None]]] = {
    "": (Scene, ("material", "domain"), {
        "name": _str, "material": _one("material"), "domain": _one("domain"),
        "supports": _many("supports"), "tractions": _many("tractions"),
        "body_force": _pair, "cracks": _many("cracks"), "exact": _field,
        "duration": _num, "efg": None, "method": None, "mlpg": None}),
    "material": (Elastic, ("E", "nu"), {"E": _num, "nu": _num, "plane": _str, "rho": _num}),
    "domain": (Domain, ("outer",), {"outer": _loop, "holes": _many("holes", _loop)}),
    "supports": (Support, ("edge",), {"edge": _str, "ux": _scalar, "uy": _scalar}),
    "tractions": (Traction, ("edge", "t"), {"edge": _str, "t": _vector}),
    "cracks": (Crack, ("vertices",), {"vertices": _points, "tips": _tips, "name": _str,
                                      "pressure": _num}),
    "zones": (Zone, ("centre", "radius", "spacing"),
              {"centre": _pair, "radius": _num, "spacing": _num}),
    "rosette": (Rosette, ("radius",), {"radius": _num, "rings": _int, "per_ring": _int}),
    "efg": (EFG, ("spacing",), {
        "spacing": _num, "zones": _many("zones"), "perturb": _num, "seed": _int,
        "coordinates": _points, "d_max": _num, "weight": _str, "alpha": _num,
        "basis": _str, "quadrature": _str, "order": _int, "refined_order": _int,
        "cell_size": _num, "bc": _str, "penalty": _num, "solver": _str,
        "crack_rule": _str, "rule_power": _num, "hole_rule": _str, "kappa": _num,
        "rosette": _one("rosette"),
        "enrichment": _str, "enrich_radius": _num, "ramp": _str, "ramp_inner": _num,
        "tip_order": _int}),
}


def _table(d, table: str, path: str):
    """Check the keys of ``d``, read each value, build the table's dataclass."""
    cls, required, readers = _SCHEMA[table]
    _keys(d, path, required, tuple(k for k in readers if k not in required))
    kw = {k: readers[k](v, _join(path, k)) for k, v in d.items() if readers[k] is not None}
    with _at(path):
        return cls(**kw)


def scene_from_dict(d: dict) -> Scene:
    """Build a :class:`Scene` from a parsed scene file (the top-level table).

    An ``efg`` key is allowed and ignored here (see :func:`efg_from_dict`).

    Raises
    ------
    ValueError, TypeError
        Naming the key path (see the module docstring).
    """
    _check_finite(d, "")
    return _table(d, "", "")


def efg_from_dict(d: dict, path: str = "efg") -> EFG:
    """Build an :class:`EFG` from the ``[efg]`` table of a scene file.

    Keys are the fields of :class:`EFG` (only ``spacing`` is required);
    ``zones`` is an array of ``{ centre, radius, spacing }`` tables and
    ``coordinates`` an array of ``[x, y]`` pairs.

    Examples
    --------
    >>> m = efg_from_dict({"spacing": 0.25, "zones": [{"centre": [0, 0], "radius": 2,
    ...                                                 "spacing": 0.1}]})
    >>> m.spacing, m.zones[0].centre
    (0.25, (0.0, 0.0))
    """
    _check_finite(d, path)
    return _table(d, "efg", path)


# --- files ------------------------------------------------------------------------------

def _read(path) -> tuple[Path, dict]:
    path = Path(path)
    with open(path, "rb") as f:
        try:
            d = tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            raise ValueError(f"{path}: not a valid TOML file: {e}") from e
    d.setdefault("name", path.stem)
    return path, d


def load_scene(path) -> Scene:
    """Read a scene file. ``name`` defaults to the file's stem.

    The whole file is checked, including an ``[efg]`` table if there is one.
    Errors are prefixed with the file path.
    """
    path, d = _read(path)
    with _at(str(path)):
        scene = scene_from_dict(d)
        if "efg" in d:
            efg_from_dict(d["efg"])
    return scene


def load_study(path) -> tuple[Scene, EFG]:
    """Read a scene file with its discretisation: ``(Scene, EFG)`` (``[efg]`` required), or
    ``(Scene, MLPG)`` with ``method = "mlpg"`` (:mod:`efgkit.methods.mlpg_file`)."""
    path, d = _read(path)
    with _at(str(path)):
        return scene_from_dict(d), study_method(d, efg_from_dict)


# --- writing (the inverse maps, for round trips and saving) -----------------------------

def _out(v, path: str):
    """A dataclass attribute as a scene-file value (TypeError for callables)."""
    if isinstance(v, Field):
        f = v.as_dict()
        return {"field": f.pop("name"), **f}
    if isinstance(v, Loop):
        return _loop_out(v)
    tables = [t for t, (cls, _, _) in _SCHEMA.items() if type(v) is cls]
    if tables:
        return _record(v, tables[0], path)
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (list, tuple)):
        return [_out(x, f"{path}[{i}]") for i, x in enumerate(v)]
    if isinstance(v, np.generic):
        return v.item()
    if callable(v):
        raise TypeError(f"{path} is a Python callable; a scene file holds only numbers, "
                        "edge names and named fields ({ field = ... })")
    return v


def _record(obj, table: str, path: str) -> dict:
    values = {k: getattr(obj, k) for k, read in _SCHEMA[table][2].items() if read}
    # () is left out, except EFG zones, where () (none) differs from None (automatic)
    return {k: _out(v, _join(path, k)) for k, v in values.items()
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
