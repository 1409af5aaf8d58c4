"""Matplotlib views of the domain dependence of K and J: K_I, K_II and J of every tip
against the J-domain radius, with their means and references (seed 001 Fig. 15).

Draws on ``ax`` (a new figure when None) and returns the figure; never calls ``show()``
(save with :func:`efgkit.io.write_figure`). Re-exported by :mod:`efgkit.plot`.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

__all__ = ["plot_domain_dependence"]


def tip_references(items, reference) -> dict:
    """``{tip id: (K_I, K_II)}`` from a mapping or a single pair (then for every tip)."""
    if reference is None:
        return {}
    ids = [r.tip.id for r in items]
    if isinstance(reference, Mapping):
        unknown = sorted(set(reference) - set(ids))
        if unknown:
            raise ValueError(f"reference names tips {unknown}, but the results are of tips {ids}")
        pairs = dict(reference)
    else:
        pairs = dict.fromkeys(ids, reference)
    out = {}
    for tid, v in pairs.items():
        arr = np.asarray(v, dtype=float)
        if arr.shape != (2,) or not np.all(np.isfinite(arr)):
            raise ValueError(f"reference of tip {tid!r} must be a finite pair (K_I, K_II), got {v!r}")
        out[tid] = (float(arr[0]), float(arr[1]))
    return out


def fit_ylim(ax, values, scale: float, marks=()) -> None:
    """y-range of ``values`` with at least +-1% of ``scale`` around them (a flat line reads
    as flat, not as magnified round-off); ``marks`` (reference levels) join the range when
    they lie within ten times its half-width, else they stay off the panel."""
    v = np.asarray(values, dtype=float)
    lo, hi = float(v.min()), float(v.max())
    half = max(0.5 * (hi - lo), 0.01 * abs(scale)) or 1.0
    mid = 0.5 * (lo + hi)
    near = [m for m in marks if abs(m - mid) <= 10 * half]
    lo, hi = min([mid - half, *near]), max([mid + half, *near])
    pad = 0.1 * (hi - lo)
    ax.set_ylim(lo - pad, hi + pad)
    ax.ticklabel_format(axis="y", useOffset=False)


def k_panels(ax):
    """``ax`` and a new axes below it sharing its x-axis, in ``ax``'s place (``ax`` keeps
    the upper half of its grid cell, or of its position without one)."""
    fig = ax.figure
    spec = ax.get_subplotspec()
    if spec is not None:
        top, bottom = spec.subgridspec(2, 1, hspace=0.08)
        ax.set_subplotspec(top)
        below = fig.add_subplot(bottom, sharex=ax)
    else:
        x, y, w, h = ax.get_position().bounds
        ax.set_position([x, y + 0.52 * h, w, 0.48 * h])
        below = fig.add_axes([x, y, w, 0.48 * h], sharex=ax)
    ax.tick_params(labelbottom=False)
    return ax, below


def draw_quantity(ax, tips, name: str, refs: dict, reference_label: str) -> None:
    """``name`` ("KI", "KII" or "J") of ``tips`` (pairs colour, TipResult) against the radius:
    markers per domain, a dotted mean, dashed levels of ``refs`` (tip id -> value), the
    legend, and the y-range of :func:`fit_ylim`."""
    sym, style = {"KI": ("$K_I$", "o-"), "KII": ("$K_{II}$", "s-"), "J": ("$J$", "^-")}[name]
    levels = {}
    for colour, res in tips:
        vals = [getattr(d, name) for d in res.domains]
        ax.plot([d.radius for d in res.domains], vals, style, color=colour, ms=5,
                label=f"{res.tip.id} per domain (max - min {np.ptp(vals):.2g})")
        ax.axhline(getattr(res, name), color=colour, ls=":", lw=1.0,
                   label=f"{res.tip.id} mean {getattr(res, name):.4g}")
        if res.tip.id in refs:
            levels.setdefault(refs[res.tip.id], []).append((colour, res.tip.id))
    for v, who in levels.items():
        shared = len(levels) == 1 and len(who) == len(tips)
        ax.axhline(v, color="k" if shared else who[0][0], ls="--", lw=1.2, label=f"{reference_label}"
                   + ("" if shared else f" ({', '.join(t for _, t in who)})") + f": {sym} = {v:.4g}")
    scale = max(abs(r.J) if name == "J" else float(np.hypot(r.KI, r.KII)) for _, r in tips)
    fit_ylim(ax, [getattr(d, name) for _, r in tips for d in r.domains], scale, list(levels))
    ax.set_ylabel(sym)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")


def plot_domain_dependence(results, ax=None, reference=None, reference_label: str = "reference"):
    """K_I, K_II and J against the J-domain radius, each on its own panel.

    Each domain's value is a marker, joined by lines; the mean over the domains is a
    dotted level, a reference a dashed one. Each panel's y-range is its own (with at
    least +-1% of ``|K|`` or ``|J|`` around the values, so round-off does not fill it).

    Parameters
    ----------
    results : TipResult or sequence of TipResult
        From :func:`efgkit.fracture.sif.tip_result`.
    ax : matplotlib Axes, optional
        Without it, a new figure with one column per tip: K_I, K_II and J stacked on a
        shared radius axis (seed 001 Fig. 15), the column titled with the tip id and the
        spread. With it, K only, every tip in the same two panels: ``ax`` keeps K_I in
        the upper half of its place and a new axes below it (in ``fig.axes``, sharing
        the radius axis) shows K_II; J is not drawn.
    reference : mapping or (float, float), optional
        Known ``(K_I, K_II)``: ``{tip id: (K_I, K_II)}``, or one pair for every tip.
        Drawn as dashed levels with legend entries ``"<reference_label>: K_I = ..."``.
    reference_label : str
        What the reference is (e.g. "exact (Westergaard)").

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
    >>> fig = plot_domain_dependence(res, reference=(1.0, 0.0))
    >>> [a.get_ylabel() for a in fig.axes]
    ['$K_I$', '$K_{II}$', '$J$']
    >>> [line.get_label() for line in fig.axes[0].lines]
    ['c:1 per domain (max - min 0.02)', 'c:1 mean 1.01', 'reference: $K_I$ = 1']
    """
    items = [results] if hasattr(results, "domains") else list(results)
    if not items or not all(hasattr(r, "domains") and hasattr(r, "tip") for r in items):
        raise TypeError("results must be a TipResult or a non-empty sequence of TipResult")
    refs = tip_references(items, reference)
    tips = [(f"C{k % 10}", r) for k, r in enumerate(items)]
    if ax is None:
        import matplotlib.pyplot as plt

        fig, grid = plt.subplots(3, len(tips), figsize=(4.8 * len(tips) + 0.6, 8.0), sharex="col",
                                 squeeze=False, layout="constrained")
        columns = [("", [tip], list(grid[:, j])) for j, tip in enumerate(tips)]
        fig.suptitle("domain dependence of $K_I$, $K_{II}$ and $J$")
    else:
        fig, columns = ax.figure, [("domain dependence of K: ", tips, list(k_panels(ax)))]
    for title, group, panels in columns:
        for q, (ax_q, name) in enumerate(zip(panels, ("KI", "KII", "J"), strict=False)):
            draw_quantity(ax_q, group, name, {t: v[q] for t, v in refs.items()} if q < 2 else {},
                          reference_label)
        panels[-1].set_xlabel("J-domain radius")
        panels[0].set_title(title + ", ".join(f"tip {r.tip.id} (spread {r.spread:.2g} of |K|)"
                                              for _, r in group))
    return fig
