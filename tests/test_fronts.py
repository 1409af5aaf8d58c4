"""Front arrival pickers and speed fits (efgkit.explicit.fronts) on pulses with known
speeds, and their error messages."""

import math

import numpy as np
import pytest

from efgkit.explicit.fronts import line_speed, lobe_signs, onset_times, peak_times, plane_front, rise_times

T = np.linspace(0.0, 30.0, 1201)  # sample times, step 0.025


def pulses(arrival, width=1.0, tail=0.0):
    """(n_t, n) Gaussian lobes peaking at ``arrival + 2 width`` (a leading edge starting near
    ``arrival``), optionally followed by an opposite lobe ``tail`` times as large, 6 widths
    later (their overlap is below 1e-15)."""
    a = np.asarray(arrival, float)[None]
    g = np.exp(-((T[:, None] - a - 2 * width) / width) ** 2)
    return g - tail * np.exp(-((T[:, None] - a - 8 * width) / width) ** 2)


def test_peak_times_exact_speed_and_sub_sample_position():
    d = np.array([5.0, 10.0, 15.0, 20.0])
    tp = peak_times(T, pulses(d / 2.5), d / 2.5, d / 2.5 + 5.0)
    # exact: the peaks are at d / 2.5 + 2 (closed form of the pulse)
    assert np.allclose(tp, d / 2.5 + 2.0, atol=1e-3)  # parabola vertex, sample step 0.025
    assert line_speed(d, tp) == pytest.approx(2.5, rel=1e-4)


def test_rise_times_half_maximum_of_a_gaussian():
    arr = np.array([3.0, 7.3, 11.1])
    tr = rise_times(T, pulses(arr, tail=0.5), arr - 1.0, arr + 5.0)
    # exact: exp(-s^2) = 1/2 at s = -sqrt(ln 2) before the peak at arrival + 2
    assert np.allclose(tr, arr + 2.0 - math.sqrt(math.log(2.0)), atol=2e-4)


def test_rise_times_ignores_an_earlier_smaller_lobe_of_the_same_sign():
    f = pulses([10.0]) + 0.3 * pulses([5.0])  # a precursor at 30 % of the peak
    tr = rise_times(T, f, 0.0, 20.0)
    assert tr[0] == pytest.approx(12.0 - math.sqrt(math.log(2.0)), abs=2e-4)


def test_onset_times_threshold_crossing():
    f = pulses([4.0, 9.0])
    to = onset_times(T, -f, 0.0, 25.0, 0.1)  # |f|: the sign does not matter
    # exact: exp(-s^2) = 0.1 at s = -sqrt(ln 10)
    assert np.allclose(to, np.array([4.0, 9.0]) + 2.0 - math.sqrt(math.log(10.0)), atol=1e-3)


def test_lobe_signs_leading_lobe_and_a_lobe_cut_by_the_gate():
    f = -pulses([2.0]) + 3.0 * pulses([6.0])  # a trough at 4, a crest 3 times as large at 8
    assert lobe_signs(T, f, 1.0, 7.5).tolist() == [-1.0]  # the crest is cut by the gate
    assert lobe_signs(T, f, 1.0, 10.0).tolist() == [1.0]  # the trough is under half the crest
    assert lobe_signs(T, f, 1.0, 10.0, lead=0.3).tolist() == [-1.0]  # ... but over 0.3 of it
    with pytest.raises(ValueError, match="no lobe of either sign"):
        lobe_signs(T, T[:, None] + 0.0, 1.0, 10.0)  # monotone
    with pytest.raises(ValueError, match=r"lead must lie in \(0, 1\]"):
        lobe_signs(T, f, 1.0, 10.0, lead=0.0)


def test_plane_front_recovers_speed_angle_and_trace():
    rng = np.random.default_rng(3)
    p = rng.uniform(0.0, 50.0, (40, 2))
    th = math.radians(32.0)
    n = np.array([math.sin(th), math.cos(th)])
    r = plane_front(p, 0.7 + p @ n / 3.2)
    assert r["speed"] == pytest.approx(3.2, rel=1e-12)
    assert np.allclose(r["normal"], n, atol=1e-12)
    assert r["trace"][0] == pytest.approx(3.2 / math.sin(th), rel=1e-12)  # speed along x
    assert r["rms"] < 1e-12


def test_bad_input_messages():
    f = pulses([5.0])
    with pytest.raises(ValueError, match="increasing sample times"):
        peak_times(T[::-1], f, 0.0, 10.0)
    with pytest.raises(ValueError, match=r"shape \(n_t, n_probes\)"):
        peak_times(T, f[:-1], 0.0, 10.0)
    with pytest.raises(ValueError, match="NaN or inf"):
        peak_times(T, np.full_like(f, np.nan), 0.0, 10.0)
    with pytest.raises(ValueError, match="fewer than 3 samples"):
        peak_times(T, f, 40.0, 50.0)
    with pytest.raises(ValueError, match=r"frac must lie in \(0, 1\)"):
        onset_times(T, f, 0.0, 10.0, 1.5)
    with pytest.raises(ValueError, match="records zero within its gate"):
        onset_times(T, 0 * f, 0.0, 10.0, 0.1)
    with pytest.raises(ValueError, match=r"frac must lie in \(0, 1\)"):
        rise_times(T, f, 0.0, 10.0, 0.0)
    with pytest.raises(ValueError, match="no lobe"):
        rise_times(T, -f, 0.0, 10.0)  # falls then rises: no local maximum inside
    with pytest.raises(ValueError, match="no positive lobe"):
        rise_times(T, -pulses([2.0]) - pulses([8.0]), 0.0, 15.0)  # the one maximum, between troughs, < 0
    with pytest.raises(ValueError, match="starts above 0.5 of the peak"):
        rise_times(T, f, 6.9, 10.0)
    with pytest.raises(ValueError, match="same length n >= 2"):
        line_speed([1.0, 2.0], [1.0])
    with pytest.raises(ValueError, match="times are all equal"):
        line_speed([1.0, 2.0], [1.0, 1.0])
    with pytest.raises(ValueError, match=r"points must be \(n, 2\)"):
        plane_front(np.zeros((2, 2)), np.zeros(2))
    with pytest.raises(ValueError, match="lie on one line"):
        plane_front(np.column_stack([np.arange(4.0), np.arange(4.0)]), np.arange(4.0))
    with pytest.raises(ValueError, match="do not vary"):
        plane_front(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.ones(3))
