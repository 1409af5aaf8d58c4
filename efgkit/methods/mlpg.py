"""The Meshless Local Petrov-Galerkin (MLPG1) discretisation description, seed 002 Sects. 2-4.

:class:`MLPG` holds every choice of the method as a frozen dataclass beside
:class:`~efgkit.methods.efg.EFG`. It carries the attributes that node generation
(:func:`efgkit.nodes.generate_nodes`) and the trial functions
(:func:`efgkit.methods.discretize.approximation`) read from an EFG (``spacing``,
``zones``, ``d_max``, ``weight``, ``alpha``, ``basis``, the crack and hole rules, the
enrichment), with the same meaning, so both methods share one cloud and one MLS.

Seed 002 Sect. 4 settings are the defaults (trial support r_I = 2.5 spacings, quadratic
basis, 5 x 8 points per disc, 8 points on every boundary piece, the visibility rule at
cracks), except four, measured (docs/theory.md, MLPG1): c_I = 0.5 r_I (0.365 gives
near-singular moment matrices at the boundary), the Gauss disc rule (the seed's
piecewise-midpoint rule of Eq. 39 is kept as ``quadrature="midpoint"``; it fails the patch
test at 3e-3), and the Gaussian exponent k = 1 with test discs r_s = 1.5 spacings instead
of the seed's k = 2 and 1.1: the flat-topped k = 2 weight makes the Petrov-Galerkin system
nearly singular for the bending mode of a traction-loaded plate at some spacings, whatever
the disc rule (``weight_k=2, test_radius=1.1`` keep the seed's choice).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .efg import (
    BASES,
    CRACK_RULES,
    WEIGHTS,
    MeshlessChoices,
    Rosette,
    Zone,
    check_choice,
    check_positive,
)

__all__ = ["EXPLICIT_CRACK_RULES", "EXPLICIT_FORMS", "EXPLICIT_WEIGHTS", "MLPG", "MLPG_BC_METHODS",
           "MLPG_QUADRATURES", "MLPG_SOLVERS"]

MLPG_BC_METHODS = ("penalty", "modified_mls", "collocation")
EXPLICIT_WEIGHTS = ("auto", "same", *WEIGHTS)  # MLPG.explicit_weight
EXPLICIT_FORMS = ("auto", "petrov_galerkin", "galerkin")  # MLPG.explicit_form
EXPLICIT_CRACK_RULES = ("auto", "same", *CRACK_RULES)  # MLPG.explicit_crack_rule
MLPG_QUADRATURES = ("midpoint", "gauss")
MLPG_SOLVERS = ("auto", "direct", "gmres", "bicgstab", "amg")


@dataclass(frozen=True, eq=False)
class MLPG(MeshlessChoices):
    """Meshless Local Petrov-Galerkin discretisation, MLPG1 of seed 002 (Eqs. 20-24).

    Every node I owns a test disc Omega_s^I of radius r_sI = ``test_radius`` c_I and a
    trial support of radius r_I = ``d_max`` c_I, with c_I the nodal spacing measure of
    :func:`efgkit.nodes.support_radii` (the distance to the 2nd nearest neighbour on a
    regular grid, which is the spacing h there: r_I = 2.5 h and r_s = 1.5 h by default;
    seed 002 Sect. 4 has r_s = 1.1 h). The test function on the disc is the quartic spline
    of Eq. (8).

    Parameters
    ----------
    spacing, zones, perturb, seed, coordinates, rosette :
        The node cloud, as for :class:`~efgkit.EFG`.
    d_max : float
        Trial support factor: r_I = d_max c_I (seed 002 r_I = 2.5 Delta x).
    test_radius : float
        Test-disc factor: r_sI = test_radius c_I (seed 002 r_s = 1.1 Delta x; default 1.5,
        with k = 1: with 1.1 the shear edge crack gave K_I 92.7 against 34.0 at h = 0.3).
        Must be below d_max (the disc lies inside the node's own support).
    weight : {"gaussian", "quartic", "cubic"}
        Trial weight; the Gaussian of seed 002 Eq. (7) with c_I = ``shape_factor`` r_I and
        exponent ``weight_k``.
    shape_factor : float
        c_I / r_I of the Gaussian. Seed 002 uses 0.365; with k = 2 and the quadratic basis its
        moment matrices at boundary points have rcond 4e-11 (measured on a 2 x 1 plate, h =
        0.25), below the 1e-10 guard of :mod:`efgkit.approx.mls`, so the default is 0.5.
    weight_k : int
        Exponent k of the Gaussian (seed 002: 2; default 1). With k = 2 and d_max 3 the
        top displacement of the clamped 7 x 16 plate under end shear is 0.88 / 0.51 / 0.68
        of EFG's at h = 0.3 / 0.45 / 0.6 with the default disc rule, and still 0.85 (h = 0.4)
        and -0.73 (h = 0.55) with a converged one; k = 1 with test_radius 1.5: within 0.4 %
        at every h = 0.3 ... 0.6 (docs/theory.md, MLPG1, "Default weight").
    basis : {"quadratic", "linear"}
    quadrature : {"gauss", "midpoint"}
        Default "gauss": it passes the patch test (errors 1e-11), the seed's 5 x 8 midpoint
        rule does not (3e-3, verification ``mlpg_patch``). Rule on the discs and sectors
        (:mod:`efgkit.quadrature.discs`): the piecewise
        midpoint rule of Eq. (39), or Gauss-Jacobi in r with the equally spaced (full
        discs) or Gauss-Legendre (sectors) rule in theta.
    radial, angular : int
        Rings (midpoint) or Gauss points (gauss) in r; sectors or points in theta
        (seed 002: 5 and 8).
    cut_angular : int
        "gauss": Gauss-Legendre points in theta on each angular piece of a disc cut by the
        boundary or a crack (between the kinks of r_max(theta)). Patch test on a perturbed
        cloud (h = 0.1, verification ``mlpg_patch``): displacement error 1e-6 with 8,
        1.4e-9 with 12, 6e-12 with 16.
    boundary_order : int
        Gauss points on every piece of the body boundary inside a disc (seed 002: 8).
    tip_radial, tip_angular : int
        With a crack-tip enrichment: the rule (points in r, points in theta per angular
        piece) on the discs whose centre lies within r_sI + c_I of a crack tip
        (:mod:`efgkit.methods.local_tips`): their integrands hold the r^(-1/2) derivatives
        of the near-tip field. Default 20 x 64: the shear edge crack's cut force below
        the crack 7.05-7.22 at h = 0.25 ... 0.5 (statics: 7) against 6.80-7.83 with the
        disc rule there (7.24 / 7.14 / 7.16 at h = 0.35 with 12 x 32 / 20 x 64 / 40 x 128).
    split_radial, split_angular : int
        Without enrichment, under the Gauss rule: the discs that a shadow ray from a tip
        crosses get every ray split where it crosses a shadow ray or a support circle,
        ``split_radial`` points per radial piece and ``split_angular`` per angular piece
        (:func:`~efgkit.methods.local_tips.split_tip_discs`). Default 3 x 48: plain SENT J
        (40 across, mean over 1-4 mm) 0.426 % above FEM; 0.426 / 0.449 % with 4 x 48 / 4 x 64,
        0.400 / 0.339 % with 8 x 48 / 12 x 96 (96 / 192 per cut piece), 0.488 / 0.164 % with
        5 x 24 / 6 x 32 (the angular count matters), against 1.77 % unsplit.
    order, refined_order, cell_size, tip_order :
        The background cells of the field quadrature (:func:`~efgkit.quadrature.cells.cell_points`)
        on which energies, errors and J integrals are integrated (MLPG's discs overlap:
        they are no partition of the body), as for EFG.
    bc : {"penalty", "modified_mls", "collocation"}
        Essential conditions: a penalty term in the local weak forms of the nodes on Gamma_u
        (alpha int_Gsu v (u - ubar); every disc reaching Gamma_u keeps the traction term),
        the modified MLS of seed 002 Eqs. 6-19 with direct row cross-out, or collocation rows
        u^h(x_I) = ubar(x_I) replacing the equations of the essential nodes.
    penalty : float, optional
        alpha in units of E / h (default 1e3).
    solver : {"auto", "direct", "gmres", "bicgstab", "amg"}
        SuperLU, or a Krylov solver with an ILU preconditioner (the system is unsymmetric),
        or ("amg") GMRES with the multigrid preconditioner of :mod:`efgkit.system.krylov_mlpg`;
        "auto" above 60k unknowns tries "amg", then ILU-GMRES, then SuperLU (reported).
    crack_rule, rule_power, hole_rule, kappa :
        How trial supports see cracks and holes, as for EFG (seed 002: visibility).
        The test discs are always clipped to the part visible from their node.
    enrichment, enrich_radius, ramp, ramp_inner :
        Crack-tip enrichment, as for EFG (default none, as the seed). ``"auto"`` chooses as
        :meth:`EFG.for_scene <efgkit.EFG.for_scene>` does.
    crack_nodes : bool
        Nodes on the crack faces at the local spacing (one per face), the grid nodes closer
        than a quarter spacing to a crack dropped (:mod:`efgkit.methods.local_nodes`): the
        traction-free faces enter the local weak forms only through the discs that reach
        them, and without nodes on them the far face of a crack between two node rows lies
        at the rim of the nearest discs (shear edge crack, h = 0.35: tractions of 262 on the
        lower face against 2.9 with face nodes, K_I 31.97 against 34.59; Wilson 34.0).
        A cloud with a node row on the crack is unchanged. False: the seed's cloud.
    explicit_weight : {"auto", "same", "gaussian", "quartic", "cubic"}
        Trial weight of explicit (central-difference) runs only
        (:func:`efgkit.explicit.explicit_mlpg`); static solves use ``weight``. "auto": with
        ``explicit_form="petrov_galerkin"``, the cubic spline when ``weight`` is the
        Gaussian, whose pairing with the quartic test function gives M^-1 K negative real
        eigenvalues (modes growing at any step; the cubic weight leaves slowly growing
        complex pairs only: docs/theory.md, "Explicit MLPG"), with a warning; otherwise
        ``weight``. "same": ``weight``. With the Galerkin
        form (``explicit_form`` "galerkin" or "auto") "auto" keeps ``weight`` (a symmetric K
        has no such modes).
    explicit_form : {"auto", "petrov_galerkin", "galerkin"}
        The equations of explicit runs only: MLPG1's local Petrov-Galerkin rows (seed 002),
        or the symmetric Bubnov-Galerkin form of the same trial functions on the field
        cells (:mod:`efgkit.explicit.galerkin_form`), whose ``M^-1 K`` has real non-negative
        eigenvalues by construction (stable below the critical step for runs of any length,
        energy conserved); it is not MLPG1. "auto" (default): the Galerkin form, with a
        warning saying so (:func:`efgkit.explicit.galerkin_form.resolve_form`): MLPG1's
        ``M^-1 K`` has modes that grow at any step, so explicit MLPG1 blows up after some
        hundreds to thousands of steps (docs/theory.md, "Explicit MLPG"); "petrov_galerkin"
        steps MLPG1 (for study).
    explicit_crack_rule : {"auto", "same", "visibility", "diffraction", "transparency", "see_through"}
        Crack rule of the trial functions of explicit runs only; static solves use
        ``crack_rule``. "auto": with the Galerkin form (``explicit_form`` "galerkin" or
        "auto") "visibility" becomes "diffraction" (the other rules stay): the visibility
        rule's jumps along the shadow rays from the nodes through the tip cross the J'
        domain (Freund's K_I(t), verification ``freund``, k = 2, h = 0.01: 1.86 % with
        visibility, 0.13 % with diffraction); with MLPG1: ``crack_rule``.
        "same": ``crack_rule``. A rule name: that rule
        (:func:`efgkit.explicit.galerkin_form.resolve_form`; docs/theory.md, "Explicit MLPG").
    explicit_weight_k : "auto", "same" or int > 0
        Gaussian exponent k of explicit runs only; static solves use ``weight_k``. "auto":
        with the Galerkin form, k = 1 (MLPG's static default, chosen against the
        near-singular bending mode of MLPG1's Petrov-Galerkin system, which a symmetric K
        has not) becomes the seed's k = 2 (Freund, diffraction rule: 0.52 / 0.13 / 0.070 % at
        h = 0.02 / 0.01 / 0.005 against 1.85 / 0.48 / 0.53 % with k = 1); other values stay; with
        MLPG1: ``weight_k``. "same": ``weight_k``. An integer: that k.

    Examples
    --------
    >>> m = MLPG(spacing=0.1)
    >>> m.d_max, m.test_radius, m.weight, m.weight_k, round(m.alpha / m.d_max, 3), m.basis
    (2.5, 1.5, 'gaussian', 1, 0.5, 'quadratic')
    """

    spacing: float
    zones: tuple[Zone, ...] | None = None
    perturb: float = 0.0
    seed: int = 0
    coordinates: np.ndarray | None = None
    d_max: float = 2.5
    test_radius: float = 1.5
    weight: str = "gaussian"
    shape_factor: float = 0.5
    weight_k: int = 1
    basis: str = "quadratic"
    quadrature: str = "gauss"
    radial: int = 5
    angular: int = 8
    cut_angular: int = 16
    boundary_order: int = 8
    tip_radial: int = 20
    tip_angular: int = 64
    split_radial: int = 3
    split_angular: int = 48
    order: int = 4
    refined_order: int = 6
    cell_size: float | None = None
    tip_order: int = 8
    bc: str = "penalty"
    penalty: float | None = None
    solver: str = "auto"
    crack_rule: str = "visibility"
    rule_power: float = 2.0
    hole_rule: str = "see_through"
    kappa: float = 0.5
    rosette: Rosette | None = None
    enrichment: str = "none"
    enrich_radius: float | None = None
    ramp: str = "quintic"
    ramp_inner: float = 0.0
    crack_nodes: bool = True
    explicit_weight: str = "auto"
    explicit_form: str = "auto"
    explicit_crack_rule: str = "auto"
    explicit_weight_k: int | str = "auto"

    kind = "mlpg"

    def __post_init__(self):
        self.check_cloud()
        check_positive("d_max", self.d_max)
        check_positive("test_radius", self.test_radius)
        if self.test_radius >= self.d_max:
            raise ValueError(f"test_radius ({self.test_radius!r}) must be smaller than d_max "
                             f"({self.d_max!r}): the test disc must lie inside the node's trial "
                             "support (seed 002: 1.1 and 2.5)")
        check_choice("weight", self.weight, WEIGHTS)
        check_positive("shape_factor", self.shape_factor)
        check_positive("weight_k", self.weight_k, integer=True)
        check_choice("basis", self.basis, BASES)
        check_choice("quadrature", self.quadrature, MLPG_QUADRATURES)
        for name in ("radial", "angular", "cut_angular", "boundary_order", "order",
                     "refined_order", "tip_order", "tip_radial", "tip_angular", "split_radial",
                     "split_angular"):
            check_positive(name, getattr(self, name), integer=True)
        if self.cell_size is not None:
            check_positive("cell_size", self.cell_size)
        check_choice("bc", self.bc, MLPG_BC_METHODS)
        if self.penalty is not None:
            check_positive("penalty", self.penalty)
        check_choice("solver", self.solver, MLPG_SOLVERS)
        check_choice("explicit_weight", self.explicit_weight, EXPLICIT_WEIGHTS)
        check_choice("explicit_form", self.explicit_form, EXPLICIT_FORMS)
        self._check_explicit_trial()
        self.check_cracks()

    def _check_explicit_trial(self) -> None:
        """Check ``explicit_crack_rule`` and ``explicit_weight_k`` (the trial functions of
        explicit runs, :func:`efgkit.explicit.galerkin_form.resolve_form`)."""
        rule, k = self.explicit_crack_rule, self.explicit_weight_k
        if rule not in EXPLICIT_CRACK_RULES:
            raise ValueError(f"explicit_crack_rule must be one of {EXPLICIT_CRACK_RULES}, got "
                             f"{rule!r}: give 'auto' (explicit runs of the Galerkin form take "
                             "'diffraction' in place of 'visibility'), 'same' (crack_rule) or "
                             "a crack rule")
        if rule == "transparency" and self.rule_power < 2:
            raise ValueError(f"explicit_crack_rule='transparency' needs rule_power >= 2 (seed "
                             f"003 Eq. 32), got rule_power={self.rule_power!r}: give "
                             "rule_power=2 or another explicit_crack_rule")
        if isinstance(k, str) and k in ("auto", "same"):
            return
        msg = (f"explicit_weight_k must be 'auto', 'same' or an integer > 0, got {k!r}: give "
               "'auto' (explicit runs of the Galerkin form take the seed's k = 2 in place of "
               "k = 1), 'same' (weight_k) or the Gaussian exponent, e.g. 2")
        if isinstance(k, bool) or not isinstance(k, (str, int, np.integer)):
            raise TypeError(msg)
        if isinstance(k, str) or k <= 0:
            raise ValueError(msg)

    @property
    def alpha(self) -> float:
        """c_I / (nodal spacing measure) of the Gaussian: shape_factor d_max, so that the
        EFG convention c = alpha c_I gives c = shape_factor r_I (seed 002 Eq. 7)."""
        return self.shape_factor * self.d_max

    def for_scene(self, scene) -> MLPG:
        """This discretisation with its automatic choices made for ``scene``: ``zones=None``
        gives the two graded tip zones of EFG with ``enrichment="auto"`` and none otherwise;
        ``enrichment="auto"`` chooses as :meth:`EFG.for_scene <efgkit.EFG.for_scene>`.

        Examples
        --------
        >>> from efgkit import Domain, Elastic, Scene
        >>> MLPG(spacing=0.1).for_scene(Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3))).zones
        ()
        """
        kw = self.automatic_choices(scene)
        return replace(self, **kw) if kw else self
