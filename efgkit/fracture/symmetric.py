"""SIFs of the tips of half and quarter models: the domain integrals over the fields mirrored
onto the whole body (:mod:`efgkit.problem.symmetry`)."""

from __future__ import annotations

from dataclasses import replace

from ..problem.symmetry import mirror_fields
from .sif import scene_tip, tip_radii, tip_result

__all__ = ["symmetric_tip_results"]


def symmetric_tip_results(scene, x, w, stress, grad, spacing, radii=None, q="wendland_c2",
                          spread_tol: float = 0.01) -> tuple:
    """One :class:`~efgkit.fracture.sif.TipResult` per modelled tip of ``scene.symmetry``.

    The fields at the model's quadrature points (``x (n, 2)``, ``w (n,)``, Voigt
    ``stress (n, 3)``, ``grad (n, 2, 2)``) are mirrored across every symmetry line
    (:func:`~efgkit.problem.symmetry.mirror_fields`), and :func:`~efgkit.fracture.sif.tip_result`
    runs the interaction integrals about the tip in the whole body (:meth:`Scene.full
    <efgkit.problem.scene.Scene.full>`): the domains are discs, as in a full model. The
    mirrored field is symmetric, so K_II is zero to rounding; it is reported as 0 (by
    symmetry). ``spacing(tip)`` is the local spacing of the default radii.
    """
    full = scene.full()
    X, W, S, G = mirror_fields(scene.symmetry, x, w, stress, grad)
    out = []
    for tip in scene.symmetry.modelled_tips(scene.domain):
        t = scene_tip(full, tip)
        rs = tip_radii(full, t, radii, spacing(tip))
        res = tip_result(full, t, X, W, S, G, rs, q=q, spread_tol=spread_tol)
        out.append(replace(res, KII=0.0, domains=tuple(replace(d, KII=0.0) for d in res.domains)))
    return tuple(out)
