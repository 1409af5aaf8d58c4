"""J, K_I, K_II and T from domain integrals of fields at points (efgkit.fracture.integrals).

The exact fields are sampled on a polar Gauss rule about the tip, with
``r = s^2`` (so the ``r^{+-1/2}`` terms become polynomials in ``s``), blocks
split at the breakpoints of ``q``, and ``theta`` running from ``-pi`` to ``pi``
so that no block straddles the crack faces: the integrals are then exact to
rounding, and every tolerance below is a rounding tolerance unless a comment
says it is a measured quadrature error.
"""

import json
import math
import warnings

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from efgkit import Crack, Domain, Elastic, Scene  # noqa: E402
from efgkit.fracture.integrals import SIF, FaceLoad, contract, domain_integrals, domain_integrands, k_from_j
from efgkit.fracture.qfunctions import QFunction  # noqa: E402
from efgkit.fracture.sif import TipResult, default_radii, tip_result  # noqa: E402
from efgkit.fracture.volumes import nodal_volumes  # noqa: E402
from efgkit.plot import plot_domain_dependence  # noqa: E402
from efgkit.problem.crack import Tip  # noqa: E402
from efgkit.problem.exact.griffith import griffith_field  # noqa: E402
from efgkit.problem.exact.williams import williams_displacement, williams_gradient, williams_stress
from efgkit.problem.frames import rotate_gradient, rotate_vectors, rotate_voigt, tip_polar
from efgkit.problem.geometry import Loop  # noqa: E402
from efgkit.quadrature.cells import cell_points  # noqa: E402

KI, KII, T = 1.3, -0.6, 0.45


def polar_rule(centre, angle, r_out, breaks=(), nr=12, nt=64):
    """Gauss rule on the disc ``r < r_out`` about ``centre``: x (n, 2), w (n,), r (n,), theta (n,).

    ``theta`` is the tip-frame angle of a frame at ``angle``; radial blocks in
    ``s = sqrt(r)`` end at ``breaks``.
    """
    edges = np.sqrt(np.array([0.0, *sorted(b for b in breaks if 0 < b < r_out), r_out]))
    tr, tw = np.polynomial.legendre.leggauss(nr)
    lo, hi = edges[:-1, None], edges[1:, None]
    s = ((lo + hi) / 2 + (hi - lo) / 2 * tr).ravel()
    ws = ((hi - lo) / 2 * tw).ravel()
    tt, twt = np.polynomial.legendre.leggauss(nt)
    S, TH = (a.ravel() for a in np.meshgrid(s, np.pi * tt, indexing="ij"))
    w = np.outer(2 * s**3 * ws, np.pi * twt).ravel()  # dA = r dr dtheta = 2 s^3 ds dtheta
    r = S**2
    x = np.asarray(centre, float) + rotate_vectors(np.column_stack([r * np.cos(TH), r * np.sin(TH)]),
                                                   angle)
    return x, w, r, TH


def williams_field(r, theta, angle, m, KI=KI, KII=KII, T=T):
    """Global stress (n, 3) and grad_u (n, 2, 2) of Williams K_I, K_II plus sigma_11 = T."""
    s = williams_stress(r, theta, KI, KII)
    s[:, 0] += T
    g = williams_gradient(r, theta, KI, KII, m.mu, m.kappa)
    e = m.compliance() @ [T, 0.0, 0.0]
    g[:, 0, 0] += e[0]
    g[:, 1, 1] += e[1]
    return rotate_voigt(s, angle), rotate_gradient(g, angle)


def breaks_of(q):
    return {"cubic_spline": [q.r_out / 2], "plateau": [q.r_in]}.get(q.kind, [])


Q_CASES = [("wendland_c2", {}), ("cubic_spline", {}), ("power", {"n": 2}), ("power", {"n": 4}),
           ("plateau", {"r_in": 0.3}), ("plateau", {"r_in": 0.0})]
TIPS = [((0.0, 0.0), 0.0), ((3.0, -2.0), 0.7), ((-1.5, 4.0), -2.5), ((10.0, 10.0), math.pi - 1e-3)]


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("tip_x, angle", TIPS)
@pytest.mark.parametrize("kind, opts", Q_CASES)
def test_exact_williams_field_every_q(kind, opts, tip_x, angle, plane):
    m = Elastic(7.0, 0.3, plane)
    tip = Tip(np.array(tip_x), angle, "c", 1)
    q = QFunction(kind, 0.8, **opts)
    x, w, r, th = polar_rule(tip.x, angle, q.r_out, breaks_of(q))
    s, g = williams_field(r, th, angle, m)
    res = domain_integrals(x, w, s, g, tip, m, q)
    K = math.hypot(KI, KII)
    assert abs(res.KI - KI) < 1e-10 * K and abs(res.KII - KII) < 1e-10 * K
    assert abs(res.T - T) < 1e-10 * K / math.sqrt(q.r_out)
    assert res.J == pytest.approx((KI**2 + KII**2) / m.E_prime, rel=1e-10)  # Irwin
    assert res.KJ == pytest.approx(math.sqrt(KI**2 + KII**2), rel=1e-10)
    assert res.n_points == len(x) and res.radius == q.r_out and res.mismatch < 1e-12


def _scene(tip_x=(0.0, 0.0), angle=0.3, extra=()):
    """A square plate with an edge crack ending at ``tip_x``, coming in along ``angle``."""
    tip_x = np.asarray(tip_x, float)
    dom = Domain.rectangle(tip_x[0] - 5, tip_x[1] - 5, tip_x[0] + 5, tip_x[1] + 5)
    # the mouth on the boundary: clip the straight crack at the square
    t = min(5 / max(abs(math.cos(angle)), 1e-12), 5 / max(abs(math.sin(angle)), 1e-12))
    mouth = tip_x - t * np.array([math.cos(angle), math.sin(angle)])
    cracks = (Crack([mouth, tip_x], tips=(False, True), name="a"), *extra)
    return Scene(dom, Elastic(200.0, 0.3), cracks=cracks)


@pytest.mark.parametrize("kind", ["wendland_c2", "cubic_spline", "plateau", "power"])
def test_path_independence_over_radii(kind):
    sc = _scene((1.0, 2.0), 0.3)
    tip = sc.tips[0]
    radii = [0.5, 1.0, 1.5, 2.0]
    x, w, r, th = polar_rule(tip.x, tip.angle, 2.0, [*radii, *(0.5 * np.array(radii))], nr=10)
    s, g = williams_field(r, th, tip.angle, sc.material)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = tip_result(sc, tip, x, w, s, g, radii, q=kind)
    assert res.spread < 1e-10 and res.warnings == ()
    assert res.KI == pytest.approx(KI, rel=1e-10) and res.KII == pytest.approx(KII, rel=1e-10)
    assert res.T == pytest.approx(T, rel=1e-9) and len(res.domains) == 4
    assert [d.radius for d in res.domains] == radii


def test_sign_convention_and_mirror():
    """K_II > 0: upper face slides +x1 relative to the lower; mirroring flips K_II only."""
    m = Elastic(1.0, 0.25, "stress")
    u = williams_displacement([0.1, 0.1], [np.pi, -np.pi], 0.0, 1.0, m.mu, m.kappa)
    assert u[0, 0] - u[1, 0] > 0  # the convention the module docstring states
    angle = 0.9
    tip = Tip(np.array([2.0, -1.0]), angle, "c", 1)
    q = QFunction("wendland_c2", 0.5)
    x, w, r, th = polar_rule(tip.x, angle, 0.5)
    s, g = williams_field(r, th, angle, m)
    base = domain_integrals(x, w, s, g, tip, m, q)
    # mirror about the crack line (tip frame): u'(x1, x2) = (u1, -u2)(x1, -x2)
    sl, gl = williams_field(r, -th, 0.0, m)
    flip = np.array([1.0, -1.0])
    sm = rotate_voigt(sl * [1.0, 1.0, -1.0], angle)
    gm = rotate_gradient(gl * flip[:, None] * flip[None, :], angle)
    mir = domain_integrals(x, w, sm, gm, tip, m, q)
    assert base.KII == pytest.approx(KII, rel=1e-10) and mir.KII == pytest.approx(-KII, rel=1e-10)
    assert mir.KI == pytest.approx(base.KI, rel=1e-10) and mir.T == pytest.approx(base.T, rel=1e-10)
    assert mir.J == pytest.approx(base.J, rel=1e-10)


def _griffith(a, p, m, R, angle=0.0, centre=(0.0, 0.0), nf=24):
    """Domain and face samples around the right tip of a pressurised Griffith crack."""
    c = np.asarray(centre, float)
    tip = Tip(c + a * np.array([math.cos(angle), math.sin(angle)]), angle, "g", 1)
    x, w, r, th = polar_rule(tip.x, angle, R, nr=16, nt=64)
    local = rotate_vectors(x - c, -angle)
    _, g, s = griffith_field(local, a, p, m.mu, m.kappa)
    tr, tw = np.polynomial.legendre.leggauss(nf)
    sf = math.sqrt(R) * (tr + 1) / 2  # r = s^2 on the faces too: the r^-1/2 of u^a
    rf, wf = sf**2, math.sqrt(R) * tw * sf
    up = np.column_stack([a - rf, np.zeros(nf)])
    lo = np.column_stack([a - rf, np.full(nf, -0.0)])
    gf = np.concatenate([griffith_field(up, a, p, m.mu, m.kappa)[1],
                         griffith_field(lo, a, p, m.mu, m.kappa)[1]])
    t = np.concatenate([np.tile([0.0, p], (nf, 1)), np.tile([0.0, -p], (nf, 1))])
    faces = FaceLoad(c + rotate_vectors(np.concatenate([up, lo]), angle), np.concatenate([wf, wf]),
                     rotate_vectors(t, angle), rotate_gradient(gf, angle),
                     np.concatenate([np.ones(nf), -np.ones(nf)]))
    return tip, x, w, rotate_voigt(s, angle), rotate_gradient(g, angle), faces


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("R, angle, centre", [(0.2, 0.0, (0.0, 0.0)), (0.5, 1.1, (3.0, -4.0)),
                                              (1.0, -2.0, (0.0, 0.0))])
def test_pressurised_griffith_crack_needs_the_face_term(R, angle, centre, plane):
    a, p = 1.0, 2.0
    m = Elastic(7.0, 0.3, plane)
    tip, x, w, s, g, faces = _griffith(a, p, m, R, angle, centre)
    K = p * math.sqrt(math.pi * a)  # Westergaard (1939): K_I = p sqrt(pi a), griffith.griffith_field
    q = QFunction("wendland_c2", R)
    res = domain_integrals(x, w, s, g, tip, m, q, faces)
    assert res.KI == pytest.approx(K, rel=1e-10) and abs(res.KII) < 1e-10 * K
    assert res.J == pytest.approx(K**2 / m.E_prime, rel=1e-10)
    assert res.T == pytest.approx(-p, rel=1e-9)  # T = -p for a pressurised crack
    no_face = domain_integrals(x, w, s, g, tip, m, q)
    # measured: -25% (R = 0.2 a), -39% (0.5 a), -55% (a) without the face term
    assert no_face.KI / K - 1 < -0.2


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("sig", [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 1.0, 0.0), (0.4, -0.7, 0.0)])
def test_uniform_stress_gives_T_only(sig, plane):
    """A uniform field with its face tractions: K = 0, J = 0, T = sigma_11 (E' I = s11 - s22)."""
    m = Elastic(3.0, 0.3, plane)
    tip = Tip(np.array([0.5, 0.5]), 0.4, "c", 1)
    R, nf = 0.5, 30
    x, w, r, th = polar_rule(tip.x, tip.angle, R)
    sig = np.asarray(sig)
    e = m.compliance() @ sig
    G = np.array([[e[0], e[2] / 2], [e[2] / 2, e[1]]])
    s = rotate_voigt(np.tile(sig, (len(x), 1)), tip.angle)
    g = rotate_gradient(np.tile(G, (len(x), 1, 1)), tip.angle)
    tr, tw = np.polynomial.legendre.leggauss(nf)
    sf = math.sqrt(R) * (tr + 1) / 2
    loc = np.concatenate([np.column_stack([-sf**2, np.zeros(nf)])] * 2)
    t = np.concatenate([np.tile(-sig[[2, 1]], (nf, 1)), np.tile(sig[[2, 1]], (nf, 1))])
    faces = FaceLoad(tip.x + rotate_vectors(loc, tip.angle), np.tile(math.sqrt(R) * tw * sf, 2),
                     rotate_vectors(t, tip.angle), g[:2 * nf], np.repeat([1.0, -1.0], nf))
    res = domain_integrals(x, w, s, g, tip, m, QFunction("wendland_c2", R), faces)
    assert abs(res.KI) < 1e-10 and abs(res.KII) < 1e-10 and abs(res.J) < 1e-10
    assert res.T == pytest.approx(sig[0], abs=1e-10)


@pytest.mark.parametrize("L, shift", [(1e3, 0.0), (1e-3, 0.0), (1.0, 1e6), (1e3, 1e6)])
def test_units_and_translation_invariance(L, shift):
    S = 1e6 if L < 1 else 1e-3  # stress unit change that goes with the length change
    m0, m1 = Elastic(200.0, 0.3), Elastic(200.0 * S, 0.3)
    tip0 = Tip(np.array([0.3, 0.2]), 0.4, "c", 1)
    tip1 = Tip(tip0.x * L + shift * np.array([1.0, -1.0]), 0.4, "c", 1)
    x, w, r, th = polar_rule(tip0.x, 0.4, 0.5)
    s, g = williams_field(r, th, 0.4, m0)
    base = domain_integrals(x, w, s, g, tip0, m0, QFunction("wendland_c2", 0.5))
    k = S * math.sqrt(L)  # K scales as stress * sqrt(length)
    s1, g1 = williams_field(r * L, th, 0.4, m1, KI=KI * k, KII=KII * k, T=T * S)
    x1 = tip1.x + (x - tip0.x) * L
    res = domain_integrals(x1, w * L * L, s1, g1, tip1, m1, QFunction("wendland_c2", 0.5 * L))
    assert res.KI / k == pytest.approx(base.KI, rel=1e-8)
    assert res.KII / k == pytest.approx(base.KII, rel=1e-8)
    assert res.T / S == pytest.approx(base.T, rel=1e-8)
    assert res.J / (S * L) == pytest.approx(base.J, rel=1e-8)


def test_k_from_j():
    m = Elastic(210e3, 0.3)  # plane strain: E' = E / (1 - nu^2) = 2 mu / (1 - nu), seed 000 Eq. 5.7
    J = 0.01
    assert k_from_j(J, m) == pytest.approx(math.sqrt(2 * m.mu * J / (1 - m.nu)), rel=1e-14)
    with pytest.raises(ValueError, match="J must be finite and >= 0"):
        k_from_j(-1.0, m)


# --- realistic quadrature: what the lead's EFG cells will see --------------------------

@pytest.mark.parametrize("n, order, kind, bound_K, bound_T", [
    # square [-1, 1]^2, tip at the centre, crack along -x1, r_out = 0.6, K_I = 1, K_II = 0.5,
    # T = 0.3, exact Williams field at the points of efgkit.quadrature.cells.cell_points.
    # Measured |K - K_exact| (K_I, K_II) and |T - T_exact|:
    # n = 20 (crack on cell edges, tip at a corner), order 4: wendland 7.0e-6, 1.9e-6 (T 5.7e-3);
    #   plateau 2.5e-5, 1.1e-5 (T 6.7e-5)
    (20, 4, "wendland_c2", 2e-5, 1e-2),
    (20, 4, "plateau", 5e-5, 2e-4),
    # n = 21 (tip at a cell centre, the middle row of cells cut by the crack, no splitting),
    # order 4 (no point on the crack line): wendland 7.4e-5, 2.7e-5 (T 2.3e-2);
    #   plateau 1.2e-4, 4.9e-5 (T 4.3e-4); order 2: up to 2.6e-3 (plateau)
    (21, 4, "wendland_c2", 2e-4, 5e-2),
    (21, 4, "plateau", 3e-4, 1e-3),
    # n = 41, order 4: wendland 2.9e-5, 3.6e-6 (T 9.2e-3); plateau 7.9e-5, 4.2e-5 (T 5.6e-5)
    (41, 4, "wendland_c2", 1e-4, 2e-2),
    (41, 4, "plateau", 2e-4, 2e-4),
    # odd orders put Gauss points ON the crack line (taken as the upper face on both sides of
    # the computation): K_II errors 1.6e-2 (n = 21, order 3, wendland), 7.5e-3 (plateau),
    # 2e-3 at n = 81. Avoid points on the crack line.
    # For comparison (not asserted: work in progress when measured), cell_points(...,
    # cracks=(crack,)) splitting the cut cells and fanning the tip cell gave, order 3 / 4:
    # wendland |dK| <= 2.4e-4 / 5.2e-5 and |dT| 1.2e-3 / 2.5e-4 at n = 21, 6.3e-5 / 9.7e-6
    # and 4.6e-4 / 9.1e-5 at n = 41; plateau |dK| ~1e-4 (its C1 kink at r_in inside cells).
    (21, 3, "wendland_c2", 3e-2, 0.3),
    (21, 3, "plateau", 1.5e-2, 5e-2),
])
def test_cell_quadrature_accuracy(n, order, kind, bound_K, bound_T):
    m = Elastic(1.0, 0.3)
    tip = Tip(np.zeros(2), 0.0, "c", 1)
    pts = cell_points(Domain.rectangle(-1, -1, 1, 1), 2.0 / n, order)
    r, th = tip_polar(pts.x, tip.x, 0.0)
    on_line = (np.abs(pts.x[:, 1]) <= 1e-12) & (pts.x[:, 0] < 0)
    th[on_line] = np.pi  # the convention of domain_integrals: on the line = upper face
    ok = r > 1e-12
    s = np.full((len(r), 3), np.inf)
    g = np.full((len(r), 2, 2), np.inf)  # a point at the tip is ignored, even if infinite
    s[ok], g[ok] = williams_field(r[ok], th[ok], 0.0, m, KI=1.0, KII=0.5, T=0.3)
    res = domain_integrals(pts.x, pts.w, s, g, tip, m, QFunction(kind, 0.6))
    assert abs(res.KI - 1.0) < bound_K and abs(res.KII - 0.5) < bound_K
    assert abs(res.T - 0.3) < bound_T


# --- point-wise evaluation (seed 001 Eq. 8) ---------------------------------------------

def test_pointwise_evaluation_on_nodes():
    m = Elastic(1.0, 0.3)
    dom = Domain.rectangle(-1, -1, 1, 1)
    tip = Tip(np.zeros(2), 0.0, "c", 1)
    g1 = np.linspace(-1, 1, 41)
    nodes = np.column_stack([a.ravel() for a in np.meshgrid(g1, g1)]) + [0.37 * 0.05, 0.29 * 0.05]
    nodes = nodes[dom.contains(nodes)]
    V = nodal_volumes(nodes, dom)
    r, th = tip_polar(nodes, tip.x, 0.0)
    s, g = williams_field(r, th, 0.0, m, KI=1.0, KII=0.5, T=0.3)
    res = domain_integrals(nodes, V, s, g, tip, m, QFunction("wendland_c2", 0.6))
    # measured: 453 nodes in the disc, K_I -1.2e-3, K_II -1.0e-3 (1.2e-4 / 1.7e-3 at 1811
    # nodes); seed 001 Sect. 10 finds ~2.5% at ~500 particles for a computed SPH field
    assert res.n_points == 453
    assert abs(res.KI - 1.0) < 3e-3 and abs(res.KII - 0.5) < 3e-3


def test_pointwise_with_a_node_at_the_tip_is_finite():
    m = Elastic(1.0, 0.3)
    g1 = np.linspace(-1, 1, 21)
    nodes = np.column_stack([a.ravel() for a in np.meshgrid(g1, g1)])  # (0, 0) is a node
    tip = Tip(np.zeros(2), 0.0, "c", 1)
    r, th = tip_polar(nodes, tip.x, 0.0)
    th = np.where((np.abs(nodes[:, 1]) < 1e-12) & (nodes[:, 0] < 0), np.pi, th)
    s, g = np.full((len(r), 3), np.inf), np.full((len(r), 2, 2), np.inf)
    s[r > 0], g[r > 0] = williams_field(r[r > 0], th[r > 0], 0.0, m, KI=1.0, KII=0.0, T=0.0)
    res = domain_integrals(nodes, np.full(len(r), 0.01), s, g, tip, m, QFunction("plateau", 0.6))
    assert all(np.isfinite([res.J, res.KI, res.KII, res.T]))
    assert abs(res.KI - 1.0) < 0.05  # measured -1.67e-2 (21 x 21 nodes, 108 in the disc)


def test_nodal_volumes():
    dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1.4, 0.5], 0.2)])
    rng = np.random.default_rng(2)
    x = rng.uniform([0, 0], [2, 1], (300, 2))
    x = x[dom.contains(x)]
    V = nodal_volumes(x, dom)
    assert V.sum() == pytest.approx(dom.area, rel=1e-12) and np.all(V >= 0)
    assert np.allclose(nodal_volumes(x, dom, "uniform"), dom.area / len(x))
    g = (np.arange(10) + 0.5) / 10
    grid = np.column_stack([a.ravel() for a in np.meshgrid(g, g)])
    Vg = nodal_volumes(grid, Domain.rectangle(0, 0, 1, 1), samples_per_node=100)
    assert np.allclose(Vg, 0.01, rtol=0.05)  # sampled Voronoi cells: a few % per cell
    with pytest.raises(ValueError, match="method must be"):
        nodal_volumes(x, dom, "delaunay")


# --- tip_result: verdicts, warnings, errors ---------------------------------------------

def _samples(sc, tip, R=2.0, breaks=()):
    breaks = [*breaks, *(0.5 * np.asarray(breaks))]  # q's outer radii and plateau r_in
    x, w, r, th = polar_rule(tip.x, tip.angle, R, breaks, nr=8, nt=48)
    s, g = williams_field(r, th, tip.angle, sc.material)
    return x, w, s, g


def test_spread_warning_for_a_domain_dependent_field():
    a, p = 1.0, 2.0
    sc = Scene(Domain.rectangle(-3, -3, 3, 3), Elastic(7.0, 0.3),
               cracks=(Crack([[-a, 0.0], [a, 0.0]], name="g"),))
    tip = sc.tips[1]
    x, w, r, th = polar_rule(tip.x, 0.0, 1.0, [0.2, 0.5], nr=12)
    _, g, s = griffith_field(x, a, p, sc.material.mu, sc.material.kappa)
    with pytest.warns(UserWarning, match=r"tip g:1: K depends on the domain: spread"):
        res = tip_result(sc, tip, x, w, s, g, [0.2, 0.5, 1.0])  # faces loaded, not given
    assert res.spread > 0.2 and len(res.warnings) == 1
    # spread = max range of K over domains / |mean K|
    KIs = [d.KI for d in res.domains]
    assert res.spread == pytest.approx((max(KIs) - min(KIs)) / abs(np.mean(KIs)), rel=1e-12)


@pytest.mark.parametrize("radii, extra, match", [
    ([0.5, 1.0, 6.0], (), r"radius 6 leaves the body"),
    ([0.5, 1.0, 1.9], (Crack([[1.0, 1.5], [3.0, 1.5]], name="b"),), r"radius 1.9 holds another tip"),
    ([0.5, 1.0, 1.7], (Crack([[-1.0, 1.5], [3.0, 1.5]], name="b"),), r"radius 1.7 crosses another crack"),
])
def test_geometry_warnings(radii, extra, match):
    sc = _scene((0.0, 0.0), 0.0, extra)
    tip = sc.tips[0]
    x, w, s, g = _samples(sc, tip, R=max(radii), breaks=radii)
    with pytest.warns(UserWarning, match=match):
        res = tip_result(sc, tip, x, w, s, g, radii)
    assert len(res.warnings) == 1 and res.spread < 1e-10  # the field is exact: only geometry


def test_kink_warning():
    sc = Scene(Domain.rectangle(-5, -5, 5, 5), Elastic(200.0, 0.3),
               cracks=(Crack([[-5.0, -1.0], [-1.0, 0.0], [-0.5, 0.0], [0.0, 0.0]],
                             tips=(False, True), name="k"),))
    tip = sc.tips[0]
    x, w, s, g = _samples(sc, tip, R=1.5, breaks=[0.5, 0.9])
    with pytest.warns(UserWarning, match=r"radius 1.5 reaches a kink of its own crack \(at 1\)"):
        res = tip_result(sc, tip, x, w, s, g, [0.5, 0.9, 1.5])  # the collinear vertex is fine
    assert len(res.warnings) == 1


def test_plane_mismatch_warning():
    sc = _scene()
    tip = sc.tips[0]
    x, w, r, th = polar_rule(tip.x, tip.angle, 1.0)
    wrong = Elastic(200.0, 0.3, "stress")  # stress from plane stress, scene in plane strain
    s, g = williams_field(r, th, tip.angle, wrong)
    with pytest.warns(UserWarning, match="check the plane"):
        tip_result(sc, tip, x, w, s, g, [0.4, 0.6, 0.9])


def test_result_record_and_json():
    sc = _scene((1.0, 2.0), 0.3)
    tip = sc.tips[0]
    x, w, s, g = _samples(sc, tip, R=1.0, breaks=[0.5, 0.7, 1.0])
    res = tip_result(sc, tip, x, w, s, g, [1.0, 0.5, 0.7])
    assert isinstance(res, TipResult) and all(isinstance(d, SIF) for d in res.domains)
    d = json.loads(json.dumps(res.as_dict()))
    assert list(d) == ["id", "x", "y", "KI", "KII", "J", "T", "spread", "error", "domains",
                       "warnings"]
    assert d["error"] is None  # estimated by Solution.sifs, not by tip_result
    assert (d["x"], d["y"]) == (1.0, 2.0) and [e["radius"] for e in d["domains"]] == [0.5, 0.7, 1.0]
    assert set(d["domains"][0]) == {"radius", "KI", "KII", "J", "T", "n_points"}
    with pytest.raises(AttributeError):
        res.KI = 0.0  # frozen
    fig = plot_domain_dependence([res, res])
    assert len(fig.axes) == 6 and len(fig.axes[0].lines) == 2  # K_I, K_II, J per tip
    plt.close(fig)


def test_default_radii():
    sc = _scene((0.0, 0.0), 0.0)
    assert default_radii(sc, sc.tips[0], 0.1) == pytest.approx((1.0, 1.25, 1.5))
    r = default_radii(sc, sc.tips[0], 1.0)  # shrunk to 0.9 of the free radius 5, no warning
    assert r == pytest.approx((3.0, 3.75, 4.5))
    with pytest.raises(ValueError, match="at least three"):
        default_radii(sc, sc.tips[0], 0.1, multiples=(10, 20))


def test_bad_input_tip_result():
    sc = _scene()
    tip = sc.tips[0]
    x, w, s, g = _samples(sc, tip, R=1.0)
    with pytest.raises(ValueError, match=r"at least three radii, got 2"):
        tip_result(sc, tip, x, w, s, g, [0.5, 1.0])
    with pytest.raises(ValueError, match=r"tip a:1 .*radius 1e-09 holds no points"):
        tip_result(sc, tip, x, w, s, g, [1e-9, 0.5, 1.0])
    with pytest.raises(TypeError, match="tip must be an efgkit.problem.crack.Tip"):
        tip_result(sc, (0.0, 0.0), x, w, s, g, [0.3, 0.5, 1.0])
    with pytest.raises(ValueError, match="is not a tip of the scene"):
        tip_result(sc, Tip(np.array([9.0, 9.0]), 0.0, "a", 1), x, w, s, g, [0.3, 0.5, 1.0])
    with pytest.raises(ValueError, match="radii must be finite and > 0"):
        tip_result(sc, tip, x, w, s, g, [0.3, -0.5, 1.0])
    with pytest.raises(TypeError, match="scene must be a Scene"):
        tip_result(None, tip, x, w, s, g, [0.3, 0.5, 1.0])


def test_bad_input_domain_integrals():
    m = Elastic(1.0, 0.3)
    tip = Tip(np.zeros(2), 0.0, "c", 1)
    q = QFunction("wendland_c2", 0.5)
    x, w, r, th = polar_rule(tip.x, 0.0, 0.5)
    s, g = williams_field(r, th, 0.0, m)
    with pytest.raises(ValueError, match=r"stress must have shape \(768, 3\), got \(768, 2\)"):
        domain_integrals(x, w, s[:, :2], g, tip, m, q)
    with pytest.raises(ValueError, match=r"grad_u must have shape"):
        domain_integrals(x, w, s, g[:-1], tip, m, q)
    bad = s.copy()
    bad[5, 1] = np.nan
    with pytest.raises(ValueError, match="stress at point 5 .* is not finite"):
        domain_integrals(x, w, bad, g, tip, m, q)
    with pytest.raises(TypeError, match="q must be a QFunction"):
        domain_integrals(x, w, s, g, tip, m, "wendland_c2")
    with pytest.raises(TypeError, match="material must be an Elastic"):
        domain_integrals(x, w, s, g, tip, None, q)
    with pytest.raises(TypeError, match="tip must be an efgkit.problem.crack.Tip"):
        domain_integrals(x, w, s, g, np.zeros(2), m, q)
    with pytest.raises(ValueError, match=r"tip c:1 .* radius 0.5 holds no points"):
        domain_integrals(x + 10.0, w, s, g, tip, m, q)
    ahead = FaceLoad(np.array([[0.1, 0.0]]), [0.1], [[0.0, 1.0]], np.zeros((1, 2, 2)), [1])
    with pytest.raises(ValueError, match="not on the crack line behind tip c:1"):
        domain_integrals(x, w, s, g, tip, m, q, ahead)
    with pytest.raises(ValueError, match=r"FaceLoad.side must hold \+1"):
        FaceLoad(np.array([[-0.1, 0.0]]), [0.1], [[0.0, 1.0]], np.zeros((1, 2, 2)), [0])


def test_one_integrand_pass_serves_every_domain():
    """contract(domain_integrands(r_max), q) is domain_integrals(q) for every q inside r_max
    (tip_result forms the integrands once per tip)."""
    m = Elastic(2.0, 0.3)
    tip, x, w, s, g, faces = _griffith(1.0, 1.5, m, 1.0, angle=0.7, centre=(2.0, -1.0))
    terms = domain_integrands(x, w, s, g, tip, m, 1.0)
    for q in (QFunction("wendland_c2", 0.3), QFunction("plateau", 0.6, r_in=0.2),
              QFunction("power", 1.0, n=3.0), QFunction("cubic_spline", 0.45)):
        a, b = contract(terms, q, faces), domain_integrals(x, w, s, g, tip, m, q, faces)
        assert a.n_points == b.n_points and a.radius == b.radius
        for key in ("J", "KI", "KII", "T", "mismatch"):
            assert getattr(a, key) == pytest.approx(getattr(b, key), rel=1e-12, abs=1e-14), key
    with pytest.raises(ValueError, match=r"q.r_out = 1.5 exceeds the radius 1 the integrands"):
        contract(terms, QFunction("wendland_c2", 1.5))
    with pytest.raises(ValueError, match=r"radius 1e-09 holds no points \(nearest point at r = "):
        contract(terms, QFunction("wendland_c2", 1e-9))
    with pytest.raises(TypeError, match="faces must be a FaceLoad or None"):
        contract(terms, QFunction("wendland_c2", 0.5), faces="none")


# --- the fields the integrals are built on (efgkit.problem.exact.williams additions) ------------

def _fd_gradient(u, x, h=1e-6):
    """Central differences of ``u: x (n, 2) -> (n, 2)``, shape (n, 2, 2)."""
    return np.stack([(u(x + e) - u(x - e)) / (2 * h) for e in (np.array([h, 0.0]), np.array([0.0, h]))],
                    axis=-1)


def _strain(g):
    return np.column_stack([g[:, 0, 0], g[:, 1, 1], g[:, 0, 1] + g[:, 1, 0]])


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_field_gradients_and_compliance(plane):
    from efgkit.problem.exact.williams import (
        point_force_displacement,
        point_force_gradient,
        point_force_stress,
    )

    m = Elastic(3.0, 0.3, plane)
    rng = np.random.default_rng(1)
    x = rng.uniform(-1, 1, (60, 2))
    x = x[np.abs(x[:, 1]) > 0.05]  # off the crack line (the fields jump across it)

    def polar(y):
        return np.hypot(y[:, 0], y[:, 1]), np.arctan2(y[:, 1], y[:, 0])

    cases = [(lambda y: williams_displacement(*polar(y), 1.3, -0.7, m.mu, m.kappa),
              williams_gradient(*polar(x), 1.3, -0.7, m.mu, m.kappa), williams_stress(*polar(x), 1.3, -0.7)),
             (lambda y: point_force_displacement(*polar(y), 1.1, m.mu, m.kappa),
              point_force_gradient(*polar(x), 1.1, m.mu, m.kappa), point_force_stress(*polar(x), 1.1))]
    u_g = lambda y: griffith_field(y, 0.7, 2.0, m.mu, m.kappa)[0]  # noqa: E731
    _, gg, sg = griffith_field(x, 0.7, 2.0, m.mu, m.kappa)
    for u, g, s in [*cases, (u_g, gg, sg)]:
        assert np.allclose(g, _fd_gradient(u, x), rtol=0, atol=1e-8 * np.abs(g).max())
        assert np.allclose(_strain(g) @ m.D.T, s, rtol=0, atol=1e-12 * np.abs(s).max())


def test_point_force_balances_f_and_griffith_faces_carry_p():
    from efgkit.problem.exact.williams import point_force_stress

    t, tw = np.polynomial.legendre.leggauss(40)
    th, w = np.pi * t, np.pi * tw
    s = point_force_stress(np.full(40, 0.3), th, 2.0)
    n = np.column_stack([np.cos(th), np.sin(th)])
    traction = np.column_stack([s[:, 0] * n[:, 0] + s[:, 2] * n[:, 1], s[:, 2] * n[:, 0] + s[:, 1] * n[:, 1]])
    assert np.allclose(0.3 * w @ traction, [-2.0, 0.0], atol=1e-12)  # the disc holds the force f
    xf = np.array([[-0.5, 0.0], [0.2, -0.0], [0.69, 0.0]])
    _, _, sf = griffith_field(xf, 0.7, 2.0, 1.0, 1.8)
    assert np.allclose(sf[:, 1:], [[-2.0, 0.0]] * 3, atol=1e-12)  # sigma_yy = -p, sigma_xy = 0
    _, gfar, sfar = griffith_field(np.array([[3e4, -4e4]]), 0.7, 2.0, 1.0, 1.8)
    assert np.abs(sfar).max() < 1e-8 and np.abs(gfar).max() < 1e-8  # unloaded at infinity
    g = np.random.default_rng(0).normal(size=(5, 2, 2))
    assert np.allclose(rotate_gradient(rotate_gradient(g, 0.7), -0.7), g)


@pytest.mark.parametrize("end", [0, 1])
def test_points_on_the_crack_line_count_on_the_polylines_left_face(end):
    # regression: they counted on the tip frame's upper face, which is the polyline's right
    # face for a tip at its first vertex (solution and auxiliary field from opposite faces)
    m = Elastic(7.0, 0.3)
    sc = Scene(Domain.rectangle(-3, -3, 3, 3), m, cracks=(Crack([[-1.0, 0.0], [1.0, 0.0]], name="g"),))
    tip = next(t for t in sc.tips if t.end == end)
    x, w, r, th = polar_rule(tip.x, tip.angle, 1.0, nr=8, nt=48)
    behind = -np.cos(tip.angle)  # +x for the tip at (-1, 0), -x for (1, 0)
    line = tip.x + np.outer(np.linspace(0.1, 0.9, 9), [behind, 0.0])
    left = np.array([0.0, 1e-9])  # the polyline runs along +x: its left face is y > 0
    K = []
    for pts in (line, line + left):
        xa = np.vstack([x, pts])
        wa = np.concatenate([w, np.full(len(pts), 0.01)])
        d = (xa - tip.x) @ np.array([[np.cos(tip.angle), -np.sin(tip.angle)],
                                     [np.sin(tip.angle), np.cos(tip.angle)]])
        theta = np.arctan2(d[:, 1], d[:, 0])
        theta[len(x):] = np.pi if end == 1 else -np.pi  # the left face in the tip frame
        s, g = williams_field(np.hypot(*d.T), theta, tip.angle, m)
        res = domain_integrals(xa, wa, s, g, tip, m, QFunction("wendland_c2", 1.0))
        K.append((res.KI, res.KII, res.T))
    assert np.allclose(K[0], K[1], rtol=0, atol=1e-6)
