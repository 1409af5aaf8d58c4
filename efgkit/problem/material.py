"""Isotropic linear-elastic material in plane strain or plane stress."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

__all__ = ["Elastic", "strain_from_gradient", "voigt_tensor"]

_PLANES = ("strain", "stress")


def strain_from_gradient(grad: np.ndarray) -> np.ndarray:
    """Small strain in Voigt form (xx, yy, xy engineering), shape (n, 3), from displacement
    gradients ``grad[n, i, j] = du_i / dx_j`` of shape (n, 2, 2)."""
    return np.column_stack([grad[:, 0, 0], grad[:, 1, 1], grad[:, 0, 1] + grad[:, 1, 0]])


def voigt_tensor(voigt: np.ndarray) -> np.ndarray:
    """Voigt stresses ``(..., 3)`` (xx, yy, xy) -> symmetric tensors ``(..., 2, 2)``."""
    return np.stack([np.stack([voigt[..., 0], voigt[..., 2]], -1),
                     np.stack([voigt[..., 2], voigt[..., 1]], -1)], -2)


def _finite_positive(name: str, value, allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")


@dataclass(frozen=True)
class Elastic:
    """Isotropic linear elasticity, 2D.

    Parameters
    ----------
    E : float
        Young's modulus, > 0 (the user's stress unit).
    nu : float
        Poisson's ratio in [0, 0.5); a warning is issued above 0.49 (near
        incompressibility locks a displacement formulation).
    plane : {"strain", "stress"}
        2D idealisation.
    rho : float, optional
        Mass density (only dynamic scenes need it).

    Examples
    --------
    >>> m = Elastic(E=210e3, nu=0.3)
    >>> m.D.shape
    (3, 3)
    >>> round(m.kappa, 6)
    1.8
    """

    E: float
    nu: float
    plane: str = "strain"
    rho: float | None = None

    def __post_init__(self):
        _finite_positive("E", self.E)
        if isinstance(self.nu, bool) or not isinstance(
            self.nu, (int, float, np.floating, np.integer)
        ):
            raise TypeError(f"nu must be a real number, got {self.nu!r}")
        if not math.isfinite(self.nu) or not 0.0 <= self.nu < 0.5:
            raise ValueError(f"nu must lie in [0, 0.5), got {self.nu!r}")
        if self.nu > 0.49:
            warnings.warn(
                f"nu = {self.nu} is close to 0.5: displacement-based EFG locks; "
                "expect stiff, inaccurate results",
                UserWarning,
                stacklevel=3,
            )
        if self.plane not in _PLANES:
            raise ValueError(f"plane must be one of {_PLANES}, got {self.plane!r}")
        _finite_positive("rho", self.rho, allow_none=True)

    @property
    def mu(self) -> float:
        """Shear modulus mu = E / (2 (1 + nu))."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def kappa(self) -> float:
        """Kolosov constant: 3 - 4 nu (plane strain), (3 - nu)/(1 + nu) (plane stress)."""
        if self.plane == "strain":
            return 3.0 - 4.0 * self.nu
        return (3.0 - self.nu) / (1.0 + self.nu)

    @property
    def E_prime(self) -> float:
        """Effective modulus E' of J = (K_I^2 + K_II^2) / E': E/(1 - nu^2) in plane strain."""
        return self.E / (1.0 - self.nu**2) if self.plane == "strain" else self.E

    @property
    def D(self) -> np.ndarray:
        """Constitutive matrix, shape (3, 3), Voigt (xx, yy, xy) with engineering shear.

        Seed 003 Eq. (23) (plane strain) and Eq. (24) (plane stress).
        """
        E, nu = self.E, self.nu
        if self.plane == "strain":
            c = E / ((1.0 + nu) * (1.0 - 2.0 * nu))
            return c * np.array([[1 - nu, nu, 0], [nu, 1 - nu, 0], [0, 0, (1 - 2 * nu) / 2]])
        c = E / (1.0 - nu**2)
        return c * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])

    @property
    def lame(self) -> tuple[float, float]:
        """(lambda*, mu): sigma = lambda* tr(eps) I + 2 mu eps in the 2D idealisation."""
        D = self.D
        return float(D[0, 1]), float(D[2, 2])

    def compliance(self) -> np.ndarray:
        """Inverse of :attr:`D`, shape (3, 3)."""
        return np.linalg.inv(self.D)

    def _require_rho(self) -> float:
        if self.rho is None:
            raise ValueError("this needs a mass density: give Elastic(..., rho=...)")
        return self.rho

    @property
    def c_dilatational(self) -> float:
        """P-wave speed c1 = sqrt((lambda* + 2 mu) / rho) in the 2D idealisation."""
        lam, mu = self.lame
        return math.sqrt((lam + 2 * mu) / self._require_rho())

    @property
    def c_shear(self) -> float:
        """S-wave speed c2 = sqrt(mu / rho)."""
        return math.sqrt(self.mu / self._require_rho())

    @property
    def c_rayleigh(self) -> float:
        """Rayleigh wave speed cR = c2 sqrt(x) in the 2D idealisation (seed 000 Eqs. 5.9-5.10).

        ``x = (cR / c2)^2`` is the root in (0, 1) of the Rayleigh equation
        ``(2 - x)^2 = 4 sqrt(1 - x) sqrt(1 - g x)``, ``g = (c2 / c1)^2``, squared out and
        divided by its spurious root ``x = 0``: ``x^3 - 8 x^2 + (24 - 16 g) x - 16 (1 - g) = 0``.
        The cubic is -16 (1 - g) < 0 at 0, 1 at 1 and increasing on [0, 1] (its derivative
        vanishes only beyond 4/3 for g <= 1/2), so the bracketed root is unique; it is found to
        rounding. Seed 000's cubic in ``eta = beta_1 / beta_2`` (Eq. 5.9, its largest root) gives
        the same speed through Eq. 5.10 (``tests/test_dynamic_sif.py``). Plane stress uses the
        plane-stress c1.

        Examples
        --------
        >>> round(Elastic(210e9, 0.3, rho=7800.0).c_rayleigh)   # seed 002 Sect. 4.3 at 210 GPa
        2984
        """
        from scipy.optimize import brentq

        g = (self.c_shear / self.c_dilatational) ** 2

        def f(x):
            return ((x - 8.0) * x + 24.0 - 16.0 * g) * x - 16.0 * (1.0 - g)

        return self.c_shear * math.sqrt(brentq(f, 0.0, 1.0, xtol=1e-17, rtol=1e-15))
