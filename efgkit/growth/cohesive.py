"""Gradual release of a released segment's support: a linear cohesive law (used by
:mod:`efgkit.growth.release`, ``LineRelease.opening``).

The seed releases a node at once (two
particles a gap apart): the support's force on the opened segment vanishes in one step,
the energy it held goes into waves and nothing is dissipated, so the model has no fracture
energy and an overdriven crack runs at the fastest pace the discrete field allows: on the
tungsten plate at 1000/s a node every 1-2 steps, 1.00-1.03 c_R over 2-4 mm
(``verification/tungsten.py``), above the Rayleigh speed that bounds any crack that takes
energy from the field (Freund, Dynamic Fracture Mechanics, Sect. 5.3: the energy release
rate of a mode-I crack vanishes as v -> c_R). With ``opening = delta_c > 0`` the force
``f_j`` the support exerted on segment j at its release (``-int lambda u_y``, from the
multipliers ``lambda = (G M^-1 G^T)^-1 G M^-1 (f - K u)``) is kept as a load and softens
linearly with the segment's opening ``w = 2 f_j.u / f_j.e_y`` (both faces):
``f_j max(0, 1 - w / delta_c)``, never growing back (a linear cohesive law). It dissipates
``G_c = sigma_c delta_c / 2`` per unit of new crack; the toughness the criterion implies at
the line's spacing h (the stress ``K / sqrt(2 pi h)`` at the node ahead, seed 000 Eq. 5.4)
gives ``delta_c = 2 G_c / sigma_c = 4 pi h sigma_c / E'`` (:func:`critical_opening`).

"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Softening", "critical_opening"]


def critical_opening(sigma_c, spacing: float, modulus):
    """The critical opening ``delta_c = 4 pi h sigma_c / E'`` of a linear cohesive release
    that dissipates the energy release rate ``G_c = K_c^2 / E'`` at the toughness
    ``K_c = sigma_c sqrt(2 pi h)`` a principal-stress criterion at the node ``h`` ahead of
    the tip implies (seed 000 Eq. 5.4): ``G_c = sigma_c delta_c / 2``. ``modulus``: E'
    (E in plane stress, E / (1 - nu^2) in plane strain); arrays broadcast.

    Examples
    --------
    >>> round(float(critical_opening(4500.0, 0.025, 400e3 / (1 - 0.29**2))), 7)
    0.0032371
    """
    if not (isinstance(spacing, (int, float)) and math.isfinite(spacing) and spacing > 0):
        raise ValueError(f"spacing must be a finite number > 0, got {spacing!r}")
    out = 4 * math.pi * spacing * np.asarray(sigma_c, float) / np.asarray(modulus, float)
    if not np.all(np.isfinite(out) & (out > 0)):
        raise ValueError("sigma_c and modulus must be finite and > 0 (stress units), got "
                         f"{sigma_c!r} and {modulus!r}")
    return out


class Softening:
    """Load factor of a released segment's support force ``f`` (n_dofs,): linear softening
    with the segment's opening ``w = 2 (f . u) / (f . e_y)`` (the force-weighted mean of
    ``u_y`` over the segment, doubled: both faces of the symmetric model),
    ``max(0, 1 - w / opening)``, never growing back."""

    def __init__(self, f: np.ndarray, resultant: float, opening: float):
        self.f, self.resultant, self.opening, self.value = f, resultant, opening, 1.0

    def update(self, u) -> None:
        w = 2.0 * float(self.f @ u) / self.resultant if self.resultant != 0 else math.inf
        self.value = min(self.value, max(0.0, 1.0 - w / self.opening))

    def __call__(self, t: float) -> float:
        return self.value
