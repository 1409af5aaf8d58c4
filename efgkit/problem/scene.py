"""The physical problem: domain, material, supports, loads and cracks.

A :class:`Scene` holds no arrays of a discretisation. Prescribed values are
floats, Python callables ``x (n, 2) -> (n,)`` / ``(n, 2)``, or a named
analytic :class:`~efgkit.problem.exact.fields.Field` evaluated with the scene's material.
Scene files (TOML) map onto these classes one to one (:mod:`efgkit.io`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from .crack import Crack
from .crack_placement import MIN_CRACK_LENGTH, check_cracks
from .exact.fields import Field
from .geometry import COORDINATE_LIMIT, Domain
from .graded import Grading
from .material import Elastic
from .supports import PointSupport, Pressure
from .symmetry import Symmetry, full_domain

__all__ = ["MIN_CRACK_LENGTH", "VALUE_LIMIT", "PointSupport", "Pressure", "Scene", "Support", "Traction",
           "evaluate_vector", "evaluate_component", "evaluate_components"]

Where = str | Callable  # edge name or x (n, 2) -> bool mask (n,)

# Prescribed values, and the stress, force, displacement and square-root-of-energy scales of a
# scene, are squared on the way (norms, energies, von Mises): they must lie within
# [1 / VALUE_LIMIT, VALUE_LIMIT] for the squares to be normal float64 numbers.
VALUE_LIMIT = COORDINATE_LIMIT
_RESCALE = "rescale the units (e.g. MPa and mm instead of Pa and m)"


def _check_value(what: str, v, vector: bool) -> None:
    if v is None or callable(v) or isinstance(v, (Field, Pressure)):
        return
    arr = np.asarray(v, dtype=float)
    if arr.shape != ((2,) if vector else ()):
        raise ValueError(f"{what} must be {'a 2-vector' if vector else 'a float'}, got {v!r}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{what} must be finite, got {v!r}")
    if np.abs(arr).max() > VALUE_LIMIT:
        raise ValueError(f"{what} = {v!r} is too large to square without overflow (|value| <= "
                         f"{VALUE_LIMIT:g}; the energy and the norms of the solve square it); {_RESCALE}")


@dataclass(frozen=True)
class Support:
    """Prescribed displacement components on an edge.

    Parameters
    ----------
    edge : str or callable
        Edge name, or ``x (n, 2) -> bool (n,)`` selecting boundary points.
    ux, uy : float, callable ``x (n, 2) -> (n,)``, Field, or None
        Prescribed component (None: free). A :class:`Field` prescribes its
        displacement component.
    history : callable or None
        Dynamic scenes: the prescribed components are ``g(t) ux(x)``, ``g(t) uy(x)``
        (:mod:`efgkit.problem.history`; ``Linear()`` with ``uy=v0``: the edge moves at the
        constant velocity ``v0``); None: constant in time.
    """

    edge: Where
    ux: float | Callable | Field | None = None
    uy: float | Callable | Field | None = None
    history: Callable | None = None

    def __post_init__(self):
        if self.ux is None and self.uy is None:
            raise ValueError(f"support on {self.edge!r} prescribes nothing: give ux and/or uy")
        _check_value(f"support on {self.edge!r}: ux", self.ux, vector=False)
        _check_value(f"support on {self.edge!r}: uy", self.uy, vector=False)
        _check_history(f"support on {self.edge!r}: history", self.history)


@dataclass(frozen=True)
class Traction:
    """Surface traction ``t (n, 2)`` on an edge (force per length).

    ``t`` is a 2-vector, a callable ``x (n, 2) -> (n, 2)``, or a :class:`Field`
    (whose traction ``sigma . n`` on the edge's outward normal is applied).
    ``history`` is a load factor ``g(t)`` (:mod:`efgkit.problem.history`, or any callable
    float -> float) for dynamic scenes: the traction is ``g(t) t(x)``; None is constant.
    """

    edge: Where
    t: tuple[float, float] | Callable | Field
    history: Callable | None = None

    def __post_init__(self):
        _check_value(f"traction on {self.edge!r}: t", self.t, vector=True)
        _check_history(f"traction on {self.edge!r}: history", self.history)


@dataclass(frozen=True)
class Scene:
    """A 2D linear-elastic boundary value problem.

    Examples
    --------
    >>> from efgkit import Domain, Elastic
    >>> s = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.25),
    ...           supports=(Support("left", ux=0.0, uy=0.0),),
    ...           tractions=(Traction("right", (1.0, 0.0)),))
    >>> s.is_static, len(s.cracks)
    (True, 0)
    """

    domain: Domain
    material: Elastic
    supports: tuple[Support, ...] = ()
    tractions: tuple[Traction, ...] = ()
    body_force: tuple[float, float] | Callable | None = None
    cracks: tuple[Crack, ...] = ()
    exact: Field | None = None
    name: str = "scene"
    duration: float | None = None  # None: static
    # Dynamic scenes only: the body force's load factor g(t) (None: constant), and the
    # initial displacement and velocity: 2-vectors (uniform), callables x (n, 2) -> (n, 2)
    # or a Field's displacement (None: zero).
    body_force_history: Callable | None = None
    initial_displacement: tuple[float, float] | Callable | Field | None = None
    initial_velocity: tuple[float, float] | Callable | Field | None = None
    point_supports: tuple[PointSupport, ...] = ()
    symmetry: Symmetry | None = None  # half and quarter models (efgkit.problem.symmetry)
    grading: Grading | None = None  # position-dependent E and rho (efgkit.problem.graded)

    def __post_init__(self):
        if not isinstance(self.domain, Domain):
            raise TypeError(f"domain must be a Domain, got {type(self.domain).__name__}")
        if not isinstance(self.material, Elastic):
            raise TypeError(f"material must be an Elastic, got {type(self.material).__name__}")
        for attr in ("supports", "tractions", "cracks", "point_supports"):
            object.__setattr__(self, attr, tuple(getattr(self, attr)))
        _check_points(self.point_supports, self.domain)
        if self.grading is not None and not isinstance(self.grading, Grading):
            raise TypeError(f"grading must be a Grading, got {type(self.grading).__name__}")
        if self.symmetry is not None:
            if not isinstance(self.symmetry, Symmetry):
                raise TypeError(f"symmetry must be a Symmetry, got {type(self.symmetry).__name__}")
            check_cracks(self.symmetry.cracks, full_domain(self.domain, self.symmetry))
            if not self.symmetry.modelled_tips(self.domain):
                raise ValueError("symmetry: no tip of the symmetry cracks lies on the model's "
                                 "boundary; the modelled tip is where the crack face meets the ligament")
        names = self.domain.edge_names
        for kind, items in (("support", self.supports), ("traction", self.tractions)):
            for it in items:
                if isinstance(it.edge, str) and it.edge not in names:
                    raise ValueError(
                        f"{kind} on edge {it.edge!r}: the domain has no such edge; "
                        f"its edges are {sorted(names)}"
                    )
        check_cracks(self.cracks, self.domain)
        if isinstance(self.body_force, Pressure):
            raise TypeError("body_force cannot be a Pressure (it acts on edges): give (bx, by)")
        _check_value("body_force", self.body_force, vector=True)
        _check_scales(self)
        if self.duration is not None and not (math.isfinite(self.duration) and self.duration > 0):
            raise ValueError(f"duration must be finite and > 0 (or None), got {self.duration!r}")
        _check_history("body_force_history", self.body_force_history)
        for name in ("initial_displacement", "initial_velocity"):
            _check_value(name, getattr(self, name), vector=True)
        timed = [n for n, v in (("body_force_history", self.body_force_history),
                                ("initial_displacement", self.initial_displacement),
                                ("initial_velocity", self.initial_velocity))
                 if v is not None] + [f"traction on {t.edge!r}: history" for t in self.tractions
                                      if t.history is not None] + [
                     f"support on {s.edge!r}: history" for s in self.supports if s.history is not None]
        if timed and self.duration is None:
            raise ValueError(f"{timed[0]} is given but duration is None (a static scene, which "
                             "has no time): give duration to run the scene in time")

    @property
    def is_static(self) -> bool:
        return self.duration is None

    @property
    def tips(self) -> tuple:
        """Every crack tip of the scene (:class:`~efgkit.problem.crack.Tip`), crack by crack."""
        return tuple(t for c in self.cracks for t in c.tip_list)

    def with_cracks(self, cracks) -> Scene:
        """A copy with ``cracks`` replaced."""
        return replace(self, cracks=tuple(cracks))

    def full(self) -> Scene:
        """The whole body of a half or quarter model (the domain glued to its mirror images,
        with the symmetry cracks; material only, no loads): the scene of its SIFs."""
        if self.symmetry is None:
            return self
        return Scene(full_domain(self.domain, self.symmetry), self.material,
                     cracks=self.cracks + self.symmetry.cracks, name=self.name)

    def with_supports(self, supports) -> Scene:
        """A copy with ``supports`` replaced."""
        return replace(self, supports=tuple(supports))


def _check_history(what: str, g) -> None:
    """A load factor: None or a callable t -> float, finite at t = 0."""
    if g is None:
        return
    if not callable(g):
        raise TypeError(f"{what} must be a callable t -> factor (efgkit.problem.history) or None, "
                        f"got {type(g).__name__}")
    v = np.asarray(g(0.0), dtype=float)
    if v.shape != () or not np.isfinite(v):
        raise ValueError(f"{what}: g(0) must be a finite float, got {v!r}")


def _check_points(points, domain: Domain) -> None:
    """Point supports are PointSupport objects at points of the closed body."""
    for p in points:
        if not isinstance(p, PointSupport):
            raise TypeError(f"point_supports must hold PointSupport objects, got {type(p).__name__}")
        x = np.array([p.x])
        if not domain.contains(x)[0] and domain.distance_to_boundary(x)[0] > 1e-9 * domain.size:
            raise ValueError(f"point support at {list(p.x)} lies outside the domain; put it inside "
                             "the body or on its boundary (e.g. at a vertex)")


def _check_scales(scene: Scene) -> None:
    """Refuse constant loads whose stress, force, displacement or energy scale has a square
    outside the normal float64 range (a traction of 1e300 solved to inf and NaN, one of
    1e-200 to zero displacement).

    Scales, from the largest constant load (L the domain size, A its area, E the modulus):
    stress S = |t|, |p| (crack pressure), |b| L (body force) or E |u| / L (prescribed
    displacement); force S L; displacement S L / E; energy S^2 A / E, whose square root is
    checked; with cracks also K = S sqrt(L), sqrt(J) = K / sqrt(E) and S L^1.5 (the load on
    enriched SIF unknowns). Loads given as callables or Fields are checked where evaluated.
    """
    dom, E = scene.domain, scene.material.E
    L = dom.size
    lL, lE = math.log10(L), math.log10(E)
    found = []  # (log10 of the stress scale, its source), in logs: nothing overflows here
    for t in scene.tractions:
        if isinstance(t.t, Pressure):
            found.append((abs(t.t.p), 0.0, f"traction on {t.edge!r}: pressure = {t.t.p!r}"))
        elif not (callable(t.t) or isinstance(t.t, Field)):
            found.append((math.hypot(*map(float, t.t)), 0.0, f"traction on {t.edge!r}: t = {t.t!r}"))
    b = scene.body_force
    if b is not None and not (callable(b) or isinstance(b, Field)):
        found.append((math.hypot(*map(float, b)), lL, f"body_force = {b!r} (times the domain size)"))
    found += [(abs(c.pressure), 0.0, f"crack {c.name!r}: pressure = {c.pressure!r}") for c in scene.cracks]
    for sup in scene.supports:
        for key in ("ux", "uy"):
            u = getattr(sup, key)
            if u is not None and not (callable(u) or isinstance(u, Field)):
                found.append((abs(float(u)), lE - lL, f"support on {sup.edge!r}: {key} = {u!r} (E u / L)"))
    found = [(math.log10(v) + shift, src) for v, shift, src in found if v > 0]
    if not found:
        return
    lS, source = max(found, key=lambda f: f[0])
    log = {"stress": lS, "force": lS + lL, "displacement": lS + lL - lE,
           "square root of the energy": lS + 0.5 * (math.log10(dom.area) - lE)}
    if scene.cracks:  # K ~ S sqrt(L), J ~ K^2 / E, and the load on enriched K unknowns ~ S L^1.5
        log.update({"stress intensity": lS + 0.5 * lL, "square root of J": lS + 0.5 * (lL - lE),
                    "load on the enrichment (SIF) unknowns": lS + 1.5 * lL})
    top = math.log10(VALUE_LIMIT)
    for what, lg in log.items():
        if abs(lg) > top:
            e = math.floor(lg)
            raise ValueError(
                f"the loads are too {'large' if lg > 0 else 'small'} for float64: the {what} scale "
                f"{10 ** (lg - e):.3g}e{e:+d} (from {source}, domain size {L:.3g}, E = {E:.3g}) lies outside "
                f"[{1 / VALUE_LIMIT:g}, {VALUE_LIMIT:g}], so its square "
                f"{'overflows' if lg > 0 else 'underflows to zero'} in the energy and the norms of "
                f"the solve; {_RESCALE}")


def evaluate_component(value, x: np.ndarray, comp: int, material: Elastic) -> np.ndarray:
    """Evaluate a prescribed scalar (float / callable / Field component) at ``x (n, 2)`` -> (n,)."""
    if isinstance(value, Field):
        out = value.displacement(x, material)[:, comp]
    elif callable(value):
        out = np.asarray(value(x), dtype=float)
        out = np.broadcast_to(out, (len(x),)).copy()
    else:
        out = np.full(len(x), float(value))
    if not np.all(np.isfinite(out)):
        raise ValueError("a prescribed displacement evaluated to NaN or inf on the boundary")
    _check_evaluated("a prescribed displacement", out)
    return out


def evaluate_components(ux, uy, x: np.ndarray, material: Elastic) -> np.ndarray:
    """Both prescribed components at ``x (n, 2)`` -> (n, 2), 0 where one is None; a
    :class:`Field` given for both is evaluated once (:func:`evaluate_component` otherwise)."""
    if ux is uy and isinstance(ux, Field):
        out = np.asarray(ux.displacement(x, material), dtype=float)  # finite (Field raises)
        _check_evaluated("a prescribed displacement", out)
        return out
    return np.column_stack([np.zeros(len(x)) if v is None else evaluate_component(v, x, c, material)
                            for c, v in enumerate((ux, uy))])


def _check_evaluated(what: str, out: np.ndarray) -> None:
    big = np.abs(out).max(initial=0.0)
    if big > VALUE_LIMIT:
        raise ValueError(f"{what} evaluated to {big:.3g}, too large to square without overflow "
                         f"(|value| <= {VALUE_LIMIT:g}); {_RESCALE}")


def evaluate_vector(value, x: np.ndarray, normal: np.ndarray, material: Elastic) -> np.ndarray:
    """Evaluate a traction / body-force value at ``x (n, 2)`` -> (n, 2).

    ``normal (n, 2)`` is the outward unit normal, used by :class:`Field` and
    :class:`Pressure` values.
    """
    if isinstance(value, Pressure):
        out = -value.p * np.asarray(normal, dtype=float)
    elif isinstance(value, Field):
        s = value.stress(x, material)
        out = np.column_stack([s[:, 0] * normal[:, 0] + s[:, 2] * normal[:, 1],
                               s[:, 2] * normal[:, 0] + s[:, 1] * normal[:, 1]])
    elif callable(value):
        out = np.broadcast_to(np.asarray(value(x), dtype=float), (len(x), 2)).copy()
    else:
        out = np.broadcast_to(np.asarray(value, dtype=float), (len(x), 2)).copy()
    if not np.all(np.isfinite(out)):
        raise ValueError("a traction or body force evaluated to NaN or inf")
    _check_evaluated("a traction or body force", out)
    return out


