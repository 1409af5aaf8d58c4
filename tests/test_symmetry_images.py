"""EFG half and quarter models on image nodes (efgkit.system.images): the tied field is the
symmetric field of the mirrored cloud, the part equals the full model on that cloud, and the
refusals."""

import warnings
from dataclasses import replace

import numpy as np
import pytest
from scipy.sparse import csr_array

from efgkit import EFG, Crack, PointSupport, Scene, Support, solve
from efgkit.gallery import cct, sent_seed001
from efgkit.methods.discretize import discretize
from efgkit.methods.efg import Rosette
from efgkit.nodes import generate_nodes
from efgkit.system.constraints import RigidBodyModeError
from efgkit.system.images import image_group, image_positions, tie
from efgkit.system.linear_system import LinearSystem

RADII = {"cct": (0.2, 0.3, 0.4), "SENT": (1.0, 2.0, 3.0)}


def _quiet(f, *a, **k):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return f(*a, **k)


@pytest.mark.parametrize("enrichment", [dict(enrichment="none", spacing=0.25),
                                        dict(enrichment="pu", enrich_radius=0.1, spacing=0.1)])
def test_tied_field_is_the_symmetric_field_of_the_mirrored_cloud(enrichment):
    # quarter CCT: u(g x) = R_g u(x) for every element g of the mirror group, and u_n = 0 on
    # the lines, for arbitrary part coefficients, with the PU unknowns tied too (rounding:
    # measured <= 6.2e-16 and 8e-18)
    sc = cct(0.5, 1.0, model="quarter")
    d = discretize(sc, EFG(bc="lagrange", **enrichment))
    tie_ = d.images
    assert tie_.T.shape[0] == d.n_dofs and d.nodes.n > 3 * tie_.n_part
    b = np.random.default_rng(0).normal(size=tie_.T.shape[1])
    a = tie_.T @ b
    x = d.points.x[:: max(1, len(d.points.x) // 200)]
    R, c = image_group(sc.symmetry.lines)
    u = d.shape_at(x, derivatives=False).displacement(a)
    scale = np.abs(u).max()
    for s in range(1, len(R)):
        us = d.shape_at(x @ R[s].T + c[s], derivatives=False).displacement(a)
        assert np.abs(us - u @ R[s].T).max() < 1e-14 * scale
    lig = np.column_stack([np.linspace(0.55, 0.95, 9), np.zeros(9)])  # y = 0, x > a
    left = np.column_stack([np.zeros(9), np.linspace(0.05, 0.95, 9)])  # x = 0
    assert np.abs(d.shape_at(lig, derivatives=False).displacement(a)[:, 1]).max() < 1e-14 * scale
    assert np.abs(d.shape_at(left, derivatives=False).displacement(a)[:, 0]).max() < 1e-14 * scale
    # the face: the copy on the part's side of each split node is the part's node
    assert d.nodes.face is not None and np.all(d.nodes.face[: tie_.n_part][d.nodes.x[: tie_.n_part, 1] == 0]
                                               >= 0)


def _full_on_mirrored_cloud(part, full, method):
    """The part and the full model on the mirror union of the part's nodes."""
    x = generate_nodes(part.domain, method).x
    y, _ = image_positions(x, part.symmetry.lines, 1e-9 * part.domain.size)
    ps = _quiet(solve, part, replace(method, coordinates=x))
    fs = _quiet(solve, full, replace(method, coordinates=y))
    return ps, fs


@pytest.mark.parametrize("specimen, model, bc, h, enrichment", [
    ("cct", "quarter", "lagrange", 0.2, "none"), ("cct", "half", "penalty", 0.2, "none"),
    ("cct", "quarter", "lagrange", 0.1, "pu"), ("SENT", "half", "lagrange", 1.0, "none"),
    ("SENT", "half", "variational", 1.0, "none"), ("SENT", "half", "lagrange", 2.0, "extrinsic_mls")])
def test_part_equals_the_full_model_on_the_mirrored_cloud(specimen, model, bc, h, enrichment):
    # the Galerkin solution over the tied space is the full model's (same MLS functions and
    # enrichment, mirror-symmetric quadrature): K_I, T, J equal up to rounding in the linear
    # solve, measured 7e-15 (cct quarter), 8e-15 (cct half, penalty), 5e-14 (SENT), and with
    # the enrichment unknowns tied 1.2e-13 (PU, quarter) and 3.4e-14 (extrinsic MLS, SENT);
    # bound 1e-12
    build = (lambda m: cct(0.5, 1.0, model=m)) if specimen == "cct" else (lambda m: sent_seed001(model=m))
    method = EFG(spacing=h, bc=bc, enrichment=enrichment, enrich_radius=h if enrichment == "pu" else None)
    ps, fs = _full_on_mirrored_cloud(build(model), build("full"), method)
    part = {r.tip.id: r for r in _quiet(ps.sifs, radii=RADII[specimen], error=False)}
    full = {r.tip.id: r for r in _quiet(fs.sifs, radii=RADII[specimen], error=False)}
    assert part
    for tid, r in part.items():
        assert r.KII == 0.0
        for k in ("KI", "T", "J"):
            assert abs(getattr(r, k) / getattr(full[tid], k) - 1) < 1e-12
    if specimen == "SENT":  # the pulled end's reaction is the full model's: 1770.5 N/mm both
        assert np.allclose(ps.reaction("right"), fs.reaction("right"), rtol=1e-8,
                           atol=1e-8 * np.abs(fs.reaction("right")).max())


def test_reaction_on_the_symmetry_line_is_refused():
    # the ligament is held by the image nodes, not by a support: no support force there
    sol = _quiet(solve, cct(0.5, 1.0, model="half"), EFG(spacing=0.25, enrichment="none"))
    with pytest.raises(ValueError, match="lies on a symmetry line"):
        sol.reaction("ligament")


HALF = cct(0.5, 1.0, model="half")
PLAIN = EFG(spacing=0.5, enrichment="none")


@pytest.mark.parametrize("scene, method, err, match", [
    (cct(0.5, 1.0, model="quarter"), EFG(spacing=0.25, enrichment="pu", enrich_radius=0.25), ValueError,
     "enrichment='pu' is not mirror-symmetric on this cloud"),
    (HALF, EFG(spacing=0.25, bc="modified_mls"), ValueError, "take no bc='modified_mls'"),
    (HALF, EFG(spacing=0.25, rosette=Rosette(0.1)), ValueError, "take no rosette"),
    (replace(HALF, cracks=(Crack([[-0.2, 0.5], [0.2, 0.5]], tips=(True, True), name="off"),)),
     EFG(spacing=0.25), ValueError, "take no cracks off the symmetry lines"),
    (replace(HALF, supports=(Support("ligament", uy=0.1),)), PLAIN, ValueError, "prescribes uy = 0.1"),
    (replace(HALF, point_supports=(PointSupport((-1.0, 0.0), ux=0.0, uy=1.0),)), PLAIN,
     ValueError, "prescribes uy = 1.0"),
    (replace(HALF, point_supports=()), PLAIN, RigidBodyModeError,
     "translation along its symmetry line"),
])
def test_refusals(scene, method, err, match):
    with pytest.raises(err, match=match):
        _quiet(solve, scene, method)


def test_tie_refuses_lines_off_the_axes_and_eliminating_systems():
    with pytest.raises(ValueError, match="along the axes"):
        tie((((0.0, 0.0), (1.0, 1.0)),), np.zeros((2, 1), int), np.zeros(1, int), np.zeros((1, 2)),
            np.ones(1))
    t = discretize(HALF, EFG(spacing=0.25, bc="lagrange", enrichment="none")).images
    n = t.T.shape[0]
    elim = LinearSystem(csr_array(np.eye(2)), np.zeros(2), True, n, free=np.arange(2),
                        fixed_values=np.zeros(n))
    with pytest.raises(ValueError, match="tie the coefficients of bc='penalty'"):
        t.reduce(elim)


def test_supports_on_the_lines_keep_their_tangential_part():
    # Support("left", ux=0, uy=0) on a quarter's line x = 0: u_x = 0 is the symmetry's (held by
    # the tie), u_y = 0 a real restraint; the tangential part stays
    from efgkit.problem.symmetry import without_mirror_conditions

    q = cct(0.5, 1.0, model="quarter")
    sc = without_mirror_conditions(replace(q, supports=(Support("ligament", uy=0.0),
                                                        Support("left", ux=0.0, uy=0.0))))
    assert sc.supports == (Support("left", uy=0.0),) and isinstance(sc, Scene)


def test_dynamic_runs_of_a_half_model_are_refused():
    from efgkit import Elastic
    from efgkit.explicit.system import dynamics

    sc = replace(HALF, material=Elastic(1.0, 0.3, rho=1.0), duration=1.0)
    with pytest.raises(ValueError, match="dynamic EFG runs of half and quarter models"):
        _quiet(dynamics, sc, EFG(spacing=0.5, enrichment="none"))


def test_collocation_is_refused():
    with pytest.raises(ValueError, match="take no bc='collocation'"):
        _quiet(solve, HALF, EFG(spacing=0.5, bc="collocation", enrichment="none"))
