"""Bad input gets a clear error naming the argument, the value and the remedy
(the list of issue [core]); each error's type and message is checked."""

import math

import numpy as np
import pytest

from efgkit import EFG, Domain, Elastic, Loop, Scene, Support, Traction
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
