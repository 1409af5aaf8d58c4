"""Gradual release of a released segment's support: a linear cohesive law that dissipates
the material's fracture energy (used by :mod:`efgkit.growth.release`,
``LineRelease.fracture_energy``).

The seed releases a node at once (two particles a gap apart): the support's force on the
opened segment vanishes in one step, the energy it held goes into waves and nothing is
dissipated, so the model has no fracture energy and an overdriven crack runs at the
fastest pace the discrete field allows: on the tungsten plate at 1000/s a node every 1-2
steps, 1.00-1.03 c_R over 2-4 mm (``verification/tungsten.py``), above the Rayleigh speed
that bounds any crack that takes energy from the field (Freund, Dynamic Fracture
Mechanics, Sect. 5.3: the energy release rate of a mode-I crack vanishes as v -> c_R).

Gradual nodal release (Kanninen and Popelar, Advanced Fracture Mechanics, 1985, Sect.
5.6; Rydholm, Fredriksson and Nilsson 1978; Kobayashi et al. 1978): the force ``f_j`` the
support exerted on segment j at its release (``-int lambda u_y``, from the multipliers
``lambda = (G M^-1 G^T)^-1 G M^-1 (f - K u)``; resultant ``F_0 = f_j . e_y``) is kept as a
load and softens linearly with the segment's opening ``w = 2 f_j.u / F_0`` (both faces):
``f_j max(0, 1 - w / delta_j)``, never growing back. The opening at which it vanishes is
set by the energy the new crack must absorb, not by a stress: the work of the softening
force on the model's face, ``|F_0| delta_j / 4`` (one face opens by w / 2), equals the
model's share ``G_c L_j / 2`` of the full body's ``G_c L_j`` (L_j the segment's length),

    delta_j = 2 G_c L_j / |F_0|                                         (opening_for)

i.e. the traction ``|F_0| / L_j`` falls linearly to zero over delta_j and dissipates
``G_c`` per unit of new crack whatever the traction at release. ``G_c = K_Ic^2 / E'`` with
the material's toughness; where only a critical stress is known (the tungsten plate), the
toughness the criterion implies at the line's spacing h (the stress ``K / sqrt(2 pi h)`` at
the node ahead, seed 000 Eq. 5.2): ``G_c = 2 pi h sigma_c^2 / E'`` (:func:`criterion_energy`).

The released node is the front of a cohesive zone; the crack proper, the stretch whose
faces carry no traction, ends where the last support softened to zero (the crack tip of a
cohesive model, e.g. Xu and Needleman, J. Mech. Phys. Solids 42, 1994): :class:`Supports`
records the instant each segment became free. In a steady run both move at one speed; in
a transient the zone can lengthen and its front outrun the tip (measured on the graded
plate: the front's 11-point speed reaches 1.019 local c_R, the tip's 0.956).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Softening", "Supports", "criterion_energy", "opening_for"]


def criterion_energy(sigma_c, spacing: float, modulus):
    """The fracture energy ``G_c = K_c^2 / E' = 2 pi h sigma_c^2 / E'`` of the toughness
    ``K_c = sigma_c sqrt(2 pi h)`` a principal-stress criterion at the node ``h`` ahead of
    the tip implies (seed 000 Eq. 5.2). ``modulus``: E' (E in plane stress, E / (1 - nu^2)
    in plane strain); arrays broadcast. Energy per unit crack area (stress x length).

    Examples
    --------
    >>> round(float(criterion_energy(4500.0, 0.025, 400e3 / (1 - 0.29**2))), 4)  # N/mm
    7.2834
    """
    if not (isinstance(spacing, (int, float)) and math.isfinite(spacing) and spacing > 0):
        raise ValueError(f"spacing must be a finite number > 0, got {spacing!r}")
    sc, mod = np.asarray(sigma_c, float), np.asarray(modulus, float)
    out = 2 * math.pi * spacing * sc**2 / np.where(mod > 0, mod, np.nan)
    if not (np.all(sc > 0) and np.all(np.isfinite(out) & (out > 0))):
        raise ValueError("sigma_c and modulus must be finite and > 0 (stress units), got "
                         f"{sigma_c!r} and {modulus!r}")
    return out


def opening_for(fracture_energy, length, resultant):
    """The opening ``delta = 2 G_c L / |F_0|`` at which a segment of length ``L`` whose
    support force had the resultant ``F_0`` at release has dissipated ``G_c L`` (both
    faces; module docstring); 0 (released at once) where ``F_0 >= 0`` (the support pushed:
    a face in compression holds no cohesive energy) or ``G_c = 0``.

    Examples
    --------
    >>> float(opening_for(7.0, 0.025, -0.2))  # G_c (N/mm), L (mm), F_0 (N/mm)
    1.75
    """
    g, L, F = (np.asarray(v, float) for v in (fracture_energy, length, resultant))
    pull = (F < 0) & (g > 0)
    return np.where(pull, 2 * g * L / np.where(pull, -F, 1.0), 0.0)


class Softening:
    """Load factor of a released segment's support force ``f`` (n_dofs,): linear softening
    with the segment's opening ``w = 2 (f . u) / (f . e_y)`` (the force-weighted mean of
    ``u_y`` over the segment, doubled: both faces of the symmetric model),
    ``max(0, 1 - w / opening)``, never growing back; ``dissipated`` the work done on the
    softening force so far, ``F_0 (w_max / 2) (1 - value / 2)`` (one face, ``|F_0|``), which
    reaches ``|F_0| opening / 4`` when the segment is free; ``t_free`` the instant w reached
    the opening (linear in time between two updates), NaN before."""

    def __init__(self, f: np.ndarray, resultant: float, opening: float):
        self.f, self.resultant, self.opening, self.value = f, resultant, opening, 1.0
        self.w, self.t_free = 0.0, math.nan  # released from u_y = 0: no opening yet

    def update(self, u, t0: float = math.nan, t1: float = math.nan) -> None:
        """The opening at ``u`` (at time ``t1``; ``t0`` the previous update's)."""
        w = 2.0 * float(self.f @ u) / self.resultant if self.resultant != 0 else math.inf
        if self.value > 0 and w >= self.opening:
            frac = (self.opening - self.w) / (w - self.w) if w > self.w else 1.0
            self.t_free = t0 + min(max(frac, 0.0), 1.0) * (t1 - t0)
        self.w = w
        self.value = min(self.value, max(0.0, 1.0 - w / self.opening))

    @property
    def dissipated(self) -> float:
        d = 1.0 - self.value  # w_max / opening
        return abs(self.resultant) * 0.5 * d * self.opening * (1.0 - 0.5 * d) if d > 0 else 0.0

    def __call__(self, t: float) -> float:
        return self.value


class Supports:
    """The softening supports of a line's released segments: their force columns and load
    factors (:class:`Softening`), the energy absorbed, and ``free_at`` (segments,): the
    instant each segment became traction free (its support gone: released at once, or
    softened to zero), NaN while it is bonded or softening; ``free0`` marks the segments
    free from the start (initial cracks, instant 0)."""

    def __init__(self, free0: np.ndarray):
        self.items, self.freed = [], 0.0
        self.free_at = np.where(free0, 0.0, math.nan)

    def add(self, segments, forces: np.ndarray, resultants, openings, t: float) -> None:
        """Segments released at ``t`` with their support forces (n_dofs, k), resultants and
        openings (k,); an opening 0 frees the segment at once."""
        for j, f, F0, d in zip(segments, forces.T, resultants, openings, strict=True):
            if d > 0:
                self.items.append((int(j), f, Softening(f, float(F0), float(d))))
            else:
                self.free_at[j] = t

    def update(self, u, t0: float, t1: float) -> None:
        for j, _, s in self.items:
            s.update(u, t0, t1)
            if s.value <= 0 and math.isnan(self.free_at[j]):
                self.free_at[j] = s.t_free

    def prune(self) -> None:
        """Drop the supports that are gone (their columns leave the system)."""
        self.freed += sum(c[2].dissipated for c in self.items if c[2].value <= 0)
        self.items = [c for c in self.items if c[2].value > 0]

    @property
    def forces(self) -> list:
        return [c[1] for c in self.items]

    @property
    def histories(self) -> tuple:
        return tuple(c[2] for c in self.items)

    @property
    def dissipated(self) -> float:
        return self.freed + sum(c[2].dissipated for c in self.items)
