"""Point supports and edge pressures: the values a :class:`~efgkit.problem.scene.Scene`
takes besides its edge supports and tractions."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .exact.fields import Field
from .geometry import COORDINATE_LIMIT

__all__ = ["PointSupport", "Pressure"]


def _check_number(what: str, v) -> None:
    """None, or a finite float whose square is a normal float64 number."""
    if v is None:
        return
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise TypeError(f"{what} must be a float, got {v!r}")
    if not np.isfinite(v):
        raise ValueError(f"{what} must be finite, got {v!r}")
    if abs(v) > COORDINATE_LIMIT:
        raise ValueError(f"{what} = {v!r} is too large to square without overflow (|value| <= "
                         f"{COORDINATE_LIMIT:g}); rescale the units (e.g. MPa and mm instead of Pa and m)")


@dataclass(frozen=True)
class PointSupport:
    """Prescribed displacement components at one point: a pin (``ux`` and ``uy``) or a
    roller (one of them), e.g. to remove the rigid-body motions of a traction-loaded body.

    The solvers collocate the displacement at ``x``: EFG by a multiplier row (bc="lagrange")
    or a spring of stiffness ``penalty * E`` (the other bc methods), FEM by fixing the DOFs of
    the mesh vertex placed at ``x``. Where the loads are in equilibrium the support carries
    no force, so the spring and the row give the same field.

    Parameters
    ----------
    x : (2,) float
        The point (inside the body or on its boundary, e.g. a vertex).
    ux, uy : float or None
        Prescribed component (None: free).

    Examples
    --------
    >>> PointSupport((0.0, 0.0), ux=0.0, uy=0.0).fixed
    (True, True)
    """

    x: tuple[float, float]
    ux: float | None = None
    uy: float | None = None

    def __post_init__(self):
        x = np.asarray(self.x, dtype=float)
        if x.shape != (2,) or not np.all(np.isfinite(x)):
            raise ValueError(f"point support: x must be a finite point (x0, y0), got {self.x!r}")
        object.__setattr__(self, "x", (float(x[0]), float(x[1])))
        if self.ux is None and self.uy is None:
            raise ValueError(f"point support at {self.x}: prescribes nothing; give ux and/or uy")
        for key in ("ux", "uy"):
            v = getattr(self, key)
            if v is not None and (callable(v) or isinstance(v, Field)):
                raise TypeError(f"point support at {self.x}: {key} must be a float, got "
                                f"{type(v).__name__}")
            _check_number(f"point support at {self.x}: {key}", v)

    @property
    def fixed(self) -> tuple[bool, bool]:
        """Which components are prescribed."""
        return (self.ux is not None, self.uy is not None)

    @property
    def values(self) -> tuple[float, float]:
        """Prescribed values (0 where free)."""
        return (float(self.ux or 0.0), float(self.uy or 0.0))


@dataclass(frozen=True)
class Pressure:
    """A pressure ``p`` on an edge, as the value of a :class:`Traction`: the traction
    ``-p n`` with ``n`` the outward normal of the body, so ``p > 0`` pushes into the
    material (a pressurised hole: ``Traction("hole", Pressure(1.0))``).

    Examples
    --------
    >>> Pressure(2.0).p
    2.0
    """

    p: float

    def __post_init__(self):
        if isinstance(self.p, bool) or not isinstance(self.p, (int, float)):
            raise TypeError(f"pressure p must be a number, got {self.p!r}")
        _check_number("pressure p", self.p)
