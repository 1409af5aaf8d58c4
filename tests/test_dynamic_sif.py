"""Dynamic J', the velocity functions, the Rayleigh speed and dynamic near-tip estimates
(efgkit.fracture.dynamic, dynamic_tip, velocity; seed 002 Eqs. 31-38, seed 000 Eqs. 5.1-5.10).

References are closed forms: the Williams field, the steadily moving crack of Freund
(efgkit.problem.exact.moving, itself checked here against the equations of motion), the
printed velocity functions evaluated in 60-digit decimal arithmetic, and the seeds'
numbers for the wave speeds."""

from decimal import Decimal, getcontext

import numpy as np
import pytest

from efgkit.fracture.dynamic import contract_dynamic, dynamic_integrands
from efgkit.fracture.dynamic_tip import dynamic_tip_result
from efgkit.fracture.extrapolation import k_from_stress
from efgkit.fracture.integrals import FaceLoad, domain_integrals
from efgkit.fracture.qfunctions import QFunction
from efgkit.fracture.velocity import k_from_dynamic_j, velocity_functions
from efgkit.problem.crack import Tip
from efgkit.problem.exact.moving import moving_crack_fields
from efgkit.problem.exact.williams import williams_gradient, williams_stress
from efgkit.problem.frames import rotate_gradient, rotate_vectors, rotate_voigt
from efgkit.problem.material import Elastic, strain_from_gradient

TIP = Tip(np.array([0.3, -0.2]), 0.4, "c", 1)  # a rotated tip: every frame change is exercised
RADII = (0.3, 0.6, 1.0)


def polar_rule(R, n=24):
    """Gauss rule on the disc r < R about the origin, r = s^2 (smooth in s for sqrt(r) fields):
    tip-frame points (n*n, 2), r, theta and weights."""
    t, tw = np.polynomial.legendre.leggauss(n)
    s = (t + 1) / 2 * np.sqrt(R)
    r, th = [a.ravel() for a in np.meshgrid(s**2, np.pi * t, indexing="ij")]
    w = np.outer(s**3 * np.sqrt(R) * tw, np.pi * tw).ravel()
    return np.column_stack([r * np.cos(th), r * np.sin(th)]), r, th, w


def ring_rule(radii, n=24):
    """polar_rule on r < radii[0] and Gauss rings between the next radii: exact for q-functions
    with a kink at any of the radii."""
    loc, r, th, w = polar_rule(radii[0], n)
    t, tw = np.polynomial.legendre.leggauss(n)
    parts = [(r, th, w)]
    for a, b in zip(radii[:-1], radii[1:], strict=True):
        rr = a + (t + 1) / 2 * (b - a)
        R_, TH = [v.ravel() for v in np.meshgrid(rr, np.pi * t, indexing="ij")]
        parts.append((R_, TH, np.outer(rr * (b - a) / 2 * tw, np.pi * tw).ravel()))
    r, th, w = (np.concatenate([p[i] for p in parts]) for i in range(3))
    return np.column_stack([r * np.cos(th), r * np.sin(th)]), r, th, w


def stress_of(g, m):
    return strain_from_gradient(g) @ m.D.T


def to_global(loc, s, g, *vectors):
    a = TIP.angle
    return (TIP.x + rotate_vectors(loc, a), rotate_voigt(s, a), rotate_gradient(g, a),
            *[rotate_vectors(v, a) for v in vectors])


# --- wave speeds (Elastic.c_rayleigh: seed 000 Eqs. 5.9-5.10) -------------------------------


def test_wave_speeds_of_the_seeds():
    # seed README / seed 002 Sect. 4.3 read with E = 210 GPa (nu = 0.3, rho = 7800, plane strain):
    # c1 = 6020, c2 = 3218, cR = 2984 m/s
    steel = Elastic(210e9, 0.3, "strain", rho=7800.0)
    assert [round(c) for c in (steel.c_dilatational, steel.c_shear, steel.c_rayleigh)] == \
        [6020, 3218, 2984]
    # seed 000 Sect. 5.2.1: tungsten E = 400 GPa, nu = 0.29, rho = 19300: C_R = 2624.1 m/s
    assert round(Elastic(400e9, 0.29, rho=19300.0).c_rayleigh, 1) == 2624.1
    # plane stress uses the plane-stress dilatational speed sqrt(E / (rho (1 - nu^2)))
    ps = Elastic(210e9, 0.3, "stress", rho=7800.0)
    assert ps.c_dilatational == pytest.approx(np.sqrt(210e9 / (7800 * (1 - 0.09))), rel=1e-15)


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_rayleigh_root_is_exact(plane):
    getcontext().prec = 50
    for nu in np.linspace(0.0, 0.49, 12):
        m = Elastic(1.0, float(nu), plane, rho=1.0)
        x = (m.c_rayleigh / m.c_shear) ** 2
        lam, mu = m.lame
        g = Decimal(mu / (lam + 2 * mu))

        def f(X, g=g):  # the unsquared Rayleigh equation, in 50 digits
            return (2 - X) ** 2 - 4 * (1 - X).sqrt() * (1 - g * X).sqrt()
        X, h = Decimal(x), Decimal("1e-25")
        err = abs(f(X) / ((f(X + h) - f(X)) / h)) / X
        assert err < 3e-15  # measured <= 7e-16 in x
        # seed 000 Eq. 5.9 (largest root of the cubic in eta) and Eq. 5.10
        ga = float(g)
        eta = max(np.roots([1, 4 * ga - 3, -1, -(1 - 2 * ga) ** 2]).real)
        assert np.sqrt((eta**2 - 1) / (eta**2 - ga)) == pytest.approx(np.sqrt(x), rel=1e-12)


def test_rayleigh_against_the_classic_approximation():
    # c_R / c_s ~ (0.862 + 1.14 nu) / (1 + nu) (plane strain): measured 1.4 % off at nu = 0,
    # falling with nu (0.66 % at 0.1)
    err = [(m.c_rayleigh / m.c_shear * (1 + m.nu) / (0.862 + 1.14 * m.nu) - 1)
           for m in (Elastic(1.0, float(nu), rho=1.0) for nu in np.linspace(0, 0.49, 50))]
    assert 0 < min(err) and max(err) < 0.015 and np.all(np.diff(err) < 0)


# --- velocity functions (seed 002 Eqs. 34-35) -------------------------------------------------


def printed_velocity_functions(b: float, g: float):
    """Seed 002 Eq. 34 as printed, in 60-digit decimal arithmetic, at b = (V/c_s)^2, g = (c_s/c_d)^2."""
    getcontext().prec = 60
    b, g = Decimal(b), Decimal(g)
    b1, b2 = (1 - g * b).sqrt(), (1 - b).sqrt()
    D, Db = 4 * b1 * b2 - (1 + b2 * b2) ** 2, 4 * b1 * b2 + (1 + b2 * b2) ** 2
    A_IV = (b1 - b2) * (1 - b2 * b2) * Db / (2 * D * D) * (
        (2 + b1 + b2) / ((1 + b1) * (1 + b2)).sqrt() - 4 * (1 + b2 * b2) / Db)
    return b1 * (1 - b2 * b2) / D, b2 * (1 - b2 * b2) / D, A_IV


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_velocity_functions_at_rest(plane):
    m = Elastic(1.0, 0.3, plane)  # no density needed at V = 0
    A = velocity_functions(0.0, m)
    assert np.allclose(A, (m.kappa + 1) / 4, rtol=2e-16, atol=0)  # seed 002 Eq. 35


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_velocity_functions_against_the_printed_form_in_high_precision(plane):
    m = Elastic(1.0, 0.3, plane, rho=1.0)
    cs, cR = m.c_shear, m.c_rayleigh
    lam, mu = m.lame
    g = mu / (lam + 2 * mu)
    ratios = np.concatenate([np.logspace(-12, -0.31, 40), np.linspace(0.5, 0.999 * cR / cs, 20)])
    V = ratios * cs
    A = np.array(velocity_functions(V, m))  # (3, n)
    ref = np.array([[float(a) for a in printed_velocity_functions(float((v / cs) ** 2), g)] for v in V]).T
    assert np.max(np.abs(A / ref - 1)) < 5e-13  # measured 1.7e-13 (at 0.999 c_R)
    assert np.all(A > 0) and np.all(np.diff(A, axis=1) >= -1e-15)  # positive, growing to c_R
    assert np.all(np.diff(A[:, 40:], axis=1) > 0) and np.all(A[:, -1] > 50 * A[:, 0])  # D -> 0 at c_R
    # the printed form in double precision cancels: 1e-6 c_s already costs > 1e-6
    v = 1e-6 * cs
    b1, b2 = np.sqrt(1 - (v / m.c_dilatational) ** 2), np.sqrt(1 - (v / cs) ** 2)
    naive = b1 * (1 - b2**2) / (4 * b1 * b2 - (1 + b2**2) ** 2)
    exact = float(printed_velocity_functions(float((v / cs) ** 2), g)[0])
    assert abs(naive / exact - 1) > 1e-6
    assert abs(float(velocity_functions(v, m)[0]) / exact - 1) < 1e-15


def test_velocity_function_errors():
    m = Elastic(1.0, 0.3, rho=1.0)
    with pytest.raises(ValueError, match=r"crack speed V = 0\.6.*Rayleigh speed c_R = 0\.575"):
        velocity_functions(0.6, m)
    with pytest.raises(ValueError, match="Rayleigh speed"):
        velocity_functions(m.c_rayleigh, m)
    with pytest.raises(ValueError, match="finite and >= 0"):
        velocity_functions(-0.1, m)
    with pytest.raises(ValueError, match="needs the wave speeds: give the material a density"):
        velocity_functions(0.1, Elastic(1.0, 0.3))
    with pytest.raises(TypeError, match="material must be an Elastic"):
        velocity_functions(0.1, "steel")


# --- inverting Eq. 33 (seed 002 Eqs. 37-38) ---------------------------------------------------


@pytest.mark.parametrize("frac", [0.0, 0.3, 0.9])
@pytest.mark.parametrize("KI, KII", [(1.3, -0.6), (-0.4, 1.1), (0.5, 0.5), (2.0, 0.0), (0.0, -1.0)])
def test_k_from_dynamic_j_round_trip(frac, KI, KII):
    m = Elastic(1.0, 0.3, rho=1.0)
    V = frac * m.c_rayleigh
    A_I, A_II, A_IV = (float(a) for a in velocity_functions(V, m))
    J1 = (A_I * KI**2 + A_II * KII**2) / (2 * m.mu)
    J2 = -A_IV * KI * KII / m.mu
    # crack-face jump behind a moving tip: delta = 2 A K sqrt(2 r / pi) / mu (checked below)
    dI, dII = 2 * A_I * KI, 2 * A_II * KII
    got = k_from_dynamic_j(J1, J2, m, V, opening=dI, sliding=dII)
    assert got == pytest.approx((KI, KII), abs=1e-12 * np.hypot(KI, KII))
    if KI > 0 and A_I * KI**2 >= A_II * KII**2:  # the opening-dominated default needs no jump
        assert k_from_dynamic_j(J1, J2, m, V) == pytest.approx((KI, KII), abs=1e-12)


def test_k_from_dynamic_j_is_seed_000_eq_5_7_for_mode_I():
    m = Elastic(75.6e3, 0.286, rho=2.45e-9)
    J = 0.0123
    # seed 000 Eq. 5.7: K = sqrt(2 mu J / (1 - nu)) (plane strain)
    assert k_from_dynamic_j(J, 0.0, m)[0] == pytest.approx(np.sqrt(2 * m.mu * J / (1 - m.nu)),
                                                           rel=1e-14)


def test_k_from_dynamic_j_errors():
    m = Elastic(1.0, 0.3, rho=1.0)
    with pytest.raises(ValueError, match="give both opening and sliding"):
        k_from_dynamic_j(1.0, 0.0, m, opening=1.0)
    with pytest.raises(ValueError, match="J1 must be finite"):
        k_from_dynamic_j(float("nan"), 0.0, m)
    with pytest.raises(ValueError, match="Rayleigh speed"):
        k_from_dynamic_j(1.0, 0.0, m, speed=1.0)


# --- the moving-crack field used as a reference ----------------------------------------------


def test_moving_crack_field_is_an_elastodynamic_crack_field():
    m = Elastic(1.0, 0.3, rho=1.0)
    cd, cs, mu = m.c_dilatational, m.c_shear, m.mu
    rng = np.random.default_rng(0)
    r, th = rng.uniform(0.1, 1, 30), rng.uniform(-3, 3, 30)
    x = np.column_stack([r * np.cos(th), r * np.sin(th)])
    lam = m.lame[0]
    for KI, KII in ((1.0, 0.0), (0.0, 1.0)):
        V = 0.6 * cs
        u, g, h = moving_crack_fields(x, KI, KII, V, mu, cd, cs)
        # sigma_ij,j = rho u''_i = rho V^2 u_i,11
        P = lam + 2 * mu
        div = np.stack([P * h[:, 0, 0, 0] + lam * h[:, 1, 1, 0] + mu * (h[:, 0, 1, 1] + h[:, 1, 0, 1]),
                        mu * (h[:, 0, 1, 0] + h[:, 1, 0, 0]) + lam * h[:, 0, 0, 1] + P * h[:, 1, 1, 1]], 1)
        assert np.abs(div - V**2 * h[:, :, 0, 0]).max() < 1e-13
        e = 1e-6  # the gradient against central differences of u
        fd = np.stack([(moving_crack_fields(x + d, KI, KII, V, mu, cd, cs)[0]
                        - moving_crack_fields(x - d, KI, KII, V, mu, cd, cs)[0]) / (2 * e)
                       for d in (np.array([e, 0]), np.array([0, e]))], -1)
        assert np.abs(fd - g).max() < 1e-8
        # traction-free faces, K by definition ahead of the tip, V -> 0 is Williams
        faces = np.array([[-0.3, 0.0], [-0.3, -0.0]])
        s = stress_of(moving_crack_fields(faces, KI, KII, V, mu, cd, cs)[1], m)
        assert np.abs(s[:, 1:]).max() < 1e-15
        s = stress_of(moving_crack_fields(np.array([[0.3, 0.0]]), KI, KII, V, mu, cd, cs)[1], m)
        assert s[0, 1:] * np.sqrt(2 * np.pi * 0.3) == pytest.approx([KI, KII], abs=1e-14)
        g0 = moving_crack_fields(x, KI, KII, 1e-4 * cs, mu, cd, cs)[1]
        assert np.abs(g0 - williams_gradient(r, th, KI, KII, mu, m.kappa)).max() < 3e-7  # O(V^2)
        # the jump behind the tip used for the signs of Eq. 38: 2 A K sqrt(2 r / pi) / mu
        uf = moving_crack_fields(faces, KI, KII, V, mu, cd, cs)[0]
        A_I, A_II, _ = velocity_functions(V, m)
        assert uf[0] - uf[1] == pytest.approx(2 * np.array([A_II * KII, A_I * KI])
                                              * np.sqrt(0.6 / np.pi) / mu, abs=1e-14)


# --- J' and the interaction integral in domain form --------------------------------------------


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("with_grad_v", [False, True])
def test_static_williams_field_gives_the_static_j_and_k(plane, with_grad_v):
    m = Elastic(2.0, 0.3, plane, rho=1.5)
    KI, KII = 1.3, -0.6
    for R in RADII:
        loc, r, th, w = polar_rule(R)
        g = williams_gradient(r, th, KI, KII, m.mu, m.kappa)
        x, s, G = to_global(loc, williams_stress(r, th, KI, KII), g)
        z = np.zeros_like(x)
        it = dynamic_integrands(x, w, s, G, z, z, None, TIP, m, R,
                                grad_v=np.zeros_like(G) if with_grad_v else None)
        res = contract_dynamic(it, QFunction("wendland_c2", R))
        static = domain_integrals(x, w, s, G, TIP, m, QFunction("wendland_c2", R))
        assert res.J1 == pytest.approx(static.J, rel=1e-13)
        assert res.J1 == pytest.approx((KI**2 + KII**2) / m.E_prime, rel=1e-13)
        assert res.J2 == pytest.approx(-2 * KI * KII / m.E_prime, rel=1e-13)  # seed 002 Eq. 33, V = 0
        assert (res.KI, res.KII) == pytest.approx((KI, KII), rel=1e-13)


def accelerated_field(m, loc, r, th, KI, KII, acc, T0=0.0):
    """Williams field plus u_p = x2^2 / 2 (rho a_1 / mu, rho a_2 / (lambda + 2 mu)) plus a uniform
    sigma_11 = T0: sigma_ij,j = rho a_i exactly, faces traction-free; grad u and stress, tip frame."""
    lam, mu = m.lame
    g = williams_gradient(r, th, KI, KII, m.mu, m.kappa)
    g[:, 0, 1] += m.rho * acc[0] / mu * loc[:, 1]
    g[:, 1, 1] += m.rho * acc[1] / (lam + 2 * mu) * loc[:, 1]
    e = m.compliance() @ np.array([T0, 0.0, 0.0])
    g[:, 0, 0] += e[0]
    g[:, 1, 1] += e[1]
    return g, stress_of(g, m)


def test_inertia_term_restores_domain_independence():
    """A Williams field under a uniform acceleration a (velocity a t): J' and K are exact on
    every domain only with the inertia term."""
    m = Elastic(2.0, 0.3, "strain", rho=1.5)
    KI, KII, acc, t = 1.3, -0.6, np.array([0.7, -0.4]), 0.8
    J1, J2 = (KI**2 + KII**2) / m.E_prime, -2 * KI * KII / m.E_prime
    without = []
    for R in RADII:
        loc, r, th, w = polar_rule(R)
        g, s = accelerated_field(m, loc, r, th, KI, KII, acc)
        one = np.ones((len(r), 1))
        x, S, G, v, a = to_global(loc, s, g, one * acc * t, one * acc)
        for grad_v in (None, np.zeros_like(G)):
            res = contract_dynamic(dynamic_integrands(x, w, S, G, v, a, None, TIP, m, R, grad_v),
                                   QFunction("wendland_c2", R))
            assert (res.J1, res.J2) == pytest.approx((J1, J2), rel=1e-13)
            assert (res.KI, res.KII) == pytest.approx((KI, KII), rel=1e-13)
        res = contract_dynamic(dynamic_integrands(x, w, S, G, v, 0 * a, None, TIP, m, R),
                               QFunction("wendland_c2", R))
        without.append((res.J1, res.J2, res.KI, res.KII))
    without = np.array(without)
    # measured: J'_1 off by 1.8e-3 .. 1.1e-2, J'_2 by 0.06 .. 0.36, K by 0.007 .. 0.08
    assert np.all(np.ptp(without, axis=0) > [3e-3, 0.1, 0.01, 0.02])


def test_kinetic_forms_agree_for_a_stationary_crack():
    """W + T with the velocity gradient and W without kinetic terms are the same integral (by
    parts) for a velocity bounded at the tip: a smooth velocity field on a Williams field."""
    m = Elastic(1.0, 0.25, "stress", rho=2.0)
    for R in RADII:
        loc, r, th, w = polar_rule(R)
        g = williams_gradient(r, th, 1.0, 0.4, m.mu, m.kappa)
        v = np.column_stack([0.3 + loc[:, 0] + loc[:, 0] ** 2 - 0.5 * loc[:, 1],
                             0.2 * loc[:, 0] * loc[:, 1]])
        gv = np.stack([np.column_stack([1 + 2 * loc[:, 0], -0.5 * np.ones(len(r))]),
                       np.column_stack([0.2 * loc[:, 1], 0.2 * loc[:, 0]])], 1)
        x, S, G, V, A = to_global(loc, stress_of(g, m), g, v, np.ones_like(v))
        a, b = (contract_dynamic(dynamic_integrands(x, w, S, G, V, A, None, TIP, m, R, gvel),
                                 QFunction("wendland_c2", R))
                for gvel in (None, rotate_gradient(gv, TIP.angle)))
        assert (a.J1, a.J2) == pytest.approx((b.J1, b.J2), rel=1e-12)
        # the kinetic terms matter: T q_,k alone is not small
        c = contract_dynamic(dynamic_integrands(x, w, S, G, V, A, None, TIP, m, R,
                                                np.zeros_like(G)), QFunction("wendland_c2", R))
        assert abs(c.J1 - a.J1) > 1e-3 * abs(a.J1)


def face_points(m, R, fields, n=12, traction=(0.0, 0.0)):
    """FaceLoad on both faces behind TIP within R (Gauss in s, r = s^2), fields(r, theta) -> grad."""
    gf, gw = np.polynomial.legendre.leggauss(n)
    s = (gf + 1) / 2 * np.sqrt(R)
    rf, wf = s**2, gw / 2 * np.sqrt(R) * 2 * s
    parts = []
    for side in (1.0, -1.0):
        g = fields(rf, np.full(n, side * np.pi))
        t = np.tile(np.array(traction) * [1.0, side], (n, 1))  # pressure p: +p e2 up, -p e2 down
        parts.append((TIP.x + rotate_vectors(np.column_stack([-rf, 0 * rf]), TIP.angle), wf,
                      rotate_vectors(t, TIP.angle), rotate_gradient(g, TIP.angle), np.full(n, side)))
    return FaceLoad(*(np.concatenate([p[i] for p in parts]) for i in range(5)))


def test_face_term_of_j2_with_a_t_stress():
    """K_II with a T-stress puts different W on the two faces: J'_2 is exact only with the face term."""
    m = Elastic(2.0, 0.3, "strain", rho=1.5)
    KI, KII, acc, T0 = 1.3, -0.6, np.array([0.7, -0.4]), 0.9
    J2 = -2 * KI * KII / m.E_prime
    off = []
    for R in RADII:
        loc, r, th, w = polar_rule(R)
        g, s = accelerated_field(m, loc, r, th, KI, KII, acc, T0)
        one = np.ones((len(r), 1))
        x, S, G, v, a = to_global(loc, s, g, one * acc * 0.5, one * acc)
        faces = face_points(m, R, lambda rr, tt: accelerated_field(
            m, np.column_stack([rr * np.cos(tt), rr * np.sin(tt) * 0]), rr, tt, KI, KII, acc, T0)[0])
        fv = np.tile(rotate_vectors((acc * 0.5)[None], TIP.angle), (len(faces.x), 1))
        it = dynamic_integrands(x, w, S, G, v, a, None, TIP, m, R, np.zeros_like(G))
        res = contract_dynamic(it, QFunction("wendland_c2", R), faces, fv)
        assert res.J2 == pytest.approx(J2, rel=1e-13)
        assert res.J1 == pytest.approx((KI**2 + KII**2) / m.E_prime, rel=1e-13)
        off.append(contract_dynamic(it, QFunction("wendland_c2", R)).J2 - J2)
        with pytest.raises(ValueError, match="needs face_velocity"):
            contract_dynamic(it, QFunction("wendland_c2", R), faces)
    assert min(np.abs(off)) > 0.1  # measured 0.26 .. 0.48 without the face term


def test_pressurised_faces_with_a_uniform_field():
    """sigma = (s11, -p, 0) with pressure p on the faces: no singularity, J'_1 = J'_2 = K = 0."""
    m = Elastic(1.0, 0.3, "strain", rho=1.0)
    p, e = 0.7, m.compliance() @ np.array([0.4, -0.7, 0.0])
    g = np.array([[e[0], 0.0], [0.0, e[1]]])
    for R in RADII:
        loc, r, th, w = polar_rule(R)
        G = np.tile(g, (len(r), 1, 1))
        x, S, GG = to_global(loc, stress_of(G, m), G)
        z = np.zeros_like(x)
        faces = face_points(m, R, lambda rr, tt: np.tile(g, (len(rr), 1, 1)), traction=(0.0, p))
        res = contract_dynamic(dynamic_integrands(x, w, S, GG, z, z, None, TIP, m, R),
                               QFunction("wendland_c2", R), faces)
        assert np.abs([res.J1, res.J2, res.KI, res.KII]).max() < 1e-14


@pytest.mark.parametrize("frac", [0.3, 0.6])
def test_moving_crack_j_prime_gives_eq_33(frac):
    """J' of the steadily moving crack field equals seed 002 Eq. 33 with the velocity functions
    on every domain (this checks the printed A_IV too), and Eq. 38 returns K_I, K_II."""
    m = Elastic(1.0, 0.3, "strain", rho=1.0)
    V = frac * m.c_shear
    KI, KII = 1.3, -0.6
    A_I, A_II, A_IV = (float(a) for a in velocity_functions(V, m))
    loc, r, th, w = ring_rule((0.5, 0.75, 1.0), 48)
    u, g, h = moving_crack_fields(loc, KI, KII, V, m.mu, m.c_dilatational, m.c_shear)
    x, S, G, v, a = to_global(loc, stress_of(g, m), g, -V * g[:, :, 0], V**2 * h[:, :, 0, 0])
    gv = rotate_gradient(-V * h[:, :, 0, :], TIP.angle)
    res = dynamic_tip_result(TIP, x, w, S, G, v, a, None, (0.5, 0.75, 1.0), m, speed=V, grad_v=gv,
                             opening=A_I * KI, sliding=A_II * KII)
    for d in res.domains:
        assert d.J1 == pytest.approx((A_I * KI**2 + A_II * KII**2) / (2 * m.mu), rel=1e-13)
        assert d.J2 == pytest.approx(-A_IV * KI * KII / m.mu, rel=1e-13)
    assert (res.KI_J, res.KII_J) == pytest.approx((KI, KII), rel=1e-13)
    assert res.KI is None and res.spread is None and res.spread_J < 1e-13
    # the W - T form is for stationary cracks only
    with pytest.raises(ValueError, match="needs grad_v"):
        dynamic_tip_result(TIP, x, w, S, G, v, a, None, (0.5, 0.75, 1.0), m, speed=V)


def test_dynamic_tip_result_side_by_side():
    m = Elastic(2.0, 0.3, "strain", rho=1.5)
    KI, KII, acc = 1.3, -0.6, np.array([0.7, -0.4])
    loc, r, th, w = polar_rule(1.0, 32)
    g, s = accelerated_field(m, loc, r, th, KI, KII, acc)
    one = np.ones((len(r), 1))
    x, S, G, v, a = to_global(loc, s, g, one * acc, one * acc)
    res = dynamic_tip_result(TIP, x, w, S, G, v, a, None, [1.0, 1.0, 1.0], m, q="power")
    assert (res.KI, res.KII, res.KI_J, res.KII_J) == pytest.approx((KI, KII, KI, KII), rel=1e-12)
    d = res.as_dict()
    assert d["KI"] == res.KI and len(d["domains"]) == 3


def test_dynamic_integral_errors():
    m = Elastic(1.0, 0.3, rho=1.0)
    loc, r, th, w = polar_rule(1.0, 8)
    g = williams_gradient(r, th, 1.0, 0.0, m.mu, m.kappa)
    x, S, G = to_global(loc, stress_of(g, m), g)
    z = np.zeros_like(x)
    with pytest.raises(TypeError, match="rho must be one number"):
        dynamic_integrands(x, w, S, G, z, z, np.ones(len(w)), TIP, m, 1.0)
    with pytest.raises(ValueError, match="rho is None and the material has no density"):
        dynamic_integrands(x, w, S, G, z, z, None, TIP, Elastic(1.0, 0.3), 1.0)
    with pytest.raises(ValueError, match="rho must be finite and > 0"):
        dynamic_integrands(x, w, S, G, z, z, -1.0, TIP, m, 1.0)
    bad = z.copy()
    bad[5] = np.nan
    with pytest.raises(ValueError, match=r"acceleration at point 5 .* is not finite"):
        dynamic_integrands(x, w, S, G, z, bad, None, TIP, m, 1.0)
    with pytest.raises(ValueError, match=r"velocity must have shape \(64, 2\), got \(64, 1\)"):
        dynamic_integrands(x, w, S, G, z[:, :1], z, None, TIP, m, 1.0)
    with pytest.raises(ValueError, match="holds no points"):
        dynamic_integrands(x + 10.0, w, S, G, z, z, None, TIP, m, 1.0)
    with pytest.raises(ValueError, match="at least three radii"):
        dynamic_tip_result(TIP, x, w, S, G, z, z, None, [0.5, 1.0], m)
    with pytest.raises(ValueError, match="speed must be finite and >= 0"):
        dynamic_tip_result(TIP, x, w, S, G, z, z, None, RADII, m, speed=-1.0)
    with pytest.raises(TypeError, match="integrands must be DynamicIntegrands"):
        contract_dynamic(None, QFunction("wendland_c2", 1.0))


# --- near-tip estimates (seed 000 Eqs. 5.2-5.5, extended to a moving tip) --------------------


@pytest.mark.parametrize("theta", [0.0, np.pi / 2, -1.0])
def test_near_tip_stress_estimate_of_a_moving_crack(theta):
    m = Elastic(1.0, 0.3, rho=1.0)
    V, KI, KII = 0.5 * m.c_shear, 1.2, -0.7
    r = np.array([0.01, 0.05])
    loc = np.column_stack([r * np.cos(theta), r * np.sin(theta)])
    s = rotate_voigt(stress_of(moving_crack_fields(loc, KI, KII, V, m.mu, m.c_dilatational,
                                                   m.c_shear)[1], m), TIP.angle)
    got = k_from_stress(TIP, r, s, theta, speed=V, material=m)
    assert np.allclose(got, [[KI, KI], [KII, KII]], rtol=1e-12)
    if theta == np.pi / 2:  # the static (Williams) reading is off for a moving tip
        static = k_from_stress(TIP, r, s, theta)
        assert abs(static[0][0] / KI - 1) > 0.05
    with pytest.raises(ValueError, match="speed must lie in"):
        k_from_stress(TIP, r, s, theta, speed=m.c_shear, material=m)
    with pytest.raises(TypeError, match="needs the material"):
        k_from_stress(TIP, r, s, theta, speed=V)


def test_pressurised_griffith_crack_under_acceleration():
    """The pressurised Griffith crack (efgkit.problem.exact.griffith, K_I = p sqrt(pi a)) plus the
    accelerated smooth field: the face term and the inertia term together give J'_1 = K^2 / E'
    on every domain."""
    from efgkit.problem.exact.griffith import griffith_field

    m = Elastic(2.0, 0.3, "strain", rho=1.5)
    lam, mu = m.lame
    a, p, acc = 1.0, 0.8, np.array([0.7, -0.4])
    tip = Tip(np.array([a, 0.0]), 0.0, "c", 1)
    K = p * np.sqrt(np.pi * a)

    def grad(x):  # tip-frame = global here; the accelerated part as in accelerated_field
        g = griffith_field(x, a, p, m.mu, m.kappa)[1]
        g[:, 0, 1] += m.rho * acc[0] / mu * x[:, 1]
        g[:, 1, 1] += m.rho * acc[1] / (lam + 2 * mu) * x[:, 1]
        return g

    gf, gw = np.polynomial.legendre.leggauss(12)
    for R in (0.2, 0.35, 0.5):
        loc, r, th, w = polar_rule(R)
        x = tip.x + loc
        g = grad(x)
        one = np.ones((len(r), 1))
        s = np.sqrt(R) * (gf + 1) / 2
        rf, wf = s**2, gw / 2 * np.sqrt(R) * 2 * s
        xf = np.concatenate([np.column_stack([a - rf, 0 * rf]), np.column_stack([a - rf, -0.0 * rf])])
        side = np.repeat([1.0, -1.0], len(rf))
        faces = FaceLoad(xf, np.tile(wf, 2), np.column_stack([0 * side, side * p]), grad(xf), side)
        for grad_v in (None, np.zeros_like(g)):
            it = dynamic_integrands(x, w, stress_of(g, m), g, one * acc, one * acc, None, tip, m, R,
                                    grad_v)
            res = contract_dynamic(it, QFunction("wendland_c2", R), faces, one[:len(xf)] * acc)
            assert res.J1 == pytest.approx(K**2 / m.E_prime, rel=1e-12)
            assert res.KI == pytest.approx(K, rel=1e-12)
            assert abs(res.J2) < 1e-13 and abs(res.KII) < 1e-13
        res = contract_dynamic(it, QFunction("wendland_c2", R), None, None)
        # measured without the face term: J'_1 48 % to 73 % low (r_out = 0.2 .. 0.5)
        assert res.J1 / (K**2 / m.E_prime) - 1 < -0.3
