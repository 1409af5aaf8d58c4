"""Named load cases in a scene file: ``[[load_cases]]`` tables, each a name and its loads.

The body, material, cracks' geometry, supports and discretisation are the scene's (the
top level); each case holds its whole load: ``tractions`` (an array of traction tables,
as ``[[tractions]]``), ``body_force`` (as the top-level key) and ``crack_pressure`` (one
number per ``[[cracks]]`` entry, in their order). A key a case leaves out is no load of
that kind. A case may give its own prescribed values: ``supports`` and ``point_supports``
(arrays of tables as ``[[supports]]`` and ``[[point_supports]]``) replace the top level's
for that case, on the same edges and points with the same components (only the values may
differ: :func:`~efgkit.loadcases.solve_cases` checks it); left out, the top level's hold.
The top level then holds no load of its own (no ``[[tractions]]``, no ``body_force``, no
crack ``pressure``): a ValueError says so, so that no load is
silently added to or dropped from the cases. A scene without ``[[load_cases]]`` is read
as before. :func:`efgkit.loadcases.solve_cases` solves the cases with one factorisation.

Examples
--------
>>> d = {"material": {"E": 1000.0, "nu": 0.3}, "domain": {"outer": {"rectangle": [0, 0, 2, 1]}},
...      "supports": [{"edge": "left", "ux": 0.0}, {"edge": "bottom", "uy": 0.0}],
...      "load_cases": [{"name": "pull", "tractions": [{"edge": "right", "t": [1.0, 0.0]}]},
...                     {"name": "weight", "body_force": [0.0, -1.0]}]}
>>> cases = cases_from_dict(d)
>>> list(cases), cases["pull"].tractions[0].t, cases["weight"].body_force
(['pull', 'weight'], (1.0, 0.0), (0.0, -1.0))
>>> cases_to_list(cases) == d["load_cases"]
True
"""

from __future__ import annotations

from dataclasses import replace

from ..problem.scene import Scene
from ..tables import check_known_keys
from .schema import SCHEMA, check_finite, join_path, key_path, scene_from_dict
from .writer import scene_to_dict

__all__ = ["CASE_KEYS", "cases_from_dict", "cases_to_list"]

CASE_KEYS = ("name", "tractions", "body_force", "crack_pressure", "supports", "point_supports")


def _check_table(d, path: str) -> dict:
    """``d`` is a table with a ``name`` and only the keys of :data:`CASE_KEYS`."""
    if not isinstance(d, dict):
        raise TypeError(f"{path} must be a table {{ name = ..., tractions = [...], ... }}, got {d!r}")
    check_known_keys(d, CASE_KEYS, f"table '{path}'", f" (a load case holds {', '.join(CASE_KEYS)})")
    if "name" not in d:
        raise ValueError(f"missing required key 'name' in table '{path}'")
    if not isinstance(d["name"], str) or not d["name"]:
        raise TypeError(f"{path}.name must be a non-empty string, got {d['name']!r}")
    return d


def _pressures(v, path: str, n: int) -> tuple[float, ...]:
    if not isinstance(v, list) or len(v) != n:
        raise ValueError(f"{path} must be an array of {n} numbers, one per [[cracks]] entry in "
                         f"their order, got {v!r}")
    for i, p in enumerate(v):
        if isinstance(p, bool) or not isinstance(p, (int, float)):
            raise TypeError(f"{path}[{i}] must be a number, got {p!r}")
    return tuple(float(p) for p in v)


def cases_from_dict(d: dict) -> dict[str, Scene] | None:
    """The load cases ``{name: Scene}`` of a parsed scene file, in file order, or None
    without ``[[load_cases]]``.

    Each case is the top-level scene with the case's loads (the module docstring).

    Raises
    ------
    ValueError, TypeError
        Naming the key path: a duplicate or missing name, an unknown key, a load at the
        top level besides the cases, a bad value (as for the top-level keys).
    """
    if "load_cases" not in d:
        return None
    check_finite(d, "")
    raw = d["load_cases"]
    if not isinstance(raw, list) or not raw:
        raise TypeError(f"load_cases must be a non-empty array of tables ([[load_cases]]), got {raw!r}")
    top = [k for k in ("tractions", "body_force") if k in d]
    top += [f"cracks[{i}].pressure" for i, c in enumerate(d.get("cracks", ()))
            if isinstance(c, dict) and c.get("pressure", 0) != 0]
    if top:
        raise ValueError(f"the top level holds loads ({', '.join(top)}) besides [[load_cases]]: "
                         "each load case lists its whole load; move them into the cases")
    base = scene_from_dict({k: v for k, v in d.items() if k != "load_cases"})
    cases: dict[str, Scene] = {}
    for i, c in enumerate(raw):
        path = f"load_cases[{i}]"
        _check_table(c, path)
        name = c["name"]
        if name in cases:
            raise ValueError(f"{path}.name: duplicate load case name {name!r} (also "
                             f"load_cases[{list(cases).index(name)}]); give each case its own name")
        readers = SCHEMA[""][2]  # the top-level readers check the values, naming the key
        loads = {"tractions": (), "body_force": None} | {
            k: readers[k](c[k], join_path(path, k))
            for k in ("tractions", "body_force", "supports", "point_supports") if k in c}
        cracks = base.cracks
        if "crack_pressure" in c:
            ps = _pressures(c["crack_pressure"], join_path(path, "crack_pressure"), len(cracks))
            with key_path(join_path(path, "crack_pressure")):
                cracks = tuple(replace(k, pressure=p) for k, p in zip(cracks, ps, strict=True))
        with key_path(path):  # the Scene checks the edges the tractions name
            cases[name] = replace(base, **loads, cracks=cracks)
    return cases


def cases_to_list(cases: dict[str, Scene]) -> list[dict]:
    """The ``[[load_cases]]`` tables of ``{name: Scene}`` (inverse of :func:`cases_from_dict`):
    each case's name, tractions, body force and, where a crack is pressurised, the crack
    pressures; empty loads are left out, and so are supports equal to the first case's (the
    top level's)."""
    out = []
    first = next(iter(cases.values()), None)
    for name, sc in cases.items():
        d = scene_to_dict(sc)
        case = {"name": name, **{k: d[k] for k in ("tractions", "body_force") if k in d}}
        for k in ("supports", "point_supports"):
            if getattr(sc, k) != getattr(first, k):
                case[k] = d.get(k, [])
        if any(c.pressure != 0 for c in sc.cracks):
            case["crack_pressure"] = [c.pressure for c in sc.cracks]
        out.append(case)
    return out
