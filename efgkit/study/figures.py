"""Figures of a study: K against each varied parameter.

One figure per parameter: K_I (and K_II where some point has one above 1e-3 of the largest
K_I: less is the noise of a mode-I problem) of every tip against the parameter's values.
In a grid, the points that share the values of the other parameters are joined by a
line, one line per combination (up to :data:`MAX_LINES`, beyond which they are drawn
as points only); in a zip study the points form one line (the parameters vary
together), in a random one a cloud. Failed and missing points are left out. Figures are
returned, never shown (design rule 10).
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_LINES", "plot_study"]

MAX_LINES = 12


def _numeric(col) -> bool:
    import pandas as pd

    return pd.api.types.is_numeric_dtype(col) and not pd.api.types.is_bool_dtype(col)


def _series(df, x: str, others: list[str]):
    """(label, sub-frame sorted by x) per combination of the other parameters."""
    if not others:
        return [("", df.sort_values(x) if _numeric(df[x]) else df)]
    groups = df.groupby(others, sort=True, dropna=False)
    return [(", ".join(f"{o} = {v:.4g}" if isinstance(v, float) else f"{o} = {v}"
                       for o, v in zip(others, key if isinstance(key, tuple) else (key,),
                                       strict=True)),
             g.sort_values(x) if _numeric(df[x]) else g) for key, g in groups]


def plot_study(df, study) -> dict:
    """K against each parameter of ``study``, from its table ``df``
    (:func:`~efgkit.study.table.study_table`).

    Returns
    -------
    dict
        parameter name -> matplotlib Figure (empty when no point has finished).
    """
    import matplotlib.pyplot as plt

    ok = df[df["status"] == "ok"]
    tips = sorted({c[3:-1] for c in df.columns if c.startswith("KI[")})
    labels = [p.label for p in study.parameters]
    figs = {}
    for x in labels:
        ks = ["KI"] + ["KII"] * any(np.nanmax(np.abs(ok[f"KII[{t}]"].to_numpy(float)), initial=0)
                                    > 1e-3 * np.nanmax(np.abs(ok[f"KI[{t}]"].to_numpy(float)),
                                                       initial=0) for t in tips)
        fig, axes = plt.subplots(1, len(ks), figsize=(5.5 * len(ks), 4.0), squeeze=False)
        grid = study.combine == "grid"
        others = [o for o in labels if o != x and ok[o].nunique() > 1] if grid and len(ok) else []
        series = _series(ok, x, others) if len(ok) else []
        joined = study.combine != "random" and len(series) * max(len(tips), 1) <= MAX_LINES
        for ax, k in zip(axes[0], ks, strict=True):
            for t in tips:
                for lab, g in series:
                    xs = g[x] if _numeric(g[x]) else g[x].astype(str)
                    name = ", ".join(s for s in (t if len(tips) > 1 else "", lab) if s)
                    ax.plot(xs, g[f"{k}[{t}]"], "o-" if joined else "o", ms=4,
                            label=name or None)
            ax.set_xlabel(x)
            ax.set_ylabel({"KI": "$K_I$", "KII": "$K_{II}$"}[k])
            ax.grid(True, alpha=0.3)
            if joined and ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=7)
        n_bad = int((df["status"] != "ok").sum())
        fig.suptitle(f"{study.name}: {len(ok)} points" + (f" ({n_bad} failed or missing, "
                                                         "not shown)" if n_bad else ""))
        fig.tight_layout()
        figs[x] = fig
    return figs
