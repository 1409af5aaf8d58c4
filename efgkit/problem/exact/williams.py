"""Williams near-tip fields of a straight crack, in the crack-tip frame.

The tip frame has ``x1`` along the crack, pointing ahead of the tip, and
``x2`` normal to it; polar coordinates ``(r, theta)`` about the tip have
``theta`` in ``[-pi, pi]`` with the crack faces at ``theta = +-pi``. These are
the leading (singular) terms of Williams' expansion; they are both the exact
field of the singular patch test and the auxiliary fields of interaction
integrals (:mod:`efgkit.fracture.auxiliary_fields`). :mod:`efgkit.problem.frames`
moves between the global and the tip frame.

Also here: the displacement gradient of the Williams fields and the point-force
(Flamant) field at a crack tip (the auxiliary field of the T-stress interaction
integral). The exact field of a Griffith crack is in
:mod:`efgkit.problem.exact.griffith`.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "point_force_displacement",
    "point_force_gradient",
    "point_force_stress",
    "williams_displacement",
    "williams_gradient",
    "williams_stress",
]


def _polar_args(r, theta) -> tuple[np.ndarray, np.ndarray]:
    r, theta = np.broadcast_arrays(np.atleast_1d(np.asarray(r, dtype=float)),
                                   np.atleast_1d(np.asarray(theta, dtype=float)))
    if r.ndim != 1:
        raise ValueError(f"r and theta must be 1-D arrays (n,), got shape {r.shape}")
    bad = ~(np.isfinite(r) & np.isfinite(theta))
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ValueError(f"r and theta must be finite; point {i} has (r, theta) = "
                         f"({r[i]!r}, {theta[i]!r})")
    bad = (r < 0) | (np.abs(theta) > np.pi)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ValueError(f"expected r >= 0 and theta in [-pi, pi]; point {i} has "
                         f"(r, theta) = ({r[i]!r}, {theta[i]!r})")
    return r, theta


def williams_displacement(r, theta, KI: float, KII: float, mu: float, kappa: float) -> np.ndarray:
    """Near-tip displacement in the tip frame, shape (n, 2) as (u1, u2).

    .. math::

        u_1 &= \\frac{K_I}{2\\mu}\\sqrt{\\frac{r}{2\\pi}}\\cos\\frac{\\theta}{2}
               \\left[\\kappa - 1 + 2\\sin^2\\frac{\\theta}{2}\\right]
             + \\frac{K_{II}}{2\\mu}\\sqrt{\\frac{r}{2\\pi}}\\sin\\frac{\\theta}{2}
               \\left[\\kappa + 1 + 2\\cos^2\\frac{\\theta}{2}\\right] \\\\
        u_2 &= \\frac{K_I}{2\\mu}\\sqrt{\\frac{r}{2\\pi}}\\sin\\frac{\\theta}{2}
               \\left[\\kappa + 1 - 2\\cos^2\\frac{\\theta}{2}\\right]
             - \\frac{K_{II}}{2\\mu}\\sqrt{\\frac{r}{2\\pi}}\\cos\\frac{\\theta}{2}
               \\left[\\kappa - 1 - 2\\sin^2\\frac{\\theta}{2}\\right]

    Mode I: seed 003 Eq. (60a-b); mode II: Anderson, *Fracture Mechanics*
    (3rd ed.), Table 2.2. ``u = 0`` at the tip ``r = 0``.

    Parameters
    ----------
    r, theta : array_like, shape (n,)
        Distance from the tip (>= 0) and angle from the crack-ahead direction,
        in ``[-pi, pi]`` (faces at ``+-pi``).
    KI, KII : float
        Mode I and mode II stress intensity factors.
    mu, kappa : float
        Shear modulus and Kolosov constant (``Elastic.mu``, ``Elastic.kappa``).

    Returns
    -------
    ndarray, shape (n, 2)
        ``(u1, u2)`` in the tip frame.

    Examples
    --------
    >>> import numpy as np
    >>> u = williams_displacement([1.0, 1.0], [np.pi, -np.pi], 1.0, 0.0, 1.0, 1.8)
    >>> opening = u[0, 1] - u[1, 1]   # (kappa + 1) / mu * K_I * sqrt(r / (2 pi))
    >>> bool(np.isclose(opening, (1.8 + 1) * np.sqrt(1 / (2 * np.pi))))
    True
    """
    r, theta = _polar_args(r, theta)
    f = np.sqrt(r / (2.0 * np.pi)) / (2.0 * mu)
    c, s = np.cos(theta / 2), np.sin(theta / 2)
    u1 = f * (KI * c * (kappa - 1 + 2 * s**2) + KII * s * (kappa + 1 + 2 * c**2))
    u2 = f * (KI * s * (kappa + 1 - 2 * c**2) - KII * c * (kappa - 1 - 2 * s**2))
    return np.column_stack([u1, u2])


def williams_stress(r, theta, KI: float, KII: float) -> np.ndarray:
    """Near-tip stress in the tip frame, shape (n, 3) as Voigt (11, 22, 12).

    .. math::

        \\sigma_{11} &= \\frac{K_I}{\\sqrt{2\\pi r}}\\cos\\frac{\\theta}{2}
            \\left[1 - \\sin\\frac{\\theta}{2}\\sin\\frac{3\\theta}{2}\\right]
          - \\frac{K_{II}}{\\sqrt{2\\pi r}}\\sin\\frac{\\theta}{2}
            \\left[2 + \\cos\\frac{\\theta}{2}\\cos\\frac{3\\theta}{2}\\right] \\\\
        \\sigma_{22} &= \\frac{K_I}{\\sqrt{2\\pi r}}\\cos\\frac{\\theta}{2}
            \\left[1 + \\sin\\frac{\\theta}{2}\\sin\\frac{3\\theta}{2}\\right]
          + \\frac{K_{II}}{\\sqrt{2\\pi r}}\\sin\\frac{\\theta}{2}
            \\cos\\frac{\\theta}{2}\\cos\\frac{3\\theta}{2} \\\\
        \\sigma_{12} &= \\frac{K_I}{\\sqrt{2\\pi r}}\\cos\\frac{\\theta}{2}
            \\sin\\frac{\\theta}{2}\\cos\\frac{3\\theta}{2}
          + \\frac{K_{II}}{\\sqrt{2\\pi r}}\\cos\\frac{\\theta}{2}
            \\left[1 - \\sin\\frac{\\theta}{2}\\sin\\frac{3\\theta}{2}\\right]

    Williams (1957); Anderson, *Fracture Mechanics* (3rd ed.), Table 2.1. The
    stress is the same in plane strain and plane stress.

    Parameters
    ----------
    r, theta : array_like, shape (n,)
        As in :func:`williams_displacement`; ``r`` must be > 0.
    KI, KII : float
        Stress intensity factors.

    Returns
    -------
    ndarray, shape (n, 3)
        ``(s11, s22, s12)`` in the tip frame.

    Raises
    ------
    ValueError
        At ``r = 0`` (the tip), where the stress is singular; the message names
        the point's index.

    Examples
    --------
    >>> import numpy as np
    >>> s = williams_stress([2 / np.pi], [0.0], KI=1.0, KII=0.0)
    >>> s.round(12).tolist()   # sigma_11 = sigma_22 = K_I / sqrt(2 pi r) ahead of the tip
    [[0.5, 0.5, 0.0]]
    """
    r, theta = _polar_args(r, theta)
    if np.any(r == 0):
        i = int(np.argmax(r == 0))
        raise ValueError(f"point {i} is at the crack tip (r = 0), where the Williams stress "
                         "is singular; evaluate the stress away from the tip")
    g = 1.0 / np.sqrt(2.0 * np.pi * r)
    c, s = np.cos(theta / 2), np.sin(theta / 2)
    c3, s3 = np.cos(1.5 * theta), np.sin(1.5 * theta)
    s11 = g * (KI * c * (1 - s * s3) - KII * s * (2 + c * c3))
    s22 = g * (KI * c * (1 + s * s3) + KII * s * c * c3)
    s12 = g * (KI * c * s * c3 + KII * c * (1 - s * s3))
    return np.column_stack([s11, s22, s12])


def _polar_derivatives(dfdr, dfdt, theta):
    """``(df/dx1, df/dx2)`` from ``df/dr`` and ``df/dtheta / r`` (chain rule)."""
    c, s = np.cos(theta), np.sin(theta)
    return c * dfdr - s * dfdt, s * dfdr + c * dfdt


def williams_gradient(r, theta, KI: float, KII: float, mu: float, kappa: float) -> np.ndarray:
    """Displacement gradient of :func:`williams_displacement`, tip frame, shape (n, 2, 2).

    ``g[:, i, j] = du_i/dx_j``. With ``u_i = sqrt(r) U_i(theta)``,
    ``du_i/dr = u_i / (2 r)`` and ``du_i/dtheta = sqrt(r) U_i'(theta)``, and
    ``d/dx1 = cos(theta) d/dr - sin(theta)/r d/dtheta``,
    ``d/dx2 = sin(theta) d/dr + cos(theta)/r d/dtheta``. The gradient is
    ``O(r^{-1/2})``: singular at the tip (``r = 0`` is refused). Its symmetric
    part is the compliance times :func:`williams_stress` (tested).

    Parameters
    ----------
    r, theta : array_like, shape (n,)
        Polar coordinates about the tip, ``r > 0``, ``theta`` in ``[-pi, pi]``.
    KI, KII, mu, kappa : float
        As in :func:`williams_displacement`.

    Returns
    -------
    ndarray, shape (n, 2, 2)

    Examples
    --------
    >>> g = williams_gradient([1.0], [0.0], KI=1.0, KII=0.0, mu=1.0, kappa=1.8)
    >>> round(float(g[0, 0, 0]), 10)   # du1/dx1 = (kappa - 1) / (4 mu sqrt(2 pi r)) at theta = 0
    0.0797884561
    """
    r, theta = _polar_args(r, theta)
    if np.any(r == 0):
        i = int(np.argmax(r == 0))
        raise ValueError(f"point {i} is at the crack tip (r = 0), where the Williams displacement "
                         "gradient is singular; evaluate it away from the tip")
    a = 1.0 / (2.0 * mu * np.sqrt(2.0 * np.pi * r))  # sqrt(r / 2 pi) / (2 mu) / r
    c, s = np.cos(theta / 2), np.sin(theta / 2)
    # U(theta) and dU/dtheta of u = sqrt(r / 2 pi) / (2 mu) U, mode I then mode II
    U1 = KI * c * (kappa - 1 + 2 * s**2) + KII * s * (kappa + 1 + 2 * c**2)
    U2 = KI * s * (kappa + 1 - 2 * c**2) - KII * c * (kappa - 1 - 2 * s**2)
    dU1 = (KI * (-0.5 * s * (kappa - 1 + 2 * s**2) + 2 * s * c**2)
           + KII * (0.5 * c * (kappa + 1 + 2 * c**2) - 2 * c * s**2))
    dU2 = (KI * (0.5 * c * (kappa + 1 - 2 * c**2) + 2 * c * s**2)
           - KII * (-0.5 * s * (kappa - 1 - 2 * s**2) - 2 * s * c**2))
    g = np.empty((len(r), 2, 2))
    g[:, 0, 0], g[:, 0, 1] = _polar_derivatives(a * U1 / 2, a * dU1, theta)
    g[:, 1, 0], g[:, 1, 1] = _polar_derivatives(a * U2 / 2, a * dU2, theta)
    return g


def point_force_stress(r, theta, f: float) -> np.ndarray:
    """Stress of a point force ``f`` along x1 at the tip of a semi-infinite crack, (n, 3).

    .. math::

        \\sigma_{11} = -\\frac{f\\cos^3\\theta}{\\pi r},\\quad
        \\sigma_{22} = -\\frac{f\\cos\\theta\\sin^2\\theta}{\\pi r},\\quad
        \\sigma_{12} = -\\frac{f\\cos^2\\theta\\sin\\theta}{\\pi r}

    The Flamant radial field ``sigma_rr = -f cos(theta) / (pi r)``,
    ``sigma_tt = sigma_rt = 0``: the faces ``theta = +-pi`` are traction
    free and the stress on any circle balances ``f``. It is the auxiliary field
    of the T-stress interaction integral (Kim and Paulino, CMAME 192, 2003;
    Nakamura and Parks, IJSS 29, 1992). Same in plane strain and
    plane stress.

    Examples
    --------
    >>> s = point_force_stress([1.0, 1.0], [0.0, np.pi], 1.0)
    >>> (s * np.pi).round(12)[:, 0].tolist()   # sigma_11 = -f cos^3(theta) / (pi r)
    [-1.0, 1.0]
    """
    r, theta = _polar_args(r, theta)
    if np.any(r == 0):
        i = int(np.argmax(r == 0))
        raise ValueError(f"point {i} is at the point force (r = 0), where its stress is singular")
    c, s = np.cos(theta), np.sin(theta)
    srr = -f * c / (np.pi * r)
    return np.column_stack([srr * c * c, srr * s * s, srr * c * s])


def point_force_displacement(r, theta, f: float, mu: float, kappa: float,
                             d: float = 1.0) -> np.ndarray:
    """Displacement of :func:`point_force_stress`, tip frame, shape (n, 2).

    .. math::

        u_1 = -\\frac{f(\\kappa + 1)}{8\\pi\\mu}\\ln\\frac{r}{d}
              - \\frac{f}{4\\pi\\mu}\\sin^2\\theta,\\qquad
        u_2 = -\\frac{f(\\kappa - 1)}{8\\pi\\mu}\\theta
              + \\frac{f}{4\\pi\\mu}\\sin\\theta\\cos\\theta

    Kim and Paulino (CMAME 192, 2003); its strain is the compliance times
    :func:`point_force_stress` (tested). ``d`` fixes the rigid translation
    (``u_1 = 0`` at ``r = d, theta = 0``). ``u_2`` jumps across the faces.

    Examples
    --------
    >>> u = point_force_displacement([1.0], [0.0], f=1.0, mu=1.0, kappa=1.8)
    >>> bool(np.allclose(u, 0.0))
    True
    """
    r, theta = _polar_args(r, theta)
    if np.any(r == 0):
        i = int(np.argmax(r == 0))
        raise ValueError(f"point {i} is at the point force (r = 0), where its displacement "
                         "is singular")
    c, s = np.cos(theta), np.sin(theta)
    k = f / (8 * np.pi * mu)
    return np.column_stack([-k * (kappa + 1) * np.log(r / d) - 2 * k * s * s,
                            -k * (kappa - 1) * theta + 2 * k * s * c])


def point_force_gradient(r, theta, f: float, mu: float, kappa: float) -> np.ndarray:
    """Displacement gradient of :func:`point_force_displacement`, shape (n, 2, 2).

    ``g[:, i, j] = du_i/dx_j`` in the tip frame, ``O(1/r)``; with
    ``k = f / (8 pi mu r)``:
    ``u1,1 = k (4 sin^2 cos - (kappa + 1) cos)``,
    ``u1,2 = -k ((kappa + 1) sin + 4 sin cos^2)``,
    ``u2,1 = k ((kappa - 1) sin - 2 cos(2 theta) sin)``,
    ``u2,2 = k (2 cos(2 theta) cos - (kappa - 1) cos)``.

    Examples
    --------
    >>> g = point_force_gradient([1.0], [0.0], f=1.0, mu=1.0, kappa=1.8)
    >>> round(float(g[0, 0, 0] * 8 * np.pi), 12)   # -(kappa + 1) at theta = 0, r = 1
    -2.8
    """
    r, theta = _polar_args(r, theta)
    if np.any(r == 0):
        i = int(np.argmax(r == 0))
        raise ValueError(f"point {i} is at the point force (r = 0), where its displacement "
                         "gradient is singular")
    c, s, c2 = np.cos(theta), np.sin(theta), np.cos(2 * theta)
    k = f / (8 * np.pi * mu * r)
    g = np.empty((len(r), 2, 2))
    g[:, 0, 0] = k * (4 * s * s * c - (kappa + 1) * c)
    g[:, 0, 1] = -k * ((kappa + 1) * s + 4 * s * c * c)
    g[:, 1, 0] = k * ((kappa - 1) * s - 2 * c2 * s)
    g[:, 1, 1] = k * (2 * c2 * c - (kappa - 1) * c)
    return g
