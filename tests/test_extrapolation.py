"""Near-tip estimates of K from stresses on rays and from crack-opening displacements."""

import math

import numpy as np
import pytest

from efgkit.fracture.extrapolation import (
    cod_sif,
    fitted_near_tip_sif,
    k_from_cod,
    k_from_stress,
    near_tip_sif,
    ray_points,
)
from efgkit.problem.crack import Tip
from efgkit.problem.exact.griffith import griffith_field
from efgkit.problem.exact.williams import williams_displacement, williams_stress
from efgkit.problem.frames import rotate_vectors, rotate_voigt, tip_polar
from efgkit.problem.material import Elastic

KI, KII, T = 1.3, -0.6, 0.45
M = Elastic(7.0, 0.3)
TIP = Tip(np.array([2.0, -1.0]), 0.8, "c", 1)


def williams_global(x, tip=TIP, KI=KI, KII=KII, T=T):
    """Global stress (n, 3) of Williams K_I, K_II plus sigma_11 = T about ``tip``."""
    r, th = tip_polar(x, tip.x, tip.angle)
    s = williams_stress(r, th, KI, KII)
    s[:, 0] += T
    return rotate_voigt(s, tip.angle)


def williams_face(sign, tip=TIP):
    """Callable: global displacement of the upper (+1) or lower (-1) face of the Williams field."""
    def u(x):
        r, _ = tip_polar(x, tip.x, tip.angle)
        return rotate_vectors(williams_displacement(r, sign * np.pi, KI, KII, M.mu, M.kappa), tip.angle)
    return u


def test_ray_points():
    x = ray_points(TIP, [0.5, 1.0], np.pi / 2)
    r, th = tip_polar(x, TIP.x, TIP.angle)
    assert np.allclose(r, [0.5, 1.0]) and np.allclose(th, np.pi / 2)


@pytest.mark.parametrize("theta", [0.0, np.pi / 2, -np.pi / 2, 2.5, -3.0])
def test_exact_williams_on_any_ray(theta):
    r = np.array([0.3, 0.01, 0.1])
    KIr, KIIr = k_from_stress(TIP, r, williams_global, theta)  # callable ...
    assert np.allclose(KIr, KI, rtol=1e-12) and np.allclose(KIIr, KII, rtol=1e-12)
    arr = williams_global(ray_points(TIP, r, theta))  # ... or array: the same
    assert np.allclose(k_from_stress(TIP, r, arr, theta), (KIr, KIIr), rtol=1e-14)
    assert near_tip_sif(TIP, r, williams_global, theta) == pytest.approx((KI, KII), rel=1e-12)


def test_seed_000_closed_forms():
    r = np.array([0.02, 0.05])
    tip = Tip(np.zeros(2), 0.0, "c", 1)
    s0 = williams_stress(r, 0.0, KI, 0.0)
    s90 = williams_stress(r, np.pi / 2, KI, 0.0)
    # seed 000 Eq. 5.2: K_I = sqrt(2 pi r) sigma_22(r, 0)
    assert np.allclose(k_from_stress(tip, r, s0, 0.0, assume_mode_I=True)[0],
                       np.sqrt(2 * np.pi * r) * s0[:, 1], rtol=1e-14)
    # seed 000 Eq. 5.3: K_I = 4/3 sqrt(pi r) sigma_22(r, 90 deg)
    assert np.allclose(k_from_stress(tip, r, s90, np.pi / 2, assume_mode_I=True)[0],
                       4 / 3 * np.sqrt(np.pi * r) * s90[:, 1], rtol=1e-14)
    # mixed mode at 90 deg (rebuilt from the Williams stresses, module docstring)
    s = williams_stress(r, np.pi / 2, KI, KII)
    KIr, KIIr = k_from_stress(tip, r, s, np.pi / 2)
    assert np.allclose(KIr, 2 * np.sqrt(np.pi * r) * (s[:, 1] + s[:, 2]), rtol=1e-13)
    assert np.allclose(KIIr, 2 * np.sqrt(np.pi * r) * (s[:, 1] + 3 * s[:, 2]), rtol=1e-13)


def test_averaging_takes_the_two_points_nearest_the_tip():
    tip = Tip(np.zeros(2), 0.0, "c", 1)
    r = np.array([0.4, 0.1, 0.3, 0.2])
    s = williams_stress(r, 0.0, 1.0, 0.0) * (1 + r)[:, None]  # apparent K = 1 + r
    assert near_tip_sif(tip, r, s) == pytest.approx((1.15, 0.0))  # mean of 1.1 and 1.2
    assert near_tip_sif(tip, r, s, n_average=1) == pytest.approx((1.1, 0.0))


@pytest.mark.parametrize("theta, rate", [(0.0, 1.0), (np.pi / 2, 2.0)])
def test_griffith_near_tip_estimate_converges(theta, rate):
    """Remote tension of a Griffith crack: the r^(1/2) Williams term makes the error O(r) on
    theta = 0; on theta = 90 deg the mixed-mode solve happens to cancel it (measured O(r^2))."""
    a, p = 1.0, 2.0
    K = p * math.sqrt(math.pi * a)  # Westergaard: K_I = p sqrt(pi a)
    tip = Tip(np.array([a, 0.0]), 0.0, "g", 1)
    err = []
    for h in (0.04, 0.01, 0.0025):
        st = lambda x: griffith_field(x, a, p, M.mu, M.kappa, loading="remote")[2]  # noqa: E731
        err.append(abs(near_tip_sif(tip, h * np.arange(1, 6), st, theta)[0] / K - 1))
    slopes = np.diff(np.log(err)) / np.log(0.25)
    assert np.all(slopes > 0.9 * rate), slopes  # measured: 0.99-1.00 (theta = 0), 2.0-2.05 (90)
    assert err[-1] < 5e-3  # measured 2.8e-3 (theta = 0), 2.5e-6 (90 deg) at h = a / 400


def test_fitted_near_tip_estimate_griffith():
    """Remote tension of a Griffith crack (Westergaard, K_I = p sqrt(pi a)) on theta = 0:
    the line K + b r through r = h..4h removes the O(r) error the mean of the two nearest
    points keeps; exact for the pure Williams field (the T-stress does not enter)."""
    r = np.array([0.1, 0.2, 0.3])
    assert fitted_near_tip_sif(TIP, r, williams_global) == pytest.approx((KI, KII), rel=1e-12)
    a, p = 1.0, 2.0
    K = p * math.sqrt(math.pi * a)
    tip = Tip(np.array([a, 0.0]), 0.0, "g", 1)
    st = lambda x: griffith_field(x, a, p, M.mu, M.kappa, loading="remote")[2]  # noqa: E731
    h = 0.01
    nearest = near_tip_sif(tip, h * np.arange(1, 7), st)[0] / K - 1
    fit = fitted_near_tip_sif(tip, h * np.arange(1.0, 4.01, 0.25), st)[0] / K - 1
    # closed form of K(r) / K - 1 at small r: 3 r / 4 a, 1.1e-2 at the mean's r = 1.5 h
    assert nearest == pytest.approx(0.75 * 1.5 * h / a, rel=0.05)
    assert abs(fit) < 2.5e-4, (nearest, fit)  # the O(r^2) remainder: measured 8.2e-5


def test_cod_exact_for_williams():
    r = np.array([0.05, 0.1, 0.2])
    KIr, KIIr = k_from_cod(TIP, r, williams_face(1), williams_face(-1), M)
    assert np.allclose(KIr, KI, rtol=1e-12) and np.allclose(KIIr, KII, rtol=1e-12)
    up = williams_face(1)(ray_points(TIP, r, np.pi))
    lo = williams_face(-1)(ray_points(TIP, r, np.pi))
    for deg in (0, 1, 2):
        assert cod_sif(TIP, r, up, lo, M, degree=deg) == pytest.approx((KI, KII), rel=1e-10)


@pytest.mark.parametrize("degree, bound", [(1, 1e-3), (2, 3e-5)])
def test_cod_extrapolation_griffith(degree, bound):
    """Pressurised Griffith crack: K(r) = p sqrt(pi a) sqrt(1 - r / 2a); the fit removes O(r)."""
    a, p = 1.0, 2.0
    K = p * math.sqrt(math.pi * a)
    angle, centre = 0.6, np.array([1.0, 3.0])
    tip = Tip(centre + a * np.array([math.cos(angle), math.sin(angle)]), angle, "g", 1)

    def face(sign):
        def u(x):
            local = rotate_vectors(x - centre, -angle)
            local[:, 1] = sign * 0.0  # on the crack line, on the asked face
            return rotate_vectors(griffith_field(local, a, p, M.mu, M.kappa)[0], angle)
        return u

    r = 0.05 * np.arange(1, 6)
    KIr, KIIr = cod_sif(tip, r, face(1.0), face(-1.0), M, degree=degree)
    # measured: 6.0e-4 (degree 1), 1.9e-5 (degree 2); the mean (degree 0) is off by 3.8%
    assert abs(KIr / K - 1) < bound and abs(KIIr) < 1e-10 * K


def test_bad_input():
    r = np.array([0.1, 0.2])
    with pytest.raises(ValueError, match=r"theta must lie in \(-pi, pi\)"):
        k_from_stress(TIP, r, williams_global, np.pi)
    with pytest.raises(ValueError, match=r"stress must have shape \(2, 3\)"):
        k_from_stress(TIP, r, np.zeros((3, 3)))
    with pytest.raises(ValueError, match="non-finite"):
        k_from_stress(TIP, r, np.full((2, 3), np.nan))
    with pytest.raises(ValueError, match="finite distances > 0"):
        k_from_stress(TIP, [0.0, 0.1], williams_global)
    with pytest.raises(ValueError, match=r"n_average must be an integer in 1..2"):
        near_tip_sif(TIP, r, williams_global, n_average=3)
    with pytest.raises(TypeError, match="tip must be an efgkit.problem.crack.Tip"):
        ray_points((0.0, 0.0), r)
    with pytest.raises(ValueError, match="degree-2 fit needs at least 3 distinct"):
        cod_sif(TIP, r, williams_face(1), williams_face(-1), M, degree=2)
    with pytest.raises(ValueError, match="degree-2 fit needs at least 3 distinct distances"):
        fitted_near_tip_sif(TIP, r, williams_global, degree=2)
    with pytest.raises(ValueError, match="degree must be an integer >= 0"):
        fitted_near_tip_sif(TIP, r, williams_global, degree=-1)
    with pytest.raises(ValueError, match=r"upper must have shape \(2, 2\)"):
        k_from_cod(TIP, r, np.zeros((2, 3)), np.zeros((2, 2)), M)
    with pytest.raises(TypeError, match="material must be an Elastic"):
        k_from_cod(TIP, r, williams_face(1), williams_face(-1), None)


def test_symmetric_rays_separate_the_modes():
    # Williams K_I = 2, K_II = -0.5 (exact by construction) plus a perturbation with the
    # mode I symmetry (sigma_22 even, sigma_12 odd in theta, growing like r^(1/2), as the
    # higher mode I terms): the single-ray 2 x 2 solve at 90 deg passes it into K_II, the
    # symmetry parts keep it in K_I alone
    from efgkit.fracture.extrapolation import k_from_symmetric_rays
    from efgkit.problem.exact.williams import williams_stress

    t = Tip(np.zeros(2), 0.0, "c", 1)
    r = np.array([0.01, 0.02, 0.04])

    def field(th):  # a mode I perturbation: even sigma_22, odd sigma_12, growing like r^(1/2)
        s = williams_stress(r, th, 2.0, -0.5)
        s[:, 1] += 3.0 * np.sqrt(r) * np.cos(th)
        s[:, 2] += 3.0 * np.sqrt(r) * np.sin(th)
        return s

    KI, KII = k_from_symmetric_rays(t, r, field(np.pi / 2), field(-np.pi / 2))
    assert np.allclose(KII, -0.5, rtol=0, atol=1e-12)
    _, KII_single = k_from_stress(t, r, field(np.pi / 2), np.pi / 2)
    assert np.abs(KII_single + 0.5).max() > 0.1  # the single ray leaks mode I into K_II
    exact = williams_stress(r, np.pi / 2, 2.0, -0.5)
    KI0, _ = k_from_symmetric_rays(t, r, exact, williams_stress(r, -np.pi / 2, 2.0, -0.5))
    assert np.allclose(KI0, 2.0, rtol=1e-12)


@pytest.mark.parametrize("theta, shape, match", [
    (0.0, (3, 3), r"theta must lie in \(0, pi\)"),
    (np.pi, (3, 3), r"theta must lie in \(0, pi\)"),
    (np.pi / 2, (2, 3), r"stress_plus must have shape \(3, 3\)"),
])
def test_symmetric_rays_errors(theta, shape, match):
    from efgkit.fracture.extrapolation import k_from_symmetric_rays

    t = Tip(np.zeros(2), 0.0, "c", 1)
    with pytest.raises(ValueError, match=match):
        k_from_symmetric_rays(t, [0.1, 0.2, 0.3], np.zeros(shape), np.zeros((3, 3)), theta)
