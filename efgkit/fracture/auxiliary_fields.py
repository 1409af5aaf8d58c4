"""The unit auxiliary fields of the interaction integrals: Williams mode I and mode II
and the point force along x1 (for T), as stress tensors and displacement gradients."""

from __future__ import annotations

import numpy as np

from ..problem.exact.williams import (
    point_force_gradient,
    point_force_stress,
    williams_gradient,
    williams_stress,
)
from ..problem.material import voigt_tensor

__all__ = ["auxiliary_fields"]


def auxiliary_fields(r, theta, material) -> tuple[np.ndarray, np.ndarray]:
    """Stress tensors and displacement gradients, both (3, m, 2, 2), of the unit auxiliary
    fields of the interaction integrals at tip-frame polar points ``(r, theta)`` (m,):
    Williams mode I, mode II and the point force along x1 (:mod:`efgkit.fracture.integrals`)."""
    mu, kappa = material.mu, material.kappa
    s = np.stack([voigt_tensor(williams_stress(r, theta, 1.0, 0.0)),
                  voigt_tensor(williams_stress(r, theta, 0.0, 1.0)),
                  voigt_tensor(point_force_stress(r, theta, 1.0))])
    g = np.stack([williams_gradient(r, theta, 1.0, 0.0, mu, kappa),
                  williams_gradient(r, theta, 0.0, 1.0, mu, kappa),
                  point_force_gradient(r, theta, 1.0, mu, kappa)])
    return s, g
