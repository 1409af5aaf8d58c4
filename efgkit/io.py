"""Files out: VTU fields for ParaView, JSON records, figures.

All file writing of the package lives here (design rule 10). Fields are
sampled on :func:`~efgkit.sampling.sample_grid` (re-exported here), a triangulation
of the material that leaves holes, notches and cracks open, so that ``warp by
vector`` in ParaView shows the deformed body with its crack faces apart.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import weakref
from pathlib import Path

import numpy as np

from .problem.material import Elastic
from .sampling import sample_grid

__all__ = ["check_finite", "jsonable", "nodes_path", "sample_grid", "sampled_fields", "von_mises",
           "write_figure", "write_json", "write_nodes_vtu", "write_vtu"]


def von_mises(stress: np.ndarray, material: Elastic) -> np.ndarray:
    """Von Mises equivalent stress, shape (n,), from in-plane ``stress (n, 3)`` (xx, yy, xy).

    sigma_vm = sqrt(((sxx - syy)^2 + (syy - szz)^2 + (szz - sxx)^2) / 2 + 3 sxy^2),
    with szz = nu (sxx + syy) in plane strain and 0 in plane stress.

    Examples
    --------
    >>> s = np.array([[1.0, 0.0, 0.0]])
    >>> von_mises(s, Elastic(1.0, 0.0, "stress")).tolist()
    [1.0]
    """
    s = np.atleast_2d(np.asarray(stress, dtype=float))
    if s.ndim != 2 or s.shape[1] != 3:
        raise ValueError(f"stress must have shape (n, 3) (xx, yy, xy), got {s.shape}")
    sxx, syy, sxy = s.T
    szz = material.nu * (sxx + syy) if material.plane == "strain" else np.zeros_like(sxx)
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy**2)


def check_finite(fields: dict, x: np.ndarray, path) -> None:
    """Refuse to write non-finite field values.

    Parameters
    ----------
    fields : dict of str to ndarray, shape (n,) or (n, k)
        The arrays to be written, one row per point.
    x : ndarray, shape (n, 2)
        The points (to name the first bad one).
    path : str or Path
        The file that is not written.

    Raises
    ------
    ValueError
        Naming the field, how many points are affected, the first one and the likely cause.
    """
    for name, v in fields.items():
        bad = ~np.isfinite(np.asarray(v, dtype=float).reshape(len(x), -1)).all(axis=1)
        if bad.any():
            k = int(np.argmax(bad))
            raise ValueError(
                f"field {name!r} is NaN or inf at {int(bad.sum())} of {len(x)} points (e.g. x = "
                f"{np.asarray(x)[k].tolist()}); {Path(path).name} is not written. Likely cause: values "
                "whose squares overflow (loads, lengths or moduli beyond ~1e150 in magnitude: "
                "rescale the units) or a solve that did not converge")


def pad3(v: np.ndarray) -> np.ndarray:
    """(n, 2) -> (n, 3) with a zero z column (VTK vectors are 3D)."""
    return np.column_stack([v, np.zeros(len(v))])


def nodes_path(path) -> Path:
    """The node-cloud file written next to a field file: ``<stem>_nodes.vtu``."""
    path = Path(path)
    return path.with_name(f"{path.stem}_nodes.vtu")


def write_nodes_vtu(nodes, path) -> Path:
    """Write a node cloud as VTU vertex cells.

    Point data: ``support_radius (n,)`` and ``boundary (n,)`` (1 on the boundary).

    Parameters
    ----------
    nodes : NodeCloud
    path : str or Path

    Returns
    -------
    Path
    """
    from .vtu import VTK_VERTEX, write_unstructured

    path = Path(path)
    data = {"support_radius": np.asarray(nodes.radius, float),
            "boundary": np.asarray(nodes.boundary, np.int32)}
    check_finite({"x": nodes.x, **data}, nodes.x, path)
    path.parent.mkdir(parents=True, exist_ok=True)
    n = nodes.n
    return write_unstructured(path, pad3(nodes.x), np.arange(n).reshape(n, 1), VTK_VERTEX, data)


_SAMPLED = weakref.WeakKeyDictionary()  # solution -> {n_target: sampled_fields(...)}


def sampled_fields(solution, n_target: int = 20000, displacement: bool = True) -> tuple:
    """The fields of ``solution`` on :func:`sample_grid`, computed once per solution and
    ``n_target`` (the VTU file and the stress figure of ``efgkit run`` share them).

    Parameters
    ----------
    solution : Solution
        Anything with ``scene`` and ``stress(x)`` (and ``displacement(x)`` when asked for;
        ``displacement_stress(x)`` gives both from one evaluation).
    n_target : int
        Approximate number of sample points.
    displacement : bool
        Whether the displacement is needed (else it may be None).

    Returns
    -------
    x : ndarray, shape (n, 2)
        Sample points.
    triangles : ndarray, shape (m, 3), int
    displacement : ndarray, shape (n, 2), or None
    stress : ndarray, shape (n, 3)
        Voigt (xx, yy, xy).

    The arrays are read-only (they are shared).
    """
    try:
        cache = _SAMPLED.setdefault(solution, {})
    except TypeError:  # not weakly referenceable: no cache
        cache = {}
    got = cache.get(n_target)
    if got is None or (displacement and got[2] is None):
        scene = solution.scene
        x, tri = got[:2] if got is not None else sample_grid(scene.domain, n_target, scene.cracks)
        both = getattr(solution, "displacement_stress", None)  # one evaluation where it can
        if both is not None:
            u, s = both(x)
        else:
            u, s = solution.displacement(x) if displacement else None, solution.stress(x)
        for v in (x, tri, u, s):
            if v is not None:
                v.flags.writeable = False
        cache[n_target] = got = (x, tri, u, s)
    return got


def write_vtu(solution, path, n_target: int = 20000) -> Path:
    """Write the fields of a solution on :func:`sample_grid` as a VTU file.

    Triangle cells; point data ``displacement (n, 3)`` (z = 0), ``stress (n, 3)``
    (xx, yy, xy) and ``von_mises (n,)`` (see :func:`von_mises`); a ValueError
    (:func:`check_finite`) instead of a file if any of them is NaN or inf. Any
    :class:`~efgkit.solution.Solution` (meshless solutions also write their node
    cloud, :meth:`MeshlessSolution.write_vtu <efgkit.meshless_solution.MeshlessSolution.write_vtu>`).

    Parameters
    ----------
    solution : Solution
    path : str or Path
        Output file; a ``.vtu`` suffix is added when missing. Parent
        directories are created.
    n_target : int
        Approximate number of sample points.

    Returns
    -------
    Path
        The field file.
    """
    from .vtu import VTK_TRIANGLE, write_unstructured

    path = Path(path)
    if path.suffix != ".vtu":
        path = path.with_name(path.name + ".vtu")
    x, tri, u, s = sampled_fields(solution, n_target)
    with np.errstate(over="ignore", invalid="ignore"):  # non-finite values are refused below
        vm = von_mises(s, solution.scene.material)
    data = {"displacement": pad3(u), "stress": s, "von_mises": vm}
    check_finite(data, x, path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_unstructured(path, pad3(x), tri, VTK_TRIANGLE, data)


def jsonable(obj):
    """A JSON-safe copy of ``obj``.

    Dataclasses become dicts of their fields, tuples and arrays lists, numpy
    scalars Python numbers, paths strings, and non-finite floats ``None``.

    Examples
    --------
    >>> jsonable({"a": np.float64(1.5), "b": np.arange(2), "c": float("nan")})
    {'a': 1.5, 'b': [0, 1], 'c': None}
    """
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [jsonable(v) for v in obj]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: jsonable(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, Path):
        return str(obj)
    if obj is None or isinstance(obj, (bool, int, float, str)):
        return obj
    raise TypeError(f"cannot write a {type(obj).__name__} as JSON: {obj!r}")


def write_json(obj, path) -> Path:
    """Write ``jsonable(obj)`` as indented JSON; parent directories are created.

    Non-finite scalars are written as ``null`` (a value not available), but a numpy array
    holding NaN or inf (a field) is refused with a ValueError naming its key.

    Returns
    -------
    Path
    """
    path = Path(path)
    key = _nonfinite_array(obj)
    if key is not None:
        raise ValueError(f"array {key} holds NaN or inf; {path.name} is not written. Likely cause: "
                         "values whose squares overflow (rescale the units) or a failed solve")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(jsonable(obj), indent=1, allow_nan=False) + "\n")
    return path


def _nonfinite_array(obj, key: str = "obj") -> str | None:
    """The key path (e.g. ``obj['u'][2]``) of the first float array in ``obj`` holding NaN or inf."""
    if isinstance(obj, np.ndarray):
        return key if obj.dtype.kind in "fc" and not np.all(np.isfinite(obj)) else None
    if isinstance(obj, dict):
        items = obj.items()
    elif isinstance(obj, (list, tuple)):
        items = enumerate(obj)
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        items = ((f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj))
    else:
        return None
    for k, v in items:
        found = _nonfinite_array(v, f"{key}[{k!r}]")
        if found is not None:
            return found
    return None


def file_name(name: str) -> str:
    """``name`` made safe as a file name: runs of other characters than letters, digits and
    ``_.-`` become ``_`` (``"scene"`` if nothing is left).

    Examples
    --------
    >>> file_name("SENT a/W = 0.5")
    'SENT_a_W_0.5'
    """
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("._") or "scene"


def write_figure(fig, path, dpi: int = 150, close: bool = True) -> Path:
    """Save a matplotlib figure (format from the suffix); parent directories are created.

    With ``close`` the figure is closed afterwards, also when saving fails (pyplot keeps
    every figure it made until it is closed). The bounding box is cropped to the drawn
    content ("tight") unless the figure has a layout engine (constrained layout places
    everything inside the figure already; a tight box would lay it out twice).
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        engine = getattr(fig, "get_layout_engine", lambda: None)()
        fig.savefig(path, dpi=dpi, bbox_inches=None if engine is not None else "tight")
    finally:
        if close:
            import matplotlib.pyplot as plt

            plt.close(fig)
    return path
