"""Near-tip fields of a crack moving steadily at speed V (Freund, *Dynamic Fracture
Mechanics*, 1990, Sect. 4.3; Anderson, *Fracture Mechanics*, Sect. 4.1.3).

In the moving tip frame (``x1`` ahead, ``x2`` normal), with ``beta_1 = sqrt(1 - V^2 / c_d^2)``,
``beta_2 = sqrt(1 - V^2 / c_s^2)``, ``z_j = x1 + i beta_j x2`` (branch cut on the crack
faces, ``arg z_j = +-pi`` there), ``a = 1 + beta_2^2`` and
``D = 4 beta_1 beta_2 - a^2`` (seed 002 Eq. 34):

.. math::

    u_1 &= \\frac{\\sqrt{2/\\pi}}{\\mu D}\\Big(K_I\\,\\mathrm{Re}[a\\sqrt{z_1}
           - 2\\beta_1\\beta_2\\sqrt{z_2}]
         + K_{II}\\,\\mathrm{Im}[2\\beta_2\\sqrt{z_1} - a\\beta_2\\sqrt{z_2}]\\Big),\\\\
    u_2 &= \\frac{\\sqrt{2/\\pi}}{\\mu D}\\Big(K_I\\,\\mathrm{Im}[-a\\beta_1\\sqrt{z_1}
           + 2\\beta_1\\sqrt{z_2}]
         + K_{II}\\,\\mathrm{Re}[2\\beta_1\\beta_2\\sqrt{z_1} - a\\sqrt{z_2}]\\Big).

Each ``sqrt(z_j)`` term solves the steady-state wave equation of its wave speed, so the
field satisfies ``sigma_ij,j = rho u''_i`` with ``u(x1 - V t, x2)``: ``u'_i = -V u_i,1`` and
``u''_i = V^2 u_i,11``; the faces are traction-free, ``sigma_22 = K_I / sqrt(2 pi r)`` and
``sigma_12 = K_II / sqrt(2 pi r)`` ahead of the tip, and ``V -> 0`` gives the Williams field
(all checked in ``tests/test_dynamic_sif.py``). Derivatives are exact: ``d sqrt(z_j) / dx1
= 1 / (2 sqrt(z_j))``, ``d / dx2 = i beta_j / (2 sqrt(z_j))``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["moving_crack_fields"]


def moving_crack_fields(x, KI: float, KII: float, speed: float, mu: float, c_d: float,
                        c_s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Displacement, its gradient and its second derivatives for a steadily moving crack.

    Parameters
    ----------
    x : ndarray (n, 2)
        Tip-frame points, not at the tip (a point on the crack line behind the tip lies
        on the upper face for ``x2 = +0.0`` and on the lower one for ``-0.0``).
    KI, KII : float
        Dynamic stress intensity factors.
    speed : float
        ``0 < V < c_R`` (the Rayleigh speed of ``c_d``, ``c_s``).
    mu, c_d, c_s : float
        Shear modulus and the wave speeds of the 2D idealisation.

    Returns
    -------
    u : ndarray (n, 2)
    grad : ndarray (n, 2, 2)
        ``du_i/dx_j``.
    hess : ndarray (n, 2, 2, 2)
        ``d^2 u_i / dx_j dx_k``.

    Examples
    --------
    >>> u, g, h = moving_crack_fields(np.array([[1.0, 0.0]]), 1.0, 0.0, 0.5, 1.0, 1.9, 1.0)
    >>> bool(abs(g[0, 1, 0]) < 1e-15)                            # u_2 = 0 ahead of a mode I tip
    True
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"x must have shape (n, 2), got {x.shape}")
    if not (0 < speed < c_s < c_d):
        raise ValueError(f"need 0 < speed < c_s < c_d, got speed = {speed!r}, c_s = {c_s!r}, "
                         f"c_d = {c_d!r}")
    beta = np.array([np.sqrt(1 - (speed / c_d) ** 2), np.sqrt(1 - (speed / c_s) ** 2)])
    a = 1 + beta[1] ** 2
    D = 4 * beta[0] * beta[1] - a**2
    if not D > 0:
        raise ValueError(f"speed = {speed!r} is not below the Rayleigh speed (D = {D!r} <= 0)")
    b1, b2 = beta
    # u_i = Re[sum_j C[i, j] sqrt(z_j)]; Im[w] = Re[-i w]
    C = np.array([[KI * a - 2j * KII * b2, -2 * KI * b1 * b2 + 1j * KII * a * b2],
                  [1j * KI * a * b1 + 2 * KII * b1 * b2, -2j * KI * b1 - KII * a]])
    C *= np.sqrt(2 / np.pi) / (mu * D)
    z = np.empty((len(x), 2), dtype=complex)  # (n, 2 waves); keeps the sign of x2 = -0.0
    z.real, z.imag = x[:, 0, None], beta[None, :] * x[:, 1, None]
    root = np.sqrt(z)
    p = np.stack([np.ones(2), 1j * beta], axis=-1)  # (wave, direction): d/dx_k factor
    F = 0.5 / root  # d sqrt(z) / dz
    H = -0.25 / (root * z)  # d^2 sqrt(z) / dz^2
    u = np.einsum("ij,nj->ni", C, root).real
    grad = np.einsum("ij,jk,nj->nik", C, p, F).real
    hess = np.einsum("ij,jk,jl,nj->nikl", C, p, p, H).real
    return u, grad, hess
