"""Material properties that vary with position: a graded (functionally graded) body.

A :class:`Grading` on a :class:`~efgkit.problem.scene.Scene` scales the scene's
:class:`~efgkit.problem.material.Elastic` point by point:

    E(x) = E * modulus(x),    rho(x) = rho * density(x),    nu constant

(with nu constant, ``mu(x)`` and ``lambda(x)`` scale with ``E(x)``, so ``D(x) =
modulus(x) D``). The assembly integrates ``K = sum_q w_q modulus(x_q) B_q^T D B_q`` and the
lumped mass ``m_I = sum_q w_q rho density(x_q) phi_I(x_q)`` at the quadrature points, i.e.
the reference matrices with the weights ``w_q modulus(x_q)`` and ``w_q density(x_q)``
(:func:`modulus_weights`, :func:`density_weights`), and stresses are ``modulus(x) D eps``.
The scene's ``Elastic`` stays the reference (wave speeds, penalty scales, the critical
step is estimated from the assembled matrices). Seed 000 Sect. 5.2.3 grades ``rho`` and
``mu`` exponentially along x.

Supported by the EFG static solve and the explicit EFG driver; the SIF and J integrals of
a homogeneous body do not hold in a graded one (they lack the term of the explicit
gradient of the strain energy density) and refuse it, as do MLPG and FEM.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["Grading", "density_weights", "modulus_weights", "refuse_grading"]


def _factor(name: str, f):
    if f is None:
        return None
    if isinstance(f, bool) or not (callable(f) or isinstance(f, (int, float))):
        raise TypeError(f"grading {name} must be a callable x (n, 2) -> (n,), an expression or a "
                        f"number, got {type(f).__name__}")
    if not callable(f) and not (np.isfinite(f) and f > 0):
        raise ValueError(f"grading {name} must be finite and > 0, got {f!r}")
    return f


@dataclass(frozen=True)
class Grading:
    """Position-dependent factors of the modulus and the density (module docstring).

    Parameters
    ----------
    modulus, density : callable ``x (n, 2) -> (n,)``, Expression, number or None
        ``E(x) / E`` and ``rho(x) / rho`` of the scene's material (None: 1). In scene files
        formulas of ``x`` and ``y`` (the ``[grading]`` table).

    Examples
    --------
    >>> g = Grading(modulus=lambda x: 1.0 + x[:, 0])
    >>> g.factors(np.array([[0.0, 0.0], [2.0, 1.0]]))
    (array([1., 3.]), array([1., 1.]))
    """

    modulus: Callable | float | None = None
    density: Callable | float | None = None

    def __post_init__(self):
        _factor("modulus", self.modulus)
        _factor("density", self.density)

    def _at(self, name: str, x: np.ndarray) -> np.ndarray:
        f = getattr(self, name)
        if f is None:
            return np.ones(len(x))
        v = np.broadcast_to(np.asarray(f(x) if callable(f) else f, float), (len(x),))
        bad = ~(np.isfinite(v) & (v > 0))
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise ValueError(f"grading {name} is {float(v[k])!r} at x = {x[k].tolist()}: it must be finite "
                             "and > 0 over the body (a factor of the material's value)")
        return np.array(v)

    def factors(self, x) -> tuple[np.ndarray, np.ndarray]:
        """``(modulus(x), density(x))`` at points ``x (n, 2)``, each (n,), checked finite > 0."""
        x = np.asarray(x, float).reshape(-1, 2)
        return self._at("modulus", x), self._at("density", x)


def modulus_weights(scene, x: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Quadrature weights ``w_q modulus(x_q)`` (n,): ``w`` unchanged without a grading."""
    g = getattr(scene, "grading", None)
    return w if g is None else w * g.factors(x)[0]


def density_weights(scene, x: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Quadrature weights ``w_q density(x_q)`` (n,): ``w`` unchanged without a grading."""
    g = getattr(scene, "grading", None)
    return w if g is None else w * g.factors(x)[1]


def refuse_grading(scene, what: str) -> None:
    """ValueError when ``scene`` is graded and ``what`` (a solver or a quantity) is not."""
    if getattr(scene, "grading", None) is not None:
        raise ValueError(f"scene {scene.name!r} has a grading (position-dependent material): "
                         f"{what} assumes a homogeneous material. Remedy: the EFG static solve "
                         "or the explicit EFG driver (without dynamic SIFs: dsif=None), or drop "
                         "the grading")
