"""How often moving nodes need a new search (seed 000 Sect. 4.2).

Between searches the nodes move; registering each support with its radius grown by
``psi h`` keeps every pair that can come within the support during
``dt = psi h / (2 |U_max|)``, since two nodes approach each other by at most
``2 |U_max| dt = psi h`` (the seed's box side (2 + psi) h for a support 2h).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Research", "research_interval"]


@dataclass(frozen=True)
class Research:
    """When to search again.

    Attributes
    ----------
    dt : float
        Time between searches, psi h / (2 |U_max|) (inf for nodes at rest).
    box_side : float
        The seed's box side (2 + psi) h for supports of radius 2 h.
    skin : float
        The radius increase psi h of the candidate lists.
    """

    dt: float
    box_side: float
    skin: float


def research_interval(h: float, u_max: float, psi: float = 0.1) -> Research:
    """Re-search interval of seed 000 Sect. 4.2: ``dt = psi h / (2 |U_max|)``.

    Parameters
    ----------
    h : float
        Smoothing length (support radius 2 h); the smallest of the cloud for a graded one.
    u_max : float
        Largest node speed |U_max|.
    psi : float
        Skin over the smoothing length; the seed takes 0.1 (larger psi: fewer searches but
        more candidates to filter at every step).

    Examples
    --------
    >>> res = research_interval(h=0.15, u_max=3000.0)   # 0.1 * 0.15 / 6000
    >>> round(res.dt, 15), round(res.box_side, 12)
    (2.5e-06, 0.315)
    """
    for name, v in (("h", h), ("psi", psi)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a positive number, got {v!r}")
    if not np.isfinite(u_max):
        raise ValueError(f"u_max must be finite, got {u_max!r}")
    speed = abs(float(u_max))
    dt = np.inf if speed == 0 else psi * h / (2.0 * speed)
    return Research(float(dt), float((2.0 + psi) * h), float(psi * h))
