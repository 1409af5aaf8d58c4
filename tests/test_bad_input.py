"""Bad input gets a clear error naming the argument, the value and the remedy
(the list of issue [core]); each error's type and message is checked."""

import math

import numpy as np
import pytest

from efgkit import EFG, Crack, Domain, Elastic, Loop, Scene, Support, Traction
from efgkit.approx.mls import SingularMomentMatrix
from efgkit.static import solve
from efgkit.system.constraints import RigidBodyModeError

SQUARE = Domain.rectangle(0, 0, 1, 1)
MAT = Elastic(1.0, 0.3)


@pytest.mark.parametrize("E", [0.0, -1.0, math.nan, math.inf])
def test_modulus_not_positive(E):
    with pytest.raises(ValueError, match=r"E must be finite and > 0, got"):
        Elastic(E, 0.3)


@pytest.mark.parametrize("nu", [-0.1, 0.5, 0.7, math.nan])
def test_poisson_ratio_out_of_range(nu):
    with pytest.raises(ValueError, match=r"nu must lie in \[0, 0.5\)"):
        Elastic(1.0, nu)


def test_poisson_ratio_near_incompressible_warns():
    with pytest.warns(UserWarning, match="close to 0.5.*locks"):
        Elastic(1.0, 0.495)


def test_unknown_plane():
    with pytest.raises(ValueError, match=r"plane must be one of \('strain', 'stress'\), got 'strian'"):
        Elastic(1.0, 0.3, plane="strian")


@pytest.mark.parametrize("build", [
    lambda: Loop.polygon([[0, 0], [1, np.nan], [1, 1]]),
    lambda: Support("left", ux=math.inf),
    lambda: Traction("right", (1.0, math.nan)),
    lambda: Scene(SQUARE, MAT, body_force=(0.0, math.inf)),
    lambda: EFG(spacing=math.nan),
], ids=["vertex", "support", "traction", "body_force", "spacing"])
def test_nan_or_inf_anywhere(build):
    with pytest.raises(ValueError, match="finite"):
        build()


def test_empty_polygon():
    with pytest.raises(ValueError, match=r"a polygon needs vertices of shape \(n >= 3, 2\)"):
        Loop.polygon(np.zeros((0, 2)))


def test_degenerate_polygon():
    with pytest.raises(ValueError, match="outer loop is empty or degenerate"):
        Domain(Loop.polygon([[0, 0], [1, 0], [2, 0]]))


def test_duplicate_vertex():
    with pytest.raises(ValueError, match="edge 1 .* has zero length.*remove the duplicate vertex"):
        Loop.polygon([[0, 0], [1, 0], [1, 0], [0, 1]])


def test_self_intersecting_polygon():
    with pytest.raises(ValueError, match="outer loop is self-intersecting"):
        Domain(Loop.polygon([[0, 0], [1, 1], [1, 0], [0, 1]]))


def test_hole_outside_domain():
    with pytest.raises(ValueError, match="hole 0 is not strictly inside the outer boundary"):
        Domain.rectangle(0, 0, 1, 1, holes=[Loop.circle([2.0, 0.5], 0.2)])


@pytest.mark.parametrize("item", [Support("lefft", ux=0.0), Traction("rigth", (1.0, 0.0))])
def test_edge_name_that_does_not_exist(item):
    kw = {"supports": (item,)} if isinstance(item, Support) else {"tractions": (item,)}
    with pytest.raises(ValueError, match=r"on edge '\w+': the domain has no such edge; its edges are"):
        Scene(SQUARE, MAT, **kw)


def test_support_too_small_for_basis():
    scene = Scene(SQUARE, MAT, supports=(Support("left", ux=0.0, uy=0.0),))
    with pytest.raises(SingularMomentMatrix, match=r"neighbour\(s\).*Remedy: enlarge the support"):
        solve(scene, EFG(spacing=0.1, d_max=1.2, basis="quadratic"))


def test_body_without_essential_bc():
    scene = Scene(SQUARE, MAT, tractions=(Traction("right", (1.0, 0.0)),))
    with pytest.raises(RigidBodyModeError, match="no essential boundary condition"):
        solve(scene, EFG(spacing=0.25))


@pytest.mark.parametrize("bc", ["penalty", "lagrange", "variational"])
def test_supports_leaving_a_rigid_mode_free(bc):
    # only ux on the left edge: translation in y is free
    scene = Scene(SQUARE, MAT, supports=(Support("left", ux=0.0),),
                  tractions=(Traction("right", (1.0, 0.0)),))
    with pytest.raises(RigidBodyModeError, match="rigid-body mode free .*translation in y"):
        solve(scene, EFG(spacing=0.25, bc=bc))


def test_support_prescribing_nothing():
    with pytest.raises(ValueError, match="prescribes nothing: give ux and/or uy"):
        Support("left")


@pytest.mark.parametrize("kw,match", [
    ({"weight": "gauss"}, r"weight must be one of \('quartic', 'gaussian', 'cubic'\), got 'gauss'"),
    ({"bc": "nitsche"}, r"bc must be one of .*got 'nitsche'"),
    ({"order": 0}, "order must be finite and > 0, got 0"),
    ({"perturb": 0.6}, r"perturb must lie in \[0, 0.5\)"),
])
def test_bad_discretisation_options(kw, match):
    with pytest.raises(ValueError, match=match):
        EFG(spacing=0.1, **kw)


def test_unknown_scene_file_key_names_nearest(tmp_path):
    from efgkit.scenefile import load_scene

    p = tmp_path / "s.toml"
    p.write_text('[material]\nE = 1.0\nnu = 0.3\n[domain]\nouter = { rectangle = [0, 0, 1, 1] }\n'
                 '[[suports]]\nedge = "left"\nux = 0.0\n')
    with pytest.raises(ValueError, match="unknown key 'suports'.*did you mean 'supports'"):
        load_scene(p)


def test_fields_outside_the_body_are_refused():
    scene = Scene(Domain.rectangle(0, 0, 1, 1, holes=[Loop.circle([0.5, 0.5], 0.2)]), MAT,
                  supports=(Support("left", ux=0.0, uy=0.0),))
    sol = solve(scene, EFG(spacing=0.1))
    with pytest.raises(ValueError, match=r"1 point\(s\) lie outside the body, e.g. x\[1\]"):
        sol.stress([[0.1, 0.1], [0.5, 0.5]])
    with pytest.raises(ValueError, match="finite points of shape"):
        sol.displacement([[np.nan, 0.0]])
    assert np.all(np.isfinite(sol.stress([[0.0, 0.0], [1.0, 1.0], [0.5, 0.3]])))


def test_global_extrinsic_fields_need_a_single_tip_crack():
    from efgkit import Crack, Field

    f = Field.named("kirsch", a=0.1)
    sup = tuple(Support(e, ux=f, uy=f) for e in ("bottom", "right", "top", "left"))
    scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3), supports=sup,
                  cracks=(Crack([[-0.3, -0.2], [0.3, 0.2]], name="g"),))
    with pytest.raises(ValueError, match="crack 'g' has two tips.*Give enrich_radius"):
        solve(scene, EFG(spacing=0.2, enrichment="extrinsic_mls"))


@pytest.mark.parametrize("enrichment", ["full", "extrinsic_mls", "pu"])
def test_visibility_with_enrichment_is_refused(enrichment):
    from efgkit import Crack

    scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
                  supports=(Support("bottom", ux=0.0, uy=0.0),),
                  cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]], (False, True)),))
    extra = {"d_max": 3.0} if enrichment == "full" else {}
    with pytest.raises(ValueError, match=f"enrichment='{enrichment}' with crack_rule='visibility' is "
                                         "not supported.*only 'radial' works with visibility"):
        solve(scene, EFG(spacing=0.25, enrichment=enrichment, crack_rule="visibility", **extra))


def test_enrichment_without_cracks_is_refused():
    scene = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3),
                  supports=(Support("left", ux=0.0, uy=0.0),))
    with pytest.raises(ValueError, match="needs a crack tip"):
        solve(scene, EFG(spacing=0.25, enrichment="full"))


def test_point_support_selecting_nothing_is_explained():
    scene = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3),
                  supports=(Support("left", ux=0.0),
                            Support(lambda x: np.hypot(*(x - [0.0, 0.5]).T) < 1e-9, uy=0.0)))
    with pytest.raises(ValueError, match="selects none of the boundary quadrature points"):
        solve(scene, EFG(spacing=0.25, bc="lagrange"))


def test_point_traction_selecting_nothing_is_refused():
    # it used to be skipped: the load was lost without a word
    scene = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3),
                  supports=(Support("left", ux=0.0, uy=0.0),),
                  tractions=(Traction(lambda x: np.hypot(*(x - [1.0, 0.5]).T) < 1e-9, (1.0, 0.0)),))
    with pytest.raises(ValueError, match=r"traction .* selects none of the boundary quadrature "
                                         r"points, so its load would be lost"):
        solve(scene, EFG(spacing=0.25))


# --- issue [trust]: no silent wrong answer from magnitudes float64 cannot square -----------------

@pytest.mark.parametrize("build,what", [
    (lambda: Domain.rectangle(0, 0, 1e300, 1e300), r"loop vertices \(and arc centres\): coordinate 1"),
    (lambda: Loop.circle([0.0, 0.0], 1e300), r"loop vertices \(and arc centres\): coordinate 0"),
    (lambda: Crack([[0.0, 0.0], [1e300, 0.0]], name="c"), "crack 'c': vertices: coordinate 1"),
], ids=["rectangle", "circle", "crack"])
def test_coordinates_too_large_to_square(build, what):
    # they raised OverflowError inside Domain, and a crack was said to have a zero-length segment
    with pytest.raises(ValueError, match=what + r" \[1e\+300, 0.0\] is too large to square without "
                       r"overflow \(\|x\| <= 1e\+150.*rescale the units"):
        build()


@pytest.mark.parametrize("build", [lambda: Domain.rectangle(0, 0, 1e-200, 1e-200),
                                   lambda: Crack([[0.0, 0.0], [1e-200, 0.0], [1e-200, 1e-200]])],
                         ids=["rectangle", "crack"])
def test_coordinates_too_small_to_square(build):
    # the squares underflow: "zero-length edge" or "zero-length segment" before
    with pytest.raises(ValueError, match=r"span 1e-200, too small to square without underflow "
                                         r"\(span >= 1e-150\); rescale the units"):
        build()


def test_geometry_near_the_coordinate_limit_is_exact_and_warning_free():
    # segments_intersect and the crack's self-intersection test form fourth powers of lengths:
    # they work in coordinates scaled by powers of two (RuntimeWarnings are errors here)
    big = 1e149
    dom = Domain.rectangle(0, 0, 10 * big, 10 * big, holes=[Loop.circle([5 * big, 5 * big], big)])
    assert math.isclose(dom.area, 100 * big**2 - math.pi * big**2, rel_tol=1e-4)
    with pytest.raises(ValueError, match="intersects itself: segments 0 and 2"):
        Crack([[0.0, 0.0], [big, 0.0], [big, big], [0.5 * big, -big]], name="c")
    with pytest.raises(ValueError, match="intersects itself: segments 0 and 2"):
        Crack([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.5, -1.0]], name="c")


def _loaded(t, E=1.0, cracks=()):
    return Scene(SQUARE, Elastic(E, 0.3), supports=(Support("left", ux=0.0, uy=0.0),),
                 tractions=(Traction("right", (t, 0.0)),), cracks=cracks)


def test_traction_too_large_to_square():
    # it solved to NaN energy and wrote inf into the VTU; the CLI then died in matplotlib
    with pytest.raises(ValueError, match=r"traction on 'right': t = \(1e\+300, 0.0\) is too large to "
                                         r"square without overflow \(\|value\| <= 1e\+150.*rescale"):
        Traction("right", (1e300, 0.0))
    with pytest.raises(ValueError, match=r"support on 'left': ux = 1e\+200 is too large to square"):
        Support("left", ux=1e200)


@pytest.mark.parametrize("kw,match", [
    (dict(t=1e150), r"too large for float64: the force scale 1.41e\+150 \(from traction on 'right': "
                    r"t = \(1e\+150, 0.0\), domain size 1.41, E = 1\) lies outside \[1e-150, 1e\+150\], "
                    r"so its square overflows"),
    (dict(t=1e100, E=1e-100), r"the displacement scale 1.41e\+200 .* E = 1e-100\) lies outside"),
    (dict(t=1e-200), r"too small for float64: the stress scale 1e-200 .* underflows to zero"),
], ids=["force", "displacement", "underflow"])
def test_load_scales_whose_squares_leave_float64(kw, match):
    """The scene refuses constant loads whose stress, force, displacement or energy scale
    squares outside float64 (issue [trust]: 1e300 solved to NaN energy, and 1e-200 to zero
    displacement, silently)."""
    with pytest.raises(ValueError, match=match + ".*rescale the units"):
        _loaded(**kw)
    assert _loaded(1e10, E=1e12).is_static  # large but representable: accepted


def test_load_scale_of_enriched_sif_unknowns():
    """With a crack the loads conjugate to enriched K unknowns scale as S L^1.5: at L = 1e105
    and t = 1 the solve's norm of the load vector overflowed (measured) while S, S L and the
    energy were representable."""
    L = 1e60
    dom = Domain.rectangle(0, 0, L, L)
    kw = dict(supports=(Support("bottom", ux=0.0, uy=0.0),), tractions=(Traction("top", (0.0, 1e62)),))
    Scene(dom, MAT, **kw)  # no crack: accepted
    with pytest.raises(ValueError, match=r"the load on the enrichment \(SIF\) unknowns scale 1.68e\+152 "
                                         r"\(from traction on 'top'.*rescale the units"):
        Scene(dom, MAT, cracks=(Crack([[0.0, 0.5 * L], [0.5 * L, 0.5 * L]], (False, True), "c"),), **kw)


def test_evaluated_loads_too_large_to_square():
    from efgkit.problem.scene import evaluate_component, evaluate_vector

    x = np.array([[1.0, 0.5]])
    with pytest.raises(ValueError, match=r"a traction or body force evaluated to 1e\+200, too large to "
                                         r"square without overflow.*rescale the units"):
        evaluate_vector(lambda x: np.full((len(x), 2), 1e200), x, np.array([[1.0, 0.0]]), MAT)
    with pytest.raises(ValueError, match=r"a prescribed displacement evaluated to 1e\+160, too large"):
        evaluate_component(lambda x: np.full(len(x), 1e160), x, 0, MAT)


def test_crack_too_short_for_any_spacing():
    # a 1e-12 crack solved, then sifs() failed and the CLI showed a traceback
    with pytest.raises(ValueError, match=r"crack 'c' is 1e-12 long, shorter than 1e-09 of the domain "
                                         r"size 1.41421: no node spacing resolves it.*remove it, or make "
                                         "it at least a few node spacings long"):
        Scene(SQUARE, MAT, cracks=(Crack([[0.5, 0.5], [0.5 + 1e-12, 0.5]], name="c"),))
    Scene(SQUARE, MAT, cracks=(Crack([[0.5, 0.5], [0.5 + 1e-8, 0.5]], name="c"),))  # accepted
