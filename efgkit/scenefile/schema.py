"""Reading scene-file tables: the schema (table -> dataclass, keys, readers) and the checks
that name the key path of every error (the package docstring says how)."""

from __future__ import annotations

import math
from collections.abc import Callable
from contextlib import contextmanager

import numpy as np

from ..methods.efg import EFG, Rosette, Zone
from ..problem import Expression, PointSupport, Scene, Support, Symmetry, Traction, VectorExpression
from ..problem.crack import Crack
from ..problem.exact.fields import Field
from ..problem.geometry import Domain, Loop
from ..problem.graded import Grading
from ..problem.history import history_from_dict, with_time_table
from ..problem.material import Elastic
from ..problem.supports import Pressure
from ..tables import check_known_keys

__all__ = ["SCHEMA", "check_finite", "efg_from_dict", "join_path", "key_path", "scene_from_dict"]

_RECTANGLE_EDGES = ("bottom", "right", "top", "left")
_LOOP_FORMS = ("vertices", "rectangle", "circle")


# --- checking helpers: each names the key path ------------------------------------------

def join_path(path: str, key) -> str:
    return f"{path}.{key}" if path else str(key)


def _where(path: str) -> str:
    return f"table '{path}'" if path else "scene file (top level)"


def _keys(d, path: str, required=(), optional=()) -> dict:
    """Check that ``d`` is a table with all ``required`` keys and no others."""
    if not isinstance(d, dict):
        raise TypeError(f"{path or 'the scene file'} must be a table, got {d!r}")
    check_known_keys(d, (*required, *optional), _where(path))
    for k in required:
        if k not in d:
            raise ValueError(f"missing required key {k!r} in {_where(path)}")
    return d


def check_finite(v, path: str) -> None:
    """Reject NaN and inf anywhere in a nested table (TOML has nan/inf literals)."""
    if isinstance(v, dict):
        for k, x in v.items():
            check_finite(x, join_path(path, k))
    elif isinstance(v, (list, tuple)):
        for i, x in enumerate(v):
            check_finite(x, f"{path}[{i}]")
    elif isinstance(v, np.ndarray) and v.dtype.kind in "fc":
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{path} holds NaN or inf; every number must be finite")
    elif isinstance(v, (float, np.floating)) and not math.isfinite(v):
        raise ValueError(f"{path} = {v!r}; every number in a scene file must be finite")


@contextmanager
def key_path(path: str):
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
    name = _str(d["field"], join_path(path, "field"))
    params = tuple((k, tuple(v) if isinstance(v, list) else v)
                   for k, v in d.items() if k != "field")
    with key_path(path):
        return Field(name, params)


def _scalar(v, path: str) -> float | Field | Expression:
    return _field(v, path) if isinstance(v, dict) else Expression(v) if isinstance(v, str) else _num(v, path)


def _vector(v, path: str) -> tuple[float, float] | Field | VectorExpression:
    return _field(v, path) if isinstance(v, dict) else VectorExpression.read(v) or _floats(v, path, 2)


def _traction(v, path: str) -> tuple[float, float] | Field | VectorExpression | Pressure:
    """A traction's ``t``: a vector, a field, or ``{ pressure = p }`` (:class:`Pressure`:
    the traction ``-p n``, ``p > 0`` pushing into the body)."""
    if isinstance(v, dict) and "pressure" in v:
        _keys(v, path, ("pressure",))
        p = _num(v["pressure"], join_path(path, "pressure"))
        with key_path(path):
            return Pressure(p)
    return _vector(v, path)


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
        c = _keys(d["circle"], join_path(path, "circle"), ("centre", "radius"))
        centre = _floats(c["centre"], join_path(path, "circle.centre"), 2)
        radius = _num(c["radius"], join_path(path, "circle.radius"))
        name = _str(d.get("name", "hole"), join_path(path, "name"))
        with key_path(path):
            return Loop.circle(centre, radius, name)
    if forms == ["rectangle"]:
        _keys(d, path, ("rectangle",), ("edges",))
        x0, y0, x1, y1 = _floats(d["rectangle"], join_path(path, "rectangle"), 4)
        if not (x1 > x0 and y1 > y0):
            raise ValueError(f"{join_path(path, 'rectangle')} = [x0, y0, x1, y1] needs x1 > x0 "
                             f"and y1 > y0, got {[x0, y0, x1, y1]}")
        names = _strs(d.get("edges", _RECTANGLE_EDGES), join_path(path, "edges"))
        with key_path(path):
            return Loop.polygon([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], names)
    _keys(d, path, ("vertices",), ("edges", "arcs"))
    v = _points(d["vertices"], join_path(path, "vertices"))
    n = len(v)
    names = (_strs(d["edges"], join_path(path, "edges")) if "edges" in d
             else tuple(f"edge{k}" for k in range(n)))
    centres, sweeps = np.full((n, 2), np.nan), np.zeros(n)
    arcs = d.get("arcs", {})
    if not isinstance(arcs, dict):
        raise TypeError(f"{join_path(path, 'arcs')} must be a table {{ edge index = {{ centre, "
                        f"sweep }} }}, got {arcs!r}")
    for key, arc in arcs.items():
        p = join_path(path, f"arcs.{key}")
        if not (str(key).isdigit() and int(key) < n):
            raise ValueError(f"{join_path(path, 'arcs')}: key {key!r} is not an edge index; a loop "
                             f"of {n} vertices has edges 0 to {n - 1} (edge k runs from "
                             "vertices[k] to vertices[k + 1])")
        _keys(arc, p, ("centre", "sweep"))
        k = int(key)
        centres[k] = _floats(arc["centre"], join_path(p, "centre"), 2)
        sweeps[k] = _num(arc["sweep"], join_path(p, "sweep"))
        if sweeps[k] == 0:
            raise ValueError(f"{p}.sweep is 0 (a straight edge); remove the arc entry")
    with key_path(path):
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
SCHEMA: dict[str, tuple[type, tuple[str, ...], dict[str, Callable | None]]] = {
    "": (Scene, ("material", "domain"), {
        "name": _str, "material": _one("material"), "domain": _one("domain"),
        "supports": _many("supports"), "tractions": _many("tractions"),
        "body_force": lambda v, path: VectorExpression.read(v) or _pair(v, path),
        "cracks": _many("cracks"), "exact": _field, "duration": _num,
        "point_supports": _many("point_supports"), "symmetry": _one("symmetry"), "efg": None,
        "time": None, "growth": None, "body_force_history": history_from_dict,
        "initial_displacement": _vector, "initial_velocity": _vector, "method": None,
        "mlpg": None, "load_cases": None, "grading": _one("grading"),
        "dsif": None}),  # [dsif]: efgkit.explicit.dsif_table
    "material": (Elastic, ("E", "nu"), {"E": _num, "nu": _num, "plane": _str, "rho": _num}),
    "domain": (Domain, ("outer",), {"outer": _loop, "holes": _many("holes", _loop)}),
    "supports": (Support, ("edge",), {"edge": _str, "ux": _scalar, "uy": _scalar,
                                        "history": history_from_dict}),
    "tractions": (Traction, ("edge", "t"), {"edge": _str, "t": _traction, "history": history_from_dict}),
    "point_supports": (PointSupport, ("x",), {"x": _pair, "ux": _num, "uy": _num}),
    "grading": (Grading, (), {"modulus": _scalar, "density": _scalar}),
    "symmetry": (Symmetry, ("lines",), {"lines": _list, "cracks": _many("cracks")}),
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
    cls, required, readers = SCHEMA[table]
    _keys(d, path, required, tuple(k for k in readers if k not in required))
    kw = {k: readers[k](v, join_path(path, k)) for k, v in d.items() if readers[k] is not None}
    with key_path(path):
        return cls(**kw)


def scene_from_dict(d: dict) -> Scene:
    """Build a :class:`Scene` from a parsed scene file (the top-level table).

    An ``efg`` key is allowed and ignored here (see :func:`efg_from_dict`).

    Raises
    ------
    ValueError, TypeError
        Naming the key path (see the module docstring).
    """
    check_finite(d, "")
    scene = _table(with_time_table(d), "", "")  # [time] carries the duration of a dynamic scene
    if "dsif" in d and scene.is_static:
        raise ValueError("a [dsif] table sets the dynamic SIFs of an explicit run, and this scene "
                         "is static: add a [time] table or remove [dsif]")
    return scene


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
    check_finite(d, path)
    return _table(d, "efg", path)
