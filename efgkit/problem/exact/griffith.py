"""The exact field of a Griffith crack in an infinite plate (Westergaard, 1939).

A test field for the interaction integrals with crack-face pressure and for the
mixed-mode ``inclined`` verification: K and T are known in closed form.
"""

from __future__ import annotations

import numpy as np

__all__ = ["griffith_field"]


def griffith_field(x: np.ndarray, a: float, p: float, mu: float, kappa: float,
                   loading: str = "pressure") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact field of a Griffith crack ``|x| <= a, y = 0`` in an infinite plate.

    Westergaard's solution for remote biaxial tension ``p``, with
    ``Z(z) = p z / sqrt(z^2 - a^2)``, ``Z' = -p a^2 / (z^2 - a^2)^{3/2}``,
    ``Zbar = p sqrt(z^2 - a^2)`` (Westergaard, J. Appl. Mech. 6, 1939; Anderson,
    *Fracture Mechanics*, Ch. 2 appendix). Gradient, stress and the
    compliance agree to rounding (tested):

    .. math::

        \\sigma_{xx} = \\Re Z - y\\Im Z',\\quad \\sigma_{yy} = \\Re Z + y\\Im Z',\\quad
        \\sigma_{xy} = -y\\Re Z', \\\\
        2\\mu u_x = \\tfrac{\\kappa - 1}{2}\\Re\\bar Z - y\\Im Z,\\quad
        2\\mu u_y = \\tfrac{\\kappa + 1}{2}\\Im\\bar Z - y\\Re Z.

    ``loading="remote"``: this field (faces traction free, ``K_I = p sqrt(pi a)``,
    ``T = 0``). ``loading="pressure"``: this field minus the uniform biaxial
    stress ``p`` (displacement ``(kappa - 1) p / (4 mu) x``): the faces carry a
    pressure ``p``, the plate is unloaded at infinity, ``K_I = p sqrt(pi a)`` and
    ``T = -p``. The branch of ``sqrt(z^2 - a^2)`` is cut along the crack; a
    point on the crack line takes the upper face for ``y = +0.0`` and the lower
    one for ``y = -0.0``.

    Parameters
    ----------
    x : ndarray (n, 2)
        Points, not at the tips ``(+-a, 0)``.
    a, p : float
        Half crack length (> 0) and remote tension / face pressure.
    mu, kappa : float
        Shear modulus and Kolosov constant.
    loading : {"pressure", "remote"}

    Returns
    -------
    u : ndarray (n, 2)
    grad_u : ndarray (n, 2, 2)
        ``grad_u[:, i, j] = du_i/dx_j``.
    stress : ndarray (n, 3)
        Voigt (xx, yy, xy).

    Examples
    --------
    >>> u, g, s = griffith_field(np.array([[0.0, 0.0], [0.0, -0.0]]), 1.0, 1.0, 1.0, 2.0)
    >>> float(u[0, 1] - u[1, 1])   # opening (kappa + 1) p a / (2 mu) at the centre
    1.5
    >>> s[:, 1].round(12).tolist()   # the faces carry the pressure: sigma_yy = -p
    [-1.0, -1.0]
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 2 or x.shape[1] != 2 or not np.all(np.isfinite(x)):
        raise ValueError(f"x must be finite points of shape (n, 2), got shape {x.shape}")
    if loading not in ("pressure", "remote"):
        raise ValueError(f"loading must be 'pressure' or 'remote', got {loading!r}")
    if not a > 0:
        raise ValueError(f"the half crack length a must be > 0, got {a!r}")
    z = np.empty(len(x), dtype=complex)
    z.real, z.imag = x[:, 0], x[:, 1]  # keeps the sign of a zero y: the face
    at_tip = np.abs(z * z - a * a) <= 1e-14 * a * a
    if np.any(at_tip):
        i = int(np.argmax(at_tip))
        raise ValueError(f"point {i} {x[i].tolist()} is at a crack tip, where the field is singular")
    root = np.sqrt(z - a) * np.sqrt(z + a)  # cut along [-a, a] only
    Z, dZ, Zb = p * z / root, -p * a * a / root**3, p * root
    y = x[:, 1]
    stress = np.column_stack([Z.real - y * dZ.imag, Z.real + y * dZ.imag, -y * dZ.real])
    u = np.column_stack([(kappa - 1) / 2 * Zb.real - y * Z.imag,
                         (kappa + 1) / 2 * Zb.imag - y * Z.real]) / (2 * mu)
    g = np.empty((len(x), 2, 2))
    g[:, 0, 0] = (kappa - 1) / 2 * Z.real - y * dZ.imag
    g[:, 0, 1] = -(kappa + 1) / 2 * Z.imag - y * dZ.real
    g[:, 1, 0] = (kappa + 1) / 2 * Z.imag - y * dZ.real
    g[:, 1, 1] = (kappa - 1) / 2 * Z.real + y * dZ.imag
    g /= 2 * mu
    if loading == "pressure":
        e = (kappa - 1) * p / (4 * mu)  # uniform biaxial strain of the subtracted field
        stress[:, :2] -= p
        u -= e * x
        g[:, 0, 0] -= e
        g[:, 1, 1] -= e
    return u, g, stress
