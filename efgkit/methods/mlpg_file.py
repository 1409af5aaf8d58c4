"""The discretisation of a scene file: ``method = "efg" | "mlpg"`` and the ``[mlpg]`` table.

A scene file chooses its method with the top-level key ``method`` (default ``"efg"``).
``method = "mlpg"`` reads the ``[mlpg]`` table (keys: the fields of :class:`MLPG`); without
one it takes the ``[efg]`` table's keys that mean the same for both methods (the cloud,
crack and hole rules, enrichment, the field-quadrature cells), so that a scene solves
with EFG or MLPG by changing that one key. Values are checked by :class:`MLPG` itself.
"""

from __future__ import annotations

import dataclasses

from ..tables import check_known_keys
from .efg import Rosette, Zone
from .mlpg import MLPG

__all__ = ["METHODS", "SHARED_KEYS", "mlpg_from_dict", "study_method"]

METHODS = ("efg", "mlpg")
# [efg] keys with the same meaning for MLPG (EFG's d_max, weight, alpha, basis, quadrature, bc,
# penalty and solver differ: MLPG's defaults are seed 002's)
SHARED_KEYS = ("spacing", "zones", "perturb", "seed", "coordinates", "order", "refined_order",
               "cell_size", "tip_order", "crack_rule", "rule_power", "hole_rule", "kappa",
               "rosette", "enrichment", "enrich_radius", "ramp", "ramp_inner")


def mlpg_from_dict(d: dict, path: str = "mlpg") -> MLPG:
    """Build an :class:`MLPG` from a scene-file table (``zones``: tables ``{centre, radius,
    spacing}``, ``rosette``: a table ``{radius, rings, per_ring}``).

    Examples
    --------
    >>> mlpg_from_dict({"spacing": 0.1, "quadrature": "midpoint"}).quadrature
    'midpoint'
    >>> mlpg_from_dict({"spacing": 0.1, "radiall": 5})
    Traceback (most recent call last):
    ...
    ValueError: unknown key 'radiall' in table 'mlpg'; did you mean 'radial'?
    """
    if not isinstance(d, dict):
        raise TypeError(f"{path} must be a table, got {type(d).__name__}")
    check_known_keys(d, [f.name for f in dataclasses.fields(MLPG)], f"table {path!r}")
    if "spacing" not in d:
        raise ValueError(f"missing required key 'spacing' in table {path!r}")
    kw = dict(d)
    try:
        if "zones" in kw:
            kw["zones"] = tuple(Zone(**z) for z in kw["zones"])
        if "rosette" in kw:
            kw["rosette"] = Rosette(**kw["rosette"])
        return MLPG(**kw)
    except (TypeError, ValueError) as err:
        raise type(err)(f"{path}: {err}") from None


def study_method(d: dict, efg_from_dict):
    """The discretisation of the parsed scene file ``d``: ``efg_from_dict(d["efg"])`` or an
    :class:`MLPG` (module docstring)."""
    method = d.get("method", "efg")
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if method == "mlpg" and "mlpg" in d:
        return mlpg_from_dict(d["mlpg"])
    if "efg" not in d:
        raise ValueError(f"missing required key {method!r} in scene file (top level): "
                         f"a study needs the discretisation table [{method}]"
                         + (" (or [efg], whose shared keys MLPG takes)" if method == "mlpg" else ""))
    if method == "efg":
        return efg_from_dict(d["efg"])
    return mlpg_from_dict({k: v for k, v in d["efg"].items() if k in SHARED_KEYS}, "efg")
