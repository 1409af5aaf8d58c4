"""Dotted paths into a parsed scene file: read and replace one value of a nested TOML table.

A path names one value of the scene-file data (``docs/scenes.md``) by its keys and
array indices joined with dots: ``material.E``, ``efg.spacing``,
``cracks.0.vertices.1.0`` (the x of the second vertex of the first crack),
``tractions.0.t.1``. ``method`` stands for the scene's method table (``efg``), so a
study can say ``method.spacing`` whatever the method is.

A path must exist in the base document: a key the base leaves at its default is
written in the base scene file first, then varied (this keeps a misspelt path an error
instead of a new key). Errors name the study path, the part that failed and what
the document holds there.

Examples
--------
>>> doc = {"material": {"E": 1.0, "nu": 0.3}, "cracks": [{"vertices": [[0, 0], [1, 0]]}],
...        "efg": {"spacing": 0.1}}
>>> get_path(doc, "cracks.0.vertices.1.0")
1
>>> new = set_path(doc, "method.spacing", 0.05)
>>> new["efg"], doc["efg"]  # a copy; the base is unchanged
({'spacing': 0.05}, {'spacing': 0.1})
>>> set_path(doc, "material.EE", 2.0)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
ValueError: study parameter 'material.EE': the scene has no key 'EE' in table 'material' ...
"""

from __future__ import annotations

import copy
import difflib

__all__ = ["METHOD_TABLES", "get_path", "resolve_path", "set_path"]

METHOD_TABLES = ("efg", "mlpg")  # the tables ``method.`` may stand for, in this order


def resolve_path(doc: dict, path: str) -> tuple:
    """The keys and indices of ``path`` in ``doc``, checked: a tuple of str and int.

    Parameters
    ----------
    doc : dict
        The parsed scene file (top-level table).
    path : str
        Dotted path (module docstring).

    Raises
    ------
    TypeError
        ``path`` is not a string.
    ValueError
        A part of ``path`` is empty, names a key the document does not have, indexes
        past the end of an array, or descends into a number or string.
    """
    if not isinstance(path, str):
        raise TypeError(f"a study parameter path must be a string such as 'material.E', got {path!r}")
    parts = path.split(".")
    if not path or any(p == "" for p in parts):
        raise ValueError(f"study parameter {path!r}: empty part in the dotted path; write keys "
                         "and indices joined by single dots, e.g. 'cracks.0.vertices.1.0'")
    if parts[0] == "method":
        tables = [t for t in METHOD_TABLES if t in doc]
        if not tables:
            raise ValueError(f"study parameter {path!r}: 'method' stands for the scene's method "
                             f"table ({' or '.join(METHOD_TABLES)}), and the base scene has none; "
                             "add an [efg] table to the base scene file")
        parts[0] = tables[0]
    keys, node, where = [], doc, ""
    for part in parts:
        if isinstance(node, dict):
            if part not in node:
                near = difflib.get_close_matches(part, [str(k) for k in node], n=1)
                hint = f"; did you mean {near[0]!r}?" if near else "."
                table = f"table {where!r}" if where else "the top level"
                raise ValueError(
                    f"study parameter {path!r}: the scene has no key {part!r} in {table} "
                    f"(its keys: {', '.join(map(str, node)) or 'none'}){hint} To vary a key the "
                    "base scene leaves at its default, write it in the base scene file")
            key = part
        elif isinstance(node, list):
            if not part.isdigit():
                raise ValueError(f"study parameter {path!r}: {where!r} is an array; {part!r} must "
                                 f"be an index 0 to {len(node) - 1}")
            key = int(part)
            if key >= len(node):
                raise ValueError(f"study parameter {path!r}: index {key} is past the end of "
                                 f"{where!r}, which has {len(node)} entries (indices 0 to "
                                 f"{len(node) - 1})")
        else:
            raise ValueError(f"study parameter {path!r}: {where!r} is the value {node!r}, which "
                             f"has no part {part!r}; the path ends at {where!r}")
        keys.append(key)
        node = node[key]
        where = f"{where}.{part}" if where else part
    return tuple(keys)


def get_path(doc: dict, path: str):
    """The value at ``path`` in ``doc`` (see :func:`resolve_path` for the errors)."""
    node = doc
    for k in resolve_path(doc, path):
        node = node[k]
    return node


def set_path(doc: dict, path: str, value) -> dict:
    """A deep copy of ``doc`` with the value at ``path`` replaced by ``value``.

    Raises
    ------
    ValueError, TypeError
        As :func:`resolve_path`.
    """
    keys = resolve_path(doc, path)
    out = copy.deepcopy(doc)
    node = out
    for k in keys[:-1]:
        node = node[k]
    node[keys[-1]] = value
    return out
