"""Crack-tip enrichment (seed 003 Sect. 5): intrinsic bases reproduce the branch functions where
the ramp is 1, the extrinsic spaces contain the Williams field, derivatives against finite
differences, the kinked-crack map (Eqs. 57-59), ramps, and the enrichment x crack-rule matrix."""

import functools
import math
import warnings
from dataclasses import replace

import numpy as np
import pytest

from efgkit import EFG, Crack, Domain, Elastic, Field, Scene, Support, solve
from efgkit.approx.tip_functions import TipGeometry, branch_functions, ramp, tip_coordinates, williams_modes
from efgkit.methods.discretize import approximation, discretize
from efgkit.nodes import generate_nodes
from efgkit.problem.exact.williams import williams_displacement

A = 1.0
MAT = Elastic(1000.0, 0.3, "strain")
SQUARE = Domain.rectangle(-A, -A, A, A)
EDGE = Crack([[-A, 0.0], [0.0, 0.0]], (False, True), "edge")
CRACKED = Scene(SQUARE, MAT, cracks=(EDGE,))
GEOM = TipGeometry.of(EDGE, 1)


def singular_patch() -> Scene:
    """Seed 003 Sect. 5.6.1: Williams mode I (k_I = 1, Eq. 60) prescribed on the boundary."""
    f = Field.named("williams", KI=1.0)
    edges = ("bottom", "right", "top", "left")
    return Scene(SQUARE, MAT, supports=tuple(Support(e, ux=f, uy=f) for e in edges),
                 cracks=(EDGE,), exact=f, name="singular_patch")


def _approx(n: int, **kw):
    m = EFG(spacing=2 * A / (n - 1), **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        nodes = generate_nodes(SQUARE, m, CRACKED.cracks)
        return approximation(CRACKED, m, nodes), nodes


def _points(rng, n, rmin, rmax):
    """Random points with rmin < r < rmax from the tip, off the crack line, shape (~n, 2)."""
    r = np.sqrt(rng.uniform(rmin**2, rmax**2, n))
    t = rng.uniform(-np.pi, np.pi, n)
    x = np.column_stack([r * np.cos(t), r * np.sin(t)])
    return x[(np.abs(x[:, 1]) > 1e-6) & (np.abs(x).max(axis=1) < A)]


# --- intrinsic enrichment ------------------------------------------------------------------

# crack on a node row (split face nodes) / between rows; see-through is refused, and so is the
# sqrt(r) basis with diffraction or transparency between rows (test_radial_basis_refusal_...)
@pytest.mark.parametrize("kind,rule,n", [
    (k, r, n) for k in ("radial", "full") for r in ("diffraction", "transparency") for n in (9, 10)
    if not (k == "radial" and n == 10)])
def test_intrinsic_basis_reproduces_the_branch_functions_where_the_ramp_is_one(kind, rule, n):
    """With R = 1 (r <= r1) the MLS of seed 003 Eq. (50) / (52) reproduces every basis
    function: sum_I phi_I F(x_I) = F(x), and its gradient, to rounding."""
    ap, nodes = _approx(n, crack_rule=rule, enrichment=kind, d_max=3.0 if kind == "full" else 2.0,
                        enrich_radius=0.9 * A, ramp_inner=0.6 * A)
    x = _points(np.random.default_rng(1), 400, 1e-3, 0.55 * A)
    sh = ap.shape(x)
    F, dF = branch_functions(*tip_coordinates(x, GEOM), kind)
    Fn = branch_functions(*tip_coordinates(nodes.x, GEOM, nodes.face), kind)[0]
    for j in range(F.shape[1]):
        np.testing.assert_allclose(sh.phi @ Fn[:, j], F[:, j], rtol=0, atol=1e-12)
        np.testing.assert_allclose(sh.dx @ Fn[:, j], dF[:, 0, j], rtol=0,
                                   atol=1e-10 * np.abs(dF[:, 0, j]).max())
        np.testing.assert_allclose(sh.dy @ Fn[:, j], dF[:, 1, j], rtol=0,
                                   atol=1e-10 * np.abs(dF[:, 1, j]).max())


@pytest.mark.parametrize("kind", ["radial", "full"])
def test_intrinsic_blend_is_consistent_and_linear_outside_the_ramp(kind):
    """phi = R phi_enr + (1 - R) phi_lin (Eq. 56): a partition of unity reproducing linear
    fields everywhere, and the plain linear-basis functions where R = 0 (r >= r2)."""
    kw = dict(crack_rule="diffraction", d_max=3.0)
    ap, nodes = _approx(17, enrichment=kind, enrich_radius=0.5 * A, ramp_inner=0.2 * A, **kw)
    plain, _ = _approx(17, **kw)
    x = _points(np.random.default_rng(2), 800, 1e-3, 0.95 * A)
    sh = ap.shape(x)
    u = 0.2 - 0.7 * nodes.x[:, 0] + 1.1 * nodes.x[:, 1]
    np.testing.assert_allclose(sh.phi @ np.ones(nodes.n), 1.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(sh.phi @ u, 0.2 - 0.7 * x[:, 0] + 1.1 * x[:, 1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(sh.dx @ u, -0.7, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sh.dy @ u, 1.1, rtol=0, atol=1e-9)
    out = np.hypot(*x.T) >= 0.5 * A
    ref = plain.shape(x[out])
    np.testing.assert_array_equal(sh.phi.toarray()[out], ref.phi.toarray())
    np.testing.assert_array_equal(sh.dx.toarray()[out], ref.dx.toarray())


ENRICHED = {
    "radial": dict(enrichment="radial", enrich_radius=0.5 * A, ramp_inner=0.1 * A),
    "full": dict(enrichment="full", d_max=3.0, enrich_radius=0.5 * A, ramp_inner=0.1 * A),
    "full_linear_ramp": dict(enrichment="full", d_max=3.0, enrich_radius=0.5 * A, ramp_inner=0.1 * A,
                             ramp="linear"),
    "extrinsic_mls": dict(enrichment="extrinsic_mls"),
    "extrinsic_mls_ramped": dict(enrichment="extrinsic_mls", enrich_radius=0.5 * A, ramp_inner=0.1 * A),
    "pu": dict(enrichment="pu", enrich_radius=0.4 * A),
}


@pytest.mark.parametrize("key", ENRICHED)
def test_enriched_derivatives_match_finite_differences(key):
    """Gradient operators (nodal and enrichment columns) against central differences of the
    displacement operators, at points inside, across and outside the ramp annulus."""
    ap, _ = _approx(17, crack_rule="diffraction", **ENRICHED[key])
    x = _points(np.random.default_rng(3), 150, 0.02 * A, 0.9 * A)
    h = 2 * A / 16
    x = x[np.abs(x[:, 1]) > 1e-2 * h]
    sh = ap.shape(x)
    Ux, Uy = sh.u_operators()
    G = sh.grad_operators()  # dux/dx, dux/dy, duy/dx, duy/dy
    eps = 1e-7 * h
    for c, e in enumerate((np.array([eps, 0.0]), np.array([0.0, eps]))):
        sp, sm = ap.shape(x + e, derivatives=False), ap.shape(x - e, derivatives=False)
        (Uxp, Uyp), (Uxm, Uym) = sp.u_operators(), sm.u_operators()
        for U_p, U_m, g in ((Uxp, Uxm, G[c]), (Uyp, Uym, G[2 + c])):
            fd = ((U_p - U_m) / (2 * eps)).toarray()
            an = g.toarray()
            assert np.abs(fd - an).max() <= 1e-6 * np.abs(an).max(), (key, c, np.abs(fd - an).max())


# --- the extrinsic spaces contain the Williams field ------------------------------------------

@pytest.mark.parametrize("key,kw", [
    ("extrinsic_mls", dict(enrichment="extrinsic_mls")),
    ("pu_all_nodes", dict(enrichment="pu", enrich_radius=10 * A)),
    ("full_R1_everywhere", dict(enrichment="full", d_max=3.0, enrich_radius=1.5 * A, ramp_inner=1.45 * A)),
])
def test_enriched_spaces_contain_the_williams_fields(key, kw):
    """Least-squares fit of the mode I and mode II Williams displacements (seed 003 Eq. 38)
    over all coefficients: the residual is at rounding level, and so is the gradient's."""
    ap, nodes = _approx(9, crack_rule="diffraction", **kw)
    x = _points(np.random.default_rng(4), 1500, 1e-2, 1.4 * A)  # 2 x 1500 > the 850 PU unknowns
    sh = ap.shape(x)
    Ux, Uy = (op.toarray() for op in sh.u_operators())
    G = [op.toarray() for op in sh.grad_operators()]
    M = np.vstack([Ux, Uy])
    r, th, gr, gt = tip_coordinates(x, GEOM)
    Q, dQ = williams_modes(*branch_functions(r, th, gr, gt, "full"), GEOM, MAT.mu, MAT.kappa)
    for mode in (0, 1):
        target = np.concatenate([Q[:, mode, 0], Q[:, mode, 1]])
        c, *_ = np.linalg.lstsq(M, target, rcond=None)
        assert np.abs(M @ c - target).max() <= 1e-9 * np.abs(target).max(), key
        grad = np.column_stack([g @ c for g in G])
        exact = np.column_stack([dQ[:, mode, 0, 0], dQ[:, mode, 0, 1], dQ[:, mode, 1, 0], dQ[:, mode, 1, 1]])
        assert np.abs(grad - exact).max() <= 1e-6 * np.abs(exact).max(), key


def _quad(h, level):
    return {} if level == 0 else dict(cell_size=h / 2, order=6, refined_order=8, tip_order=12)


# Measured on 9 x 9 nodes with Nitsche (bc="variational"), diffraction lambda = 2 (this
# test's settings; verification/near_tip.py's quadrature study, 2026-11): extrinsic MLS
# 2.5e-4 (default quadrature) and 2.0e-5 (cells h/2, 6/8/12 points); PU with every node
# enriched 6.7e-3 and 3.0e-4; the linear basis 0.26 whatever the quadrature.
@pytest.mark.parametrize("kw,bound", [
    (dict(enrichment="extrinsic_mls"), 5e-5),
    (dict(enrichment="pu", enrich_radius=10 * A), 1e-3),
])
def test_singular_patch_error_is_quadrature_error(kw, bound):
    """Seed 003 Sect. 5.6.1: the enriched spaces contain the exact solution, so the energy
    error (Eq. 36) of a consistent (Nitsche) solve is quadrature error: it falls by an order
    of magnitude with finer cells, far below the linear basis."""
    h = 2 * A / 8
    sc = singular_patch()
    err = [solve(sc, EFG(spacing=h, bc="variational", **kw, **_quad(h, q))).errors()["energy"]
           for q in (0, 1)]
    linear = solve(sc, EFG(spacing=h, bc="variational", enrichment="none")).errors()["energy"]
    assert err[1] <= bound
    assert err[1] <= 0.2 * err[0]
    assert err[0] <= 0.05 * linear


# --- tip coordinates, the kinked-crack map and the Williams modes -----------------------------

KINKED = Crack([[-1.0, 0.4], [-0.2, 0.0], [0.2, 0.2]], (False, True), "kinked")
KGEOM = TipGeometry.of(KINKED, 1)


def test_kinked_geometry_is_recognised():
    d_lead = np.array([0.4, 0.2])
    d_prev = np.array([-0.8, 0.4])  # from the kink back along the preceding segment
    expect = (math.atan2(d_prev[1], d_prev[0]) - math.atan2(d_lead[1], d_lead[0])) % (2 * math.pi)
    assert KGEOM.kink is not None and np.allclose(KGEOM.kink, [-0.2, 0.0])
    assert math.isclose(KGEOM.theta_r, expect)
    assert GEOM.kink is None and GEOM.theta_r == math.pi


def test_straight_crack_tip_coordinates_are_polar():
    x = _points(np.random.default_rng(5), 200, 1e-3, 1.0)
    r, th, gr, gt = tip_coordinates(x, GEOM)
    np.testing.assert_allclose(r, np.hypot(*x.T), rtol=1e-14)
    np.testing.assert_allclose(th, np.arctan2(x[:, 1], x[:, 0]), rtol=0, atol=1e-14)
    np.testing.assert_allclose(gr, x / r[:, None], rtol=1e-13)
    np.testing.assert_allclose(gt, np.column_stack([-x[:, 1], x[:, 0]]) / (r**2)[:, None], rtol=1e-12)


def _kink_frame(u):
    """Global points from tip-frame coordinates relative to the kink, u (n, 2)."""
    Q = KGEOM.tip.rotation
    k = Q @ (KGEOM.kink - KGEOM.tip.x)
    return KGEOM.tip.x + (u + k) @ Q


def test_kinked_map_is_continuous_across_the_normal_through_the_kink():
    """The map acts behind the normal to the leading segment through the kink (the dotted line
    of seed 003 Fig. 32); r and theta are continuous across it."""
    s = np.linspace(-0.6, 0.6, 41)
    s = s[np.abs(s) > 1e-3]
    for eps in (1e-9, 1e-11):
        ahead, behind = _kink_frame(np.column_stack([np.full_like(s, eps), s])), _kink_frame(
            np.column_stack([np.full_like(s, -eps), s]))
        ra, ta, *_ = tip_coordinates(ahead, KGEOM)
        rb, tb, *_ = tip_coordinates(behind, KGEOM)
        np.testing.assert_allclose(ra, rb, rtol=0, atol=10 * eps)
        np.testing.assert_allclose(ta, tb, rtol=0, atol=100 * eps / 0.1)


def test_kinked_map_puts_the_preceding_segment_at_theta_pi():
    """Points on the preceding segment map onto the line behind the tip: theta = +pi on the
    polyline's left face, -pi on its right (Eq. 57)."""
    t = np.linspace(0.05, 0.95, 19)
    a, b = KINKED.vertices[0], KINKED.vertices[1]
    on = a + t[:, None] * (b - a)
    left = np.array([-(b - a)[1], (b - a)[0]]) / np.hypot(*(b - a))
    for side, sign in ((1e-10, 1.0), (-1e-10, -1.0)):
        _, th, *_ = tip_coordinates(on + side * left, KGEOM)
        np.testing.assert_allclose(th, sign * np.pi, rtol=0, atol=1e-8)
    _, th_up, *_ = tip_coordinates(on, KGEOM, np.ones(len(on), int))
    _, th_lo, *_ = tip_coordinates(on, KGEOM, -np.ones(len(on), int))
    np.testing.assert_allclose(th_up, np.pi, rtol=0, atol=1e-12)
    np.testing.assert_allclose(th_lo, -np.pi, rtol=0, atol=1e-12)
    # the leading segment's own faces are at +-pi as for a straight crack
    lead = KGEOM.tip.x + np.array([-0.1, -0.05])
    nrm = np.array([-0.2, 0.4]) / np.hypot(0.2, 0.4)
    _, th, *_ = tip_coordinates(np.array([lead + 1e-10 * nrm, lead - 1e-10 * nrm]), KGEOM)
    np.testing.assert_allclose(th, [np.pi, -np.pi], rtol=0, atol=1e-8)


@pytest.mark.parametrize("geom", [GEOM, KGEOM], ids=["straight", "kinked"])
def test_tip_coordinate_and_branch_function_derivatives(geom):
    rng = np.random.default_rng(6)
    x = geom.tip.x + _points(rng, 400, 0.05, 0.8)
    r0, *_ = tip_coordinates(x, geom)
    # away from the faces (theta jumps there) and from the normal through the kink
    Q = geom.tip.rotation
    loc = (x - geom.tip.x) @ Q.T
    keep = np.ones(len(x), bool)
    if geom.kink is not None:
        keep &= np.abs(loc[:, 0] - (Q @ (geom.kink - geom.tip.x))[0]) > 1e-3
    _, th, *_ = tip_coordinates(x, geom)
    keep &= np.abs(np.abs(th) - np.pi) > 1e-2
    x = x[keep]
    r, th, gr, gt = tip_coordinates(x, geom)
    F, dF = branch_functions(r, th, gr, gt, "full")
    eps = 1e-7
    for c in range(2):
        e = np.zeros(2)
        e[c] = eps
        rp, tp, *_ = tip_coordinates(x + e, geom)
        rm, tm, *_ = tip_coordinates(x - e, geom)
        np.testing.assert_allclose((rp - rm) / (2 * eps), gr[:, c], rtol=0, atol=1e-7)
        np.testing.assert_allclose((tp - tm) / (2 * eps), gt[:, c], rtol=0, atol=1e-6 * np.abs(gt).max())
        Fp = branch_functions(rp, tp, *tip_coordinates(x + e, geom)[2:], "full")[0]
        Fm = branch_functions(rm, tm, *tip_coordinates(x - e, geom)[2:], "full")[0]
        np.testing.assert_allclose((Fp - Fm) / (2 * eps), dF[:, c, :], rtol=0,
                                   atol=1e-6 * np.abs(dF).max())


def test_williams_modes_match_the_closed_form_on_an_inclined_crack():
    ang = 0.7
    tip = np.array([0.3, -0.2])
    crack = Crack([tip - 0.8 * np.array([math.cos(ang), math.sin(ang)]), tip], (True, True), "c")
    geom = TipGeometry.of(crack, 1)
    x = tip + _points(np.random.default_rng(7), 200, 1e-2, 0.7)
    r, th, gr, gt = tip_coordinates(x, geom)
    Q, _ = williams_modes(*branch_functions(r, th, gr, gt, "full"), geom, MAT.mu, MAT.kappa)
    R = np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]])  # local -> global
    for mode, (KI, KII) in enumerate(((1.0, 0.0), (0.0, 1.0))):
        u_loc = williams_displacement(r, th, KI, KII, MAT.mu, MAT.kappa)
        np.testing.assert_allclose(Q[:, mode, :], u_loc @ R.T, rtol=0, atol=1e-14)


@pytest.mark.parametrize("kind", ["linear", "quintic"])
def test_ramp_values_and_derivatives(kind):
    r = np.linspace(0.0, 1.0, 1001)
    gr = np.column_stack([np.ones_like(r), np.zeros_like(r)])
    R, dR = ramp(r, gr, 0.3, 0.7, kind)
    assert np.all(R[r <= 0.3] == 1.0) and np.all(R[r >= 0.7] == 0.0)
    assert np.all(np.diff(R) <= 0)
    inner = (r > 0.31) & (r < 0.69)
    eps = 1e-7
    Rp, _ = ramp(r + eps, gr, 0.3, 0.7, kind)
    Rm, _ = ramp(r - eps, gr, 0.3, 0.7, kind)
    np.testing.assert_allclose(((Rp - Rm) / (2 * eps))[inner], dR[inner, 0], rtol=0, atol=1e-6)
    if kind == "quintic":  # C1 at both radii (seed 003 Eq. 54: the strain stays continuous)
        assert abs(dR[np.argmin(np.abs(r - 0.3001)), 0]) < 1e-4
        assert abs(dR[np.argmin(np.abs(r - 0.6999)), 0]) < 1e-4
    with pytest.raises(ValueError, match="ramp must be 'linear' or 'quintic'"):
        ramp(r, gr, 0.3, 0.7, "cubic")


# --- every enrichment with every crack rule -----------------------------------------------------

ENRICHMENTS = {
    "none": {"enrichment": "none"},  # the linear basis (the default is automatic enrichment)
    "radial": dict(enrichment="radial", enrich_radius=0.5 * A, ramp_inner=0.25 * A),
    "full": dict(enrichment="full", d_max=3.0, enrich_radius=0.5 * A, ramp_inner=0.25 * A),
    "extrinsic_mls": dict(enrichment="extrinsic_mls"),
    "pu": dict(enrichment="pu", enrich_radius=10 * A),
}
RULES = ("visibility", "diffraction", "transparency", "see_through")
LAYOUT_N = {"face_nodes": 9, "between_rows": 10}  # crack on a node row (split nodes) / between rows


@functools.cache
def _combination(enrichment: str, rule: str, layout: str) -> dict:
    """Solve the singular patch with one combination: its status, energy error, K_I."""
    n = LAYOUT_N[layout]
    m = EFG(spacing=2 * A / (n - 1), bc="lagrange", crack_rule=rule, **ENRICHMENTS[enrichment])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", UserWarning)
        try:
            sol = solve(singular_patch(), m)
        except ValueError as err:
            return {"status": "refused", "message": str(err)}
    out = {"status": "solved", "energy": sol.errors()["energy"],
           "finite": bool(np.all(np.isfinite(sol.stress())) and np.all(np.isfinite(sol.coeffs))),
           "warned": any(str(w.message).startswith("crack_rule='transparency'") for w in caught),
           "radial_warning": [str(w.message) for w in caught
                              if str(w.message).startswith("enrichment='radial' with")]}
    if enrichment == "extrinsic_mls":
        out["KI"] = float(sol.coeffs[2 * sol.nodes.n])
    return out


COMBINATIONS = [(e, r, lay) for e in ENRICHMENTS for r in RULES for lay in LAYOUT_N]


@pytest.mark.parametrize("enrichment,rule,layout", COMBINATIONS)
def test_every_enrichment_with_every_crack_rule_solves_or_refuses_clearly(enrichment, rule, layout):
    """Singular patch (seed 003 Sect. 5.6.1) on 9 x 9 (split face nodes) and 10 x 10 nodes
    (crack between rows): each combination either solves with finite fields or raises a
    ValueError naming both choices; transparency on split face nodes warns (Sect. 4.3)."""
    res = _combination(enrichment, rule, layout)
    if res["status"] == "refused":
        assert enrichment in res["message"] and rule in res["message"], res["message"]
        return
    assert res["finite"] and np.isfinite(res["energy"])
    assert res["warned"] == (rule == "transparency" and layout == "face_nodes")
    assert bool(res["radial_warning"]) == (enrichment == "radial" and rule == "diffraction")


# Refused with an error that names both choices (test above): intrinsic bases with see-through
# (energy 0.76-1.10 against 0.28-0.34 with diffraction when they were allowed), extrinsic ones
# with transparency on split face nodes (extrinsic K_I 0.62, PU energy 0.49), the sqrt(r) basis
# with diffraction or transparency when no node lies near the crack at the tip (energy 0.49 and
# 0.63 against 0.34 and 0.50, test_radial_basis_refusal_between_rows_is_measured below).
REFUSED = {(e, "see_through", lay) for e in ("radial", "full") for lay in LAYOUT_N} | {
    (e, "transparency", "face_nodes") for e in ("extrinsic_mls", "pu")} | {
    ("radial", r, "between_rows") for r in ("diffraction", "transparency")}


def _usable_params():
    out = []
    for e, r, lay in COMBINATIONS:
        if e == "none" or (r == "visibility" and e != "radial") or (e, r, lay) in REFUSED:
            continue  # the linear references; visibility is refused with all but sqrt(r)
        out.append(pytest.param(e, r, lay, id=f"{e}-{r}-{lay}"))
    return out


@pytest.mark.parametrize("enrichment,rule,layout", _usable_params())
def test_enriched_combinations_are_no_worse_than_the_linear_basis(enrichment, rule, layout):
    """An enrichment that solves must be usable: energy error within 10 % of the linear basis
    under the same rule (under diffraction for see-through, which the seed recommends only
    with enrichment, Sect. 4.4), and the extrinsic K_I within 0.3 % of the prescribed 1."""
    res = _combination(enrichment, rule, layout)
    assert res["status"] == "solved"
    ref = _combination("none", "diffraction" if rule == "see_through" else rule, layout)["energy"]
    assert res["energy"] <= 1.1 * ref, (res["energy"], ref)
    # K_I = 1: the prescribed Williams field (seed 003 Sect. 5.6.1). Measured: extrinsic K_I
    # within 8.9e-4 of 1 (transparency, between rows; the others 1.4e-5 to 5.8e-4); energy
    # error / linear basis under diffraction: extrinsic 4.0e-4 and 9.8e-4, PU 0.022 and 0.032
    if enrichment == "extrinsic_mls":
        assert abs(res["KI"] - 1.0) <= 3e-3, res["KI"]
    if rule == "diffraction" and enrichment in ("extrinsic_mls", "pu"):  # contain the exact field
        assert res["energy"] <= (3e-3 if enrichment == "extrinsic_mls" else 0.05) * ref


def test_intrinsic_blend_is_continuous_across_the_straight_r2_circle_of_a_kinked_crack():
    # regression: points were picked by straight distance < r2, the ramp used the kink-mapped r
    # (smaller behind the kink): the shape functions jumped by 8e-4 across |x - tip| = r2
    tip = np.array([0.5, 0.0])
    sc = Scene(Domain.rectangle(-1.5, -1.5, 1.5, 1.5), Elastic(1.0, 0.3),
               cracks=(Crack([[-1.5, 1.5], [0.0, 0.0], [0.5, 0.0]], tips=(False, True)),))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = discretize(sc, EFG(spacing=0.1, enrichment="full", d_max=3.0, enrich_radius=0.8,
                               ramp_inner=0.2))
    ang = np.linspace(0.55 * np.pi, 1.45 * np.pi, 400)
    u = np.column_stack([np.cos(ang), np.sin(ang)])
    x_in, x_out = tip + (0.8 - 1e-9) * u, tip + (0.8 + 1e-9) * u
    keep = sc.domain.contains(x_in) & sc.domain.contains(x_out)
    a = d.shape_at(x_in[keep], derivatives=False).phi.toarray()
    b = d.shape_at(x_out[keep], derivatives=False).phi.toarray()
    assert np.abs(a - b).max() < 1e-7


def test_radial_basis_is_more_accurate_with_visibility_than_with_diffraction():
    """Seed 003 Sect. 5.3.2: the sqrt(r) basis needs no smoothing; with visibility (allowed for it
    alone among the enrichments) its energy error on the 9 x 9 singular patch is 0.216 against
    0.272 with diffraction (measured 2026-11); the reason visibility is not refused for it."""
    vis = _combination("radial", "visibility", "face_nodes")
    dif = _combination("radial", "diffraction", "face_nodes")
    assert vis["status"] == dif["status"] == "solved"
    assert vis["energy"] < 0.85 * dif["energy"], (vis["energy"], dif["energy"])


@pytest.mark.parametrize("rule", ["diffraction", "transparency"])
def test_radial_basis_refusal_between_rows_is_measured(rule, monkeypatch):
    """The sqrt(r) basis with diffraction or transparency and no node within h/4 of the crack near
    the tip is refused, with the cause and the remedies in the message; and the refusal is true:
    with the check lifted the energy error is above the linear basis's under the same rule
    (measured 1.42 and 1.26 times, 0.485 and 0.630 against 0.342 and 0.498: the even sqrt(r)
    term mixes the two faces' opposite amplitudes of u_y, whose quasi-interpolant gradient error
    rises from 0.20 to 0.33 under diffraction). If a change makes the basis accurate here, this
    fails: lift the refusal in efgkit.methods.discretize."""
    res = _combination("radial", rule, "between_rows")
    assert res["status"] == "refused"
    for part in (f"enrichment='radial' with crack_rule={rule!r}", "no node lies within h/4",
                 "tip at [0.0, 0.0]", "mixes the two faces' opposite sqrt(r)",
                 "Use enrichment='extrinsic_mls', 'pu' or 'full'", "crack_rule='visibility' with d_max"):
        assert part in res["message"], (part, res["message"])
    monkeypatch.setattr("efgkit.methods.crack_choices._check_radial_rule", lambda *a, **k: None)
    m = EFG(spacing=2 * A / 9, bc="lagrange", crack_rule=rule, **ENRICHMENTS["radial"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        energy = solve(singular_patch(), m).errors()["energy"]
    ref = _combination("none", rule, "between_rows")["energy"]
    assert 1.15 * ref < energy < 1.6 * ref, (energy, ref)


def test_radial_basis_with_diffraction_warns_where_it_is_no_better_than_linear():
    """Allowed with nodes on the crack faces, but measured no more accurate than the linear basis
    under diffraction (energy 0.272 against 0.264 here, 1.03-1.21 times over d_max 2-3): a warning
    naming both choices and the remedies; rule_power >= 4 (0.879 and 0.774 times) does not warn."""
    res = _combination("radial", "diffraction", "face_nodes")
    assert len(res["radial_warning"]) == 1
    msg = res["radial_warning"][0]
    for part in ("crack_rule='diffraction' and rule_power < 4", "no more accurate than the linear",
                 "enrichment='extrinsic_mls', 'pu' or 'full'", "crack_rule='visibility'"):
        assert part in msg, (part, msg)
    ref = _combination("none", "diffraction", "face_nodes")["energy"]
    assert ref < res["energy"] < 1.1 * ref, (res["energy"], ref)  # the warning's claim
    m = EFG(spacing=2 * A / 8, bc="lagrange", crack_rule="diffraction", rule_power=4.0,
            **ENRICHMENTS["radial"])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", UserWarning)
        energy = solve(singular_patch(), m).errors()["energy"]
        ref = solve(singular_patch(), replace(m, enrichment="none")).errors()["energy"]
    assert not [w for w in caught if "enrichment='radial'" in str(w.message)]
    assert energy < ref, (energy, ref)  # measured 0.238 against 0.271
