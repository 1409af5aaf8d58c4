"""Study files: ``STUDY.toml``, a base scene file and the parameters to vary.

Every key is documented in ``docs/studies.md``. The reader is strict like the scene-file
reader (:mod:`efgkit.scenefile`): an unknown key is an error naming the key and the
nearest valid one; errors are prefixed with the file path.

=================  ============================================================
``scene``          the base scene file, relative to the study file (required; it must
                   have an ``[efg]`` table)
``name``           the study's name (default: the study file's stem)
``kind``           what a point runs: ``"static"`` (default)
``combine``        ``"grid"`` (default), ``"zip"`` or ``"random"``
``samples``        ``random``: the number of points
``seed``           ``random``: the seed of ``np.random.default_rng``
``error_estimate`` estimate the error of K at each point (default true)
``out``            output directory, relative to the current directory (default
                   ``out/<name>``)
``scheduler``      ``"local"`` (default: a local cluster), ``"synchronous"`` (in this
                   process, no dask), ``"inprocess"`` (a dask cluster of threads in this
                   process), a scheduler address ``tcp://host:8786`` or a scheduler
                   file ``*.json``
``workers``        local cluster: number of worker processes (default: one per core)
``[[parameters]]`` ``path`` (required), ``name``, and ``values = [...]``, or ``start``,
                   ``stop``, ``num`` (evenly spaced, both ends included), or ``low``,
                   ``high`` (``random`` only: uniform)
=================  ============================================================
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..tables import check_known_keys
from .spec import Parameter, Study, base_document

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["StudyFile", "read_study"]

_TOP = ("scene", "name", "kind", "combine", "samples", "seed", "error_estimate", "out",
        "scheduler", "workers", "parameters")
_PARAMETER = ("path", "name", "values", "start", "stop", "num", "low", "high")


@dataclass(frozen=True)
class StudyFile:
    """A study file read: the :class:`Study` and where and how to run it.

    ``out`` is None for the default ``out/<name>``; ``scheduler`` and ``workers`` None
    where the file does not say.
    """

    study: Study
    path: Path
    out: Path | None = None
    scheduler: str | None = None
    workers: int | None = None


def _check_keys(d, valid, where: str) -> None:
    if not isinstance(d, dict):
        raise TypeError(f"{where} must be a table, got {d!r}")
    check_known_keys(d, valid, where)


def _typed(d: dict, key: str, types, what: str, where: str):
    v = d.get(key)
    if v is not None and (not isinstance(v, types) or (isinstance(v, bool) and bool not in types)):
        raise TypeError(f"{where}: {key} must be {what}, got {v!r}")
    return v


def _parameter(d, i: int) -> Parameter:
    where = f"parameters[{i}]"
    _check_keys(d, _PARAMETER, where)
    if "path" not in d:
        raise ValueError(f"missing required key 'path' in {where} (a dotted path into the "
                         "scene file, e.g. 'material.E')")
    path = _typed(d, "path", (str,), "a dotted path string", where)
    name = _typed(d, "name", (str,), "a string", where)
    lin = [k for k in ("start", "stop", "num") if k in d]
    forms = ["values"] * ("values" in d) + ["start/stop/num"] * bool(lin) \
        + ["low/high"] * ("low" in d or "high" in d)
    if len(forms) != 1:
        raise ValueError(f"{where} ({path}) needs exactly one of: values = [...]; start, stop, "
                         f"num; low, high (random studies); got {forms or 'none of them'}")
    if lin:
        if len(lin) != 3:
            raise ValueError(f"{where} ({path}): start, stop and num go together; missing "
                             f"{[k for k in ('start', 'stop', 'num') if k not in d]}")
        start = _typed(d, "start", (int, float), "a number", where)
        stop = _typed(d, "stop", (int, float), "a number", where)
        num = _typed(d, "num", (int,), "an integer >= 1", where)
        return Parameter.linspace(path, start, stop, num, name=name)
    if "values" in d:
        values = _typed(d, "values", (list,), "an array", where)
        return Parameter(path, tuple(values), name=name)
    return Parameter(path, low=d.get("low"), high=d.get("high"), name=name)


def read_study(path) -> StudyFile:
    """Read a study file (module docstring) and its base scene file.

    Raises
    ------
    ValueError, TypeError
        Naming the study file and the key (or the parameter path) at fault.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"study file {str(path)!r} " + ("is not a file" if path.exists()
                                                         else "not found"))
    with open(path, "rb") as f:
        try:
            d = tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            raise ValueError(f"{path}: not a valid TOML file: {e}") from e
    try:
        return _read(d, path)
    except (ValueError, TypeError) as e:
        cls = TypeError if isinstance(e, TypeError) else ValueError
        msg = str(e)
        raise cls(msg if msg.startswith(str(path)) else f"{path}: {msg}") from e


def _read(d: dict, path: Path) -> StudyFile:
    where = "the study file (top level)"
    _check_keys(d, _TOP, where)
    for k in ("scene", "parameters"):
        if k not in d:
            raise ValueError(f"missing required key {k!r} in {where}"
                             + (" (the base scene file)" if k == "scene"
                                else " (at least one [[parameters]] table)"))
    scene = _typed(d, "scene", (str,), "a path string", where)
    params = d["parameters"]
    if not isinstance(params, list) or not params:
        raise TypeError(f"parameters must be an array of tables ([[parameters]]), got {params!r}")
    base = base_document(path.parent / scene)
    kw = {k: _typed(d, k, t, what, where) for k, t, what in (
        ("name", (str,), "a string"), ("kind", (str,), "a string"),
        ("combine", (str,), "a string"), ("samples", (int,), "an integer"),
        ("seed", (int,), "an integer"), ("error_estimate", (bool,), "true or false"))
        if k in d}
    kw.setdefault("name", path.stem)
    study = Study(base, tuple(_parameter(p, i) for i, p in enumerate(params)), **kw)
    out = _typed(d, "out", (str,), "a directory path string", where)
    scheduler = _typed(d, "scheduler", (str,), "a string", where)
    workers = _typed(d, "workers", (int,), "an integer >= 1", where)
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    return StudyFile(study, path, Path(out) if out is not None else None, scheduler, workers)
