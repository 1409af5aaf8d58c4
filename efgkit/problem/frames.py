"""Crack-tip frames: polar coordinates about a tip, and rotations of vectors, Voigt
stresses and gradients between the global and a tip frame.

A tip frame has ``x1`` along the crack's last segment, pointing ahead of the tip,
and ``x2`` normal to it, at ``angle`` (radians, counter-clockwise) from the global
x axis.
"""

from __future__ import annotations

import numpy as np

__all__ = ["rotate_gradient", "rotate_vectors", "rotate_voigt", "tip_polar"]


def tip_polar(x: np.ndarray, tip, angle: float) -> tuple[np.ndarray, np.ndarray]:
    """Polar coordinates ``(r (n,), theta (n,))`` of ``x (n, 2)`` about a crack tip.

    ``theta = atan2(x2, x1)`` in the tip frame whose ``x1`` axis makes ``angle``
    (radians, counter-clockwise) with the global x axis; ``theta`` lies in
    ``[-pi, pi]`` (``-pi`` only for points on the crack line with ``x2 = -0.0``).

    Examples
    --------
    >>> import numpy as np
    >>> r, t = tip_polar(np.array([[1.0, 2.0]]), (1.0, 1.0), np.pi / 2)
    >>> round(float(r[0]), 12), round(float(t[0]), 12)   # straight ahead of the tip
    (1.0, 0.0)
    """
    d = np.asarray(x, dtype=float) - np.asarray(tip, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    x1 = c * d[:, 0] + s * d[:, 1]
    x2 = -s * d[:, 0] + c * d[:, 1]
    return np.hypot(x1, x2), np.arctan2(x2, x1)


def rotate_vectors(v: np.ndarray, angle: float) -> np.ndarray:
    """Rotate vectors ``v (n, 2)`` counter-clockwise by ``angle``: tip frame -> global.

    Examples
    --------
    >>> rotate_vectors(np.array([[1.0, 0.0]]), np.pi / 2).round(12).tolist()
    [[0.0, 1.0]]
    """
    c, s = np.cos(angle), np.sin(angle)
    return np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])


def rotate_voigt(sig: np.ndarray, angle: float) -> np.ndarray:
    """Rotate stresses ``sig (n, 3)`` Voigt (xx, yy, xy) by ``angle``: ``R sigma R^T``.

    ``R = [[cos, -sin], [sin, cos]]``, so tip-frame stresses map to global ones
    for a tip frame at ``angle``. Not for engineering-shear strains.

    Examples
    --------
    >>> rotate_voigt(np.array([[1.0, 0.0, 0.0]]), np.pi / 2).round(12).tolist()
    [[0.0, 1.0, 0.0]]
    """
    c, s = np.cos(angle), np.sin(angle)
    a, b, t = sig[:, 0], sig[:, 1], sig[:, 2]
    return np.column_stack([
        c * c * a + s * s * b - 2 * c * s * t,
        s * s * a + c * c * b + 2 * c * s * t,
        c * s * (a - b) + (c * c - s * s) * t,
    ])


def rotate_gradient(g: np.ndarray, angle: float) -> np.ndarray:
    """Rotate second-order tensors ``g (n, 2, 2)`` by ``angle``: ``R g R^T``.

    ``R = [[cos, -sin], [sin, cos]]``: a displacement gradient
    ``g[:, i, j] = du_i/dx_j`` in a tip frame at ``angle`` maps to global
    coordinates; ``rotate_gradient(g, -angle)`` maps back.

    Examples
    --------
    >>> g = np.array([[[1.0, 0.0], [0.0, 0.0]]])   # du1/dx1 = 1 in the tip frame
    >>> rotate_gradient(g, np.pi / 2).round(12).tolist()
    [[[0.0, 0.0], [0.0, 1.0]]]
    """
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]])
    return np.einsum("ik,nkl,jl->nij", R, np.asarray(g, dtype=float), R)
