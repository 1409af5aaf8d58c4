"""The exact field of an inclined Griffith crack under remote uniaxial tension.

A crack of length 2a through the origin at the angle beta to the x axis, remote tension
sigma along y. In the crack frame the remote stress is sigma'_11 = sigma sin^2 beta,
sigma'_22 = sigma cos^2 beta, sigma'_12 = sigma sin beta cos beta, and the field is the sum
of the mode-I Westergaard field of remote biaxial tension sigma'_22
(:func:`~efgkit.problem.exact.griffith.griffith_field`), the uniform stress
sigma'_11 - sigma'_22 along the crack and the mode-II Westergaard field of remote shear
sigma'_12 (:func:`mode_ii_field`). At both tips (Tada, Paris & Irwin, *The Stress Analysis
of Cracks Handbook*, 3rd ed., p. 5.11)::

    K_I = sigma sqrt(pi a) cos^2 beta,  K_II = sigma sqrt(pi a) sin beta cos beta,
    T = -sigma cos(2 beta)
"""

from __future__ import annotations

import math

import numpy as np

from ..material import Elastic
from .griffith import griffith_field

__all__ = ["inclined_field", "mode_ii_field"]


def mode_ii_field(x: np.ndarray, a: float, tau: float, mu: float, kappa: float):
    """Westergaard's mode-II field of a crack |x| <= a, y = 0 under remote shear ``tau``.

    ``Z = tau z / sqrt(z^2 - a^2)``, ``Zbar = tau sqrt(z^2 - a^2)``:
    sigma_xx = 2 Im Z + y Re Z', sigma_yy = -y Re Z', sigma_xy = Re Z - y Im Z',
    2 mu u_x = (kappa + 1)/2 Im Zbar + y Re Z, 2 mu u_y = -(kappa - 1)/2 Re Zbar - y Im Z
    (Westergaard 1939; Anderson, Fracture Mechanics, 3rd ed., Appendix 2); K_II = tau sqrt(pi a).
    The gradient is checked against finite differences and Hooke's law by
    ``verification/inclined.py``.

    Returns u (n, 2), grad_u (n, 2, 2) (``[:, i, j] = du_i/dx_j``), stress (n, 3).
    """
    z = x[:, 0] + 1j * x[:, 1]
    root = np.sqrt(z - a) * np.sqrt(z + a)  # cut along [-a, a] only
    Z, dZ, Zb = tau * z / root, -tau * a * a / root**3, tau * root
    y = x[:, 1]
    s = np.column_stack([2 * Z.imag + y * dZ.real, -y * dZ.real, Z.real - y * dZ.imag])
    u = np.column_stack([(kappa + 1) / 2 * Zb.imag + y * Z.real,
                         -(kappa - 1) / 2 * Zb.real - y * Z.imag]) / (2 * mu)
    g = np.empty((len(x), 2, 2))
    g[:, 0, 0] = (kappa + 1) / 2 * Z.imag + y * dZ.real
    g[:, 0, 1] = (kappa + 3) / 2 * Z.real - y * dZ.imag
    g[:, 1, 0] = -(kappa - 1) / 2 * Z.real - y * dZ.imag
    g[:, 1, 1] = (kappa - 3) / 2 * Z.imag - y * dZ.real
    return u, g / (2 * mu), s


def inclined_field(x: np.ndarray, beta: float, a: float, sigma: float, material: Elastic):
    """Displacement (n, 2), gradient (n, 2, 2) and stress (n, 3), global axes, at ``x (n, 2)``.

    Examples
    --------
    >>> m = Elastic(1.0, 0.3, "strain")
    >>> s = inclined_field(np.array([[3e5, 4e5]]), 0.3, 1.0, 1.0, m)[2]   # remote: (0, 1, 0)
    >>> bool(np.allclose(s, [[0.0, 1.0, 0.0]], atol=1e-4))
    True
    """
    c, s = math.cos(beta), math.sin(beta)
    R = np.array([[c, s], [-s, c]])  # rows: the crack frame's axes
    xl = x @ R.T
    s11, s22, s12 = sigma * s * s, sigma * c * c, sigma * s * c
    u1, g1, t1 = griffith_field(xl, a, s22, material.mu, material.kappa, "remote")
    u2, g2, t2 = mode_ii_field(xl, a, s12, material.mu, material.kappa)
    e = material.compliance() @ np.array([s11 - s22, 0.0, 0.0])  # the uniform stress along the crack
    G3 = np.array([[e[0], e[2] / 2], [e[2] / 2, e[1]]])
    u = u1 + u2 + xl @ G3.T
    g = g1 + g2 + G3
    t = t1 + t2 + np.array([s11 - s22, 0.0, 0.0])
    S = np.stack([np.column_stack([t[:, 0], t[:, 2]]), np.column_stack([t[:, 2], t[:, 1]])], axis=1)
    Sg = np.einsum("ki,nkl,lj->nij", R, S, R)
    return u @ R, np.einsum("ki,nkl,lj->nij", R, g, R), np.column_stack([Sg[:, 0, 0], Sg[:, 1, 1],
                                                                           Sg[:, 0, 1]])
