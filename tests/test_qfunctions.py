"""Weight functions q of the domain integrals (efgkit.fracture.qfunctions)."""

import numpy as np
import pytest

from efgkit.fracture.qfunctions import KINDS, QFunction
from efgkit.problem.crack import Tip

R_OUT = 0.8
CASES = [
    QFunction("cubic_spline", R_OUT),
    QFunction("wendland_c2", R_OUT),
    QFunction("power", R_OUT, n=2),
    QFunction("power", R_OUT, n=3.5),
    QFunction("plateau", R_OUT),
    QFunction("plateau", R_OUT, r_in=0.0),
    QFunction("plateau", R_OUT, r_in=0.7),
]
IDS = [f"{q.kind}-{q.n or q.r_in}" for q in CASES]
TIP = Tip(np.array([1.5, -0.5]), 2.1, "c", 1)


def _ring(r, n=7):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False) + 0.3
    return TIP.x + np.column_stack([r * np.cos(t), r * np.sin(t)])


@pytest.mark.parametrize("q", CASES, ids=IDS)
def test_one_at_the_tip_zero_from_r_out_on(q):
    assert q.value(TIP.x[None], TIP)[0] == 1.0
    for r in ((1 + 1e-12) * R_OUT, 1.2 * R_OUT, 10 * R_OUT):  # exactly 0 from r_out on
        assert np.all(q.value(_ring(r), TIP) == 0.0)
        assert np.all(q.gradient(_ring(r), TIP) == 0.0)
    # on the circle (up to the rounding of the ring's coordinates)
    assert np.allclose(q.value(_ring(R_OUT), TIP), 0.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("q", CASES, ids=IDS)
def test_gradient_finite_and_zero_at_the_tip(q):
    x = TIP.x + np.array([[0.0, 0.0], [1e-300, 0.0], [0.0, 1e-14]])
    g = q.gradient(x, TIP)
    assert np.all(np.isfinite(g)) and np.allclose(g, 0.0, atol=1e-12)


@pytest.mark.parametrize("q", CASES, ids=IDS)
def test_gradient_matches_finite_differences(q):
    rng = np.random.default_rng(4)
    r = rng.uniform(0.02, 0.97, 200) * R_OUT
    t = rng.uniform(-np.pi, np.pi, 200)
    x = TIP.x + np.column_stack([r * np.cos(t), r * np.sin(t)])
    h = 1e-6 * R_OUT
    fd = np.column_stack([(q.value(x + e, TIP) - q.value(x - e, TIP)) / (2 * h)
                          for e in (np.array([h, 0.0]), np.array([0.0, h]))])
    g = q.gradient(x, TIP)
    # central differences of a piecewise-polynomial profile: O(h^2) except at the C1
    # breakpoints (z = 1 of the cubic spline, r_in of the plateau), where it is O(h)
    assert np.allclose(g, fd, rtol=0, atol=1e-6 / R_OUT)
    qv, gv = q.value_and_gradient(x, TIP)
    assert np.array_equal(qv, q.value(x, TIP)) and np.array_equal(gv, g)


@pytest.mark.parametrize("q", CASES, ids=IDS)
def test_decreasing_from_one_to_zero(q):
    r = np.linspace(0, R_OUT, 401)
    x = TIP.x + np.column_stack([r, np.zeros_like(r)])
    v = q.value(x, TIP)
    assert np.all(np.diff(v) <= 1e-15) and v[0] == 1.0 and abs(v[-1]) < 1e-12
    assert np.all((v >= 0) & (v <= 1))


@pytest.mark.parametrize("q", [c for c in CASES if c.kind != "power"],
                         ids=[i for c, i in zip(CASES, IDS, strict=True) if c.kind != "power"])
def test_smooth_kinds_have_zero_slope_at_r_out(q):
    x = TIP.x + np.array([[R_OUT * (1 - 1e-9), 0.0]])
    assert np.abs(q.gradient(x, TIP)).max() < 1e-6 / R_OUT


def test_power_keeps_its_slope_at_r_out():
    # seed 001 Eq. 14: dq/dr = -n z^(n-1) / r_out -> -n / r_out at the outer circle
    q = QFunction("power", 2.0, n=3)
    g = q.gradient(np.array([[2.0 * (1 - 1e-12), 0.0]]), [0.0, 0.0])
    assert g[0, 0] == pytest.approx(-1.5, rel=1e-9)


def test_closed_forms():
    x = np.array([[0.5, 0.0], [1.0, 0.0], [1.5, 0.0]])
    # seed 001 Eq. 10, h = r_out / 2 = 1: q = 1 - 3/2 z^2 + 3/4 z^3 (z < 1), (2 - z)^3 / 4
    assert np.allclose(QFunction("cubic_spline", 2.0).value(x, [0, 0]),
                       [1 - 1.5 * 0.25 + 0.75 * 0.125, 0.25, 0.5**3 / 4])
    # seed 001 Eq. 13, z = r / 2: (1 - z)^3 (1 + 3 z)
    z = x[:, 0] / 2
    assert np.allclose(QFunction("wendland_c2", 2.0).value(x, [0, 0]), (1 - z) ** 3 * (1 + 3 * z))
    # seed 001 Eq. 14
    assert np.allclose(QFunction("power", 2.0, n=4).value(x, [0, 0]), 1 - z**4)
    # plateau: 1 up to r_in = 1, then 1 - 3 s^2 + 2 s^3
    assert np.allclose(QFunction("plateau", 2.0).value(x, [0, 0]), [1.0, 1.0, 0.5])


def test_tip_or_point_and_frame_independence():
    q = QFunction("wendland_c2", 1.0)
    x = _ring(0.4)
    assert np.array_equal(q.value(x, TIP), q.value(x, TIP.x))
    g = q.gradient(x, TIP)  # radial: parallel to x - tip, pointing inwards
    d = x - TIP.x
    assert np.allclose(d[:, 0] * g[:, 1] - d[:, 1] * g[:, 0], 0.0, atol=1e-14)
    assert np.all(np.sum(d * g, axis=1) < 0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(kind="plateau", r_out=1.0, r_in=1.0), "r_in < r_out"),
    (dict(kind="plateau", r_out=1.0, r_in=2.0), "r_in < r_out"),
    (dict(kind="plateau", r_out=1.0, r_in=-0.1), "0 <= r_in"),
    (dict(kind="wendland_c2", r_out=0.0), "r_out must be > 0"),
    (dict(kind="wendland_c2", r_out=-1.0), "r_out must be > 0"),
    (dict(kind="wendland_c2", r_out=float("nan")), "finite"),
    (dict(kind="wendland", r_out=1.0), "did you mean 'wendland_c2'"),
    (dict(kind="cubic", r_out=1.0), "did you mean 'cubic_spline'"),
    (dict(kind="power", r_out=1.0), "needs the exponent n"),
    (dict(kind="power", r_out=1.0, n=1), "n >= 2"),
    (dict(kind="wendland_c2", r_out=1.0, r_in=0.5), "only by kind 'plateau'"),
    (dict(kind="cubic_spline", r_out=1.0, n=2), "only by kind 'power'"),
])
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        QFunction(**kwargs)


@pytest.mark.parametrize("kwargs", [dict(kind="wendland_c2", r_out="1"),
                                    dict(kind="wendland_c2", r_out=True),
                                    dict(kind="power", r_out=1.0, n="2")])
def test_bad_types(kwargs):
    with pytest.raises(TypeError, match="must be a real number"):
        QFunction(**kwargs)


def test_bad_points_and_tip():
    q = QFunction("wendland_c2", 1.0)
    with pytest.raises(ValueError, match=r"shape \(n, 2\)"):
        q.value(np.zeros(3), TIP)
    with pytest.raises(ValueError, match="tip must be a Tip or a finite point"):
        q.value(np.zeros((1, 2)), [0.0, np.nan])


def test_kinds_listed():
    assert set(KINDS) == {"cubic_spline", "plateau", "power", "wendland_c2"}
