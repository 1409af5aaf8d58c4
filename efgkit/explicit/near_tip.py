"""Near-tip estimates of the dynamic SIF hook: K from the stresses on rays from a tip.

:class:`NearTipRays` holds, for one tip, the gradient operators (points x MLS
coefficients) on the rays theta = 0 and +-90 degrees (tip frame) and gives, for the
coefficients ``u`` of an output instant, side by side (seed 000 Eqs. 5.2-5.5, Sect. 5.1):

* ``"stress_0"``: the mean of the apparent ``K = sqrt(2 pi r) (sigma_22, sigma_12)`` at
  the two points nearest the tip on theta = 0, ``r = h`` and ``2 h``
  (:func:`~efgkit.fracture.extrapolation.near_tip_sif`; seed 000 Fig. 8);
* ``"stress_0_fit"``: the straight line ``K + b r`` fitted by least squares to the
  apparent values on theta = 0 at ``r = h, 1.25 h, ..., 4 h`` (:data:`FIT_SPACINGS`),
  evaluated at ``r = 0``
  (:func:`~efgkit.fracture.extrapolation.fitted_near_tip_sif`): it removes the ``b r``
  error of the Williams ``r^(1/2)`` term that the mean at ``1.5 h`` keeps;
* ``"stress_90"``: each mode from its symmetry part of the rays +-90 degrees
  (:func:`~efgkit.fracture.extrapolation.k_from_symmetric_rays`), mean of the two points
  nearest the tip.

``h`` is the local node spacing, or a sixth of 0.9 times the distance from the tip to the
nearest boundary, kink or other crack where that is smaller (the rays stay in the free
disc about the tip). Measured against ``K`` from ``J'`` on the centre-cracked plate
(``verification/center_crack_dynamic.py``, median of ``|K / K_J - 1|``): the fit is the
better theta = 0 estimate in mode I on 0.5 mm nodes (2.0 % against 4.3 %) and in mode II
with PU enrichment (1.7 % against 7.4 %), the worse one in mode II without enrichment and
in mode I with PU on the seed's 1 mm nodes, where the inertia term of the near field
(``K''(t) r^2`` in ``K(r)``) is already large at a few spacings (docs/theory.md,
"Near-tip estimates under dynamic load"). Both are given side by side.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array, vstack

from ..fracture.extrapolation import fitted_near_tip_sif, k_from_symmetric_rays, near_tip_sif, ray_points
from ..problem.crack import Tip
from ..problem.material import strain_from_gradient

__all__ = ["FIT_SPACINGS", "NEAREST_SPACINGS", "NEAR_TIP_ESTIMATES", "NearTipRays"]

NEAREST_SPACINGS = np.arange(1.0, 7.0)
"""Distances of the ray points of ``"stress_0"`` and ``"stress_90"``, in ``h`` (1 to 6)."""

FIT_SPACINGS = np.arange(1.0, 4.0 + 1e-9, 0.25)
"""Distances of the fitted points of ``"stress_0_fit"``, in ``h`` (1 to 4 by 1/4)."""

NEAR_TIP_ESTIMATES = ("stress_0", "stress_0_fit", "stress_90")


def _grad_op(disc, x) -> csr_array:
    """Rows (d ux/dx, d ux/dy, d uy/dx, d uy/dy) x points -> coefficients, (4 m, n_dofs)."""
    return csr_array(vstack(list(disc.shape_at(x, derivatives=True).grad_operators()), format="csr"))


class NearTipRays:
    """The ray operators of one tip and its near-tip estimates (module docstring).

    Parameters
    ----------
    disc : Discretization
        Gives ``shape_at`` (the MLS functions at new points).
    tip : Tip
    h : float
        Local node spacing at the tip, > 0.
    free : float
        Distance from the tip to the nearest boundary, kink or other crack, > 0.
    D : ndarray (3, 3)
        Elasticity matrix (Voigt, engineering shear).
    """

    def __init__(self, disc, tip: Tip, h: float, free: float, D: np.ndarray):
        if not (np.isfinite(h) and h > 0 and np.isfinite(free) and free > 0):
            raise ValueError(f"h and free must be finite and > 0 (the spacing at the tip and its "
                             f"free distance), got h = {h!r}, free = {free!r}")
        self.tip, self.D = tip, np.asarray(D, float)
        base = min(float(h), 0.9 * float(free) / NEAREST_SPACINGS[-1])
        self.r, self.r_fit = base * NEAREST_SPACINGS, base * FIT_SPACINGS
        x = [ray_points(tip, self.r, th) for th in (0.0, np.pi / 2, -np.pi / 2)]
        x.append(ray_points(tip, self.r_fit, 0.0))
        self._op = _grad_op(disc, np.concatenate(x))
        self._split = np.cumsum([len(p) for p in x])[:-1]

    def estimates(self, u: np.ndarray) -> dict:
        """``{"stress_0", "stress_0_fit", "stress_90"}: ndarray (2,)`` (``K_I``, ``K_II``)
        for the coefficients ``u (n_dofs,)``."""
        g = (self._op @ u).reshape(2, 2, -1).transpose(2, 0, 1)
        s0, s90, s270, sfit = np.split(strain_from_gradient(g) @ self.D.T, self._split)
        KI, KII = k_from_symmetric_rays(self.tip, self.r, s90, s270)
        return {"stress_0": np.array(near_tip_sif(self.tip, self.r, s0, 0.0)),
                "stress_0_fit": np.array(fitted_near_tip_sif(self.tip, self.r_fit, sfit, 0.0)),
                "stress_90": np.array([KI[:2].mean(), KII[:2].mean()])}
