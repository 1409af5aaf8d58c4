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

from pathlib import Path

from ..methods.efg import EFG
from ..methods.mlpg import MLPG
from ..methods.mlpg_file import study_method
from ..problem.scene import Scene
from .cases import cases_from_dict, cases_to_list
from .schema import SCHEMA, efg_from_dict, key_path, scene_from_dict
from .writer import efg_to_dict, scene_to_dict

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["SCHEMA", "cases_from_dict", "cases_to_list", "efg_from_dict", "efg_to_dict",
           "load_cases", "load_scene", "load_study", "scene_from_dict", "scene_to_dict"]


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
    with key_path(str(path)):
        scene = scene_from_dict(d)
        if "efg" in d:
            efg_from_dict(d["efg"])
        cases_from_dict(d)  # [[load_cases]], if any
    return scene


def load_cases(path) -> dict[str, Scene] | None:
    """The named load cases ``{name: Scene}`` of a scene file's ``[[load_cases]]``
    (:mod:`efgkit.scenefile.cases`), or None without them. Errors name the file path."""
    path, d = _read(path)
    with key_path(str(path)):
        return cases_from_dict(d)


def load_study(path) -> tuple[Scene, EFG | MLPG]:
    """Read a scene file with its discretisation: ``(Scene, EFG)`` (``[efg]`` required), or
    ``(Scene, MLPG)`` with ``method = "mlpg"`` (:mod:`efgkit.methods.mlpg_file`)."""
    path, d = _read(path)
    with key_path(str(path)):
        return scene_from_dict(d), study_method(d, efg_from_dict)
