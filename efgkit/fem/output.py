"""Outputs of a finite-element solution on its own mesh: vertex stresses, VTU, the mesh and
stress figures. The record and the output directory are those of every
:class:`efgkit.solution.Solution`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..problem.material import strain_from_gradient

__all__ = ["nodal_stress", "plot_mesh", "plot_stress", "write_vtu"]


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

    from ..io import pad3, von_mises

    path = Path(path)
    if path.suffix != ".vtu":
        path = path.with_name(path.name + ".vtu")
    sb = sol._sbasis
    cells = sb.element_dofs.T
    kind = "triangle6" if cells.shape[1] == 6 else "triangle"
    s = _stress_at(sol, np.full((2, sol.mesh.n_elements), 1 / 3))
    path.parent.mkdir(parents=True, exist_ok=True)
    meshio.write_points_cells(
        path, pad3(sb.doflocs.T), [(kind, cells)],
        point_data={"displacement": pad3(np.column_stack([sol.u[0::2], sol.u[1::2]]))},
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

    from ..io import von_mises
    from ..plot import COMPONENTS, LABELS, draw_outline, new_axes

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
    fig, ax = new_axes(ax, sol.scene.domain, width=8.0)
    tri = Triangulation(sol.mesh.x[:, 0], sol.mesh.x[:, 1], sol.mesh.t)
    cs = ax.tricontourf(tri, z, levels=bounds, cmap="viridis", extend="both")
    fig.colorbar(cs, ax=ax, label=LABELS[component])
    draw_outline(ax, sol.scene.domain, sol.scene.cracks)
    ax.set_aspect("equal")
    ax.set_title(f"{sol.scene.name} (FEM P{sol.fem.order}): {LABELS[component]}")
    return fig


def plot_mesh(mesh, ax=None):
    """Mesh lines, boundary (black), crack faces (red) and tips (red dots); returns the figure.

    Examples
    --------
    >>> from efgkit import Domain, Elastic, Scene
    >>> from efgkit.fem.mesh import mesh_scene
    >>> fig = plot_mesh(mesh_scene(Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3)), 0.5))
    >>> fig.axes[0].get_aspect()
    1.0
    """
    from ..plot import new_axes

    fig, ax = new_axes(ax, mesh.domain)
    ax.triplot(mesh.x[:, 0], mesh.x[:, 1], mesh.t, color="0.6", lw=0.4)
    f = mesh.facets
    for sel, colour in ((mesh.facet_owner >= 0, "k"), (mesh.facet_owner < 0, "tab:red")):
        seg = mesh.x[f[sel]]
        ax.plot(seg[:, :, 0].T, seg[:, :, 1].T, color=colour, lw=1.0)
    if mesh.tip_nodes:
        ax.plot(*mesh.x[list(mesh.tip_nodes)].T, "o", color="tab:red", ms=4)
    ax.set_aspect("equal")
    ax.set_title(f"{mesh.n_elements} elements, {mesh.n_nodes} nodes")
    return fig
