"""Properties of the named closed-form fields (efgkit.problem.exact.fields, efgkit.problem.exact.williams)."""

import numpy as np
import pytest

from efgkit.problem.exact.fields import FIELDS, Field
from efgkit.problem.exact.williams import williams_displacement, williams_stress
from efgkit.problem.frames import rotate_voigt
from efgkit.problem.material import Elastic

PLANES = ("strain", "stress")
RTOL = 1e-6


def _annulus(rng, n, centre, r0, r1):
    r, t = rng.uniform(r0, r1, n), rng.uniform(-np.pi, np.pi, n)
    return np.asarray(centre) + np.column_stack([r * np.cos(t), r * np.sin(t)])


def _kirsch_points(rng, n):
    return _annulus(rng, n, (0.3, -0.2), 1.1 * 0.7, 4 * 0.7)


def _williams_points(rng, n):
    # tip (0.5, 0.25), angle 0.6; theta kept off the faces so stencils do not cross the crack
    r, t = rng.uniform(0.2, 1.0, n), rng.uniform(-0.9, 0.9, n) * np.pi + 0.6
    return np.array([0.5, 0.25]) + np.column_stack([r * np.cos(t), r * np.sin(t)])


def _beam_points(rng, n):
    return np.column_stack([rng.uniform(0, 48, n), rng.uniform(-6, 6, n)])


# name -> (field, point sampler away from singularities, length scale for the FD step)
CASES = {
    "kirsch": (Field.named("kirsch", a=0.7, centre=(0.3, -0.2), sigma=2.5), _kirsch_points, 0.7),
    "williams": (Field.named("williams", tip=(0.5, 0.25), angle=0.6, KI=1.3, KII=-0.7),
                 _williams_points, 0.2),
    "cantilever": (Field.named("cantilever", L=48.0, D=12.0, P=1000.0), _beam_points, 12.0),
}


def _material(plane):
    return Elastic(E=3.0e7, nu=0.3, plane=plane)


def _fd(fun, x, h):
    """Central differences of fun (n, 2) -> (n, k): (d/dx, d/dy), each (n, k)."""
    ex, ey = np.array([h, 0.0]), np.array([0.0, h])
    return (fun(x + ex) - fun(x - ex)) / (2 * h), (fun(x + ey) - fun(x - ey)) / (2 * h)


def _close(a, b, rtol):
    """Per-point |a - b| <= rtol |b| (+ a floor of 1e-3 rtol max |b| for near-zero rows)."""
    err, ref = np.linalg.norm(a - b, axis=1), np.linalg.norm(b, axis=1)
    return bool(np.all(err <= rtol * (ref + 1e-3 * ref.max())))


def test_registry_is_complete():
    assert sorted(FIELDS) == sorted(CASES)


@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("name", sorted(CASES))
def test_strain_of_displacement_is_compliance_times_stress(name, plane):
    field, sample, scale = CASES[name]
    mat, x = _material(plane), sample(np.random.default_rng(0), 200)
    ux, uy = _fd(lambda p: field.displacement(p, mat), x, 1e-5 * scale)
    eps_fd = np.column_stack([ux[:, 0], uy[:, 1], uy[:, 0] + ux[:, 1]])
    assert _close(eps_fd, field.stress(x, mat) @ mat.compliance().T, RTOL)
    assert _close(field.strain(x, mat), eps_fd, RTOL)


@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("name", sorted(CASES))
def test_stress_is_in_equilibrium(name, plane):
    field, sample, scale = CASES[name]
    mat, x = _material(plane), sample(np.random.default_rng(1), 200)
    sx, sy = _fd(lambda p: field.stress(p, mat), x, 1e-5 * scale)
    div = np.column_stack([sx[:, 0] + sy[:, 2], sx[:, 2] + sy[:, 1]])
    sig = np.linalg.norm(field.stress(x, mat), axis=1)
    assert np.all(np.linalg.norm(div, axis=1) * scale <= RTOL * sig)


# --- kirsch ----------------------------------------------------------------------------

@pytest.mark.parametrize("plane", PLANES)
def test_kirsch_stress_concentration_is_three(plane):
    field = Field.named("kirsch", a=0.7, centre=(0.3, -0.2), sigma=2.5)
    s = field.stress(np.array([[0.3, -0.2 + 0.7], [0.3, -0.2 - 0.7]]), _material(plane))
    np.testing.assert_allclose(s[:, 0], 3 * 2.5, rtol=1e-13)  # seed 003 Sec. 4.5.1


@pytest.mark.parametrize("plane", PLANES)
def test_kirsch_hole_surface_is_traction_free(plane):
    field, _, _ = CASES["kirsch"]
    t = np.linspace(-np.pi, np.pi, 37)
    n = np.column_stack([np.cos(t), np.sin(t)])
    s = field.stress(np.array([0.3, -0.2]) + 0.7 * n, _material(plane))
    traction = np.column_stack([s[:, 0] * n[:, 0] + s[:, 2] * n[:, 1],
                                s[:, 2] * n[:, 0] + s[:, 1] * n[:, 1]])
    np.testing.assert_allclose(traction, 0.0, atol=1e-13 * 2.5)


def test_kirsch_far_field_is_the_remote_stress():
    field, _, _ = CASES["kirsch"]
    x = _annulus(np.random.default_rng(2), 20, (0.3, -0.2), 1e4, 2e4)
    np.testing.assert_allclose(field.stress(x, _material("strain")), [[2.5, 0, 0]] * 20,
                               atol=2.5 * 1.5 * 1e-8 * 3)  # leading decay 3 (a/r)^2


def test_kirsch_centre_is_rejected():
    with pytest.raises(ValueError, match=r"point \[0.3, -0.2\] is at the hole centre"):
        CASES["kirsch"][0].displacement(np.array([[0.3, -0.2]]), _material("strain"))


# --- williams --------------------------------------------------------------------------

@pytest.mark.parametrize("K", [(1.0, 0.0), (0.0, 1.0)], ids=["mode-I", "mode-II"])
@pytest.mark.parametrize("angle", [0.0, 0.6, -2.5])
def test_williams_crack_faces_are_traction_free(K, angle):
    field = Field.named("williams", tip=(0.5, 0.25), angle=angle, KI=K[0], KII=K[1])
    r = np.linspace(0.1, 1.0, 10)
    for side in (1, -1):  # just off the upper (theta -> pi) and lower (theta -> -pi) face
        t = angle + side * (np.pi - 1e-10)
        x = np.array([0.5, 0.25]) + np.column_stack([r * np.cos(t), r * np.sin(t)])
        s = field.stress(x, _material("strain"))
        nrm = np.array([-np.sin(angle), np.cos(angle)])
        traction = np.column_stack([s[:, 0] * nrm[0] + s[:, 2] * nrm[1],
                                    s[:, 2] * nrm[0] + s[:, 1] * nrm[1]])
        np.testing.assert_allclose(traction, 0.0, atol=1e-8 * np.abs(s).max())


@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("K", [(1.3, 0.0), (0.0, -0.7), (1.3, -0.7)])
def test_williams_mode_mixity_signs(K, plane):
    """Ahead: (s22, s12) = (KI, KII)/sqrt(2 pi r); faces: jump (u1, u2) = (kappa+1)/mu
    (KII, KI) sqrt(r/2pi) (Anderson, Fracture Mechanics, Tables 2.1-2.2)."""
    mat, r = _material(plane), np.array([0.01, 0.1, 1.0])
    s = williams_stress(r, np.zeros(3), *K)
    np.testing.assert_allclose(s[:, 1:] * np.sqrt(2 * np.pi * r)[:, None], [K] * 3,
                               atol=1e-14)
    up = williams_displacement(r, np.full(3, np.pi), *K, mat.mu, mat.kappa)
    lo = williams_displacement(r, np.full(3, -np.pi), *K, mat.mu, mat.kappa)
    jump = (up - lo) * mat.mu / ((mat.kappa + 1) * np.sqrt(r / (2 * np.pi)))[:, None]
    np.testing.assert_allclose(jump, [K[::-1]] * 3, atol=1e-14)


@pytest.mark.parametrize("angle", [0.6, -2.5, np.pi / 2])
def test_williams_rotating_the_field_equals_rotating_the_points(angle):
    mat = _material("stress")
    base = Field.named("williams", KI=1.3, KII=-0.7)
    turned = Field.named("williams", KI=1.3, KII=-0.7, angle=angle)
    x = _williams_points(np.random.default_rng(3), 50) - [0.5, 0.25]
    x = x @ np.array([[np.cos(0.6), -np.sin(0.6)], [np.sin(0.6), np.cos(0.6)]])  # angle 0
    R = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    np.testing.assert_allclose(turned.displacement(x @ R.T, mat),
                               base.displacement(x, mat) @ R.T, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(turned.stress(x @ R.T, mat),
                               rotate_voigt(base.stress(x, mat), angle), rtol=1e-12, atol=1e-12)


def test_williams_tip_displacement_is_zero_and_stress_raises():
    field, mat = CASES["williams"][0], _material("strain")
    x = np.array([[1.0, 1.0], [0.5, 0.25]])
    assert np.all(field.displacement(x, mat)[1] == 0.0)
    with pytest.raises(ValueError, match=r"point \[0.5, 0.25\] is at the crack tip"):
        field.stress(x, mat)
    with pytest.raises(ValueError, match="point 1 is at the crack tip"):
        williams_stress([1.0, 0.0], [0.0, 0.0], 1.0, 0.0)


# --- cantilever ------------------------------------------------------------------------

@pytest.mark.parametrize("plane", PLANES)
def test_cantilever_end_traction_resultant_is_plus_P(plane):
    field, mat = CASES["cantilever"][0], _material(plane)
    g, w = np.polynomial.legendre.leggauss(4)  # exact for the quadratic shear profile
    y, w = 6.0 * g, 6.0 * w
    s = field.stress(np.column_stack([np.full(4, 48.0), y]), mat)
    force = [w @ s[:, 0], w @ s[:, 2]]  # outward normal (1, 0)
    np.testing.assert_allclose(force, [0.0, 1000.0], rtol=1e-13, atol=1e-9)
    assert abs(w @ (s[:, 0] * y)) < 1e-9  # no end moment
    sides = field.stress(np.column_stack([np.linspace(0, 48, 9), np.full(9, 6.0)]), mat)
    np.testing.assert_allclose(sides[:, 1:], 0.0, atol=1e-9)  # top edge traction free


@pytest.mark.parametrize("plane", PLANES)
def test_cantilever_slender_tip_deflection_is_euler_bernoulli(plane):
    mat, L, D, P = _material(plane), 100.0, 1.0, 2.0
    E = mat.E if plane == "stress" else mat.E / (1 - mat.nu**2)
    u = Field.named("cantilever", L=L, D=D, P=P).displacement(np.array([[0, 0], [L, 0]]), mat)
    assert np.all(u[0] == 0.0)
    eb = P * L**3 / (3 * E * D**3 / 12)  # shear adds O((D/L)^2) = 1e-4
    assert abs(u[1, 1] / eb - 1) < 3e-4


# --- construction and validation -------------------------------------------------------

def test_named_fills_defaults_and_round_trips():
    f = Field.named("williams", KI=1)
    assert f == Field.named("williams", KII=0.0, KI=1.0, tip=[0, 0], angle=0)
    assert hash(f) == hash(Field("williams", {"KI": 1.0}))
    assert f.params == tuple(sorted(f.params))
    assert Field.named(**f.as_dict()) == f


@pytest.mark.parametrize("name, params, exc, match", [
    ("kirch", {"a": 1.0}, ValueError,
     r"unknown field 'kirch' \(did you mean 'kirsch'\?\); known fields: "
     r"\['cantilever', 'kirsch', 'williams'\]"),
    ("williams", {"KIII": 1.0}, ValueError,
     r"no parameter 'KIII' \(did you mean 'KII'\?\); valid parameters: "
     r"\['KI', 'KII', 'angle', 'tip'\]"),
    ("kirsch", {}, ValueError, r"'kirsch' needs parameter\(s\) \['a'\]"),
    ("kirsch", {"a": float("nan")}, ValueError, r"parameter 'a' must be finite, got nan"),
    ("williams", {"tip": (0.0, np.inf)}, ValueError, r"parameter 'tip' must be finite"),
    ("cantilever", {"L": 1.0, "D": -1.0}, ValueError, r"parameter 'D' must be > 0"),
    ("kirsch", {"a": 1.0, "centre": 0.0}, ValueError, r"'centre' must be a point \(x, y\)"),
    ("kirsch", {"a": True}, TypeError, r"parameter 'a' must be a real number"),
], ids=["name", "param", "missing", "nan", "inf-point", "negative", "not-point", "bool"])
def test_named_rejects_bad_input(name, params, exc, match):
    with pytest.raises(exc, match=match):
        Field.named(name, **params)


@pytest.mark.parametrize("x, match", [
    (np.zeros(2), r"x must have shape \(n, 2\)"),
    (np.array([[np.nan, 1.0]]), "x must be finite"),
])
def test_evaluation_rejects_bad_points(x, match):
    with pytest.raises(ValueError, match=match):
        CASES["cantilever"][0].stress(x, _material("strain"))
