"""The Bubnov-Galerkin form of an MLPG discretisation for explicit runs (``MLPG.explicit_form``).

Central differences (and any non-dissipative scheme) stay bounded over runs of any length
exactly when ``M^-1 K`` (on the admissible motions) is diagonalisable with real eigenvalues
in ``[0, 4 / dt^2)``; an eigenvalue off the non-negative real axis is a mode of the
semi-discrete system itself that grows like ``exp(gamma t)``, which no step size and no time
integrator without dissipation removes (:func:`~efgkit.explicit.spectrum.growth_rate`).
MLPG1's local Petrov-Galerkin rows (test function ``v_I`` on the disc, trial ``phi_J``) give
an unsymmetric K with such eigenvalues for every trial weight, test radius and mass measured
(docs/theory.md, "Explicit MLPG"). A symmetric positive semi-definite K with a positive
diagonal M has none, by construction: ``M^-1 K`` is similar to ``M^-1/2 K M^-1/2``, and the
modified energy of :mod:`efgkit.explicit.integrate` is conserved.

``explicit_form="galerkin"`` steps that operator for an MLPG discretisation: the same
nodes, trial functions (MLPG's weight, ``d_max``, basis, crack rule and crack-face nodes) and
essential-condition method, with the test functions equal to the trial functions and every
node's sub-domain its whole trial support, so that the local weak forms add up to the global
one (the test = trial member of the MLPG family), all integrated on the field cells of the
discretisation (``Discretization.post_points``, the quadrature of J' and the energies):

    K_IJ = int_Omega eps(phi_I)^T D eps(phi_J),   M_I = rho int_Omega phi_I (row sum),
    f_I = int_Gt phi_I tbar + int_Omega phi_I b (+ the crack-face pressure),

so the masses add up to ``rho`` times the area (MLPG1's disc masses do not). ``bc="penalty"``:
``alpha int_Gu phi_I phi_J`` (symmetric, semi-definite; ``alpha`` as MLPG's local penalty),
the prescribed values as forcing; ``"modified_mls"`` and ``"collocation"`` as for MLPG1's
explicit runs (fixed coefficients; rows imposed by the M-orthogonal projection, which keeps
the constrained operator symmetric in the M inner product). This is not MLPG1: static solves
and the default explicit form keep the local Petrov-Galerkin rows.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.sparse import csr_array

from ..methods.boundary import essential_conditions, loads
from ..methods.discretize import Discretization
from ..system.assemble import stiffness
from ..system.constraints import penalty
from ..system.mass import row_sum_mass
from .moving import split_values, still_scene

__all__ = ["galerkin_discretization", "galerkin_system"]


def galerkin_discretization(disc: Discretization) -> Discretization:
    """The MLPG discretisation ``disc`` with its field cells as the quadrature and no test
    functions: the Bubnov-Galerkin form of its trial functions (module docstring)."""
    if disc.field_points is None or disc.test is None:
        raise ValueError("disc must be an MLPG discretisation (with test functions and field "
                         "cells, efgkit.methods.local.discretize_local)")
    return replace(disc, points=disc.field_points, shape=disc.post_shape, field_points=None,
                   test=None, local=None)


def galerkin_system(scene, disc: Discretization, parts: list, alpha: float | None):
    """K, lumped M and loads of the Galerkin form (module docstring).

    Parameters
    ----------
    scene : Scene
    disc : Discretization
        The MLPG discretisation.
    parts : list of (Scene, history)
        The scene split by load history (one load vector each).
    alpha : float or None
        Penalty factor (force / length^3) of ``bc="penalty"`` with supports, else None.

    Returns
    -------
    gdisc : Discretization
        :func:`galerkin_discretization` of ``disc``.
    K : csr_array (n_dofs, n_dofs)
        Symmetric, with the penalty term.
    m : ndarray (n_dofs,)
        Row-sum mass, checked positive and adding up to ``rho`` times the area.
    F : ndarray (n_dofs, n_loads)
    f_bc : ndarray (n_dofs,)
        The penalty forcing of the prescribed values (zeros without penalty).
    Q, q_histories : ndarray (n_dofs, k) or None, tuple
        Penalty forcing of moving supports per history (:func:`~efgkit.explicit.moving.split_values`).
    """
    g = galerkin_discretization(disc)
    mat = scene.material
    K = csr_array(stiffness(g.shape, g.points.w, mat.D))
    m = row_sum_mass(g.shape, g.points.w, mat.rho, node_x=g.nodes.x, area=scene.domain.area)
    F = np.column_stack([loads(replace(g, scene=s)) for s, _ in parts]) if parts \
        else np.zeros((g.n_dofs, 0))
    f_bc, Q, qh = np.zeros(g.n_dofs), None, ()
    if alpha is not None:
        K0, zero = K, np.zeros(g.n_dofs)

        def pen(s):
            bc = essential_conditions(replace(g, scene=s), derivatives=False)
            return penalty(K0, zero, bc, alpha, g.nodes.x, check=False)

        lin = pen(still_scene(scene))
        K, f_bc = csr_array(lin.A), lin.b
        Q, qh = split_values(scene, lambda s: pen(s).b)
    return g, K, m, F, f_bc, Q, qh
