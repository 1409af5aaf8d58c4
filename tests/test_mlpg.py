"""MLPG1 (seed 002 Eqs. 20-24): the description, the patch test per BC method and disc rule,
the unsymmetric solvers and the Solution contract."""

import numpy as np
import pytest

from efgkit import MLPG, Domain, Elastic, Scene, Support, Traction, solve
from efgkit.system.krylov import solve_unsymmetric
from efgkit.system.linear_system import LinearSystem


def _tension():
    # uniform tension sigma_xx = 1 on a 2 x 1 plate: u = (x / E, -nu y / E) (closed form)
    return Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.25, "stress"),
                 supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
                 tractions=(Traction("right", (1.0, 0.0)),))


def _errors(sol):
    x = np.array([[2.0, 0.5], [1.0, 1.0], [0.3, 0.7], [1.1, 0.05]])
    u = sol.displacement(x)
    exact = np.column_stack([x[:, 0] / 1000.0, -0.25 * x[:, 1] / 1000.0])
    return np.abs(u - exact).max() / 0.002, np.abs(sol.stress(x) - [1.0, 0.0, 0.0]).max()


@pytest.mark.parametrize("bc", ["penalty", "collocation"])
@pytest.mark.parametrize("basis", ["linear", "quadratic"])
def test_patch_gauss(bc, basis):
    du, ds = _errors(solve(_tension(), MLPG(spacing=0.25, bc=bc, basis=basis)))
    assert du < 1e-9 and ds < 1e-8  # measured 9e-12 and 5e-11


def test_patch_modified_mls_linear():
    du, ds = _errors(solve(_tension(), MLPG(spacing=0.25, bc="modified_mls", basis="linear")))
    assert du < 1e-9 and ds < 1e-8  # measured 8e-12, 1e-11 (regular grid, straight edges)


def test_patch_seed_midpoint_rule_fails_by_its_quadrature():
    du, _ = _errors(solve(_tension(), MLPG(spacing=0.25, quadrature="midpoint")))
    assert 1e-4 < du < 1e-1  # measured 2.7e-3: the 5 x 8 rule is not exact on cut discs


def test_solution_contract():
    sol = solve(_tension(), MLPG(spacing=0.25))
    assert sol.kind == "mlpg"
    # U = 1/2 sigma^2 / E * area = 1e-3 on the field quadrature (closed form)
    assert abs(sol.strain_energy() - 1e-3) < 1e-12
    assert np.allclose(sol.reaction("left"), [-1.0, 0.0], atol=1e-9)


def test_krylov_solvers_reach_tolerance():
    sol = solve(_tension(), MLPG(spacing=0.25))
    # the same system through GMRES and BiCGSTAB
    from efgkit.methods.local import DEFAULT_MLPG_PENALTY, local_system

    K, f = local_system(sol.disc, DEFAULT_MLPG_PENALTY * 1000.0 / 0.25)
    for kind in ("gmres", "bicgstab"):
        z, info = solve_unsymmetric(LinearSystem(K, f, False, K.shape[0]), kind)
        assert info["residual"] <= 1e-8 and info["iterations"] > 0
        assert np.abs(z - sol.coeffs).max() < 1e-6 * np.abs(sol.coeffs).max()


@pytest.mark.parametrize(("kw", "match"), [
    ({"test_radius": 3.0}, "test_radius"),
    ({"quadrature": "simpson"}, "quadrature must be one of"),
    ({"bc": "lagrange"}, "bc must be one of"),
    ({"solver": "multigrid"}, "solver must be one of"),
    ({"weight_k": 0}, "weight_k must be"),
    ({"radial": 1.5}, "radial must be an integer"),
])
def test_bad_input(kw, match):
    with pytest.raises((ValueError, TypeError), match=match):
        MLPG(spacing=0.1, **kw)


def test_coarsened_and_for_scene():
    m = MLPG(spacing=0.1)
    assert m.coarsened().spacing == 0.2
    assert m.for_scene(_tension()).zones == ()


def test_scene_file_method_key_and_cli(tmp_path, capsys):
    # examples/patch.toml solved by MLPG by adding the one key ``method = "mlpg"``
    import json
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    from efgkit.cli import main
    from efgkit.scenefile import load_study

    src = (Path(__file__).resolve().parents[1] / "examples" / "patch.toml").read_text()
    path = tmp_path / "patch_mlpg.toml"
    path.write_text('method = "mlpg"\n' + src)
    _, method = load_study(path)
    assert isinstance(method, MLPG)
    rc = main(["run", str(path), "--out", str(tmp_path / "out"), "--json", "--samples", "500"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    rep = json.loads(out)
    assert rep["method"]["test_radius"] == 1.5 and rep["solver"]["residual"] <= 1e-8
    # U = sigma^2 / (2 E) * area = 5e-4 (closed form of the uniform tension patch)
    assert abs(rep["energy"] - 5e-4) < 1e-12


def test_scene_file_errors():
    from efgkit.methods.mlpg_file import study_method

    with pytest.raises(ValueError, match="method must be one of"):
        study_method({"method": "fem", "efg": {"spacing": 0.1}}, None)
    with pytest.raises(ValueError, match="unknown key 'radiall' in table 'mlpg'"):
        study_method({"method": "mlpg", "mlpg": {"spacing": 0.1, "radiall": 3}}, None)
    with pytest.raises(ValueError, match=r"needs the discretisation table \[mlpg\]"):
        study_method({"method": "mlpg"}, None)


def test_seed_gaussian_is_near_singular_at_the_boundary():
    # docs/robustness.md: seed 002's c_I = 0.365 r_I with k = 2 and the quadratic basis
    from efgkit.approx.mls import SingularMomentMatrix

    with pytest.raises(SingularMomentMatrix, match="ill-conditioned"):
        solve(_tension(), MLPG(spacing=0.25, shape_factor=0.365, weight_k=2))


def test_krylov_refuses_singular_and_empty_rows():
    from scipy.sparse import csr_array

    from efgkit.system.linalg import SolverError

    zero_row = csr_array(np.array([[1.0, 0.0], [0.0, 0.0]]))
    with pytest.raises(SolverError, match="row 1 of the system matrix is zero"):
        solve_unsymmetric(LinearSystem(zero_row, np.ones(2), False, 2), "gmres")
    singular = csr_array(np.array([[1.0, 1.0], [1.0, 1.0]]))  # b not in the range
    with pytest.raises(SolverError, match="singular|residual"):
        solve_unsymmetric(LinearSystem(singular, np.array([1.0, 0.0]), False, 2), "bicgstab")
