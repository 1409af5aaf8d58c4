"""What a study is: a base scene, a method, and the parameters to vary.

A :class:`Study` holds the parsed base scene file (a dict, with its ``[efg]`` table)
and :class:`Parameter` s, each a dotted path into it (:mod:`efgkit.study.paths`) with
the values it takes. The parameters combine in one of three ways:

=========  ==============================================================
``grid``   every combination (the product), in the order the parameters are given,
           the last one varying fastest
``zip``    the i-th values of all parameters together (equal lengths)
``random`` ``samples`` points, each value drawn independently from
           ``np.random.default_rng(seed)``: uniform in ``[low, high)``, or a choice
           among ``values``
=========  ==============================================================

Each point is the base document with its values put in (:class:`Point`), identified
by ``key``, a hash of everything that decides its result (the point's whole scene
document, the kind of run and its options): equal points share a key, and a changed
base scene changes every key, so a finished point is recognised and never computed
twice. ``kind`` says what a point runs; ``"static"`` (one solve and its stress
intensity factors) is the one there is, and growth paths can join as another kind.

A study file (``STUDY.toml``, ``docs/studies.md``) is read by :func:`read_study`.

Examples
--------
>>> doc = {"material": {"E": 1.0, "nu": 0.3},
...        "domain": {"outer": {"rectangle": [0.0, 0.0, 1.0, 1.0]}},
...        "supports": [{"edge": "left", "ux": 0.0, "uy": 0.0}],
...        "tractions": [{"edge": "right", "t": [1.0, 0.0]}], "efg": {"spacing": 0.25}}
>>> s = Study(doc, (Parameter("material.nu", (0.2, 0.3)), Parameter("efg.spacing", (0.5, 0.25))))
>>> [tuple(p.params.values()) for p in s.points()]
[(0.2, 0.5), (0.2, 0.25), (0.3, 0.5), (0.3, 0.25)]
>>> len(Study(doc, s.parameters, combine="zip").points())
2
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..scenefile import efg_from_dict, efg_to_dict, scene_from_dict, scene_to_dict
from .paths import set_path

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["COMBINE", "KINDS", "Parameter", "Point", "Study", "base_document", "point_key"]

COMBINE = ("grid", "zip", "random")
KINDS = ("static",)  # what a point runs; a growth path joins here as another kind


def _plain(v, what: str):
    """A TOML-like Python value (numpy scalars and arrays made plain), finite numbers only."""
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, (list, tuple)):
        return [_plain(x, what) for x in v]
    if isinstance(v, float) and not math.isfinite(v):
        raise ValueError(f"{what} holds {v!r}; every value of a study must be finite")
    if not isinstance(v, (bool, int, float, str, list)):
        raise TypeError(f"{what} holds {v!r} ({type(v).__name__}); a study value is a number, "
                        "a string, a boolean or an array of them")
    return v


@dataclass(frozen=True)
class Parameter:
    """One varied value of a study: a dotted ``path`` and the values it takes.

    Parameters
    ----------
    path : str
        Dotted path into the scene file (``material.E``, ``cracks.0.vertices.1.0``,
        ``method.spacing``; :mod:`efgkit.study.paths`).
    values : sequence, optional
        The values (``grid`` and ``zip``), or the choices (``random`` without
        ``low``/``high``).
    low, high : float, optional
        ``random`` only: the value is uniform in ``[low, high)``.
    name : str, optional
        Column name in the table and label in the figures (default: ``path``).
    """

    path: str
    values: tuple = ()
    low: float | None = None
    high: float | None = None
    name: str | None = None

    def __post_init__(self):
        if not isinstance(self.path, str) or not self.path:
            raise TypeError(f"Parameter path must be a dotted path such as 'material.E', "
                            f"got {self.path!r}")
        if isinstance(self.values, (str, bytes)) or not hasattr(self.values, "__iter__"):
            raise TypeError(f"Parameter {self.path!r}: values must be a sequence, got {self.values!r}")
        object.__setattr__(self, "values", tuple(_plain(v, f"parameter {self.path!r}")
                                                 for v in self.values))
        if (self.low is None) != (self.high is None):
            raise ValueError(f"Parameter {self.path!r}: give both low and high (a uniform range) "
                             f"or neither, got low={self.low!r}, high={self.high!r}")
        if self.low is not None:
            for k in ("low", "high"):
                v = getattr(self, k)
                if isinstance(v, bool) or not isinstance(v, (int, float, np.number)) \
                        or not math.isfinite(v):
                    raise TypeError(f"Parameter {self.path!r}: {k} must be a finite number, got {v!r}")
            if not self.high > self.low:
                raise ValueError(f"Parameter {self.path!r}: needs high > low, got low={self.low!r}, "
                                 f"high={self.high!r}")
            if self.values:
                raise ValueError(f"Parameter {self.path!r}: give values or low/high, not both")
        elif not self.values:
            raise ValueError(f"Parameter {self.path!r} has no values: give values = [...] "
                             "(or low and high for a random study)")
        if self.name is not None and (not isinstance(self.name, str) or not self.name):
            raise TypeError(f"Parameter {self.path!r}: name must be a non-empty string, got "
                            f"{self.name!r}")

    @classmethod
    def linspace(cls, path: str, start: float, stop: float, num: int, name=None) -> Parameter:
        """``num`` values evenly spaced from ``start`` to ``stop`` (both included)."""
        if isinstance(num, bool) or not isinstance(num, (int, np.integer)) or num < 1:
            raise ValueError(f"Parameter {path!r}: num must be an integer >= 1, got {num!r}")
        return cls(path, tuple(float(f"{v:.15g}") for v in np.linspace(start, stop, num)), name=name)

    @property
    def label(self) -> str:
        """The column name: ``name`` or the path."""
        return self.name or self.path


def point_key(kind: str, doc: dict, options: dict) -> str:
    """A stable 16-hex-digit key of one point: SHA-256 of its canonical JSON.

    The same document, kind and options give the same key in every process and
    Python version (keys sorted, no whitespace, floats as their shortest repr).

    Examples
    --------
    >>> point_key("static", {"b": 1.0, "a": [1, 2]}, {}) == point_key("static", {"a": [1, 2], "b": 1.0}, {})
    True
    """
    text = json.dumps({"kind": kind, "doc": doc, "options": options}, sort_keys=True,
                      separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Point:
    """One point of a study: its ``key``, its parameter values (path -> value), the
    scene document to run (``doc``), and the run's ``kind`` and ``options``."""

    key: str
    params: dict
    doc: dict = field(repr=False)
    kind: str = "static"
    options: dict = field(default_factory=dict)

    def task(self) -> str:
        """The JSON text sent to a worker (scene data only: no arrays, no matrices)."""
        return json.dumps({"key": self.key, "kind": self.kind, "params": self.params,
                           "doc": self.doc, "options": self.options}, allow_nan=False)


@dataclass(frozen=True)
class Study:
    """A base scene document and the parameters to vary (module docstring).

    Parameters
    ----------
    base : dict
        The parsed scene file with an ``[efg]`` table (``tomllib.load`` of a scene
        file; see :meth:`from_scene` for a :class:`~efgkit.Scene`). It is copied.
    parameters : sequence of Parameter
        At least one; each path must exist in ``base``.
    combine : {"grid", "zip", "random"}
    samples, seed : int, optional
        ``random`` only (both required there): the number of points and the seed of
        ``np.random.default_rng``.
    kind : str
        What a point runs (:data:`KINDS`).
    name : str
        The study's name: file names of the table and figures.
    error_estimate : bool
        Estimate the discretisation error of K at each point (one solve at twice the
        spacing, about a quarter of the cost; :meth:`efgkit.Solution.sifs`).

    Raises
    ------
    ValueError, TypeError
        A bad path (naming it), a base that is not a valid scene file, options that
        do not fit ``combine``.
    """

    base: dict = field(repr=False)
    parameters: tuple
    combine: str = "grid"
    samples: int | None = None
    seed: int | None = None
    kind: str = "static"
    name: str = "study"
    error_estimate: bool = True

    def __post_init__(self):
        if not isinstance(self.base, dict):
            raise TypeError(f"Study base must be a parsed scene file (dict), got "
                            f"{type(self.base).__name__}; use Study.from_scene for a Scene")
        object.__setattr__(self, "base", copy.deepcopy(self.base))
        params = tuple(self.parameters) if hasattr(self.parameters, "__iter__") else None
        if not params or not all(isinstance(p, Parameter) for p in params):
            raise TypeError(f"Study parameters must be a non-empty sequence of Parameter, got "
                            f"{self.parameters!r}")
        object.__setattr__(self, "parameters", params)
        if self.combine not in COMBINE:
            raise ValueError(f"Study combine must be one of {COMBINE}, got {self.combine!r}")
        if self.kind not in KINDS:
            raise ValueError(f"Study kind must be one of {KINDS}, got {self.kind!r}")
        if not isinstance(self.name, str) or not self.name:
            raise TypeError(f"Study name must be a non-empty string, got {self.name!r}")
        if "efg" not in self.base:
            raise ValueError("the base scene has no [efg] table: a study needs the "
                             "discretisation; add [efg] (at least spacing) to the scene file")
        if "load_cases" in self.base:  # a point solves one scene: the cases' loads would be lost
            raise ValueError("the base scene has [[load_cases]]: a study point solves one load; "
                             "give the load as [[tractions]] / body_force, one study per case")
        scene_from_dict(self.base)  # the base must be a valid scene file
        efg_from_dict(self.base["efg"])
        labels = [p.label for p in params]
        dup = sorted({x for x in labels if labels.count(x) > 1})
        if dup:
            raise ValueError(f"Study parameters repeat the name(s) {dup}; each varied value needs "
                             "its own path or name")
        for p in params:
            set_path(self.base, p.path, None)  # check the path exists (errors name it)
        self._check_combine(params)

    def _check_combine(self, params) -> None:
        if self.combine == "random":
            for k in ("samples", "seed"):
                v = getattr(self, k)
                if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < (k == "samples"):
                    raise ValueError(f"a random study needs {k} = an integer >= "
                                     f"{int(k == 'samples')}, got {v!r}")
            return
        ranged = [p.path for p in params if p.low is not None]
        if ranged:
            raise ValueError(f"parameter(s) {ranged} give low/high, which only a random study "
                             f"draws from; a {self.combine} study needs values = [...]")
        if self.combine == "zip":
            n = {p.label: len(p.values) for p in params}
            if len(set(n.values())) > 1:
                raise ValueError(f"a zip study takes the i-th value of every parameter together, "
                                 f"so all need as many values; got {n}")

    @classmethod
    def from_scene(cls, scene, method, parameters, **kw) -> Study:
        """A study of a :class:`~efgkit.Scene` and :class:`~efgkit.EFG` (converted to their
        scene-file document; TypeError where the scene holds a Python callable)."""
        return cls({**scene_to_dict(scene), "efg": efg_to_dict(method)}, parameters, **kw)

    def values(self) -> list[tuple]:
        """The values of every point, one tuple per point in the parameters' order."""
        params = self.parameters
        if self.combine == "grid":
            return list(itertools.product(*(p.values for p in params)))
        if self.combine == "zip":
            return list(zip(*(p.values for p in params), strict=True))
        rng = np.random.default_rng(self.seed)
        cols = []
        for p in params:  # one column per parameter, drawn in order: stable in the seed
            if p.low is not None:
                cols.append(rng.uniform(p.low, p.high, self.samples).tolist())
            else:
                idx = rng.integers(0, len(p.values), self.samples)
                cols.append([p.values[i] for i in idx])
        return list(zip(*cols, strict=True))

    @property
    def options(self) -> dict:
        """The options every point runs with (part of its key)."""
        return {"error_estimate": bool(self.error_estimate)}

    def points(self) -> list[Point]:
        """Every point of the study, in order (duplicates, which share a key, once)."""
        out, seen = [], set()
        for vals in self.values():
            doc = self.base
            for p, v in zip(self.parameters, vals, strict=True):
                doc = set_path(doc, p.path, v)
            key = point_key(self.kind, doc, self.options)
            if key not in seen:
                seen.add(key)
                out.append(Point(key, {p.label: v for p, v in zip(self.parameters, vals,
                                                                   strict=True)},
                                 doc, self.kind, self.options))
        return out


def base_document(path) -> dict:
    """The parsed scene file at ``path`` (``name`` defaults to its stem), checked to be a
    valid scene file with an ``[efg]`` table (errors name the file)."""
    from ..scenefile import load_study

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"base scene file {str(path)!r} " + ("is not a file" if path.exists()
                                                            else "not found"))
    load_study(path)  # checks the whole file, errors prefixed with its path
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    doc.setdefault("name", path.stem)
    return doc
