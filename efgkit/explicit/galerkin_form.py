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
keep the local Petrov-Galerkin rows.

It is the default of explicit runs (``explicit_form="auto"``, :func:`resolve_form`, with a
warning saying so): explicit MLPG1 (``explicit_form="petrov_galerkin"``) blows up at any
step after a number of steps set by its growing modes (on the free 2 x 1 plate of
``verification/stability.py`` at h = 0.125 and 0.98 dt_c: 38 steps with the Gaussian
weight, 1882 with the cubic weight that ``explicit_weight="auto"`` steps in its place), so
it is kept for study only (docs/theory.md, "Explicit MLPG").

Its trial functions are MLPG's with two choices of explicit runs (:func:`trial_choices`,
``MLPG.explicit_crack_rule`` and ``explicit_weight_k``, "auto"): the diffraction crack rule
in place of visibility, whose jumps along the shadow rays from the nodes through a tip
cross the J' domain, and the seed's Gaussian ``k = 2`` (seed 002 Eq. 7) in place of
``k = 1``, MLPG's static default chosen against the near-singular bending mode of MLPG1's
Petrov-Galerkin system, which a symmetric K does not have. Measured on Freund's K_I(t)
(``verification/freund.py``, :func:`spacings` there; error of K from J' at h = 0.02 / 0.01
/ 0.005): k = 2 with diffraction 0.52 / 0.13 / 0.070 %, k = 1 with diffraction 1.85 / 0.48 /
0.53 %, k = 2 with visibility 2.74 / 1.86 / 1.39 %, k = 1 with visibility (the static
trial functions) 8.80 / 6.45 / 4.22 % (with the face fit of :mod:`efgkit.fracture.face_fit`;
before it 0.23 / 0.88 / 0.78, 2.95 / 3.88 / 0.77, 1.85 / 1.38 / 1.51 and 9.52 / 4.10 / 4.51 %).
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
from scipy.sparse import csr_array

from ..methods.boundary import essential_conditions, loads
from ..methods.discretize import Discretization
from ..methods.mlpg import MLPG
from ..system.assemble import stiffness
from ..system.constraints import penalty
from ..system.mass import row_sum_mass
from .moving import split_values, still_scene

__all__ = ["EXPLICIT_AUTO_CRACK_RULE", "EXPLICIT_AUTO_WEIGHT_K", "galerkin_discretization",
           "galerkin_system", "resolve_form", "trial_choices"]


EXPLICIT_AUTO_CRACK_RULE = "diffraction"  # explicit_crack_rule="auto" in place of visibility
EXPLICIT_AUTO_WEIGHT_K = 2  # explicit_weight_k="auto" in place of k = 1 (seed 002 Eq. 7)


def trial_choices(method: MLPG) -> dict:
    """The trial-function changes of ``method``'s explicit runs as keyword changes:
    ``explicit_crack_rule`` and ``explicit_weight_k`` (a name or an integer: that value;
    "same": none; "auto": with the Galerkin form, ``"visibility"`` becomes
    :data:`EXPLICIT_AUTO_CRACK_RULE` and the Gaussian's ``k = 1`` becomes
    :data:`EXPLICIT_AUTO_WEIGHT_K`, measured on Freund's K_I(t): docs/theory.md, "Explicit
    MLPG"). ``method.explicit_form`` must be resolved (not "auto").

    Examples
    --------
    >>> trial_choices(MLPG(spacing=0.1, explicit_form="galerkin"))
    {'crack_rule': 'diffraction', 'weight_k': 2}
    >>> trial_choices(MLPG(spacing=0.1, explicit_form="petrov_galerkin"))
    {}
    >>> trial_choices(MLPG(spacing=0.1, explicit_form="galerkin", explicit_crack_rule="same",
    ...                    explicit_weight_k=3))
    {'weight_k': 3}
    """
    galerkin = method.explicit_form == "galerkin"
    kw = {}
    rule, k = method.explicit_crack_rule, method.explicit_weight_k
    if rule == "auto":
        rule = EXPLICIT_AUTO_CRACK_RULE if galerkin and method.crack_rule == "visibility" else "same"
    if rule not in ("same", method.crack_rule):
        kw["crack_rule"] = rule
    if k == "auto":
        k = EXPLICIT_AUTO_WEIGHT_K if galerkin and method.weight_k == 1 else "same"
    if k not in ("same", method.weight_k):
        kw["weight_k"] = int(k)
    return kw


def resolve_form(method: MLPG, warn: bool = True, cracked: bool = True,
                 trial: bool = True) -> MLPG:
    """``method`` with the equations of its explicit runs decided (``method.explicit_form``)
    and, with ``trial``, their trial functions (:func:`trial_choices`).

    ``"auto"`` becomes ``"galerkin"`` (module docstring), with one ``UserWarning`` saying so
    when ``warn``, which also names the trial-function changes (the crack rule only when
    ``cracked``: the scene has cracks; the exponent only with the Gaussian weight);
    ``"galerkin"`` and ``"petrov_galerkin"`` stay, silently. ``trial=False`` (a
    discretisation given, whose trial functions are used): the form only.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     m = resolve_form(MLPG(spacing=0.1))
    >>> m.explicit_form, m.crack_rule, m.weight_k
    ('galerkin', 'diffraction', 2)
    >>> resolve_form(MLPG(spacing=0.1, explicit_form="petrov_galerkin")).weight_k
    1
    """
    if not isinstance(method, MLPG):
        raise TypeError(f"method must be an MLPG description, got {type(method).__name__}")
    auto = method.explicit_form == "auto"
    resolved = replace(method, explicit_form="galerkin") if auto else method
    kw = trial_choices(resolved) if trial else {}
    if warn and auto:
        said = [f"crack_rule={v!r} in place of {method.crack_rule!r}" for n, v in kw.items()
                if n == "crack_rule" and cracked]
        said += [f"the Gaussian exponent k = {v} in place of {method.weight_k}"
                 for n, v in kw.items() if n == "weight_k" and method.weight == "gaussian"]
        trial_text = (" Its trial functions take " + " and ".join(said) + " (MLPG."
                      "explicit_crack_rule / explicit_weight_k = 'auto': Freund's K_I(t) from "
                      "J' within 0.52 / 0.13 / 0.07 % at h = 0.02 / 0.01 / 0.005, against "
                      "6.4 % at h = 0.01 with k = 1 and the visibility rule, whose jumps along "
                      "the shadow rays cross the J' domain).") if said else ""
        warnings.warn(
            "explicit MLPG: this run steps the symmetric Galerkin form of MLPG's trial "
            "functions on the field cells (MLPG.explicit_form='auto'), not MLPG1's local "
            "Petrov-Galerkin rows, whose M^-1 K has modes that grow at any time step (a free "
            "2 x 1 plate at h = 0.125 and 0.98 dt_c blows up after 1882 steps with the cubic "
            "weight, 38 with the Gaussian; the Galerkin form runs 1e4 steps with an energy "
            f"drift below 1e-12; docs/theory.md, 'Explicit MLPG').{trial_text} Static solves "
            "keep MLPG1 and its trial functions. "
            "Give MLPG(explicit_form='galerkin') (scene file: [mlpg] explicit_form = "
            "\"galerkin\") to silence this, or explicit_form='petrov_galerkin' to step MLPG1 "
            "(for study: it blows up)", UserWarning, stacklevel=4)
    return replace(resolved, **kw) if kw else resolved


def galerkin_discretization(disc: Discretization) -> Discretization:
    """The MLPG discretisation ``disc`` with its field cells as the quadrature and no test
    functions: the Bubnov-Galerkin form of its trial functions (module docstring)."""
    if disc.field_points is None or disc.test is None:
        raise ValueError("disc must be an MLPG discretisation (with test functions and field "
                         "cells, efgkit.methods.local.discretize_local)")
    return replace(disc, points=disc.field_points, shape=disc.post_shape, field_points=None,
                   test=None, local=None)


def galerkin_system(scene, disc: Discretization, parts: list, alpha: float | None,
                    enrichment_mass: str = "diagonal"):
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
    enrichment_mass : {"diagonal", "abs_row_sum"}
        The mass of tip-enrichment unknowns (:func:`~efgkit.system.mass.row_sum_mass`), as
        for EFG.

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
    m = row_sum_mass(g.shape, g.points.w, mat.rho, node_x=g.nodes.x, area=scene.domain.area,
                     enrichment=enrichment_mass)
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
