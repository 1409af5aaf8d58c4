"""Dynamic stress intensity factors at the output instants of an explicit run: the hook.

:func:`~efgkit.explicit.integrate.integrate` calls ONE function at every output instant,
``dsif(dyn, u, v, a, t) -> {estimate: ndarray (n_tips, 2)}`` (K_I, K_II of every tip of
``scene.tips``), with the MLS coefficients of the displacement ``u``, velocity ``v`` and
acceleration ``a`` at ``t`` (each ``(n_dofs,)``). The dynamic J' of seed 002 Eqs. (31)-(38)
plugs in here (it needs ``v`` and ``a`` for the kinetic and inertia terms). Until then
:func:`quasi_static_dsif` evaluates the static estimates on the current displacement,
which omit the inertia terms.
"""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["quasi_static_dsif"]


def quasi_static_dsif(dyn, u: np.ndarray, v: np.ndarray, a: np.ndarray, t: float) -> dict:
    """Quasi-static K_I, K_II of every tip from the displacement ``u`` at ``t``.

    Estimates (each ndarray (n_tips, 2)):

    * ``"interaction"``: the static interaction integral over the default domains
      (:func:`efgkit.fracture.sif.tip_result`, without the error estimate; no inertia term);
    * ``"stress_0"``, ``"stress_90"``: from the near-tip stresses on theta = 0 and 90
      degrees (seed 000 Eqs. 5.2-5.5; :meth:`MeshlessSolution.near_tip_estimates`).

    ``v`` and ``a`` are unused here (the dynamic J' needs them). The domain-spread warnings
    of the static integral are silenced: they fire at every instant before the waves
    arrive, where K is zero.
    """
    from .system import solution_at

    sol = solution_at(dyn, u, t)
    tips = sol.scene.tips
    out = {k: np.zeros((len(tips), 2)) for k in ("interaction", "stress_0", "stress_90")}
    if not tips:
        return out
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = sol.sifs(error=False)
        for k, (tip, r) in enumerate(zip(tips, res, strict=True)):
            out["interaction"][k] = (r.KI, r.KII)
            est = sol.near_tip_estimates(tip)
            out["stress_0"][k] = est["stress_0"]
            out["stress_90"][k] = est["stress_90"]
    return out
