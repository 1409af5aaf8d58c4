"""Matplotlib views of node clouds, stress fields and (from :mod:`efgkit.sif_plot`) the
domain dependence of K and J.

Every function draws on ``ax`` (a new figure when None) and returns the
figure; none calls ``show()`` or writes files (save with
:func:`efgkit.io.write_figure`).
"""

from __future__ import annotations

import numpy as np

from .io import sampled_fields, von_mises
from .problem.geometry import Domain
from .sif_plot import plot_domain_dependence

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


def draw_outline(ax, domain: Domain, cracks=(), label: bool = False) -> None:
    """Draw the boundary loops (black) and the cracks (red; with ``label``, "crack" in the legend)."""
    for loop in domain.loops:
        p, _ = loop.polyline()
        p = np.vstack([p, p[:1]])
        ax.plot(p[:, 0], p[:, 1], color="k", lw=1.0)
    for k, crack in enumerate(cracks):
        v = crack.vertices
        ax.plot(v[:, 0], v[:, 1], color="tab:red", lw=1.5,
                label="crack" + "s" * (len(cracks) > 1) if label and k == 0 else None)


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


def edge_samples(domain: Domain, where, m: int):
    """``(edge, x (m, 2), unit tangent (m, 2), selected (m,))`` for every edge of ``domain``:
    ``m`` points from end to end and which of them ``where`` (edge name or mask) selects."""
    for e in domain.edges():
        x, t = e.at(np.linspace(0.0, 1.0, m))
        sel = np.full(m, e.name == where) if isinstance(where, str) else np.asarray(where(x), bool)
        yield e, x, t, sel.reshape(m)


def support_label(s) -> str:
    """``"$u_x$, $u_y$ fixed on left"``: the constrained components (fixed: prescribed 0)."""
    comps = [(c, v) for c, v in (("$u_x$", s.ux), ("$u_y$", s.uy)) if v is not None]
    fixed = [c for c, v in comps if isinstance(v, (int, float)) and float(v) == 0.0]
    given = [c for c, _ in comps if c not in fixed]
    text = "; ".join(f"{', '.join(cs)} {how}" for cs, how in ((fixed, "fixed"), (given, "prescribed")) if cs)
    return f"{text} on {s.edge if isinstance(s.edge, str) else 'selected boundary'}"


def draw_supports(ax, scene) -> int:
    """Thick coloured lines on the supported boundary, one legend entry per support (colour:
    which components it constrains); returns how many were drawn."""
    colour = {(True, False): "tab:cyan", (False, True): "tab:olive", (True, True): "tab:brown"}
    drawn = 0
    for s in scene.supports:
        parts = [np.vstack([np.where(sel[:, None], x, np.nan), [[np.nan, np.nan]]])
                 for _, x, _, sel in edge_samples(scene.domain, s.edge, 101) if sel.any()]
        if parts:
            xy = np.vstack(parts)
            ax.plot(xy[:, 0], xy[:, 1], lw=6, alpha=0.55, solid_capstyle="butt", zorder=1,
                    color=colour[s.ux is not None, s.uy is not None], label=support_label(s))
            drawn += 1
    return drawn


def draw_tractions(ax, scene, per_edge: int = 7) -> int:
    """Arrows of the scene's tractions at a few points of each loaded edge (interior points,
    more on longer edges), just outside the body so that shear reads too; one scale for all:
    the largest ``|t|`` is 12% of the body's size or 80% of the arrow spacing, the less.
    Returns the number of arrows."""
    from .problem.scene import evaluate_vector

    x0, y0, x1, y1 = scene.domain.bbox
    size = max(x1 - x0, y1 - y0)
    longest = max(e.length for e in scene.domain.edges())
    at, t, gap = [], [], 0.12 * size
    for tr in scene.tractions:
        for e, x, tan, sel in edge_samples(scene.domain, tr.edge, 61):
            idx = np.flatnonzero(sel)
            if not len(idx):
                continue
            k = int(np.clip(round(per_edge * e.length / longest), 2, per_edge))
            pick = idx[np.round(np.linspace(0, len(idx) - 1, k + 2)[1:-1]).astype(int)]
            normal = np.column_stack([tan[pick, 1], -tan[pick, 0]])
            at.append(x[pick] + 0.02 * size * normal)
            t.append(evaluate_vector(tr.t, x[pick], normal, scene.material))
            gap = min(gap, 0.8 * e.length * (idx[-1] - idx[0]) / 60 / (k + 1))
    if not at:
        return 0
    at, t = np.vstack(at), np.vstack(t)
    tmax = float(np.hypot(*t.T).max())
    if tmax == 0.0:
        return 0
    ax.quiver(at[:, 0], at[:, 1], t[:, 0], t[:, 1], angles="xy", scale_units="xy",
              scale=tmax / gap, color="tab:purple", width=0.004, zorder=4,
              label=f"traction (largest |t| = {tmax:.3g})")
    ax.update_datalim(at + t * (gap / tmax))
    return len(at)


def plot_nodes(solution_or_nodes, domain=None, ax=None, supports_of=None):
    """The nodes, the supported and loaded boundary, the cracks and a few support circles.

    Supported edges are thick coloured lines (legend: the constrained components,
    e.g. "$u_x$, $u_y$ fixed on left"), tractions arrows at a few points of each
    loaded edge (one scale; the legend gives the largest ``|t|``), cracks red lines,
    and each support circle is named in the legend ("support of node k (radius d)").

    Parameters
    ----------
    solution_or_nodes : Solution, Discretization or NodeCloud
        Anything with ``.nodes`` (then ``domain``, supports, loads and cracks default to
        its scene's), or a NodeCloud (``x (n, 2)``, ``radius (n,)``, ``boundary (n,)``).
    domain : Domain or Scene, optional
        Required with a bare NodeCloud; a Scene also gives the supports, loads and cracks.
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
    >>> len(fig.axes[0].patches), fig.axes[0].get_title()
    (1, 'nodes (25), 1 support circle')
    """
    from matplotlib.patches import Circle

    from .problem.scene import Scene

    src = solution_or_nodes
    nodes = getattr(src, "nodes", src)
    scene = domain if isinstance(domain, Scene) else getattr(src, "scene", None)
    if domain is None or isinstance(domain, Scene):
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
    draw_outline(ax, domain, cracks, label=True)
    what = [f"nodes ({nodes.n})"]
    if scene is not None:
        what += ["supports"] * bool(draw_supports(ax, scene)) + ["loads"] * bool(draw_tractions(ax, scene))
    what += ["cracks"] * bool(cracks)
    b = np.asarray(nodes.boundary, bool)
    ax.plot(*nodes.x[~b].T, ".", ms=3, color="tab:blue", label="interior nodes")
    ax.plot(*nodes.x[b].T, ".", ms=4, color="tab:orange", label="boundary nodes")
    shades = ("tab:green", "darkgreen", "yellowgreen", "teal")
    for k, i in enumerate(idx):
        label = (f"support of node {i} (radius {nodes.radius[i]:.3g})" if len(idx) <= len(shades)
                 else f"supports of {len(idx)} nodes (radius {nodes.radius[idx].min():.3g} "
                 f"to {nodes.radius[idx].max():.3g})" if k == 0 else None)
        colour = shades[k % len(shades)] if len(idx) <= len(shades) else "tab:green"
        ax.add_patch(Circle(nodes.x[i], nodes.radius[i], fill=False, ls="--", color=colour, lw=1.2,
                            label=label))
        ax.plot(*nodes.x[i], "o", ms=5, color=colour)
    if len(idx):
        what.append(f"{len(idx)} support circle{'s' * (len(idx) > 1)}")
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_title((f"{scene.name}: " if scene is not None else "") + ", ".join(what))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=2, fontsize="small",
              frameon=False)
    return fig


def plot_stress(solution, component: str = "von_mises", ax=None, n_target: int = 20000,
                levels: int = 30, limits=None):
    """Filled contours of a stress component on :func:`~efgkit.io.sample_grid`
    (:func:`~efgkit.io.sampled_fields`: computed once per solution and ``n_target``).

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
    x, tri, _, s = sampled_fields(solution, n_target, displacement=False)  # shared with the VTU
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
