"""Numerical dispersion of explicit EFG: the plane-wave speeds of the interior symbol of
M^-1 K (:func:`efgkit.explicit.phase_speeds`), against the material's c_1 and c_2."""

import math

import numpy as np
import pytest

from efgkit import EFG, Domain, Elastic, Scene
from efgkit.explicit import dynamics, phase_speeds, stable_step

MAT = Elastic(1.0, 0.25, "strain", rho=1.0)
EXACT = np.array([MAT.c_shear, MAT.c_dilatational])  # sqrt(mu / rho), sqrt((lambda + 2 mu) / rho)
CENTRE = 60  # node (5, 5) of the 11 x 11 grid: its rows (support 2.25 h, pairs within 4.5 h) see no edge


def _dyn(**kw):
    return dynamics(Scene(Domain.rectangle(0, 0, 10, 10), MAT, duration=1.0), EFG(spacing=1.0, **kw))


@pytest.fixture(scope="module")
def linear():
    return _dyn()


@pytest.fixture(scope="module")
def quadratic():
    return _dyn(basis="quadratic", d_max=2.25)


def _error(dyn, wavelength, dt=None):
    k = 2 * math.pi / wavelength
    xi = [[k, 0.0], [k / math.sqrt(2), k / math.sqrt(2)]]  # along x and at 45 degrees
    return phase_speeds(dyn, CENTRE, xi, dt) / EXACT - 1  # (2 directions, 2 branches)


def test_long_waves_converge_at_second_order(linear):
    # exact: c_2, c_1 at every wavelength; measured -0.44 % at 40 h and -1.74 % at 20 h (both
    # branches, both directions): the error scales with (k h)^2, a ratio of 4
    e40, e20 = _error(linear, 40.0), _error(linear, 20.0)
    assert np.all(e40 < 0) and np.all(np.abs(e40) < 0.013)
    assert np.allclose(e20 / e40, 4.0, atol=0.2)


def test_quadratic_basis_is_far_less_dispersive(quadratic, linear):
    # at 6 h (near the impact pulse's shortest S wave at 1 mm, 5.4 h: verification/wave_diffraction.py):
    # measured -1.4 to -1.6 % (quadratic, d_max 2.25) against -18 % (linear, d_max 2)
    q, lin = _error(quadratic, 6.0), _error(linear, 6.0)
    assert np.all(np.abs(q) < 0.045)
    assert np.all(np.abs(lin) > 0.06)


def test_central_differences_add_a_phase_lead(linear):
    # closed form of the scheme: omega_dt = (2 / dt) asin(omega dt / 2) > omega
    dt = 0.9 * stable_step(linear)[0]
    semi, full = _error(linear, 10.0), _error(linear, 10.0, dt)
    k = 2 * math.pi / 10.0
    w = (1 + semi) * EXACT * k
    assert np.allclose(full, 2 / dt * np.arcsin(w * dt / 2) / k / EXACT - 1, rtol=0, atol=1e-12)
    assert np.all(full > semi)


def test_bad_input(linear):
    with pytest.raises(ValueError, match="wavenumbers must be non-zero"):
        phase_speeds(linear, CENTRE, [[0.0, 0.0]])
    with pytest.raises(ValueError, match="dt must be finite and > 0"):
        phase_speeds(linear, CENTRE, [[0.5, 0.0]], dt=-1.0)
    with pytest.raises(ValueError, match="above the stable step"):
        phase_speeds(linear, CENTRE, [[0.5, 0.0]], dt=100.0)
