"""Near-tip estimates of K: stresses along a ray and crack-opening displacements.

These are the quick checks that domain integrals are compared with.

*Stresses along a ray.* On the ray ``theta`` from the tip (tip frame), the
Williams stresses give (seed 000 Eq. 5.1 and its mode II counterpart,
Anderson, *Fracture Mechanics*, Table 2.1)

.. math::

    \\sqrt{2\\pi r}\\begin{pmatrix}\\sigma_{22}\\\\ \\sigma_{12}\\end{pmatrix} =
    \\begin{pmatrix} c(1 + s s_3) & s c c_3 \\\\ c s c_3 & c(1 - s s_3)\\end{pmatrix}
    \\begin{pmatrix}K_I\\\\ K_{II}\\end{pmatrix},

``c, s = cos, sin(theta/2)``, ``c_3, s_3 = cos, sin(3 theta/2)``, a matrix of
determinant ``cos^4(theta/2) > 0`` for ``|theta| < pi``. At ``theta = 0`` it is
the identity: ``K_I = sqrt(2 pi r) sigma_22`` (seed 000 Eq. 5.2) and
``K_II = sqrt(2 pi r) sigma_12``. At ``theta = 90 deg``,
``K_I = 2 sqrt(pi r) (sigma_22 + sigma_12)`` and
``K_II = 2 sqrt(pi r) (sigma_22 + 3 sigma_12)``; for pure mode I seed 000
Eq. 5.3 uses ``sigma_22`` alone, ``K_I = 4/3 sqrt(pi r) sigma_22``
(``assume_mode_I=True``). The T-stress (a uniform ``sigma_11``) does not
enter. Seed 000 (Sect. 5.1, Figs. 7-8) takes the average of the estimates at
the two points closest to the tip, one below and one above the true value.

*Crack-opening displacement.* Behind the tip (``theta = +-pi``) the face
displacement jump ``[u] = u(+pi) - u(-pi)`` of the Williams field is
``[u_2] = (kappa + 1) K_I sqrt(r / 2 pi) / mu`` and ``[u_1] = (kappa + 1)
K_II sqrt(r / 2 pi) / mu`` (seed 003 Eq. 60, Anderson Table 2.2), so
``K(r) = mu / (kappa + 1) sqrt(2 pi / r) [u]``; a least-squares polynomial in
``r`` through these apparent values, evaluated at ``r = 0``, removes the
``O(r)`` error of the higher Williams terms.

Seed 000's text extraction kept Eqs. 5.1-5.5 readable; the mode II and the
mixed ``theta = 90 deg`` forms above are rebuilt from the Williams stresses,
not taken from the seed.

*Dynamic SIF.* The near field of a stationary crack under dynamic load has the
static angular form, so the same estimates give the dynamic SIF (seed 000 Sect. 5.1).
For a tip moving at speed ``V > 0`` (``speed``, with the material), the matrix above
is replaced by the moving-crack one, ``sqrt(2 pi r) (sigma_22, sigma_12)`` of the
unit-``K`` fields of :mod:`efgkit.problem.exact.moving` on the ray; at ``theta = 0``
it is still the identity.
"""

from __future__ import annotations

import numpy as np

from ..problem.crack import Tip
from ..problem.exact.moving import moving_crack_fields
from ..problem.frames import rotate_vectors, rotate_voigt
from ..problem.material import Elastic, strain_from_gradient

__all__ = ["cod_sif", "fitted_near_tip_sif", "k_from_cod", "k_from_stress", "k_from_symmetric_rays",
           "near_tip_sif", "ray_points"]


def _radii(r) -> np.ndarray:
    r = np.atleast_1d(np.asarray(r, dtype=float))
    if r.ndim != 1 or len(r) == 0 or not np.all(np.isfinite(r) & (r > 0)):
        raise ValueError(f"r must be a non-empty 1-D array of finite distances > 0, got {r!r}")
    return r


def _fit_radii(r, degree) -> np.ndarray:
    """The distances ``r`` (n,) of a degree-``degree`` fit in r, checked."""
    r = _radii(r)
    if isinstance(degree, bool) or not isinstance(degree, (int, np.integer)) or degree < 0:
        raise ValueError(f"degree must be an integer >= 0, got {degree!r}")
    if len(np.unique(r)) < degree + 1:
        raise ValueError(f"a degree-{degree} fit needs at least {degree + 1} distinct distances, got "
                         f"{len(np.unique(r))}: give more points on the ray or a lower degree")
    return r


def _value_at_tip(r: np.ndarray, KI, KII, degree: int) -> tuple[float, float]:
    """Least-squares polynomials of degree ``degree`` in r through the apparent ``K_I(r)``,
    ``K_II(r)`` (n,), evaluated at r = 0."""
    V = np.vander(r, degree + 1, increasing=True)
    coef = np.linalg.lstsq(V, np.column_stack([KI, KII]), rcond=None)[0]
    return float(coef[0, 0]), float(coef[0, 1])


def _tip(tip) -> Tip:
    if not isinstance(tip, Tip):
        raise TypeError(f"tip must be an efgkit.problem.crack.Tip, got {type(tip).__name__}")
    return tip


def ray_points(tip: Tip, r, theta: float = 0.0) -> np.ndarray:
    """Global points at distances ``r (n,)`` from the tip on the ray ``theta`` (tip frame).

    ``theta = +-pi`` are the two crack faces (behind the tip).

    Examples
    --------
    >>> t = Tip(np.array([1.0, 1.0]), np.pi / 2, "c", 1)
    >>> ray_points(t, [0.5], 0.0).round(12).tolist()
    [[1.0, 1.5]]
    """
    tip, r = _tip(tip), _radii(r)
    local = np.column_stack([r * np.cos(theta), r * np.sin(theta)])
    return tip.x + rotate_vectors(local, tip.angle)


def _sample(values, x: np.ndarray, name: str, width: int) -> np.ndarray:
    """``values`` given as an array (n, width) at ``x`` or a callable ``x -> (n, width)``."""
    v = values(x) if callable(values) else values
    v = np.asarray(v, dtype=float)
    if v.shape != (len(x), width):
        raise ValueError(f"{name} must have shape ({len(x)}, {width}) (one row per point on the "
                         f"ray), got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} holds non-finite values; evaluate it away from the tip")
    return v


def _ray_matrix(theta: float, speed: float, material) -> np.ndarray:
    """``sqrt(2 pi r) (sigma_22, sigma_12)`` per unit ``(K_I, K_II)`` on the ray ``theta``, (2, 2)."""
    c, si, c3, s3 = np.cos(theta / 2), np.sin(theta / 2), np.cos(1.5 * theta), np.sin(1.5 * theta)
    if speed == 0:
        return np.array([[c * (1 + si * s3), si * c * c3], [c * si * c3, c * (1 - si * s3)]])
    if not isinstance(material, Elastic):
        raise TypeError(f"a crack speed needs the material (an Elastic), got {type(material).__name__}")
    if not (np.isfinite(speed) and 0 < speed < material.c_rayleigh):
        raise ValueError(f"speed must lie in [0, c_R) with c_R = {material.c_rayleigh!r} the Rayleigh "
                         f"speed, got {speed!r}")
    x = np.array([[np.cos(theta), np.sin(theta)]])
    g = np.stack([moving_crack_fields(x, k1, k2, speed, material.mu, material.c_dilatational,
                                      material.c_shear)[1][0] for k1, k2 in ((1.0, 0.0), (0.0, 1.0))])
    s = strain_from_gradient(g) @ material.D.T  # rows: unit K_I, unit K_II at r = 1
    return np.sqrt(2 * np.pi) * s[:, 1:].T


def k_from_stress(tip: Tip, r, stress, theta: float = 0.0, assume_mode_I: bool = False,
                  speed: float = 0.0, material: Elastic | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Apparent ``K_I (n,)``, ``K_II (n,)`` from stresses on the ray ``theta``.

    Parameters
    ----------
    tip : Tip
    r : array_like (n,)
        Distances from the tip, > 0.
    stress : ndarray (n, 3) or callable
        Global Voigt stresses at ``ray_points(tip, r, theta)``, or a callable
        ``x (n, 2) -> (n, 3)`` evaluated there.
    theta : float
        Ray angle in the tip frame, ``|theta| < pi`` (0 and ``pi / 2`` are the
        rays of seed 000 Eqs. 5.2-5.3).
    assume_mode_I : bool
        Use ``sigma_22`` alone (seed 000 Eqs. 5.2-5.3, generalised to any
        ray) and return ``K_II = 0``.
    speed : float
        Crack speed ``V``, ``0 <= V < c_R`` (module docstring); ``V > 0`` needs ``material``
        with a density.
    material : Elastic, optional

    Returns
    -------
    KI, KII : ndarray (n,)

    Examples
    --------
    >>> from efgkit.problem.exact.williams import williams_stress
    >>> t = Tip(np.zeros(2), 0.0, "c", 1)
    >>> r = np.array([0.01, 0.02])
    >>> KI, KII = k_from_stress(t, r, williams_stress(r, np.pi / 2, 3.0, -1.0), np.pi / 2)
    >>> KI.round(12).tolist(), KII.round(12).tolist()
    ([3.0, 3.0], [-1.0, -1.0])
    """
    tip, r = _tip(tip), _radii(r)
    if not (np.isfinite(theta) and abs(theta) < np.pi):
        raise ValueError(f"theta must lie in (-pi, pi) (off the crack faces), got {theta!r}")
    s = rotate_voigt(_sample(stress, ray_points(tip, r, theta), "stress", 3), -tip.angle)
    root = np.sqrt(2 * np.pi * r)
    A = _ray_matrix(theta, speed, material)
    if assume_mode_I:
        return root * s[:, 1] / A[0, 0], np.zeros(len(r))
    K = np.linalg.solve(A, root * np.vstack([s[:, 1], s[:, 2]]))  # rows: sigma_22, sigma_12
    return K[0], K[1]


def near_tip_sif(tip: Tip, r, stress, theta: float = 0.0, n_average: int = 2,
                 assume_mode_I: bool = False, speed: float = 0.0,
                 material: Elastic | None = None) -> tuple[float, float]:
    """``(K_I, K_II)``: mean of :func:`k_from_stress` at the ``n_average`` points nearest the tip.

    Seed 000 (Sect. 5.1, Fig. 8) averages the first two particles from the
    tip, whose estimates bracket the true value. Arguments as in
    :func:`k_from_stress`.

    Examples
    --------
    >>> from efgkit.problem.exact.williams import williams_stress
    >>> t = Tip(np.zeros(2), 0.0, "c", 1)
    >>> r = np.array([0.3, 0.1, 0.2])
    >>> KI, KII = near_tip_sif(t, r, williams_stress(r, 0.0, 2.0, 0.5))
    >>> round(KI, 12), round(KII, 12)
    (2.0, 0.5)
    """
    r = _radii(r)
    if isinstance(n_average, bool) or not isinstance(n_average, (int, np.integer)) or not (
            1 <= n_average <= len(r)):
        raise ValueError(f"n_average must be an integer in 1..{len(r)} (the points given), got "
                         f"{n_average!r}")
    KI, KII = k_from_stress(tip, r, stress, theta, assume_mode_I, speed, material)
    near = np.argsort(r, kind="stable")[:n_average]
    return float(np.mean(KI[near])), float(np.mean(KII[near]))


def fitted_near_tip_sif(tip: Tip, r, stress, theta: float = 0.0, degree: int = 1,
                        speed: float = 0.0, material: Elastic | None = None) -> tuple[float, float]:
    """``(K_I, K_II)`` extrapolated to the tip from :func:`k_from_stress` on the ray ``theta``.

    The apparent values ``K(r) = sqrt(2 pi r) sigma`` (``theta = 0``: seed 000 Eq. 5.2 and
    its mode II row) are the Williams series ``K + b r + ...`` (the ``r^(1/2)`` stress term
    gives ``b r``; the T-stress does not enter ``sigma_22``, ``sigma_12``): a least-squares
    polynomial of ``degree`` in ``r`` through them, evaluated at ``r = 0``, removes the
    ``O(r)`` error that the mean of the nearest points (:func:`near_tip_sif`, seed 000)
    keeps, as :func:`cod_sif` does for the opening. Under dynamic load the series holds its
    static form up to the ``r^(1/2)`` term; inertia enters at ``r^(3/2)`` (``K''(t) r^2`` in
    ``K(r)``), so the points must lie well inside the distance a wave runs while ``K``
    changes (docs/theory.md). Needs at least ``degree + 1`` distinct distances; other
    arguments as in :func:`k_from_stress`.

    Examples
    --------
    >>> from efgkit.problem.exact.williams import williams_stress
    >>> t = Tip(np.zeros(2), 0.0, "c", 1)
    >>> r = np.array([0.1, 0.2, 0.3])
    >>> s = williams_stress(r, 0.0, 2.0, 0.5) * (1 + 0.5 * r)[:, None]  # K(r) = K (1 + r / 2)
    >>> [round(k, 12) for k in fitted_near_tip_sif(t, r, s)]
    [2.0, 0.5]
    """
    r = _fit_radii(r, degree)
    return _value_at_tip(r, *k_from_stress(tip, r, stress, theta, speed=speed, material=material),
                         degree)


def k_from_symmetric_rays(tip: Tip, r, stress_plus, stress_minus,
                          theta: float = np.pi / 2) -> tuple[np.ndarray, np.ndarray]:
    """Apparent ``K_I (n,)``, ``K_II (n,)`` from the stresses on the rays ``+theta`` and ``-theta``,
    each mode fitted to its own symmetry part (stationary tip).

    The mode I stresses ``sigma_22`` and ``sigma_12`` are even and odd in ``theta``, the
    mode II ones odd and even, so the parts ``s_22 = (sigma_22(+) + sigma_22(-)) / 2``,
    ``a_12 = (sigma_12(+) - sigma_12(-)) / 2`` hold mode I alone and ``a_22``, ``s_12``
    mode II alone (the leading terms exactly). Each ``K`` is the least-squares fit of its
    two angular functions (the matrix ``A`` of the module docstring):
    ``K_I = sqrt(2 pi r) (A_11 s_22 + A_21 a_12) / (A_11^2 + A_21^2)`` and
    ``K_II = sqrt(2 pi r) (A_12 a_22 + A_22 s_12) / (A_12^2 + A_22^2)``. On the single ray
    of :func:`k_from_stress` at ``theta = 90 deg`` the coupled 2 x 2 solve passes the error
    of the shear stress (angular factor ``0.35``) into both ``K``: a pure mode I field gets
    a spurious ``K_II``. Seed 000 Eq. 5.3 is the ``sigma_22`` row of the mode I fit.

    Parameters
    ----------
    tip : Tip
    r : array_like (n,)
        Distances from the tip, > 0.
    stress_plus, stress_minus : ndarray (n, 3) or callable
        Global Voigt stresses at ``ray_points(tip, r, theta)`` and at
        ``ray_points(tip, r, -theta)`` (or callables evaluated there).
    theta : float
        ``0 < theta < pi``.

    Returns
    -------
    KI, KII : ndarray (n,)

    Examples
    --------
    >>> from efgkit.problem.exact.williams import williams_stress
    >>> t = Tip(np.zeros(2), 0.3, "c", 1)
    >>> r = np.array([0.01, 0.02])
    >>> def glob(th):  # tip-frame Williams stresses, rotated to the global frame
    ...     return rotate_voigt(williams_stress(r, th, 3.0, -1.0), t.angle)
    >>> KI, KII = k_from_symmetric_rays(t, r, glob(np.pi / 2), glob(-np.pi / 2))
    >>> KI.round(12).tolist(), KII.round(12).tolist()
    ([3.0, 3.0], [-1.0, -1.0])
    """
    tip, r = _tip(tip), _radii(r)
    if not (np.isfinite(theta) and 0 < theta < np.pi):
        raise ValueError(f"theta must lie in (0, pi) (the rays +theta and -theta), got {theta!r}")
    sp = rotate_voigt(_sample(stress_plus, ray_points(tip, r, theta), "stress_plus", 3), -tip.angle)
    sm = rotate_voigt(_sample(stress_minus, ray_points(tip, r, -theta), "stress_minus", 3),
                      -tip.angle)
    A = _ray_matrix(theta, 0.0, None)
    root = np.sqrt(2 * np.pi * r)
    s22, a22 = (sp[:, 1] + sm[:, 1]) / 2, (sp[:, 1] - sm[:, 1]) / 2
    s12, a12 = (sp[:, 2] + sm[:, 2]) / 2, (sp[:, 2] - sm[:, 2]) / 2
    KI = root * (A[0, 0] * s22 + A[1, 0] * a12) / (A[0, 0] ** 2 + A[1, 0] ** 2)
    KII = root * (A[0, 1] * a22 + A[1, 1] * s12) / (A[0, 1] ** 2 + A[1, 1] ** 2)
    return KI, KII


def k_from_cod(tip: Tip, r, upper, lower, material: Elastic) -> tuple[np.ndarray, np.ndarray]:
    """Apparent ``K_I (n,)``, ``K_II (n,)`` from the face displacement jump at ``r`` behind the tip.

    ``K = mu / (kappa + 1) sqrt(2 pi / r) [u]``, ``[u] = u(upper) - u(lower)``
    in the tip frame (module docstring).

    Parameters
    ----------
    tip : Tip
    r : array_like (n,)
        Distances behind the tip, > 0.
    upper, lower : ndarray (n, 2) or callable
        Global displacements of the upper face (``theta = +pi``, left of the
        crack seen from behind the tip) and of the lower face at
        ``ray_points(tip, r, pi)``, or callables ``x (n, 2) -> (n, 2)`` that
        return that face's displacement there (a discontinuous solution must
        be told the side, e.g. by nudging the points by ``+-delta e2``).
    material : Elastic

    Returns
    -------
    KI, KII : ndarray (n,)

    Examples
    --------
    >>> from efgkit.problem.exact.williams import williams_displacement
    >>> m = Elastic(1.0, 0.3)
    >>> t = Tip(np.zeros(2), 0.0, "c", 1)
    >>> r = np.array([0.1, 0.2])
    >>> up = williams_displacement(r, np.pi, 1.5, -0.5, m.mu, m.kappa)
    >>> lo = williams_displacement(r, -np.pi, 1.5, -0.5, m.mu, m.kappa)
    >>> [k.round(12).tolist() for k in k_from_cod(t, r, up, lo, m)]
    [[1.5, 1.5], [-0.5, -0.5]]
    """
    tip, r = _tip(tip), _radii(r)
    if not isinstance(material, Elastic):
        raise TypeError(f"material must be an Elastic, got {type(material).__name__}")
    x = ray_points(tip, r, np.pi)
    jump = _sample(upper, x, "upper", 2) - _sample(lower, x, "lower", 2)
    jump = rotate_vectors(jump, -tip.angle)
    f = material.mu / (material.kappa + 1) * np.sqrt(2 * np.pi / r)
    return f * jump[:, 1], f * jump[:, 0]


def cod_sif(tip: Tip, r, upper, lower, material: Elastic, degree: int = 1) -> tuple[float, float]:
    """``(K_I, K_II)`` extrapolated to the tip from :func:`k_from_cod`.

    A least-squares polynomial of ``degree`` in ``r`` is fitted to the
    apparent values and evaluated at ``r = 0`` (``degree = 0``: their mean).
    Needs at least ``degree + 1`` distinct distances. Arguments as in
    :func:`k_from_cod`.

    Examples
    --------
    >>> m = Elastic(1.0, 0.3)
    >>> t = Tip(np.zeros(2), 0.0, "c", 1)
    >>> r = np.array([0.1, 0.2, 0.3])
    >>> f = (m.kappa + 1) / m.mu * np.sqrt(r / (2 * np.pi)) * (2.0 + 0.5 * r)  # K(r) = 2 + r / 2
    >>> up = np.column_stack([np.zeros(3), f / 2]); lo = -up
    >>> [round(k, 12) for k in cod_sif(t, r, up, lo, m)]
    [2.0, 0.0]
    """
    r = _fit_radii(r, degree)
    return _value_at_tip(r, *k_from_cod(tip, r, upper, lower, material), degree)

