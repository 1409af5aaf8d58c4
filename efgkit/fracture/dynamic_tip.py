"""Dynamic stress intensity factors of a tip at one instant, over several domains.

:func:`dynamic_tip_result` is what a time integrator calls at its output instants: from
arrays at points (no scene, no discretisation) it evaluates the dynamic ``J'`` of
Nishioka and Atluri and the interaction integral with inertia
(:mod:`efgkit.fracture.dynamic`) over several domains about the tip, and returns
``K_I``, ``K_II`` both ways side by side: from ``J'_1``, ``J'_2`` through the velocity
functions (:mod:`efgkit.fracture.velocity`, seed 002 Eqs. 33-38) and from the
interaction integrals (stationary crack), with the domain spread of each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..problem.crack import Tip
from ..problem.material import Elastic
from .dynamic import DynamicSIF, contract_dynamic, dynamic_integrands
from .integrals import FaceLoad
from .qfunctions import QFunction
from .velocity import k_from_dynamic_j

__all__ = ["DynamicTipResult", "dynamic_tip_result"]


@dataclass(frozen=True)
class DynamicTipResult:
    """Dynamic SIFs of one tip at one instant, averaged over several domains.

    Attributes
    ----------
    tip : Tip
    speed : float
        Crack speed ``V`` the velocity functions were taken at.
    J1, J2 : float
        Means of ``J'_1``, ``J'_2`` (tip frame) over the domains.
    KI_J, KII_J : float
        From the mean ``J'_1``, ``J'_2`` (:func:`~efgkit.fracture.velocity.k_from_dynamic_j`).
    KI, KII : float or None
        Means of the interaction-integral values; None for a moving tip (``V > 0``), whose
        auxiliary fields would be the moving-crack ones.
    spread_J : float
        ``max(ptp K_I^J, ptp K_II^J) / |K^J|`` over the domains (``K^J`` per domain from its
        own ``J'``): 0 for a domain-independent ``J'``.
    spread : float or None
        The same for the interaction values (None when ``KI`` is).
    domains : tuple of DynamicSIF
        Per-domain values, by increasing radius.
    """

    tip: Tip
    speed: float
    J1: float
    J2: float
    KI_J: float
    KII_J: float
    KI: float | None
    KII: float | None
    spread_J: float
    spread: float | None
    domains: tuple[DynamicSIF, ...]

    def as_dict(self) -> dict:
        """JSON-ready: ``id, x, y, speed, J1, J2, KI_J, KII_J, KI, KII, spread_J, spread, domains``."""
        return {"id": self.tip.id, "x": float(self.tip.x[0]), "y": float(self.tip.x[1]),
                "speed": self.speed, "J1": self.J1, "J2": self.J2, "KI_J": self.KI_J,
                "KII_J": self.KII_J, "KI": self.KI, "KII": self.KII, "spread_J": self.spread_J,
                "spread": self.spread,
                "domains": [{"radius": d.radius, "J1": d.J1, "J2": d.J2, "KI": d.KI, "KII": d.KII,
                             "n_points": d.n_points} for d in self.domains]}


def _spread(KI: np.ndarray, KII: np.ndarray) -> float:
    """``max(ptp KI, ptp KII) / |mean K|`` (largest domain value if the means vanish; 0 if all are 0)."""
    norm = math.hypot(np.mean(KI), np.mean(KII)) or float(np.max(np.hypot(KI, KII)))
    return max(float(np.ptp(KI)), float(np.ptp(KII))) / norm if norm > 0 else 0.0


def _qfunctions(q, radii) -> list[QFunction]:
    try:
        rs = np.sort(np.asarray(radii, dtype=float).reshape(-1))
    except (TypeError, ValueError) as err:
        raise TypeError(f"radii must be a sequence of numbers, got {radii!r}") from err
    if len(rs) < 3:
        raise ValueError(f"domain independence needs at least three radii, got {len(rs)} "
                         f"({rs.tolist()}); see efgkit.fracture.sif.default_radii")
    if not np.all(np.isfinite(rs) & (rs > 0)):
        raise ValueError(f"radii must be finite and > 0, got {rs.tolist()}")
    out = []
    for R in rs:
        f = q(float(R)) if callable(q) else QFunction(q, float(R), n=2.0 if q == "power" else None)
        if not isinstance(f, QFunction):
            raise TypeError(f"q(radius) must return a QFunction, got {type(f).__name__}")
        out.append(f)
    return out


def dynamic_tip_result(tip: Tip, x, w, stress, grad_u, velocity, acceleration, rho, radii,
                       material: Elastic, speed: float = 0.0, q="wendland_c2",
                       faces: FaceLoad | None = None, grad_v=None, face_velocity=None,
                       body_force=None, opening: float | None = None,
                       sliding: float | None = None) -> DynamicTipResult:
    """``K_I``, ``K_II`` of a tip at one instant from ``J'`` and from the interaction integrals.

    Parameters
    ----------
    tip : Tip
        The tip and its frame (``x1`` ahead).
    x : ndarray (n, 2)
        Points, global (Gauss points with their areas, or nodes with their volumes).
    w : ndarray (n,)
        Weights (areas).
    stress : ndarray (n, 3)
        Voigt (xx, yy, xy), global.
    grad_u : ndarray (n, 2, 2)
        ``du_i/dx_j``, global.
    velocity, acceleration : ndarray (n, 2)
        ``u'`` and ``u''`` at ``x``, global (the velocity enters only with ``grad_v``).
    rho : float or None
        Homogeneous density (None: ``material.rho``).
    radii : sequence of float
        At least three domain radii (e.g. :func:`~efgkit.fracture.sif.default_radii`).
    material : Elastic
    speed : float
        Crack speed ``V``, ``0 <= V < c_R``. ``V > 0`` needs ``grad_v`` (the ``W + T`` form)
        and gives no interaction values.
    q : str or callable
        A :class:`~efgkit.fracture.qfunctions.QFunction` kind, or ``radius -> QFunction``.
    faces : FaceLoad, optional
        Crack-face points within the largest radius with their tractions (zero on
        unloaded faces) and displacement gradients: the face terms of ``J'_1`` (loaded
        faces) and ``J'_2`` (``W`` on the faces, also when unloaded), and of the
        interaction integrals.
    grad_v : ndarray (n, 2, 2), optional
        Velocity gradient ``du'_i/dx_j``; selects the ``W + T`` form.
    face_velocity : ndarray (m, 2), optional
        Velocity at ``faces.x`` (the ``W + T`` form with faces).
    body_force : ndarray (n, 2), optional
    opening, sliding : float, optional
        Tip-frame crack-face displacement jump behind the tip, for the branch and signs
        of :func:`~efgkit.fracture.velocity.k_from_dynamic_j`. Without them and with
        ``V = 0``, the interaction ``K_I``, ``K_II`` stand in for them (at ``V = 0`` the
        jump is proportional to ``K``).

    Returns
    -------
    DynamicTipResult

    Raises
    ------
    ValueError
        Fewer than three radii, a non-positive radius, an empty domain, non-finite fields
        in a domain, ``V`` outside ``[0, c_R)``, ``V > 0`` without ``grad_v``, shapes.

    Examples
    --------
    A static Williams field (no velocity, no acceleration): ``J'`` is the static J and both
    estimates give ``K_I = 1``, ``K_II = 0.5``.

    >>> from efgkit.problem.exact.williams import williams_gradient, williams_stress
    >>> m = Elastic(1.0, 0.3, rho=1.0)
    >>> t, tw = np.polynomial.legendre.leggauss(16)
    >>> s = (t + 1) / 2 * np.sqrt(0.8); r = s**2; th = np.pi * t
    >>> R, TH = [a.ravel() for a in np.meshgrid(r, th, indexing="ij")]
    >>> W = np.outer(s**3 * np.sqrt(0.8) * tw, np.pi * tw).ravel()
    >>> x = np.column_stack([R * np.cos(TH), R * np.sin(TH)]); z = np.zeros_like(x)
    >>> res = dynamic_tip_result(Tip(np.zeros(2), 0.0, "c", 1), x, W,
    ...                          williams_stress(R, TH, 1.0, 0.5),
    ...                          williams_gradient(R, TH, 1.0, 0.5, m.mu, m.kappa), z, z, None,
    ...                          [0.8, 0.8, 0.8], m)
    >>> round(res.KI, 9), round(res.KII, 9), round(res.KI_J, 9), round(res.KII_J, 9)
    (1.0, 0.5, 1.0, 0.5)
    """
    if isinstance(speed, bool) or not isinstance(speed, (int, float, np.integer, np.floating)):
        raise TypeError(f"speed must be a real number, got {speed!r}")
    if not (math.isfinite(speed) and speed >= 0):
        raise ValueError(f"speed must be finite and >= 0 (the crack speed V), got {speed!r}")
    if speed > 0 and grad_v is None:
        raise ValueError(f"a moving tip (speed = {speed!r}) needs grad_v, the velocity gradient "
                         "(n, 2, 2): J' without the kinetic terms holds only for a stationary crack")
    qs = _qfunctions(q, radii)
    terms = dynamic_integrands(x, w, stress, grad_u, velocity, acceleration, rho, tip, material,
                               max(f.r_out for f in qs), grad_v, body_force)
    doms = [contract_dynamic(terms, f, faces, face_velocity) for f in qs]
    stationary = speed == 0
    KI = np.array([d.KI for d in doms])
    KII = np.array([d.KII for d in doms])
    J1 = float(np.mean([d.J1 for d in doms]))
    J2 = float(np.mean([d.J2 for d in doms]))

    def from_j(j1: float, j2: float) -> tuple[float, float]:
        if opening is None and sliding is None and stationary:
            return k_from_dynamic_j(j1, j2, material, 0.0, float(np.mean(KI)), float(np.mean(KII)))
        return k_from_dynamic_j(j1, j2, material, speed, opening, sliding)

    KJ = np.array([from_j(d.J1, d.J2) for d in doms])
    KI_J, KII_J = from_j(J1, J2)
    return DynamicTipResult(
        tip=tip, speed=float(speed), J1=J1, J2=J2, KI_J=KI_J, KII_J=KII_J,
        KI=float(np.mean(KI)) if stationary else None,
        KII=float(np.mean(KII)) if stationary else None,
        spread_J=_spread(KJ[:, 0], KJ[:, 1]),
        spread=_spread(KI, KII) if stationary else None, domains=tuple(doms))
