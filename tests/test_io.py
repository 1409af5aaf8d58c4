"""efgkit.io: sample grids that keep holes, notches and cracks open; VTU/JSON files."""

import json
import math

import meshio
import numpy as np
import pytest

from efgkit import EFG, Crack, Domain, Elastic, Loop, Scene, Support, Traction
from efgkit.io import (
    jsonable,
    nodes_path,
    sample_grid,
    von_mises,
    write_figure,
    write_json,
    write_nodes_vtu,
    write_vtu,
)
from efgkit.problem.geometry import segments_intersect
from efgkit.static import solve

HOLE_C, HOLE_R = np.array([1.0, 0.5]), 0.25
HOLED = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle(HOLE_C, HOLE_R)])
# unit square with a V-notch from the top edge down to (0.5, 0.3)
NOTCHED = Domain(Loop.polygon([[0, 0], [1, 0], [1, 1], [0.55, 1], [0.5, 0.3], [0.45, 1], [0, 1]]))
NOTCH = np.array([[0.55, 1], [0.5, 0.3], [0.45, 1]])


def _areas(x, tri):
    p = x[tri]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


@pytest.mark.parametrize("domain", [HOLED, NOTCHED], ids=["hole", "notch"])
def test_sample_grid_covers_only_material(domain):
    x, tri = sample_grid(domain, n_target=3000)
    assert x.shape[1] == 2 and tri.shape[1] == 3
    assert domain.contains(x, tol=1e-9).all()
    assert domain.contains(x[tri].mean(axis=1)).all()
    a = _areas(x, tri)
    assert (a > 0).all()  # counter-clockwise, none degenerate
    # the triangles tile the material up to the polyline sag of arcs (48 points a turn)
    assert abs(a.sum() - domain.area) <= 5e-3 * domain.area
    assert 0.5 * 3000 <= len(x) <= 2 * 3000


def test_sample_grid_leaves_hole_open():
    x, tri = sample_grid(HOLED, n_target=2000)
    r = np.linalg.norm(x[tri].mean(axis=1) - HOLE_C, axis=1)
    assert (r > HOLE_R * math.cos(math.pi / 48)).all()  # no centroid inside the hole


def test_sample_grid_leaves_notch_open():
    from matplotlib.path import Path

    x, tri = sample_grid(NOTCHED, n_target=2000)
    assert not Path(NOTCH).contains_points(x[tri].mean(axis=1)).any()


def test_sample_grid_no_triangle_crosses_a_crack():
    crack = Crack(np.array([[0.0, 0.5], [0.7, 0.5]]), tips=(False, True))
    dom = Domain.rectangle(0, 0, 2, 1)
    x, tri = sample_grid(dom, n_target=2000, cracks=[crack])
    a, b = crack.vertices
    for i, j in ((0, 1), (1, 2), (2, 0)):
        p, q = x[tri[:, i]], x[tri[:, j]]
        m = len(p)
        assert not segments_intersect(p, q, np.broadcast_to(a, (m, 2)),
                                      np.broadcast_to(b, (m, 2))).any()
    # both faces are sampled: points just above and just below the crack line
    near = (x[:, 0] > 0.05) & (x[:, 0] < 0.65) & (np.abs(x[:, 1] - 0.5) < 0.01)
    assert (x[near, 1] > 0.5).any() and (x[near, 1] < 0.5).any()


@pytest.mark.parametrize("n_target", [0, 2.5, True])
def test_sample_grid_rejects_bad_n_target(n_target):
    with pytest.raises(ValueError, match="n_target"):
        sample_grid(HOLED, n_target=n_target)


@pytest.mark.parametrize(
    ("stress", "plane", "nu", "expected"),
    [
        ([2.0, 0.0, 0.0], "stress", 0.3, 2.0),  # uniaxial
        ([0.0, 0.0, 1.0], "stress", 0.3, math.sqrt(3)),  # pure shear
        ([1.0, 1.0, 0.0], "stress", 0.3, 1.0),  # equibiaxial, szz = 0
        ([1.0, 1.0, 0.0], "strain", 0.3, 1 - 2 * 0.3),  # equibiaxial, szz = 2 nu
    ],
)
def test_von_mises_closed_forms(stress, plane, nu, expected):
    vm = von_mises(np.array([stress]), Elastic(1.0, nu, plane))
    assert vm.shape == (1,)
    assert vm[0] == pytest.approx(expected, rel=1e-14)


@pytest.fixture(scope="module")
def holed_solution():
    scene = Scene(HOLED, Elastic(1000.0, 0.25, "strain"),
                  supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
                  tractions=(Traction("right", (1.0, 0.0)),), name="holed")
    return solve(scene, EFG(spacing=0.125, bc="lagrange"))


def test_write_vtu_round_trip(holed_solution, tmp_path):
    sol = holed_solution
    path = sol.write_vtu(tmp_path / "sub" / "holed", n_target=1500)
    assert path == tmp_path / "sub" / "holed.vtu" and path.is_file()
    mesh = meshio.read(path)
    x = mesh.points[:, :2]
    tri = mesh.cells_dict["triangle"]
    assert sol.scene.domain.contains(x[tri].mean(axis=1)).all()
    u, s = mesh.point_data["displacement"], mesh.point_data["stress"]
    assert u.shape == (len(x), 3) and s.shape == (len(x), 3)
    assert np.all(u[:, 2] == 0)
    np.testing.assert_allclose(u[:, :2], sol.displacement(x), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(s, sol.stress(x), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(mesh.point_data["von_mises"], von_mises(s, sol.scene.material))

    nodes = meshio.read(nodes_path(path))
    assert nodes_path(path).name == "holed_nodes.vtu"
    np.testing.assert_array_equal(nodes.points[:, :2], sol.nodes.x)
    np.testing.assert_array_equal(nodes.point_data["support_radius"], sol.nodes.radius)
    np.testing.assert_array_equal(nodes.point_data["boundary"].astype(bool), sol.nodes.boundary)
    assert len(nodes.cells_dict["vertex"]) == sol.nodes.n


def test_write_nodes_vtu_alone(holed_solution, tmp_path):
    p = write_nodes_vtu(holed_solution.nodes, tmp_path / "n.vtu")
    assert len(meshio.read(p).points) == holed_solution.nodes.n


def test_write_json_round_trip(tmp_path):
    obj = {"a": np.float64(1.5), "b": np.arange(3), "c": (1, 2), "d": float("inf"),
           "e": tmp_path, "f": {"g": np.bool_(True)}, "z": Elastic(1.0, 0.25)}
    p = write_json(obj, tmp_path / "deep" / "r.json")
    back = json.loads(p.read_text())
    assert back == {"a": 1.5, "b": [0, 1, 2], "c": [1, 2], "d": None, "e": str(tmp_path),
                    "f": {"g": True}, "z": {"E": 1.0, "nu": 0.25, "plane": "strain",
                                            "rho": None}}


class _Spoiled:
    """A solution with stresses scaled by ``factor`` and a NaN displacement at the first point
    if ``nan_u`` (stand-ins for the loads too large to square, which the scene now refuses)."""

    def __init__(self, sol, factor, nan_u):
        self.scene, self.sol, self.factor, self.nan_u = sol.scene, sol, factor, nan_u

    def displacement(self, x):
        u = self.sol.displacement(x)
        u[0] = np.nan if self.nan_u else u[0]
        return u

    def stress(self, x):
        return self.factor * self.sol.stress(x)


@pytest.mark.parametrize("factor,nan_u,field", [(1e160, False, "von_mises"), (1.0, True, "displacement")])
def test_write_vtu_refuses_non_finite_fields(holed_solution, tmp_path, factor, nan_u, field):
    # a traction of 1e300 solved and wrote inf into the VTU; the CLI then died in matplotlib.
    # Stresses of 1e160 are finite, but von Mises squares them.
    with pytest.raises(ValueError, match=rf"field '{field}' is NaN or inf at \d+ of \d+ points \(e.g. x = "
                                         r"\[.*\]\); f.vtu is not written. Likely cause: values whose "
                                         r"squares overflow .*rescale the units\) or a solve"):
        write_vtu(_Spoiled(holed_solution, factor, nan_u), tmp_path / "f", n_target=300)
    assert not (tmp_path / "f.vtu").exists()


def test_write_nodes_vtu_refuses_non_finite_radii(holed_solution, tmp_path):
    import dataclasses

    nodes = dataclasses.replace(holed_solution.nodes, radius=np.full(holed_solution.nodes.n, np.nan))
    with pytest.raises(ValueError, match=r"field 'support_radius' is NaN or inf at \d+ of \d+ points"):
        write_nodes_vtu(nodes, tmp_path / "n.vtu")
    assert not (tmp_path / "n.vtu").exists()


def test_write_json_refuses_non_finite_arrays(tmp_path):
    # a non-finite scalar is a value not available (null); a field with inf is an error
    with pytest.raises(ValueError, match=r"array obj\['r'\]\[1\]\['u'\] holds NaN or inf; r.json is not "
                                         "written. Likely cause: values whose squares overflow"):
        write_json({"r": [{"u": np.zeros(2)}, {"u": np.array([1.0, np.inf])}]}, tmp_path / "r.json")
    assert not (tmp_path / "r.json").exists()


def test_jsonable_rejects_unknown_objects():
    with pytest.raises(TypeError, match="JSON"):
        jsonable({"x": object()})


def test_write_figure_closes_the_figure_also_when_saving_fails(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, _ = plt.subplots()
    path = write_figure(fig, tmp_path / "a" / "f.png")
    assert path.exists() and not plt.fignum_exists(fig.number)
    fig, _ = plt.subplots()
    with pytest.raises(ValueError, match="xyz"):
        write_figure(fig, tmp_path / "f.xyz")
    assert not plt.fignum_exists(fig.number)
    fig, _ = plt.subplots()
    write_figure(fig, tmp_path / "g.png", close=False)
    assert plt.fignum_exists(fig.number)
    plt.close(fig)
