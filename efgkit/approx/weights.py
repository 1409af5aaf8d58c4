"""MLS weight functions of the normalised distance s = d / d_m.

Each function returns ``(w, g)`` with ``w(s)`` and ``g(s) = w'(s) / s``, the
form in which the gradient stays finite at s = 0:
``dw/dx = g(s) (x - x_I) / d_m**2`` (seed 003 Eqs. 1a-b).
"""

from __future__ import annotations

import numpy as np

__all__ = ["weight_function", "pair_weights", "quartic", "cubic", "gaussian"]


def quartic(s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quartic spline, seed 003 Eq. (1b): w = 1 - 6 s^2 + 8 s^3 - 3 s^4 for s <= 1.

    Examples
    --------
    >>> w, g = quartic(np.array([0.0, 0.5, 1.0]))
    >>> w.tolist(), g.tolist()
    ([1.0, 0.3125, 0.0], [-12.0, -3.0, 0.0])
    """
    inside = s < 1.0
    sc = np.where(inside, s, 1.0)
    w = np.where(inside, 1.0 + sc * sc * (-6.0 + sc * (8.0 - 3.0 * sc)), 0.0)
    g = np.where(inside, -12.0 + sc * (24.0 - 12.0 * sc), 0.0)
    return w, g


def cubic(s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cubic spline: 2/3 - 4 s^2 + 4 s^3 (s <= 1/2), 4/3 (1 - s)^3 (1/2 < s <= 1)."""
    inside = s < 1.0
    sc = np.where(inside, s, 1.0)
    near = sc <= 0.5
    w = np.where(near, 2 / 3 - 4 * sc**2 + 4 * sc**3, 4 / 3 * (1 - sc) ** 3)
    # w'/s: (-8 s + 12 s^2)/s = -8 + 12 s ; -4 (1 - s)^2 / s (s > 1/2, no singularity).
    g = np.where(near, -8.0 + 12.0 * sc, -4.0 * (1 - sc) ** 2 / np.maximum(sc, 0.5))
    return np.where(inside, w, 0.0), np.where(inside, g, 0.0)


def gaussian(s: np.ndarray, beta: float, k: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Truncated Gaussian of exponent k: seed 003 Eq. (1a) (k = 1) and seed 002 Eq. (7).

    With beta = d_m / c (EFG: d_max / alpha; MLPG: r_I / c_I = 1 / 0.365),

        w = (exp(-(beta s)^(2k)) - exp(-beta^(2k))) / (1 - exp(-beta^(2k)))   for s <= 1,

    so w(0) = 1 and w(1) = 0 with w'(1) = -2k beta^(2k) e^(-beta^(2k)) / (1 - e^(-beta^(2k))),
    tiny (8e-23 for the seed 002 choice beta = 1 / 0.365, k = 2; 4e-6 for EFG's default
    beta = 4, k = 1). Seed 002 Eq. (7) prints the
    denominator exponent as 2: it must be 2k for w(0) = 1 (the normalisation of Eq. 7 is
    1 - w_unnormalised(r_I)); we use 2k. ``g = w'(s) / s = -2k beta^(2k) s^(2k-2) e / (1 - eb)``.
    k = 1 evaluates exactly the expressions of the k = 1 rule (bit-identical to before).

    Examples
    --------
    >>> w, g = gaussian(np.array([0.0, 1.0]), 1 / 0.365, k=2)
    >>> w.tolist()
    [1.0, 0.0]
    """
    inside = s < 1.0
    sc = np.where(inside, s, 1.0)
    if k == 1:
        e = np.exp(-((beta * sc) ** 2))
        eb = np.exp(-(beta**2))
        w = np.where(inside, (e - eb) / (1.0 - eb), 0.0)
        g = np.where(inside, -2.0 * beta**2 * e / (1.0 - eb), 0.0)
        return w, g
    b2k = beta ** (2 * k)
    e = np.exp(-b2k * sc ** (2 * k))
    eb = np.exp(-b2k)
    w = np.where(inside, (e - eb) / (1.0 - eb), 0.0)
    g = np.where(inside, -2.0 * k * b2k * sc ** (2 * k - 2) * e / (1.0 - eb), 0.0)
    return w, g


def weight_function(name: str, d_max: float = 2.0, alpha: float = 0.5, k: int = 1):
    """The weight ``s -> (w, w'/s)`` called ``name`` ("quartic", "cubic", "gaussian");
    the Gaussian has beta = d_max / alpha and exponent ``k`` (:func:`gaussian`)."""
    if name == "quartic":
        return quartic
    if name == "cubic":
        return cubic
    if name == "gaussian":
        beta = d_max / alpha
        if k == 1:
            return lambda s: gaussian(s, beta)
        return lambda s: gaussian(s, beta, k)
    raise ValueError(f"weight must be one of ('quartic', 'gaussian', 'cubic'), got {name!r}")


def pair_weights(x: np.ndarray, nodes, nb, wfun, derivatives: bool = True):
    """Weights of the (point, neighbour) pairs from the distances.

    ``x (n, 2)``, ``nb`` padded neighbours (n, k); returns ``w (n, k)`` and
    ``dw (n, k, 2)`` with ``dw/dx = g(s) (x - x_I) / d_mI^2`` (None without
    derivatives), 0 where masked.
    """
    X = nodes.x[nb.idx] - x[:, None, :]  # x_I - x, (n, k, 2)
    r = nodes.radius[nb.idx]
    w, g = wfun(np.sqrt((X**2).sum(-1)) / r)
    w = np.where(nb.mask, w, 0.0)
    if not derivatives:
        return w, None
    return w, np.where(nb.mask[..., None], -g[..., None] * X / (r**2)[..., None], 0.0)
