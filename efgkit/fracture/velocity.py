"""Crack-speed functions of the dynamic J' and the dynamic SIF from J' (seed 002 Eqs. 33-38).

For a crack moving at speed ``V`` (tip frame), the dynamic J' of Nishioka and Atluri
(:mod:`efgkit.fracture.dynamic`) is related to the instantaneous dynamic stress
intensity factors by (seed 002 Eq. 33)

.. math::

    J'_1 = \\frac{A_I(V) K_I^2 + A_{II}(V) K_{II}^2}{2\\mu},\\qquad
    J'_2 = -\\frac{A_{IV}(V)}{\\mu} K_I K_{II},

with (seed 002 Eq. 34) ``beta_1 = sqrt(1 - (V / c_d)^2)``, ``beta_2 = sqrt(1 - (V / c_s)^2)``,
``D = 4 beta_1 beta_2 - (1 + beta_2^2)^2``, ``Dbar = 4 beta_1 beta_2 + (1 + beta_2^2)^2``,

.. math::

    A_I = \\frac{\\beta_1 (1 - \\beta_2^2)}{D},\\quad
    A_{II} = \\frac{\\beta_2 (1 - \\beta_2^2)}{D},\\quad
    A_{IV} = \\frac{(\\beta_1 - \\beta_2)(1 - \\beta_2^2)\\bar D}{2 D^2}
      \\left[\\frac{2 + \\beta_1 + \\beta_2}{\\sqrt{(1 + \\beta_1)(1 + \\beta_2)}}
      - \\frac{4 (1 + \\beta_2^2)}{\\bar D}\\right].

``c_d`` and ``c_s`` are :attr:`Elastic.c_dilatational <efgkit.problem.material.Elastic.c_dilatational>`
(the plane-stress speed in plane stress) and :attr:`Elastic.c_shear
<efgkit.problem.material.Elastic.c_shear>`. At ``V = 0`` all three are ``(kappa + 1) / 4``
(seed 002 Eq. 35), and ``D`` and ``1 - beta_2^2`` vanish together: the printed quotients
lose ``~ 2 log10(c_s / V)`` digits to cancellation. Here they are evaluated in a
rationalised form with no cancellation at any ``0 <= V < c_R``: with
``b = (V / c_s)^2`` and ``g = (c_s / c_d)^2``,

.. math::

    D \\bar D = 16 \\beta_1^2 \\beta_2^2 - (1 + \\beta_2^2)^4 = b\\,R(b),\\qquad
    R(b) = 16 (1 - g) - (24 - 16 g) b + 8 b^2 - b^3,

(``R`` is minus the Rayleigh cubic of :attr:`Elastic.c_rayleigh
<efgkit.problem.material.Elastic.c_rayleigh>`, positive below ``c_R``), and
``beta_1 - beta_2 = (1 - g) b / (beta_1 + beta_2)``, so that

.. math::

    A_I = \\frac{\\beta_1 \\bar D}{R},\\quad A_{II} = \\frac{\\beta_2 \\bar D}{R},\\quad
    A_{IV} = \\frac{(1 - g) \\bar D^3}{2 (\\beta_1 + \\beta_2) R^2}[\\ldots],

exact algebraic identities (no series and no switch): ``A(0) = 8 / (16 (1 - g)) =
1 / (2 (1 - g)) = (kappa + 1) / 4`` in either plane. ``tests/test_dynamic_sif.py`` checks
them against the printed formulas evaluated with 60-digit ``decimal`` arithmetic
(relative error < 1e-13 for ``1e-12 <= V / c_s <= 0.999 c_R / c_s``).

*Inverting Eq. 33* (seed 002 Eqs. 37-38): with ``X = A_I K_I^2`` and ``Y = A_II K_II^2``,
``J'_1 = (X + Y) / 2 mu`` and ``(A_I A_II / A_IV^2) J'_2^2 = X Y / mu^2``, so

.. math::

    K_I^2 = \\frac{\\mu}{A_I}\\left\\{J'_1 \\pm
        \\sqrt{J_1'^2 - \\frac{A_I A_{II}}{A_{IV}^2} J_2'^2}\\right\\},
    \\qquad
    K_{II}^2 = \\frac{\\mu}{A_{II}}\\left\\{J'_1 \\mp \\sqrt{\\ldots}\\right\\},

the upper signs when ``X >= Y``. The seed takes the upper signs when ``|delta_I| >=
|delta_II|`` (crack opening and sliding displacements) and the signs of ``K_I``, ``K_II``
from those of ``delta_I``, ``delta_II``. Behind a moving tip ``delta_I = 2 A_I K_I
sqrt(2 r / pi) / mu`` and ``delta_II = 2 A_II K_II sqrt(2 r / pi) / mu`` (Freund,
*Dynamic Fracture Mechanics*, 1990, Sect. 4.3), so ``X >= Y`` is ``A_II delta_I^2 >=
A_I delta_II^2``: the seed's rule at ``V = 0`` (``A_I = A_II``), and the exact one used
here for ``V > 0``. Negative brackets (rounding, or a ``J'`` polluted by
discretisation error) are taken as 0, the Macaulay brackets ``< >`` of Eq. 38.
"""

from __future__ import annotations

import math

import numpy as np

from ..problem.material import Elastic

__all__ = ["k_from_dynamic_j", "velocity_functions"]


def _material(material) -> Elastic:
    if not isinstance(material, Elastic):
        raise TypeError(f"material must be an Elastic, got {type(material).__name__}")
    return material


def velocity_functions(speed, material: Elastic) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``A_I(V), A_II(V), A_IV(V)`` of seed 002 Eq. 34, each the shape of ``speed``.

    Evaluated in the rationalised form of the module docstring: accurate to rounding
    for every ``0 <= V < c_R``, including ``V -> 0`` where the printed quotients cancel.

    Parameters
    ----------
    speed : float or ndarray
        Crack speed(s) ``V >= 0`` (the user's velocity unit). ``V > 0`` needs
        ``material.rho``.
    material : Elastic
        Gives ``c_d``, ``c_s`` and ``c_R`` (plane-stress speeds in plane stress).

    Returns
    -------
    A_I, A_II, A_IV : ndarray, shape of ``speed``

    Raises
    ------
    ValueError
        ``V`` negative or not finite, ``V >= c_R`` (names ``V`` and ``c_R``), ``V > 0``
        without a density.
    TypeError
        ``material`` not an Elastic.

    Examples
    --------
    >>> m = Elastic(1.0, 0.3, "strain")
    >>> [float(a) for a in velocity_functions(0.0, m)]    # (kappa + 1) / 4 = 1 - nu
    [0.7, 0.7, 0.7]
    """
    m = _material(material)
    v = np.asarray(speed, dtype=float)
    if not np.all(np.isfinite(v)) or np.any(v < 0):
        raise ValueError(f"speed must be finite and >= 0 (the crack speed V), got {speed!r}")
    lam, mu = m.lame
    g = mu / (lam + 2 * mu)  # (c_s / c_d)^2, no density needed
    if np.any(v > 0):
        if m.rho is None:
            raise ValueError(f"a crack speed V = {float(np.max(v))!r} > 0 needs the wave speeds: "
                             "give the material a density, Elastic(..., rho=...)")
        cs, cR = m.c_shear, m.c_rayleigh
        if np.any(v >= cR):
            raise ValueError(f"crack speed V = {float(np.max(v))!r} is not below the Rayleigh speed "
                             f"c_R = {cR!r} of the material: the velocity functions of seed 002 "
                             "Eq. 34 are defined for 0 <= V < c_R")
        b = (v / cs) ** 2
    else:
        b = np.zeros_like(v)
    b1, b2 = np.sqrt(1 - g * b), np.sqrt(1 - b)
    Dbar = 4 * b1 * b2 + (2 - b) ** 2
    R = ((8 - b) * b - (24 - 16 * g)) * b + 16 * (1 - g)
    bracket = (2 + b1 + b2) / np.sqrt((1 + b1) * (1 + b2)) - 4 * (2 - b) / Dbar
    A_I = b1 * Dbar / R
    A_II = b2 * Dbar / R
    A_IV = (1 - g) * Dbar**3 / (2 * (b1 + b2) * R**2) * bracket
    return A_I, A_II, A_IV


def _real(name: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {v!r}")
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {v!r}")
    return float(v)


def k_from_dynamic_j(J1: float, J2: float, material: Elastic, speed: float = 0.0,
                     opening: float | None = None, sliding: float | None = None) -> tuple[float, float]:
    """``(K_I, K_II)`` from the tip-frame dynamic ``J'_1``, ``J'_2`` (seed 002 Eqs. 33, 38).

    The branch and signs follow the crack-opening and sliding displacements
    (module docstring): ``X >= Y`` when ``A_II opening^2 >= A_I sliding^2`` (the seed's
    ``|delta_I| >= |delta_II|`` at ``V = 0``), ``sign K_I = sign(opening)``,
    ``sign K_II = sign(sliding)``. Without them the crack is taken as
    opening-dominated: the upper branch, ``K_I >= 0`` and ``sign K_II = -sign J'_2``
    (from ``J'_2 = -A_IV K_I K_II / mu``, ``A_IV > 0``). With ``J'_2 = 0`` and ``V = 0``
    this is seed 000 Eq. 5.7 (``K = sqrt(2 mu J / (1 - nu))`` in plane strain) and,
    divided by ``sigma_0 sqrt(pi a)``, Eq. 5.8.

    Parameters
    ----------
    J1, J2 : float
        ``J'_1``, ``J'_2`` in the tip frame (seed 002 Eq. 32).
    material : Elastic
    speed : float
        Crack speed ``V``, ``0 <= V < c_R``.
    opening, sliding : float, optional
        ``delta_I = [u_2]``, ``delta_II = [u_1]``: tip-frame jump ``u(upper face) -
        u(lower face)`` behind the tip (``theta = +pi`` minus ``theta = -pi``), as in
        :func:`~efgkit.fracture.extrapolation.k_from_cod`. Give both or neither.

    Returns
    -------
    KI, KII : float

    Examples
    --------
    >>> m = Elastic(1.0, 0.25, "stress")          # A = (kappa + 1) / 4 = 1 / (1 + nu) = 0.8
    >>> J1 = 0.8 * (2.0**2 + 0.5**2) / (2 * m.mu); J2 = -0.8 * 2.0 * 0.5 / m.mu
    >>> [round(k, 12) for k in k_from_dynamic_j(J1, J2, m)]
    [2.0, 0.5]
    >>> [round(k, 12) for k in k_from_dynamic_j(J1, -J2, m, opening=1e-3, sliding=-1e-4)]
    [2.0, -0.5]
    """
    J1, J2 = _real("J1", J1), _real("J2", J2)
    if (opening is None) != (sliding is None):
        raise ValueError(f"give both opening and sliding (the crack-face displacement jump) or "
                         f"neither, got opening = {opening!r} and sliding = {sliding!r}")
    A_I, A_II, A_IV = (float(a) for a in velocity_functions(_real("speed", speed), material))
    mu = material.mu
    root = math.sqrt(max(J1 * J1 - A_I * A_II / A_IV**2 * J2 * J2, 0.0))
    if opening is None:
        upper, s_I, s_II = True, 1.0, -math.copysign(1.0, J2) if J2 != 0 else 1.0
    else:
        dI, dII = _real("opening", opening), _real("sliding", sliding)
        upper = A_II * dI * dI >= A_I * dII * dII
        s_I, s_II = math.copysign(1.0, dI), math.copysign(1.0, dII)
    sgn = 1.0 if upper else -1.0
    KI = s_I * math.sqrt(max(mu / A_I * (J1 + sgn * root), 0.0))
    KII = s_II * math.sqrt(max(mu / A_II * (J1 - sgn * root), 0.0))
    return KI, KII
