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


def gaussian(s: np.ndarray, beta: float) -> tuple[np.ndarray, np.ndarray]:
    """Truncated Gaussian, seed 003 Eq. (1a) with beta = d_max / alpha = d_m / c.

    w = (exp(-(beta s)^2) - exp(-beta^2)) / (1 - exp(-beta^2)) for s <= 1.
    """
    inside = s < 1.0
    e = np.exp(-((beta * np.where(inside, s, 1.0)) ** 2))
    eb = np.exp(-(beta**2))
    w = np.where(inside, (e - eb) / (1.0 - eb), 0.0)
    g = np.where(inside, -2.0 * beta**2 * e / (1.0 - eb), 0.0)
    return w, g


def weight_function(name: str, d_max: float = 2.0, alpha: float = 0.5):
    """The weight ``s -> (w, w'/s)`` called ``name`` ("quartic", "cubic", "gaussian")."""
    if name == "quartic":
        return quartic
    if name == "cubic":
        return cubic
    if name == "gaussian":
        beta = d_max / alpha
        return lambda s: gaussian(s, beta)
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
