"""Supports that move: prescribed displacements ``g_k(t) ubar_k(x)`` in an explicit run.

A :class:`~efgkit.problem.scene.Support` with a ``history`` prescribes ``g(t)`` times its
components. Every constraint the explicit system imposes is linear in the prescribed
values (the right-hand side ``q`` of the Lagrange rows ``G u = q`` or of the collocation
rows, the fixed coefficients of the modified MLS, the penalty / Nitsche forcing), and ``G``
itself does not depend on them, so

    q(t) = q_0 + sum_k g_k(t) q_k

with ``q_0`` the value vector of the supports without history (the moving ones set to 0)
and ``q_k`` that of moving support k alone (all other values 0). :func:`split_values`
builds ``q_0`` and the columns ``q_k`` from any function that maps a scene to its value
vector; :mod:`efgkit.explicit.system` passes the one of the method's constraint.

Imposing ``G u^{n+1} = q(t_{n+1})`` by the M-orthogonal projection (the forward-increment
Lagrange multipliers of Carpenter, Taylor and Katona 1991, as for fixed supports) is
exact kinematics on the constrained motion: the staggered velocity of the projected step is
``(u^{n+1} - u^n) / dt``, so ``G v^{n+1/2} = (q(t_{n+1}) - q(t_n)) / dt``. The constraint
force of step n is ``r^n = -M du / dt^2`` (du the projection's correction); a moving
support does work ``r^n . (u^{n+1} - u^{n-1}) / 2``, added to the time-centred work so that
the modified-energy balance of :mod:`efgkit.explicit.integrate` holds as before (for a
fixed support ``r^n = G^T lambda`` and ``G (u^{n+1} - u^{n-1}) = 0``: no work).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

__all__ = ["split_values", "still_scene"]


def _zeroed(sup):
    """The support with its prescribed components 0 (free ones stay free), no history."""
    return replace(sup, ux=None if sup.ux is None else 0.0, uy=None if sup.uy is None else 0.0,
                   history=None)


def still_scene(scene):
    """The scene with every moving support's values set to 0 (its ``q_0`` scene)."""
    return scene.with_supports(tuple(_zeroed(s) if s.history is not None else s
                                      for s in scene.supports))


def split_values(scene, values) -> tuple[np.ndarray | None, tuple]:
    """``(Q (r, k), histories (k,))`` of the moving supports of ``scene``: column ``k`` is
    ``values(scene_k)``, the value vector with only moving support k prescribing (its
    history stripped) and every other value 0 (module docstring). ``(None, ())`` without
    moving supports. ``values(scene) -> (r,)``: the constraint's value vector.
    """
    moving = [i for i, s in enumerate(scene.supports) if s.history is not None]
    if not moving:
        return None, ()
    cols = []
    for i in moving:
        sups = tuple(replace(s, history=None) if j == i else _zeroed(s)
                     for j, s in enumerate(scene.supports))
        cols.append(np.asarray(values(scene.with_supports(sups)), float))
    return np.column_stack(cols), tuple(scene.supports[i].history for i in moving)
