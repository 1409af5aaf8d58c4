"""Matplotlib views of node clouds and stress fields.

Every function draws on ``ax`` (a new figure when None) and returns the
figure; none calls ``show()`` or writes files (save with
:func:`efgkit.io.write_figure`).
"""

from __future__ import annotations

import numpy as np

from .io import sample_grid, von_mises
from .problem.geometry import Domain

__all__ = ["COMPONENTS", "plot_domain_dependence", "plot_nodes", "plot_stress"]

COMPONENTS = ("von_mises", "xx", "yy", "xy")
LABELS = {"von_mises": "von Mises stress", "xx": r"$\sigma_{xx}$", "yy": r"$\sigma_{yy}$",
           "xy": r"$\sigma_{xy}$"}


def new_axes(ax, domain: Domain, width: float = 7.0):
    """``ax`` and its figure, or a new figure shaped to the domain's bounding box."""
    if ax is None:
        import matplotlib.pyplot as plt

        x0, y0, x1, y1 = domain.bbox
        height = float(np.clip(0.8 * width * (y1 - y0) / (x1 - x0) + 1.0, 2.5, 9.0))
        fig, ax = plt.subplots(figsize=(width, height))
        return fig, ax
    return ax.figure, ax


def draw_outline(ax, domain: Domain, cracks=()) -> None:
    """Draw the boundary loops (black) and the cracks (red)."""
    for loop in domain.loops:
        p, _ = loop.polyline()
        p = np.vstack([p, p[:1]])
        ax.plot(p[:, 0], p[:, 1], color="k", lw=1.0)
    for crack in cracks:
        v = crack.vertices
        ax.plot(v[:, 0], v[:, 1], color="tab:red", lw=1.5)


def _representative(nodes, domain: Domain) -> tuple[int, ...]:
    """An interior node near the centre, a boundary node near a corner, the widest support."""
    x0, y0, x1, y1 = domain.bbox
    inner = np.flatnonzero(~np.asarray(nodes.boundary, bool))
    pick = []
    if len(inner):
        c = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
        pick.append(int(inner[np.argmin(np.linalg.norm(nodes.x[inner] - c, axis=1))]))
    edge = np.flatnonzero(nodes.boundary)
    if len(edge):
        pick.append(int(edge[np.argmin(np.linalg.norm(nodes.x[edge] - [x0, y0], axis=1))]))
    pick.append(int(np.argmax(nodes.radius)))
    return tuple(dict.fromkeys(pick))


def plot_nodes(solution_or_nodes, domain: Domain | None = None, ax=None, supports_of=None):
    """Domain outline, nodes as dots and the support circles of a few nodes.

    Parameters
    ----------
    solution_or_nodes : Solution, Discretization or NodeCloud
        Anything with ``.nodes`` (then ``domain`` and cracks default to its
        scene's), or a NodeCloud (``x (n, 2)``, ``radius (n,)``, ``boundary (n,)``).
    domain : Domain, optional
        Required with a bare NodeCloud.
    ax : matplotlib Axes, optional
    supports_of : sequence of int, optional
        Nodes whose support discs are drawn; default: an interior node near
        the centre, a boundary node near the lower-left corner and the node of
        the widest support. ``()`` draws none.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from efgkit import EFG
    >>> from efgkit.nodes import generate_nodes
    >>> dom = Domain.rectangle(0, 0, 1, 1)
    >>> fig = plot_nodes(generate_nodes(dom, EFG(spacing=0.25)), dom, supports_of=[0])
    >>> len(fig.axes[0].patches)
    1
    """
    from matplotlib.patches import Circle

    src = solution_or_nodes
    nodes = getattr(src, "nodes", src)
    scene = getattr(src, "scene", None)
    if domain is None:
        if scene is None:
            raise ValueError("plot_nodes needs a domain with a bare NodeCloud: pass domain=...")
        domain = scene.domain
    cracks = scene.cracks if scene is not None else ()
    if supports_of is None:
        supports_of = _representative(nodes, domain)
    idx = np.asarray(supports_of, dtype=int).reshape(-1)
    if np.any((idx < 0) | (idx >= nodes.n)):
        raise ValueError(f"supports_of must index nodes 0..{nodes.n - 1}, got {list(supports_of)}")
    fig, ax = new_axes(ax, domain)
    draw_outline(ax, domain, cracks)
    b = np.asarray(nodes.boundary, bool)
    ax.plot(*nodes.x[~b].T, ".", ms=3, color="tab:blue", label="interior nodes")
    ax.plot(*nodes.x[b].T, ".", ms=4, color="tab:orange", label="boundary nodes")
    for i in idx:
        ax.add_patch(Circle(nodes.x[i], nodes.radius[i], fill=False, ls="--",
                            color="tab:green", lw=1.0))
        ax.plot(*nodes.x[i], "o", ms=5, color="tab:green")
    ax.set_aspect("equal")
    ax.set_title(f"{nodes.n} nodes" + (f": {scene.name}" if scene is not None else ""))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=2, fontsize="small",
              frameon=False)
    return fig


def plot_stress(solution, component: str = "von_mises", ax=None, n_target: int = 20000,
                levels: int = 30, limits=None):
    """Filled contours of a stress component on :func:`~efgkit.io.sample_grid`.

    Parameters
    ----------
    solution : Solution
    component : {"von_mises", "xx", "yy", "xy"}
        Von Mises (with sigma_zz of plane strain, see :func:`~efgkit.io.von_mises`)
        or a Voigt component.
    ax : matplotlib Axes, optional
    n_target : int
        Approximate number of sample points.
    levels : int
        Number of contour levels. A field constant to rounding (a patch test)
        is drawn as one colour.
    limits : (lo, hi), optional
        Colour range (give the same to two plots to compare them); by default the
        field's range, or its 0.5-99.5 percentiles when a crack-tip singularity
        would take the whole range.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if component not in COMPONENTS:
        raise ValueError(f"component must be one of {COMPONENTS}, got {component!r}")
    if isinstance(levels, bool) or not isinstance(levels, (int, np.integer)) or levels < 1:
        raise ValueError(f"levels must be a positive integer, got {levels!r}")
    from matplotlib.tri import Triangulation

    scene = solution.scene
    x, tri = sample_grid(scene.domain, n_target, scene.cracks)
    s = solution.stress(x)
    z = von_mises(s, scene.material) if component == "von_mises" else s[:, COMPONENTS.index(
        component) - 1]
    lo, hi = float(z.min()), float(z.max())
    label = LABELS[component]
    if limits is not None:
        lo, hi = (float(v) for v in limits)
    elif scene.cracks:  # a crack-tip singularity would take the whole colour range
        clo, chi = (float(v) for v in np.percentile(z, [0.5, 99.5]))
        if hi - lo > 4 * (chi - clo):
            lo, hi, label = clo, chi, f"{label} (0.5-99.5 percentile range)"
    scale = max(abs(lo), abs(hi), np.finfo(float).tiny)
    if hi - lo <= 1e-9 * scale:  # constant field: contour levels of round-off would mislead
        mid = 0.5 * (lo + hi)
        bounds = np.linspace(mid - 1e-3 * scale, mid + 1e-3 * scale, levels + 1)
    else:
        bounds = np.linspace(lo, hi, levels + 1)
    fig, ax = new_axes(ax, scene.domain, width=8.0)
    cs = ax.tricontourf(Triangulation(x[:, 0], x[:, 1], tri), z, levels=bounds, cmap="viridis",
                        extend="both")
    fig.colorbar(cs, ax=ax, label=label)
    draw_outline(ax, scene.domain, scene.cracks)
    ax.set_aspect("equal")
    ax.set_title(f"{scene.name}: {LABELS[component]}")
    return fig


def plot_domain_dependence(results, ax=None):
    """K_I and K_II against the J-domain radius, one pair of lines per tip, and J beside.

    Parameters
    ----------
    results : TipResult or sequence of TipResult
        From :func:`efgkit.fracture.sif.tip_result`; each domain's
        values are drawn as markers joined by lines (K_I solid, K_II dashed)
        and the mean over the domains as a dotted level. Without ``ax`` a
        second panel shows J against the radius (seed 001 Fig. 15).
    ax : matplotlib Axes, optional
        Draw K only, into these axes.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from efgkit.problem.crack import Tip
    >>> from efgkit.fracture.integrals import SIF
    >>> from efgkit.fracture.sif import TipResult
    >>> doms = tuple(SIF(1.0, 1.0 + 0.01 * k, 0.0, 0.0, 1.0, 100, 0.1 * (k + 1)) for k in range(3))
    >>> res = TipResult(Tip(np.zeros(2), 0.0, "c", 1), 1.01, 0.0, 1.0, 0.0, 0.02, doms)
    >>> fig = plot_domain_dependence(res)
    >>> len(fig.axes[0].lines)
    4
    """
    items = [results] if hasattr(results, "domains") else list(results)
    if not items or not all(hasattr(r, "domains") and hasattr(r, "tip") for r in items):
        raise TypeError("results must be a TipResult or a non-empty sequence of TipResult")
    ax_j = None
    if ax is None:
        import matplotlib.pyplot as plt

        fig, (ax, ax_j) = plt.subplots(1, 2, figsize=(10.0, 4.0))
    else:
        fig = ax.figure
    for k, res in enumerate(items):
        colour = f"C{k % 10}"
        radius = [d.radius for d in res.domains]
        ax.plot(radius, [d.KI for d in res.domains], "o-", color=colour,
                label=f"{res.tip.id}: $K_I$ (spread {res.spread:.2g})")
        ax.plot(radius, [d.KII for d in res.domains], "s--", color=colour,
                label=f"{res.tip.id}: $K_{{II}}$")
        ax.axhline(res.KI, color=colour, ls=":", lw=0.8)
        ax.axhline(res.KII, color=colour, ls=":", lw=0.8)
        if ax_j is not None:
            ax_j.plot(radius, [d.J for d in res.domains], "o-", color=colour, label=res.tip.id)
            ax_j.axhline(res.J, color=colour, ls=":", lw=0.8)
    ax.set_xlabel("J-domain radius")
    ax.set_ylabel("stress intensity factor")
    ax.set_title("domain dependence of K")
    ax.legend(fontsize="small")
    if ax_j is not None:  # at least +-2% around the values: a flat line reads as flat
        js = np.array([d.J for r in items for d in r.domains])
        lo, hi, mid = js.min(), js.max(), 0.5 * (js.min() + js.max())
        half = max(0.5 * (hi - lo), 0.02 * abs(mid))
        ax_j.set_ylim(mid - 1.1 * half, mid + 1.1 * half)
        ax_j.ticklabel_format(axis="y", useOffset=False)
        ax_j.set_xlabel("J-domain radius")
        ax_j.set_ylabel("J")
        ax_j.set_title("domain dependence of J")
        ax_j.legend(fontsize="small")
        fig.tight_layout()
    return fig
