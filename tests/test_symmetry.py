"""Half and quarter models: the whole body rebuilt by mirroring, the mirrored fields, and K
of the modelled tips against the full model."""

import warnings

import numpy as np
import pytest

from efgkit import EFG, FEM, Crack, Domain, Elastic, Field, Loop, Scene, Support, solve, solve_fem
from efgkit.gallery import cct
from efgkit.problem.symmetry import Symmetry, full_domain, mirror_fields

ON_X = ((0.0, 0.0), (0.0, 1.0))  # the line y = 0
RADII = (0.2, 0.3, 0.4)


@pytest.mark.parametrize("model", ["half", "quarter"])
def test_full_domain_is_the_whole_plate(model):
    sc = cct(0.5, 1.5, model=model)
    dom = full_domain(sc.domain, sc.symmetry)
    assert dom.area == pytest.approx(2.0 * 3.0)
    corners = {(-1.0, -1.5), (1.0, -1.5), (1.0, 1.5), (-1.0, 1.5)}
    assert corners <= {tuple(v) for v in dom.outer.vertices.tolist()}
    assert [t.id for t in sc.full().tips] == ["crack:0", "crack:1"]


def test_mirrored_williams_field_is_the_field():
    # mode I is symmetric about the crack line: the mirror of the field at x is the field at x'
    m = Elastic(1.0, 0.3)
    W = Field.named("williams", KI=1.0)
    rng = np.random.default_rng(0)
    x = rng.uniform([-1, 0.01], [1, 1], (20, 2))
    g = np.stack([W.displacement(x + d, m) - W.displacement(x - d, m) for d in
                  (np.array([1e-6, 0]), np.array([0, 1e-6]))], axis=2) / 2e-6
    X, w, S, G = mirror_fields(Symmetry((ON_X,)), x, np.ones(20), W.stress(x, m), g)
    xm = X[20:]
    assert np.allclose(xm, x * [1, -1]) and np.array_equal(w, np.ones(40))
    assert np.abs(S[20:] - W.stress(xm, m)).max() < 1e-12
    gm = np.stack([W.displacement(xm + d, m) - W.displacement(xm - d, m) for d in
                   (np.array([1e-6, 0]), np.array([0, 1e-6]))], axis=2) / 2e-6
    assert np.abs(G[20:] - gm).max() < 1e-8


def test_fem_half_and_quarter_give_the_full_k():
    # same mesh settings, no quarter points (the part's tip gets none): measured |dK_I| / K_I
    # 7e-5 (half) and 4e-5 (quarter) at h = 0.1, tip h = 0.01 (verification/symmetry.py)
    fem = FEM(0.1, tip_h=0.01, quarter_point=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = {m: {r.tip.id: r for r in solve_fem(cct(0.5, 1.5, model=m), fem).sifs(radii=RADII, error=False)}
               for m in ("full", "half", "quarter")}
    assert set(res["half"]) == {"crack:0", "crack:1"} and set(res["quarter"]) == {"crack:1"}
    for m in ("half", "quarter"):
        for tid, r in res[m].items():
            assert abs(r.KI / res["full"][tid].KI - 1) < 2e-4
            assert r.KII == 0.0  # by symmetry
            assert abs(r.J / res["full"][tid].J - 1) < 4e-4  # measured 1.3e-4


def test_efg_half_equals_quarter():
    # both are the full model on the same mirrored cloud (image nodes, efgkit.system.images):
    # equal up to rounding, measured 6e-15 at h = 0.1 (before image nodes: 1.5e-4)
    m = EFG(spacing=0.1, bc="lagrange", enrichment="none")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        k = [solve(cct(0.5, 1.5, model=mod), m).sifs(radii=RADII, error=False)[-1]
             for mod in ("half", "quarter")]
    assert abs(k[0].KI / k[1].KI - 1) < 1e-12 and abs(k[0].T / k[1].T - 1) < 1e-12


def test_sifs_error_estimate_of_a_half_model():
    sc = cct(0.5, 1.5, model="half")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = solve_fem(sc, FEM(0.2, tip_h=0.02, quarter_point=False)).sifs(radii=RADII)
    assert len(res) == 2 and all(r.error is not None and r.error < 0.05 for r in res)


HALF = Domain(Loop.polygon([[-1, 0], [-0.5, 0], [0.5, 0], [1, 0], [1, 1], [-1, 1]],
                           ["lig", "face", "lig", "right", "top", "left"]))
CRACK = Crack([[-0.5, 0.0], [0.5, 0.0]], name="c")


@pytest.mark.parametrize("make, err, match", [
    (lambda: Symmetry(()), ValueError, "one or two lines"),
    (lambda: Symmetry((((0, 0), (0, 1)), ((0, 0), (1, 1)))), ValueError, "perpendicular"),
    (lambda: Symmetry(((0, 0),)), ValueError, "pairs"),
    (lambda: Symmetry((((0, 0), (0, 0)),)), ValueError, "normal non-zero"),
    (lambda: Symmetry((ON_X,), (Crack([[-0.5, 0.1], [0.5, 0.1]], name="c"),)), ValueError,
     "does not lie on a symmetry line"),
    (lambda: Symmetry((ON_X,), (Crack([[-0.5, 0.0], [0.5, 0.0]], name="c", pressure=1.0),)), ValueError,
     "pressure must be 0"),
    (lambda: Symmetry((ON_X,), ("c",)), TypeError, "must be Crack objects"),
    (lambda: Scene(HALF, Elastic(1.0, 0.3), symmetry=Symmetry((((0, 0.5), (0, 1)),), ())), ValueError,
     "no edge of the outer boundary lies on it"),
    (lambda: Scene(HALF, Elastic(1.0, 0.3), symmetry=Symmetry((ON_X,), ())), ValueError,
     "no tip of the symmetry cracks"),
    (lambda: Scene(HALF, Elastic(1.0, 0.3), symmetry=(ON_X,)), TypeError, "must be a Symmetry"),
])
def test_bad_input(make, err, match):
    with pytest.raises(err, match=match):
        make()


def test_a_half_model_solves_and_supports():
    sc = Scene(HALF, Elastic(1.0, 0.3), supports=(Support("lig", uy=0.0), Support("top", ux=0.0, uy=0.01)),
               symmetry=Symmetry((ON_X,), (CRACK,)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = solve_fem(sc, FEM(0.1, tip_h=0.01, quarter_point=False))
        res = sol.sifs(radii=(0.1, 0.15, 0.2), error=False)
    assert len(res) == 2 and res[0].KI > 0 and res[0].KI == pytest.approx(res[1].KI, rel=1e-3)


def test_efg_defaults_grade_toward_the_modelled_tips():
    # EFG(spacing) alone: graded zones at the modelled tips, multipliers, and the whole body's
    # automatic enrichment (PU for its two tips) on the image nodes; K_I against Tada's 1.48672
    # (p. 2.2, 0.1 %) for a/b = 0.5, h/b = 3: measured +0.030 % at h = b/10 (the full model's
    # defaults: +0.030 % too); the bound is the fit's accuracy
    from efgkit.gallery import reference_k

    sc = cct(0.5, 3.0, model="half")
    m = EFG(spacing=0.1).for_scene(sc)
    assert m.bc == "lagrange" and len(m.zones) == 4 and m.enrichment == "pu"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = solve(sc, EFG(spacing=0.1)).sifs(error=False)
    for r in res:
        assert abs(r.KI / reference_k("cct", a_over_b=0.5)["KI"] - 1) < 1e-3
