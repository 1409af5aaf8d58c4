"""The acceleration of the inertia term of the dynamic ``J'``: the driver's lumped-mass
acceleration moved towards the consistent-mass one by Jacobi steps (used by
:class:`~efgkit.explicit.dsif.TipOperators`; seed 002 Eqs. 31-38 for ``J'``).

The driver's ``a^n = M_L^-1 (f(t_n) - K u^n)`` (the lumped mass ``M_L``; the same time
level as ``u^n``) does not balance the discrete stresses in the weak sense the domain form
of ``J'`` relies on: the field ``a^h = sum psi_I a_I`` does so when ``M_C a = M_L a^n``
(``M_C`` the consistent mass, :func:`~efgkit.system.mass.consistent_mass`). ``M_L^-1 M_C``
has eigenvalues in (0, 1], down to ~1e-5 for MLS functions: solving would amplify the
unresolved short waves, so ``iterations`` (``DynamicDSIF.mass_iterations``) Jacobi steps
``a <- a + M_L^-1 (M_L a^n - M_C a)`` from ``a^n`` are taken instead (a truncated Neumann
series of ``M_C^-1 M_L``): they correct the resolved
modes, whose eigenvalues lie near 1, and leave the short ones near ``a^n``. On the
centre-cracked plate (``verification/center_crack_dynamic.py``, 209 x 83 nodes) the
path dependence of ``J'_1`` falls from 2.2 % (lumped) to 0.5 % (mode I) and from 1.6 % to
0.9 % (mode II, whose static path dependence on that grid is 0.85 %) with 4 steps. The
steps are exact on the points within ``R_max + (2 k + 2) r_support`` of the tips, so
``M_C`` is assembled there only (everywhere with enrichment, whose unknowns couple the
body). The row-sum masses bound the eigenvalues of the nodal block by about 1. An
enrichment unknown takes the steps only where its lumped mass bounds its absolute row sum
of ``M_C`` (``enrichment_mass="abs_row_sum"``, :mod:`efgkit.system.mass`: by Gershgorin the
step then contracts); with the default diagonal of their consistent block the largest
eigenvalue of ``M_L^-1 M_C`` is 9.5 (PU) and 1.6 (extrinsic MLS; ``verification/freund.py``
scene, spacing 0.02), a Jacobi step diverges above 2 (with PU, ``K`` came out 20 times too
large), and they keep ``a^n``. With the abs-row-sum mass and 16 steps, PU enrichment brings
the centre-cracked plate on the seed's 1 mm grid to 0.89 % (mode I) and 0.69 % (mode II)
path dependence, from 2.07 % and 1.98 % without enrichment (4 steps; 16 do not help there,
2.10 %). With the diagonal mass the enriched runs of ``verification/freund.py`` (spacing
0.01) come within 0.44 % (extrinsic MLS) and 4.4 % (PU) of Freund's K_I, from 9.3 % and
13.6 % with ``a^n``. MLPG1
keeps ``a^n``: its consistent mass is the Petrov-Galerkin ``int v_I psi_J`` of the
sub-domains, not assembled; MLPG's Galerkin form (the default of explicit MLPG runs) takes
the steps as EFG.
"""

from __future__ import annotations

import numpy as np

from ..system.mass import consistent_mass

__all__ = ["AccelerationRecovery"]


class AccelerationRecovery:
    """The acceleration recovery of one explicit run (module docstring).

    Parameters
    ----------
    dyn : Dynamics
        The run (:func:`~efgkit.explicit.system.dynamics`): its discretisation, lumped mass
        ``m`` and inverse ``minv`` (n_dofs,) and constraint projection.
    centres : sequence of ndarray (2,)
        The crack tips.
    radii : sequence of float
        The largest J-domain radius of each tip: the steps are exact within
        ``radius + (2 k + 2) r_support`` of its tip (``k`` steps).

    Calling it as ``recovery(a, iterations)`` returns the recovered acceleration (n_dofs,);
    the consistent mass near the tips is assembled once per number of steps.
    """

    def __init__(self, dyn, centres, radii):
        self.dyn = dyn
        self.centres = list(centres)
        self.radii = list(radii)
        self._mass = {}  # iterations -> (the consistent mass near the tips, the Jacobi step)

    def __call__(self, a: np.ndarray, iterations: int) -> np.ndarray:
        """``iterations`` Jacobi steps ``a <- a + M_L^-1 (M_L a^n - M_C a)`` from the driver's
        acceleration ``a^n (n_dofs,)`` towards the consistent one (module docstring), then
        the constraint projection of the run, if any; enrichment unknowns only where their
        lumped mass bounds their absolute row sum of ``M_C`` (module docstring).
        MLPG1 and ``iterations = 0``: ``a^n``."""
        dyn, disc = self.dyn, self.dyn.disc
        if iterations == 0 or disc.test is not None:
            return a
        M = self._mass.get(iterations)
        if M is None:
            rows = None
            if disc.shape.extra is None:  # local: exact within R_max + (2 k + 2) r_support
                x = disc.points.x
                near = np.zeros(len(x), bool)
                reach = (2 * iterations + 2) * float(disc.nodes.radius.max())
                for centre, radius in zip(self.centres, self.radii, strict=True):
                    near |= np.hypot(*(x - centre).T) <= radius + reach
                rows = np.flatnonzero(near)
            M = consistent_mass(disc.shape, disc.points.w, disc.scene.material.rho, rows)
            step, n = dyn.minv.copy(), 2 * disc.nodes.n  # enrichment: where m >= sum_j |M_ij|
            step[n:][dyn.m[n:] < (1 - 1e-9) * abs(M[n:]).sum(axis=1)] = 0.0  # (module docstring)
            M = self._mass[iterations] = (M, step)
        M, step = M
        r = dyn.m * a
        out = a.copy()
        for _ in range(iterations):
            out += step * (r - M @ out)
        P = dyn.projection
        if P is not None:
            out -= P.minv_GT @ P.lu.solve(P.G @ out)
        return out
