"""Discretisation descriptions: what a method is, not what it computes.

:class:`EFG` holds every discretisation choice of the Element-Free Galerkin
method (seed 003 Sects. 2-3); :class:`Zone` is a graded-refinement region.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["EFG", "MeshlessChoices", "check_choice", "check_positive", "Zone", "Rosette",
           "WEIGHTS", "BASES", "BC_METHODS", "QUADRATURES", "SOLVERS", "CRACK_RULES", "HOLE_RULES",
           "ENRICHMENTS", "RAMPS"]

WEIGHTS = ("quartic", "gaussian", "cubic")
BASES = ("linear", "quadratic")
BC_METHODS = ("auto", "penalty", "lagrange", "variational", "modified_mls", "collocation")
QUADRATURES = ("cells", "triangles")
SOLVERS = ("auto", "direct", "amg")
CRACK_RULES = ("visibility", "diffraction", "transparency", "see_through")
HOLE_RULES = ("see_through", "visibility", "diffraction")
ENRICHMENTS = ("auto", "none", "radial", "full", "extrinsic_mls", "pu")
INTRINSIC = ("radial", "full")  # enrichments that widen the MLS basis (no extra unknowns)
RAMPS = ("linear", "quintic")
# Graded zones of the automatic tip refinement: (radius, spacing) in units of the spacing h.
# Two steps (an abrupt change of spacing makes stresses ripple); docs/verification.md
# (``defaults``) measures them.
AUTO_TIP_ZONES = ((6.0, 0.5), (3.0, 0.25))


def check_positive(name, v, integer=False):
    """Raise unless ``v`` is a finite number > 0 (an integer with ``integer``), naming ``name``."""
    ok = isinstance(v, (int, np.integer)) if integer else isinstance(v, (int, float, np.number))
    if isinstance(v, bool) or not ok:
        raise TypeError(f"{name} must be {'an integer' if integer else 'a real number'}, got {v!r}")
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be finite and > 0, got {v!r}")


def check_choice(name, v, options):
    """Raise unless ``v`` is one of ``options``, naming ``name``."""
    if v not in options:
        raise ValueError(f"{name} must be one of {options}, got {v!r}")


@dataclass(frozen=True)
class Zone:
    """Graded refinement: nodal spacing ``spacing`` inside the disc (``centre``, ``radius``).

    Quadrature cells inside the zone use the zone spacing and ``EFG.refined_order``.
    """

    centre: tuple[float, float]
    radius: float
    spacing: float

    def __post_init__(self):
        c = tuple(float(v) for v in np.asarray(self.centre, dtype=float).reshape(2))
        if not all(map(math.isfinite, c)):
            raise ValueError(f"zone centre must be finite, got {self.centre!r}")
        object.__setattr__(self, "centre", c)
        check_positive("zone radius", self.radius)
        check_positive("zone spacing", self.spacing)


@dataclass(frozen=True)
class Rosette:
    """Star-shaped node array around every crack tip (seed 003 Sect. 2.2, Fig. 29).

    ``rings`` rings of radii ``radius k / rings`` (k = 1..rings), each of
    ``per_ring`` nodes counted as in the seed (the node on the crack faces
    counts twice, once per face), and a node at the tip. Background nodes
    inside the rosette are switched off; the rosette moves with the tip.
    """

    radius: float
    rings: int = 4
    per_ring: int = 9

    def __post_init__(self):
        check_positive("rosette radius", self.radius)
        check_positive("rosette rings", self.rings, integer=True)
        check_positive("rosette per_ring", self.per_ring, integer=True)
        if self.per_ring < 4:
            raise ValueError(f"rosette per_ring must be >= 4 (three distinct angles and the "
                             f"split face node), got {self.per_ring!r}")


def _symmetry_tips(scene) -> tuple:
    """The modelled tips of a half or quarter model (boundary points: graded, not enriched)."""
    sym = getattr(scene, "symmetry", None)
    return () if sym is None else sym.modelled_tips(scene.domain)


class MeshlessChoices:
    """What EFG and MLPG share: the node cloud (spacing, zones, perturbation, coordinates,
    rosette), the crack and hole rules and the crack-tip enrichment; their checks, the radii
    derived from them, the automatic choices and the coarsened companion. The descriptions
    (:class:`EFG`, :class:`~efgkit.methods.mlpg.MLPG`) are frozen dataclasses with these
    fields; node generation and the approximation read them alike."""

    def check_cloud(self) -> None:
        """Check (and normalise) spacing, zones, perturb and coordinates."""
        check_positive("spacing", self.spacing)
        if self.zones is not None:
            object.__setattr__(self, "zones", tuple(self.zones))
        for z in self.zones or ():
            if not isinstance(z, Zone):
                raise TypeError(f"zones must hold Zone objects, got {type(z).__name__}")
        if not (isinstance(self.perturb, (int, float)) and 0 <= self.perturb < 0.5):
            raise ValueError(f"perturb must lie in [0, 0.5) (fraction of the spacing), got {self.perturb!r}")
        if self.coordinates is not None:
            c = np.asarray(self.coordinates, dtype=float)
            if c.ndim != 2 or c.shape[1] != 2 or not np.all(np.isfinite(c)):
                raise ValueError(f"coordinates must be a finite array of shape (n, 2), got shape {c.shape}")
            object.__setattr__(self, "coordinates", c)

    def check_cracks(self) -> None:
        """Check the crack and hole rules, the rosette and the enrichment fields."""
        check_choice("crack_rule", self.crack_rule, CRACK_RULES)
        check_positive("rule_power", self.rule_power)
        if self.crack_rule == "transparency" and self.rule_power < 2:
            raise ValueError(f"crack_rule='transparency' needs rule_power >= 2 (seed 003 Eq. 32), "
                             f"got {self.rule_power!r}")
        check_choice("hole_rule", self.hole_rule, HOLE_RULES)
        check_positive("kappa", self.kappa)
        if self.rosette is not None and not isinstance(self.rosette, Rosette):
            raise TypeError(f"rosette must be a Rosette, got {type(self.rosette).__name__}")
        check_choice("enrichment", self.enrichment, ENRICHMENTS)
        if self.enrich_radius is not None:
            check_positive("enrich_radius", self.enrich_radius)
        check_choice("ramp", self.ramp, RAMPS)
        if not (isinstance(self.ramp_inner, (int, float)) and math.isfinite(self.ramp_inner)
                and 0 <= self.ramp_inner < self.ramp_outer):
            raise ValueError(f"ramp_inner must lie in [0, enrich_radius = {self.ramp_outer}), "
                             f"got {self.ramp_inner!r}")

    def automatic_choices(self, scene) -> dict:
        """The automatic zones and enrichment for ``scene`` as keyword changes (see
        :meth:`EFG.for_scene`): zones at the tips (and the modelled tips of a symmetry
        model) with the automatic enrichment; extrinsic MLS for one tip, PU for several,
        none without tips or with the visibility rule."""
        tips = scene.tips
        kw = {}
        if self.zones is None:
            kw["zones"] = () if self.coordinates is not None or self.enrichment != "auto" else tuple(
                Zone(tuple(t.x), r * self.spacing, f * self.spacing)
                for t in tips + _symmetry_tips(scene) for r, f in AUTO_TIP_ZONES)
        if self.enrichment == "auto":
            if not tips or self.crack_rule == "visibility":
                kw["enrichment"] = "none"
            elif len(tips) == 1:
                kw["enrichment"] = "extrinsic_mls"
            else:
                kw["enrichment"] = "pu"
                kw["enrich_radius"] = self.spacing if self.enrich_radius is None else self.enrich_radius
        return kw

    def tip_cell_zones(self, scene) -> tuple[Zone, ...]:
        """Quadrature zones around the crack tips of ``scene``: cells within max(2 h, the
        intrinsic enrichment radius) of a tip are split 2 x 2 and use ``refined_order`` (the
        cells holding the tip itself get the fan rule of order ``tip_order``)."""
        h = self.cell_size or self.spacing
        radius = 2.0 * h
        if self.enrichment in INTRINSIC:
            radius = max(radius, self.ramp_outer)
        return tuple(Zone(tuple(t.x), radius, h / 2) for t in scene.tips)

    def coarsened(self, factor: float = 2.0):
        """The same discretisation with every spacing (grid, zones, cells, rosette radius)
        ``factor`` times larger: the companion solve of the error estimate
        (:meth:`efgkit.solution.Solution.sifs`). Lengths of the geometry (enrichment and
        ramp radii, zone radii) stay. User ``coordinates`` cannot be coarsened.

        Examples
        --------
        >>> EFG(spacing=0.1, zones=(Zone((0, 0), 1.0, 0.05),)).coarsened().zones[0].spacing
        0.1
        """
        if self.coordinates is not None:
            raise ValueError(f"an {type(self).__name__} with user coordinates cannot be coarsened: "
                             "give spacing and zones instead, or skip the error estimate "
                             "(sifs(error=False))")
        check_positive("factor", factor)
        return replace(
            self, spacing=self.spacing * factor,
            zones=None if self.zones is None else tuple(
                Zone(z.centre, z.radius, z.spacing * factor) for z in self.zones),
            cell_size=None if self.cell_size is None else self.cell_size * factor,
            rosette=None if self.rosette is None else replace(
                self.rosette, radius=self.rosette.radius * factor),
            enrich_radius=self.ramp_outer if self.enrichment in INTRINSIC
            else self.pu_radius if self.enrichment == "pu" else self.enrich_radius)

    @property
    def ramp_outer(self) -> float:
        """r2 of the intrinsic ramp (Eq. 54)."""
        return self.enrich_radius if self.enrich_radius is not None else 4.0 * self.spacing

    @property
    def pu_radius(self) -> float:
        """PU enrichment: nodes whose support comes this close to a tip are enriched."""
        return self.enrich_radius if self.enrich_radius is not None else 2.0 * self.spacing

    @property
    def regular(self) -> bool:
        """Whether nodes lie on a regular grid (decides c_I: 2nd or 3rd neighbour)."""
        return self.coordinates is None and self.perturb == 0 and not self.zones


@dataclass(frozen=True, eq=False)
class EFG(MeshlessChoices):
    """Element-Free Galerkin discretisation (seed 003).

    Parameters
    ----------
    spacing : float
        Nodal spacing h of the regular grid (the user's length unit).
    zones : tuple of Zone, optional
        Graded refinement zones; None (default): two graded zones at every crack
        tip when the enrichment is automatic too (:meth:`for_scene`), ``()`` for none.
    perturb : float
        Random perturbation of interior nodes, as a fraction of the local
        spacing (0: regular grid); drawn from ``np.random.default_rng(seed)``.
    seed : int
        Seed of the perturbation.
    coordinates : array_like (n, 2), optional
        User-given nodes; replaces the generated cloud.
    d_max : float
        Support radius factor, seed 003 Eq. (2): d_mI = d_max c_I, with c_I
        the distance to the 2nd (regular) or 3rd (perturbed/user) nearest
        neighbour.
    weight : {"quartic", "gaussian", "cubic"}
        Seed 003 Eq. (1b), Eq. (1a) with c = alpha c_I (Eq. 3), or the cubic spline.
    alpha : float
        Gaussian shape parameter (Eq. 3); the seed advises d_max / alpha >= 4.
    basis : {"linear", "quadratic"}
        Polynomial basis, seed 003 Eq. (5c-d).
    quadrature : {"cells", "triangles"}
        Background square cells clipped to the domain, or the cells of a
        triangulation of the nodes.
    order : int
        Gauss points per direction in a cell (triangles: a rule exact to
        degree 2 * order - 1).
    refined_order : int
        The same in refinement zones.
    cell_size : float, optional
        Background cell size (default: ``spacing``).
    bc : {"auto", "penalty", "lagrange", "variational", "modified_mls", "collocation"}
        Essential boundary conditions ("auto": Lagrange with crack tips, penalty
        otherwise, :meth:`for_scene`): penalty (seed 003 Eq. 28), Lagrange
        multipliers (Eq. 26), modified variational principle (Eq. 27,
        ``"variational"``, Nitsche-stabilised), the modified MLS of seed 002 (Eqs. 6-19)
        or the modified collocation method of Zhu and Atluri (1998, Comput. Mech. 21:211-222:
        the equations of the prescribed components of the boundary nodes replaced by
        ``u^h(x_I) = ubar(x_I)``; plain MLS, unsymmetric system, SuperLU only).
    penalty : float, optional
        bc="penalty": beta in units of E / h (default 1e3). The consistency
        error falls like E / (beta h) but large beta over-constrains the
        boundary (locking): see docs/theory.md.
        bc="variational": the Nitsche stabilisation in the same units
        (default 1e2).
    solver : {"auto", "direct", "amg"}
        SuperLU or CG with a multigrid preconditioner; "auto" picks by size.
    crack_rule : {"visibility", "diffraction", "transparency", "see_through"}
        How supports see cracks (:mod:`efgkit.approx.crack_rules`). Enrichment
        refuses visibility, except the sqrt(r) basis (``enrichment="radial"``),
        which needs no smoothing (seed 003 Sect. 5.3.2) and is more accurate
        with it on grid-aligned cracks, less on inclined ones (verification
        ``singular_patch``, ``inclined``); the sqrt(r) basis with diffraction or
        transparency is refused where no node lies within h/4 of the crack near a tip
        (worse than the linear basis there, docs/theory.md).
    rule_power : float
        lambda of the diffraction (Eq. 29) or transparency (Eq. 32, >= 2) rule.
    hole_rule : {"see_through", "visibility", "diffraction"}
        How supports see holes (:mod:`efgkit.approx.hole_rules`); diffraction
        wraps around the tangent point (seed 003 Sect. 4.2, Fig. 11b).
    kappa : float
        Transparency: opaque at kappa h behind the tip (Eq. 33).
    rosette : Rosette, optional
        Star-shaped node array at every tip.
    enrichment : {"auto", "none", "radial", "full", "extrinsic_mls", "pu"}
        Crack-tip enrichment ("auto": extrinsic MLS for one tip, PU for several,
        none without tips, :meth:`for_scene`) (seed 003 Sect. 5): intrinsic sqrt(r) basis
        (Eq. 52) or full near-tip basis (Eq. 50), ramped to the linear basis
        (Eqs. 53-56); extrinsic MLS with global K_I, K_II unknowns per tip
        (Eqs. 37-47); extrinsic partition of unity (Eqs. 48-49).
    enrich_radius : float, optional
        Intrinsic: the outer ramp radius r2 (default 4 spacings); PU: nodes
        whose support comes within this distance of a tip are enriched
        (default 2 spacings); extrinsic MLS: the fields are global (ignored).
    ramp : {"linear", "quintic"}
        Intrinsic ramp R of Eq. (54).
    ramp_inner : float
        r1 of Eq. (54): R = 1 inside it.
    tip_order : int
        Gauss points per direction of the collapsed fan rules in the cells
        holding a tip (:mod:`efgkit.quadrature.tip_cells`). The cells within
        max(2 cell sizes, ``enrich_radius`` of intrinsic enrichment) of a tip
        are split 2 x 2 and use ``refined_order``.
    """

    spacing: float
    zones: tuple[Zone, ...] | None = None
    perturb: float = 0.0
    seed: int = 0
    coordinates: np.ndarray | None = None
    d_max: float = 2.0
    weight: str = "quartic"
    alpha: float = 0.5
    basis: str = "linear"
    quadrature: str = "cells"
    order: int = 4
    refined_order: int = 6
    cell_size: float | None = None
    bc: str = "auto"
    penalty: float | None = None
    solver: str = "auto"
    crack_rule: str = "diffraction"
    rule_power: float = 2.0
    hole_rule: str = "see_through"
    kappa: float = 0.5
    rosette: Rosette | None = None
    enrichment: str = "auto"
    enrich_radius: float | None = None
    ramp: str = "quintic"
    ramp_inner: float = 0.0
    tip_order: int = 8

    def __post_init__(self):
        self.check_cloud()
        check_positive("d_max", self.d_max)
        check_choice("weight", self.weight, WEIGHTS)
        check_positive("alpha", self.alpha)
        check_choice("basis", self.basis, BASES)
        check_choice("quadrature", self.quadrature, QUADRATURES)
        check_positive("order", self.order, integer=True)
        check_positive("refined_order", self.refined_order, integer=True)
        if self.cell_size is not None:
            check_positive("cell_size", self.cell_size)
        check_choice("bc", self.bc, BC_METHODS)
        if self.penalty is not None:
            check_positive("penalty", self.penalty)
        check_choice("solver", self.solver, SOLVERS)
        self.check_cracks()
        check_positive("tip_order", self.tip_order, integer=True)

    def for_scene(self, scene) -> EFG:
        """This discretisation with its automatic choices made for ``scene``.

        * ``zones=None``: with the automatic enrichment, two graded zones at every crack
          tip (:data:`AUTO_TIP_ZONES`: spacing h/2 within 6h, h/4 within 3h); none
          without tips, with user ``coordinates``, or with an explicit enrichment (a
          hand-built discretisation: the intrinsic ramp and PU radii default to
          multiples of ``spacing``, which zones would silently change);
        * ``enrichment="auto"``: extrinsic MLS (global K_I, K_II unknowns, seed 003 Eqs.
          37-47) for a single tip, extrinsic partition of unity with ``enrich_radius``
          = h for several (the global Williams fields of two tips would overlap), and
          none without tips or with the visibility rule (which the extrinsic
          enrichments refuse);
        * ``bc="auto"``: Lagrange multipliers with crack tips (K as accurate as with the
          penalty method, or up to 13 times more, at equal cost, docs/verification.md
          ``defaults``), the penalty method otherwise; :func:`efgkit.static.solve` then
          takes Nitsche (``"variational"``, as consistent, fewer CG iterations) for
          Lagrange on systems that CG solves (:func:`efgkit.static.large_system_bc`).

        A scene without cracks gets none of the crack work. Explicit choices are kept.

        Examples
        --------
        >>> from efgkit import Crack, Domain, Elastic, Scene
        >>> sc = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1.0, 0.3),
        ...            cracks=(Crack([[0.0, 0.5], [1.0, 0.5]], tips=(False, True)),))
        >>> m = EFG(spacing=0.1).for_scene(sc)
        >>> m.enrichment, m.bc, [(z.radius, z.spacing) for z in m.zones]
        ('extrinsic_mls', 'lagrange', [(0.6000000000000001, 0.05), (0.30000000000000004, 0.025)])
        >>> EFG(spacing=0.1).for_scene(Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3))).bc
        'penalty'
        """
        kw = self.automatic_choices(scene)
        if self.enrichment == "auto" and _symmetry_tips(scene) and self.crack_rule != "visibility":
            # a half or quarter model: the whole body's tips decide (image nodes, system.images)
            kw |= self.automatic_choices(scene.full()) | {"zones": kw["zones"]}
        if self.bc == "auto":
            kw["bc"] = "lagrange" if scene.tips or _symmetry_tips(scene) else "penalty"
        return replace(self, **kw) if kw else self
