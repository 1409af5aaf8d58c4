"""Figures of a growth loop: the crack paths over the stress field, K against crack
length, and a(N) of a fatigue loop. Each returns the figure and never calls ``show()``
(save with :func:`efgkit.io.write_figure`)."""

from __future__ import annotations

import numpy as np

from ..plot import plot_stress

__all__ = ["plot_k", "plot_life", "plot_path"]


def _check(steps):
    steps = list(steps)
    if not steps:
        raise ValueError("steps is empty: give the GrowthStep objects of a loop (list(grow(...)))")
    return steps


def plot_path(steps, component: str = "von_mises", ax=None, n_target: int = 20000):
    """The last step's stress field (``component`` as in :func:`efgkit.plot.plot_stress`)
    with every crack's path and the tip position of each step (dots)."""
    steps = _check(steps)
    last = steps[-1]
    fig = plot_stress(last.solution, component, ax=ax, n_target=n_target)
    ax = fig.axes[0]
    tips = np.array([t.tip.x for s in steps for t in s.tips]).reshape(-1, 2)
    ax.plot(tips[:, 0], tips[:, 1], "o", ms=2.5, color="w", mec="k", mew=0.4, label="tip per step")
    ax.set_title(f"{last.scene.name}: crack paths after {last.index} steps over the "
                 f"{component.replace('_', ' ')} stress")
    ax.legend(loc="best", fontsize=7)
    return fig


def _series(steps, key):
    """tip id -> (crack lengths (k,), values (k,)) over the steps where the tip exists."""
    out = {}
    for s in steps:
        for t, keq in zip(s.tips, s.K_eq, strict=True):
            v = {"KI": t.KI, "KII": t.KII, "K_eq": float(keq)}[key]
            out.setdefault(t.tip.id, ([], []))
            out[t.tip.id][0].append(s.lengths[t.tip.crack])
            out[t.tip.id][1].append(v)
    return out


def plot_k(steps, ax=None):
    """K_I (solid), K_II (dashed) and K_eq (dotted) of every tip against its crack's length."""
    import matplotlib.pyplot as plt

    steps = _check(steps)
    fig, ax = plt.subplots(figsize=(6.5, 4.0)) if ax is None else (ax.figure, ax)
    for k, tip in enumerate(_series(steps, "KI")):
        for key, style in (("KI", "-o"), ("KII", "--s"), ("K_eq", ":")):
            a, v = _series(steps, key)[tip]
            ax.plot(a, v, style, color=f"C{k}", ms=3, label=f"{tip}: {key}")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("crack length")
    ax.set_ylabel("stress intensity factor")
    ax.set_title(f"{steps[-1].scene.name}: K against crack length")
    ax.legend(fontsize=7)
    return fig


def plot_life(steps, ax=None):
    """Crack length against cycles, a(N), of a Paris loop."""
    import matplotlib.pyplot as plt

    steps = _check(steps)
    if steps[-1].cycles is None:
        raise ValueError("plot_life needs the steps of a Paris loop (criterion='paris'); these "
                         "steps carry no cycles")
    fig, ax = plt.subplots(figsize=(6.5, 4.0)) if ax is None else (ax.figure, ax)
    N = [s.cycles for s in steps]
    for k, name in enumerate(steps[0].lengths):
        ax.plot(N, [s.lengths.get(name, np.nan) for s in steps], "-o", ms=3, color=f"C{k}",
                label=name)
    ax.set_xlabel("cycles N")
    ax.set_ylabel("crack length a")
    ax.set_title(f"{steps[-1].scene.name}: fatigue crack growth a(N)")
    ax.legend(fontsize=7)
    return fig
