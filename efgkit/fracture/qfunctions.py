"""Weight functions ``q`` of domain integrals, with analytic gradients.

The domain (equivalent-area) form of J and of the interaction integrals weighs
the integrand by the gradient of a function ``q`` that is 1 at the crack tip
and 0 on and outside the outer contour ``r = r_out`` (seed 001 Eq. 7; Moran
and Shih 1987, cited in seed 003 Sect. 5.6). A ``q`` of the distance ``r`` to
the tip alone makes the domain a disc that ignores any mesh or node layout,
and its gradient ``dq/dr (x - x_tip) / r`` is exact at every point (seed 001
Sect. 3.2). The kinds, with ``z`` a normalised distance:

``"cubic_spline"``
    the cubic B-spline kernel with support ``r_out = 2 h``, divided by its
    value at the tip (seed 001 Eq. 10): ``z = r / h``,
    ``q = 1 - 3/2 z^2 + 3/4 z^3`` for ``z < 1``, ``q = (2 - z)^3 / 4`` for
    ``1 <= z < 2``;
``"wendland_c2"``
    ``q = (1 - z)^3 (1 + 3 z)``, ``z = r / r_out`` (seed 001 Eq. 13; the
    Wendland function written there is the C2 one of one space dimension);
``"power"``
    ``q = 1 - z^n``, ``z = r / r_out``, ``n >= 2`` (seed 001 Eq. 14; its
    gradient does not vanish at ``r_out``, and seed 001 Sect. 8 reports J
    oscillating with the point layout, more so for larger ``n``);
``"plateau"``
    the classical finite-element shape: ``q = 1`` for ``r <= r_in`` and the
    C1 cubic ``q = 1 - 3 s^2 + 2 s^3``, ``s = (r - r_in) / (r_out - r_in)``,
    down to 0 at ``r_out`` (zero slope at both ends); ``r_in`` defaults to
    ``r_out / 2``.

Every kind has ``q(tip) = 1``, ``q = 0`` and ``grad q = 0`` for ``r >= r_out``,
and a finite gradient (zero) at the tip: ``grad q`` is evaluated as
``(dq/dr / r) (x - x_tip)`` with ``dq/dr / r`` written out without division.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass

import numpy as np

from ..problem.crack import Tip

__all__ = ["KINDS", "QFunction"]

KINDS = ("cubic_spline", "plateau", "power", "wendland_c2")


def _real(name: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {v!r}")
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {v!r}")
    return float(v)


@dataclass(frozen=True)
class QFunction:
    """A radial weight ``q(r)`` about a crack tip: 1 at the tip, 0 from ``r_out`` on.

    Parameters
    ----------
    kind : {"cubic_spline", "wendland_c2", "power", "plateau"}
        Shape (module docstring; seed 001 Eqs. 10, 13, 14).
    r_out : float
        Outer radius of the integration domain, > 0.
    r_in : float, optional
        ``"plateau"`` only: radius of the region where ``q = 1``,
        ``0 <= r_in < r_out`` (default ``r_out / 2``).
    n : float, optional
        ``"power"`` only (required): exponent, ``n >= 2`` (``n < 2`` has a
        gradient that is discontinuous or infinite at the tip).

    Raises
    ------
    ValueError
        Unknown kind (the nearest kind is named), ``r_out <= 0``,
        ``r_in >= r_out`` or ``r_in < 0``, ``n`` missing or ``< 2`` for
        ``"power"``, ``r_in``/``n`` given to a kind that does not use them.

    Examples
    --------
    >>> q = QFunction("wendland_c2", r_out=2.0)
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> q.value(x, [0.0, 0.0]).tolist()            # (1 - z)^3 (1 + 3 z), z = r / 2
    [1.0, 0.3125, 0.0]
    >>> (q.gradient(x, [0.0, 0.0])[:, 0] + 0.0).round(12).tolist()   # -12 z (1 - z)^2 / r_out
    [0.0, -0.75, 0.0]
    """

    kind: str
    r_out: float
    r_in: float | None = None
    n: float | None = None

    def __post_init__(self):
        if not isinstance(self.kind, str) or self.kind not in KINDS:
            near = difflib.get_close_matches(str(self.kind), KINDS, n=1, cutoff=0.0)
            raise ValueError(f"unknown q-function kind {self.kind!r}: did you mean {near[0]!r}? "
                             f"The kinds are {KINDS}")
        r_out = _real("r_out", self.r_out)
        if r_out <= 0:
            raise ValueError(f"r_out must be > 0 (the outer radius of the J domain), got {r_out!r}")
        object.__setattr__(self, "r_out", r_out)
        if self.kind == "plateau":
            r_in = 0.5 * r_out if self.r_in is None else _real("r_in", self.r_in)
            if not 0 <= r_in < r_out:
                raise ValueError(f"plateau q-function needs 0 <= r_in < r_out, got r_in = {r_in!r} "
                                 f"and r_out = {r_out!r}; choose r_in smaller than r_out")
            object.__setattr__(self, "r_in", r_in)
        elif self.r_in is not None:
            raise ValueError(f"r_in is used only by kind 'plateau', got r_in = {self.r_in!r} with "
                             f"kind {self.kind!r}; leave it out")
        if self.kind == "power":
            if self.n is None:
                raise ValueError("the 'power' q-function 1 - (r / r_out)^n needs the exponent n "
                                 "(seed 001 Eq. 14 uses 2 to 5): give n >= 2")
            n = _real("n", self.n)
            if n < 2:
                raise ValueError(f"the power q-function needs n >= 2 (a finite, continuous "
                                 f"gradient at the tip), got n = {n!r}")
            object.__setattr__(self, "n", n)
        elif self.n is not None:
            raise ValueError(f"n is used only by kind 'power', got n = {self.n!r} with kind "
                             f"{self.kind!r}; leave it out")

    # --- radial profile ----------------------------------------------------------------

    def _profile(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``q(r)`` and ``dq/dr / r`` for ``0 <= r < r_out``, each (m,)."""
        R = self.r_out
        if self.kind == "cubic_spline":  # seed 001 Eq. 10 with h = r_out / 2, W(0) = C
            h = 0.5 * R
            z = r / h
            inner = z < 1
            q = np.where(inner, 1 - 1.5 * z**2 + 0.75 * z**3, 0.25 * (2 - z) ** 3)
            # dq/dr / r: (9/4 z^2 - 3 z) / (z h^2) and -3/4 (2 - z)^2 / (z h^2), z >= 1 there
            zo = np.where(inner, 1.0, z)
            g = np.where(inner, (2.25 * z - 3) / h**2, -0.75 * (2 - z) ** 2 / (zo * h**2))
            return q, g
        z = r / R
        if self.kind == "wendland_c2":  # seed 001 Eq. 13
            return (1 - z) ** 3 * (1 + 3 * z), -12 * (1 - z) ** 2 / R**2
        if self.kind == "power":  # seed 001 Eq. 14
            n = self.n
            return 1 - z**n, -n * z ** (n - 2) / R**2
        # plateau: smoothstep from r_in to r_out
        r_in = self.r_in
        s = np.clip((r - r_in) / (R - r_in), 0.0, 1.0)
        q = 1 - 3 * s**2 + 2 * s**3
        if r_in > 0:
            ro = np.maximum(r, r_in)
            g = np.where(r > r_in, -6 * s * (1 - s) / ((R - r_in) * ro), 0.0)
        else:  # s = r / R, dq/dr / r = -6 (1 - s) / R^2
            g = -6 * (1 - s) / R**2
        return q, g

    def _radial(self, x, tip) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        centre = tip.x if isinstance(tip, Tip) else np.asarray(tip, dtype=float)
        if centre.shape != (2,) or not np.all(np.isfinite(centre)):
            raise ValueError(f"tip must be a Tip or a finite point (2,), got {tip!r}")
        x = np.asarray(x, dtype=float)
        if x.ndim != 2 or x.shape[1] != 2:
            raise ValueError(f"x must have shape (n, 2), got {x.shape}")
        d = x - centre
        r = np.hypot(d[:, 0], d[:, 1])
        return d, r, r < self.r_out

    def value(self, x: np.ndarray, tip) -> np.ndarray:
        """``q`` at points ``x (n, 2)`` about ``tip`` (a Tip or a point (2,)), shape (n,)."""
        _, r, inside = self._radial(x, tip)
        out = np.zeros(len(r))
        out[inside] = self._profile(r[inside])[0]
        return out

    def gradient(self, x: np.ndarray, tip) -> np.ndarray:
        """``grad q`` in global coordinates at ``x (n, 2)``, shape (n, 2); zero at the tip."""
        d, r, inside = self._radial(x, tip)
        out = np.zeros((len(r), 2))
        out[inside] = self._profile(r[inside])[1][:, None] * d[inside]
        return out

    def value_and_gradient(self, x: np.ndarray, tip) -> tuple[np.ndarray, np.ndarray]:
        """``(q (n,), grad q (n, 2))`` in one pass."""
        d, r, inside = self._radial(x, tip)
        q, g = np.zeros(len(r)), np.zeros((len(r), 2))
        qi, gi = self._profile(r[inside])
        q[inside], g[inside] = qi, gi[:, None] * d[inside]
        return q, g
