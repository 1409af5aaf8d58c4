"""Cold start of `efgkit run`: a small run loads only what it uses, and the VTU writer."""

import subprocess
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

from efgkit.vtu import VTK_TRIANGLE, VTK_VERTEX, write_unstructured

ROOT = Path(__file__).resolve().parents[1]


def test_small_run_imports_no_compiler_and_no_other_drivers(tmp_path):
    """A run below efgkit.jit.COMPILED_MIN points computes in numpy: numba (0.2-0.8 s to
    import), meshio, scikit-fem, dask and pandas, and the explicit, FEM, growth and MLPG
    drivers stay unloaded."""
    heavy = ("numba", "meshio", "skfem", "dask", "pandas", "pyamg", "efgkit.explicit",
             "efgkit.fem", "efgkit.growth", "efgkit.methods.local")
    code = ("import sys; from efgkit.cli import main; "
            f"status = main(['run', {str(ROOT / 'examples' / 'patch.toml')!r}, '--json', "
            f"'--samples', '500', '--out', {str(tmp_path / 'out')!r}]); "
            f"print(status, sorted(m for m in {heavy!r} if m in sys.modules), file=sys.stderr)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=ROOT)
    assert out.stderr.strip().splitlines()[-1] == "0 []"
    assert (tmp_path / "out" / "patch.vtu").is_file()


def test_vtu_round_trip_through_meshio(tmp_path):
    x = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    tri = np.array([[0, 1, 2], [1, 3, 2]])
    data = {"s": np.arange(4.0), "v": np.arange(12.0).reshape(4, 3), "flag": np.array([1, 0, 1, 0], np.int32),
            "b": np.array([True, False, True, True])}
    p = write_unstructured(tmp_path / "a.vtu", x, tri, VTK_TRIANGLE, data)
    m = meshio.read(p)
    np.testing.assert_array_equal(m.points, x)
    np.testing.assert_array_equal(m.cells_dict["triangle"], tri)
    for k, v in data.items():
        np.testing.assert_array_equal(m.point_data[k], v)
    q = write_unstructured(tmp_path / "n.vtu", x, np.arange(4).reshape(4, 1), VTK_VERTEX)
    assert len(meshio.read(q).cells_dict["vertex"]) == 4


@pytest.mark.parametrize("points,cells,data,err,match", [
    (np.zeros((3, 2)), np.zeros((1, 3), int), None, ValueError,
     r"points must have shape \(n, 3\), got \(3, 2\)"),
    (np.zeros((3, 3)), np.zeros(3, int), None, ValueError, r"cells must have shape \(m, k\), got \(3,\)"),
    (np.zeros((3, 3)), np.zeros((1, 3), int), {"a": np.zeros(2)}, ValueError,
     r"point_data\['a'\] must have shape \(3,\) or \(3, c\), got \(2,\)"),
    (np.zeros((3, 3)), np.zeros((1, 3), int), {"a": np.array(["x", "y", "z"])}, TypeError,
     r"cannot write a <U1 array to VTU: give float, integer or bool arrays"),
])
def test_vtu_refuses_bad_arrays(tmp_path, points, cells, data, err, match):
    with pytest.raises(err, match=match):
        write_unstructured(tmp_path / "bad.vtu", points, cells, VTK_TRIANGLE, data)
    assert not (tmp_path / "bad.vtu").exists()


def test_public_names_resolve_on_first_use():
    """`efgkit` imports its public names when first used (PEP 562): each of __all__ resolves
    to the object of its module, and an unknown name is an AttributeError."""
    code = ("import efgkit, sys; objs = {n: getattr(efgkit, n) for n in efgkit.__all__}; "
            "from efgkit.static import solve; from efgkit.fem import FEM; "
            "assert objs['solve'] is solve and objs['FEM'] is FEM and efgkit.fem.FEM is FEM; "
            "print(hasattr(efgkit, 'no_such_name'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=ROOT)
    assert out.stdout.strip() == "False"
