"""Discretisation descriptions: what a method is, not what it computes.

:class:`EFG` holds every discretisation choice of the Element-Free Galerkin
method (seed 003 Sects. 2-3); :class:`Zone` is a graded-refinement region.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["EFG", "Zone", "WEIGHTS", "BASES", "BC_METHODS", "QUADRATURES", "SOLVERS"]

WEIGHTS = ("quartic", "gaussian", "cubic")
BASES = ("linear", "quadratic")
BC_METHODS = ("penalty", "lagrange", "variational", "modified_mls")
QUADRATURES = ("cells", "triangles")
SOLVERS = ("auto", "direct", "amg")


def _positive(name, v, integer=False):
    ok = isinstance(v, (int, np.integer)) if integer else isinstance(v, (int, float, np.number))
    if isinstance(v, bool) or not ok:
        raise TypeError(f"{name} must be {'an integer' if integer else 'a real number'}, got {v!r}")
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be finite and > 0, got {v!r}")


def _choice(name, v, options):
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
        _positive("zone radius", self.radius)
        _positive("zone spacing", self.spacing)


@dataclass(frozen=True, eq=False)
class EFG:
    """Element-Free Galerkin discretisation (seed 003).

    Parameters
    ----------
    spacing : float
        Nodal spacing h of the regular grid (the user's length unit).
    zones : tuple of Zone
        Graded refinement zones.
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
    bc : {"penalty", "lagrange", "variational", "modified_mls"}
        Essential boundary conditions: penalty (seed 003 Eq. 28), Lagrange
        multipliers (Eq. 26), modified variational principle (Eq. 27,
        ``"variational"``, Nitsche-stabilised) or the modified MLS of seed 002 (Eqs. 6-19).
    penalty : float, optional
        bc="penalty": beta in units of E / h (default 1e3). The consistency
        error falls like E / (beta h) but large beta over-constrains the
        boundary (locking): see docs/theory.md.
        bc="variational": the Nitsche stabilisation in the same units
        (default 1e2).
    solver : {"auto", "direct", "amg"}
        SuperLU or pyamg smoothed aggregation + CG; "auto" picks by size.
    """

    spacing: float
    zones: tuple[Zone, ...] = ()
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
    bc: str = "penalty"
    penalty: float | None = None
    solver: str = "auto"

    def __post_init__(self):
        _positive("spacing", self.spacing)
        object.__setattr__(self, "zones", tuple(self.zones))
        for z in self.zones:
            if not isinstance(z, Zone):
                raise TypeError(f"zones must hold Zone objects, got {type(z).__name__}")
        if not (isinstance(self.perturb, (int, float)) and 0 <= self.perturb < 0.5):
            raise ValueError(f"perturb must lie in [0, 0.5) (fraction of the spacing), got {self.perturb!r}")
        if self.coordinates is not None:
            c = np.asarray(self.coordinates, dtype=float)
            if c.ndim != 2 or c.shape[1] != 2 or not np.all(np.isfinite(c)):
                raise ValueError(f"coordinates must be a finite array of shape (n, 2), got shape {c.shape}")
            object.__setattr__(self, "coordinates", c)
        _positive("d_max", self.d_max)
        _choice("weight", self.weight, WEIGHTS)
        _positive("alpha", self.alpha)
        _choice("basis", self.basis, BASES)
        _choice("quadrature", self.quadrature, QUADRATURES)
        _positive("order", self.order, integer=True)
        _positive("refined_order", self.refined_order, integer=True)
        if self.cell_size is not None:
            _positive("cell_size", self.cell_size)
        _choice("bc", self.bc, BC_METHODS)
        if self.penalty is not None:
            _positive("penalty", self.penalty)
        _choice("solver", self.solver, SOLVERS)

    @property
    def regular(self) -> bool:
        """Whether nodes lie on a regular grid (decides c_I: 2nd or 3rd neighbour)."""
        return self.coordinates is None and self.perturb == 0 and not self.zones
