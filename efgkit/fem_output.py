"""Outputs of a finite-element solution: vertex stresses, VTU, figures and the JSON record.

The same outputs as an EFG run (``efgkit run``): fields for ParaView, a mesh
and a stress figure, and a JSON record with the solver information, timings,
strain energy, errors against an exact field and the stress intensity factors
of every tip (:meth:`efgkit.fem_solution.FEMSolution.sifs`).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from .material import strain_from_gradient

__all__ = ["nodal_stress", "plot_stress", "record", "write", "write_vtu"]


def _stress_at(sol, X) -> np.ndarray:
    """Stress (n_elements, 3) at one reference point ``X (2, n_elements)`` of every element."""
    g = sol._at(np.arange(sol.mesh.n_elements), X, grad=True)
    return strain_from_gradient(g) @ sol.scene.material.D.T


def nodal_stress(sol) -> np.ndarray:
    """Stress (n_nodes, 3) at the mesh vertices, averaged over the elements at each vertex.

    Each element is evaluated a hair (1e-3 of the way to its centroid) inside its
    vertex, so quarter-point tips give large finite values; crack faces are not averaged
    across (their nodes are distinct).
    """
    sk, n, m = sol.basis.mesh, sol.mesh.n_elements, sol.mesh.n_nodes
    acc, cnt = np.zeros((m, 3)), np.bincount(sk.t.ravel(), minlength=m)
    for k, ref in enumerate(([0, 0], [1, 0], [0, 1])):
        X = np.repeat((0.999 * np.array(ref) + 0.001 / 3)[:, None], n, axis=1)
        np.add.at(acc, sk.t[k], _stress_at(sol, X))
    return acc / np.maximum(cnt, 1)[:, None]


def write_vtu(sol, path) -> Path:
    """Write the mesh and fields as VTU (``triangle6`` cells for P2, ``triangle`` for P1).

    Point data ``displacement (n, 3)`` (z = 0); cell data ``stress (n_elements, 3)``
    (xx, yy, xy at the centroids) and ``von_mises``. A ``.vtu`` suffix is added when
    missing; parent directories are created.
    """
    import meshio

    from .io import _pad3, von_mises

    path = Path(path)
    if path.suffix != ".vtu":
        path = path.with_name(path.name + ".vtu")
    sb = sol._sbasis
    cells = sb.element_dofs.T
    kind = "triangle6" if cells.shape[1] == 6 else "triangle"
    s = _stress_at(sol, np.full((2, sol.mesh.n_elements), 1 / 3))
    path.parent.mkdir(parents=True, exist_ok=True)
    meshio.write_points_cells(
        path, _pad3(sb.doflocs.T), [(kind, cells)],
        point_data={"displacement": _pad3(np.column_stack([sol.u[0::2], sol.u[1::2]]))},
        cell_data={"stress": [s], "von_mises": [von_mises(s, sol.scene.material)]})
    return path


def plot_stress(sol, component: str = "von_mises", ax=None, levels: int = 30, limits=None):
    """Filled contours of a vertex-averaged stress component; returns the figure.

    ``component`` is one of :data:`efgkit.plot.COMPONENTS`. The colour range is
    ``limits = (lo, hi)`` (give the same to two plots to compare them) or, by
    default, the 0.5 to 99.5 percentiles of the vertex values, so that the
    singular values at crack tips do not flatten the picture (values beyond are
    drawn in the end colours).
    """
    from matplotlib.tri import Triangulation

    from .io import von_mises
    from .plot import _LABELS, COMPONENTS, _axes, _outline

    if component not in COMPONENTS:
        raise ValueError(f"component must be one of {COMPONENTS}, got {component!r}")
    if isinstance(levels, bool) or not isinstance(levels, (int, np.integer)) or levels < 1:
        raise ValueError(f"levels must be a positive integer, got {levels!r}")
    s = nodal_stress(sol)
    z = von_mises(s, sol.scene.material) if component == "von_mises" else s[
        :, COMPONENTS.index(component) - 1]
    if limits is None:
        lo, hi = (float(v) for v in np.percentile(z, [0.5, 99.5]))  # singular tips clipped
    else:
        lo, hi = (float(v) for v in np.asarray(limits, dtype=float).reshape(2))
        if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
            raise ValueError(f"limits must be finite (lo, hi) with lo <= hi, got {limits!r}")
    scale = max(abs(lo), abs(hi), np.finfo(float).tiny)
    mid = 0.5 * (lo + hi)
    bounds = (np.linspace(lo, hi, levels + 1) if hi - lo > 1e-9 * scale else
              np.linspace(mid - 1e-3 * scale, mid + 1e-3 * scale, levels + 1))
    fig, ax = _axes(ax, sol.scene.domain, width=8.0)
    tri = Triangulation(sol.mesh.x[:, 0], sol.mesh.x[:, 1], sol.mesh.t)
    cs = ax.tricontourf(tri, z, levels=bounds, cmap="viridis", extend="both")
    fig.colorbar(cs, ax=ax, label=_LABELS[component])
    _outline(ax, sol.scene.domain, sol.scene.cracks)
    ax.set_aspect("equal")
    ax.set_title(f"{sol.scene.name} (FEM P{sol.fem.order}): {_LABELS[component]}")
    return fig


def record(sol, radii=None, q="wendland_c2") -> dict:
    """JSON-ready summary of a solution, with the keys of the ``efgkit run`` report.

    Returns
    -------
    dict
        ``scene``, ``method`` (the :class:`~efgkit.fem.FEM` fields and ``"kind": "fem"``),
        ``n_nodes`` (mesh vertices), ``n_elements``, ``n_dofs``, ``timings``, ``solver``,
        ``energy`` (strain energy), ``errors`` (against ``scene.exact``, or None),
        ``tips`` (:meth:`TipResult.as_dict` of every tip, from
        :meth:`~efgkit.fem_solution.FEMSolution.sifs` with ``radii`` and ``q``) and
        ``cmod`` (crack name -> opening, for cracks with a mouth).
    """
    import dataclasses

    from .io import jsonable

    fem = sol.fem
    tips = sol.sifs(radii=radii, q=q) if sol.scene.tips else ()
    out = {"scene": sol.scene.name, "method": {"kind": "fem", **{f.name: getattr(fem, f.name)
                                                                   for f in dataclasses.fields(fem)}},
           "n_nodes": sol.mesh.n_nodes, "n_elements": sol.mesh.n_elements, "n_dofs": sol.n_dofs,
           "timings": dict(sol.timings), "solver": dict(sol.info), "energy": sol.strain_energy(),
           "errors": sol.errors() if sol.scene.exact is not None else None,
           "tips": [t.as_dict() for t in tips],
           "cmod": {c.name: sol.cmod(c) for c in sol.scene.cracks if not all(c.tips)}}
    return jsonable(out)


def write(sol, out, name: str | None = None, radii=None) -> dict:
    """Write ``<name>.vtu``, ``<name>_mesh.png``, ``<name>_stress.png`` (von Mises) and
    ``<name>.json`` (:func:`record` with ``outputs``) into the directory ``out``.

    ``name`` defaults to the scene's name made file-safe. Returns the record.
    """
    from .io import write_figure, write_json

    out = Path(out)
    name = name or (re.sub(r"[^A-Za-z0-9_.-]+", "_", sol.scene.name).strip("._") or "scene")
    rec = record(sol, radii)
    paths = [write_vtu(sol, out / f"{name}.vtu")]
    for suffix, draw in (("mesh", sol.plot_mesh), ("stress", sol.plot_stress)):
        paths.append(write_figure(draw(), out / f"{name}_{suffix}.png"))
    rec["outputs"] = [str(p) for p in paths + [out / f"{name}.json"]]
    write_json(rec, out / f"{name}.json")
    return rec
