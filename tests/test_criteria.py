"""Growth criteria: maximum hoop stress kink angle, closure, K_Ic load factor, Paris law."""

import math

import mpmath
import numpy as np
import pytest

from efgkit.fracture.criteria import (
    critical_load_factor,
    delta_k,
    hoop_stress,
    kink_angle,
    paris_cycles,
    paris_life,
    paris_rate,
)

RATIOS = [0.0, 1e-12, 0.1, 0.5, 1.0, 5.0]


def textbook(ratio: float) -> float:
    """Erdogan-Sih theta_c = 2 atan((K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)) with K_I = 1,
    in 50-digit arithmetic (mpmath; the cancellation is harmless there)."""
    mpmath.mp.dps = 50
    if ratio == 0:
        return 0.0
    r = mpmath.mpf(ratio)
    return float(2 * mpmath.atan((1 - mpmath.sqrt(1 + 8 * r * r)) / (4 * r)))


@pytest.mark.parametrize("ratio", RATIOS)
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_kink_angle_against_textbook_form(ratio, sign):
    got = float(kink_angle(2.5, sign * ratio * 2.5))
    assert abs(got - sign * textbook(ratio)) <= 1e-15 * max(1.0, abs(got))
    assert math.isfinite(got)


def test_kink_angle_small_ratio_is_linear():
    # series of the exact root: theta = -2 r + O(r^3) for r = K_II / K_I
    r = np.array([1e-12, 1e-9, 1e-6])
    np.testing.assert_allclose(kink_angle(np.ones(3), r), -2 * r, rtol=1e-11)


def test_pure_mode_two():
    # pure mode II: theta_c = -/+ acos(1/3) = -/+ 70.5288 degrees (Erdogan and Sih 1963)
    h = hoop_stress([0.0, 0.0], [1.0, -1.0])
    np.testing.assert_allclose(h.angle, [-math.acos(1 / 3), math.acos(1 / 3)], rtol=1e-15)
    np.testing.assert_allclose(h.K_eq, 2 / math.sqrt(3), rtol=1e-15)  # sigma_tt max = 2/sqrt(3) K_II
    assert not h.closed.any()


def test_angle_is_the_hoop_stress_maximum():
    # the hoop stress cos(t/2) [K_I cos^2(t/2) - 1.5 K_II sin t] sampled on a fine grid
    t = np.linspace(-math.pi + 1e-6, math.pi - 1e-6, 400001)
    for ki, kii in [(1.0, 0.3), (1.0, -2.0), (0.2, 1.0)]:
        s = np.cos(t / 2) * (ki * np.cos(t / 2) ** 2 - 1.5 * kii * np.sin(t))
        h = hoop_stress(ki, kii)
        assert abs(h.angle[0] - t[np.argmax(s)]) < 2e-5
        assert abs(h.K_eq[0] - s.max()) < 1e-9


def test_closure():
    h = hoop_stress([-1.0, 0.0, 1e-300], [0.3, 0.0, 0.0])
    assert h.closed.tolist() == [True, True, False]
    assert h.angle[:2].tolist() == [0.0, 0.0] and h.K_eq[:2].tolist() == [0.0, 0.0]
    with pytest.raises(ValueError, match="KI must be >= 0.*closes the crack"):
        kink_angle(-1.0, 0.0)
    with pytest.raises(ValueError, match="KII must be finite"):
        hoop_stress(1.0, math.nan)


def test_critical_load_factor():
    assert critical_load_factor([1.0, 0.0, 4.0], 2.0) == 0.5  # K_Ic / max K_eq
    with pytest.raises(ValueError, match="every tip is closed"):
        critical_load_factor([0.0, 0.0], 1.0)
    with pytest.raises(ValueError, match="K_Ic must be a finite number > 0"):
        critical_load_factor([1.0], -1.0)


def test_paris_rate_threshold_and_ratio():
    dK = delta_k([10.0, -3.0], R=0.5)
    assert dK.tolist() == [5.0, 0.0]  # (1 - R) K_max; closed gives 0
    rate = paris_rate([1.0, 2.0, 3.0], C=2.0, m=3.0, dK_th=2.0)
    assert rate.tolist() == [0.0, 0.0, 54.0]  # no growth at or below the threshold, never < 0
    with pytest.raises(ValueError, match="load ratio R"):
        delta_k(1.0, R=-0.1)
    with pytest.raises(ValueError, match="Paris m must be"):
        paris_rate(1.0, C=1.0, m=0.0)
    with pytest.raises(ValueError, match="threshold dK_th"):
        paris_rate(1.0, C=1.0, m=2.0, dK_th=-1.0)


S, W, C = 2.0, 10.0, 1e-3  # stress, width and Paris C of the closed forms below
A0, A1 = 1.0, 5.0


def test_paris_cycles_exact_for_power_law():
    # K = S sqrt(pi a): N = (a1^(1 - m/2) - a0^(1 - m/2)) / ((1 - m/2) C (S sqrt(pi))^m), m != 2,
    # and ln(a1 / a0) / (C S^2 pi) for m = 2 (integrals of da / (C K^m))
    a = np.array([A0, 2.0, A1])
    dK = S * np.sqrt(np.pi * a)
    n2 = paris_cycles(a, dK, C, 2.0)[-1]
    assert abs(n2 / (math.log(A1 / A0) / (C * S * S * math.pi)) - 1) < 1e-13
    m = 3.5
    exact = (A1 ** (1 - m / 2) - A0 ** (1 - m / 2)) / ((1 - m / 2) * C * (S * math.sqrt(math.pi)) ** m)
    assert abs(paris_cycles(a, dK, C, m)[-1] / exact - 1) < 1e-13


def _K(a):
    return S * math.sqrt(math.pi * a) / (1 - a / W)


@pytest.mark.parametrize("m", [2.0, 4.0])
def test_paris_life_closed_form(m):
    # K = S sqrt(pi a) / (1 - a/W): 1 / (C K^m) integrates in closed form
    if m == 2.0:  # int (1 - a/W)^2 / a da
        F = lambda a: math.log(a) - 2 * a / W + a * a / (2 * W * W)  # noqa: E731
        exact = (F(A1) - F(A0)) / (C * S**2 * math.pi)
    else:  # int (1 - a/W)^4 / a^2 da
        G = lambda a: -1 / a - 4 / W * math.log(a) + 6 * a / W**2 - 2 * a * a / W**3 + a**3 / (3 * W**4)  # noqa: E731
        exact = (G(A1) - G(A0)) / (C * S**4 * math.pi**2)
    life = paris_life(_K, A0, A1, C, m)
    # rtol 1e-6 asked; measured 6e-12 (m = 2) and 1e-11 (m = 4) with about 500-700 K calls
    assert abs(life.cycles / exact - 1) < 1e-9
    assert life.reason == "a_end reached" and np.all(np.diff(life.N) > 0)
    coarse = paris_life(_K, A0, A1, C, m, rtol=1e-4)  # measured 6e-8 with 55 calls (m = 2)
    assert abs(coarse.cycles / exact - 1) < 1e-6 and coarse.n_evaluations < life.n_evaluations


def test_paris_life_threshold_and_errors():
    life = paris_life(lambda a: 1.0 / a, 1.0, 10.0, C=1.0, m=2.0, dK_th=0.5)
    assert life.reason == "below threshold" and life.a[-1] <= 2.0 + 1e-9  # dK = 1/a <= 0.5 from a = 2
    with pytest.raises(ValueError, match="0 < a0 < a_end"):
        paris_life(_K, 2.0, 1.0, C, 2.0)
    with pytest.raises(ValueError, match="increasing"):
        paris_cycles([2.0, 1.0], [1.0, 1.0], C, 2.0)
    with pytest.raises(ValueError, match="dK must be > 0"):
        paris_cycles([1.0, 2.0], [1.0, 0.0], C, 2.0)
