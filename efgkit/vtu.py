"""VTU files (VTK XML unstructured grids) written straight from numpy arrays.

One DataArray per array in VTK's inline ``binary`` format: base64 of a UInt64 byte count
followed by the raw little- or big-endian bytes (the machine's order, named in the file
header), no compression. Writing is a handful of vectorised encodes and one file write;
no XML tree and no Python loop over points or cells (ParaView, VTK and meshio read it).
"""

from __future__ import annotations

import base64
from pathlib import Path
from sys import byteorder

import numpy as np

__all__ = ["VTK_TRIANGLE", "VTK_VERTEX", "write_unstructured"]

VTK_VERTEX = 1  # VTK cell type ids (vtkCellType.h)
VTK_TRIANGLE = 5


def _vtk_type(a: np.ndarray) -> tuple[str, np.dtype]:
    """The VTK type name and the numpy type an array is written as."""
    if a.dtype.kind == "f":
        return "Float64", np.dtype(np.float64)
    if a.dtype.kind == "b" or a.dtype == np.uint8:
        return "UInt8", np.dtype(np.uint8)
    if a.dtype.kind == "u":
        return "UInt64", np.dtype(np.uint64)
    if a.dtype.kind == "i":
        return "Int64", np.dtype(np.int64)
    raise TypeError(f"cannot write a {a.dtype} array to VTU: give float, integer or bool arrays")


def _data_array(name: str, a: np.ndarray) -> str:
    """One ``<DataArray>`` element: ``a (n,)`` or ``(n, k)`` as base64 of a UInt64 length
    header and the bytes of ``a`` (floats as Float64, integers as Int64/UInt64, bools and
    uint8 as UInt8)."""
    vtk, dtype = _vtk_type(a)
    a = np.ascontiguousarray(a, dtype=dtype)
    raw = a.tobytes()
    head = np.array([len(raw)], dtype=np.uint64).tobytes()
    comps = f' NumberOfComponents="{a.shape[1]}"' if a.ndim == 2 else ""
    return (f'<DataArray type="{vtk}" Name="{name}"{comps} format="binary">'
            f"{base64.b64encode(head + raw).decode('ascii')}</DataArray>\n")


def write_unstructured(path, points: np.ndarray, cells: np.ndarray, cell_type: int,
                       point_data: dict | None = None) -> Path:
    """Write points, cells of one type and point data as a VTU file.

    Parameters
    ----------
    path : str or Path
        The file (written as given; parent directories must exist).
    points : ndarray, shape (n, 3)
        Point coordinates (z included).
    cells : ndarray, shape (m, k), int
        Vertex indices of each cell (``k`` = 1 for vertices, 3 for triangles).
    cell_type : int
        VTK cell type id (:data:`VTK_VERTEX`, :data:`VTK_TRIANGLE`).
    point_data : dict of str to ndarray, shape (n,) or (n, c)
        Float, integer or bool arrays, one row per point.

    Returns
    -------
    Path

    Examples
    --------
    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "t.vtu"
    >>> x = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    >>> _ = write_unstructured(p, x, np.array([[0, 1, 2]]), VTK_TRIANGLE, {"a": np.ones(3)})
    >>> p.read_text().count("<DataArray")
    5
    """
    points = np.asarray(points, dtype=float)
    cells = np.asarray(cells, dtype=np.int64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3), got {points.shape}")
    if cells.ndim != 2:
        raise ValueError(f"cells must have shape (m, k), got {cells.shape}")
    n, (m, k) = len(points), cells.shape
    parts = [f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
             f'byte_order="{"LittleEndian" if byteorder == "little" else "BigEndian"}" '
             f'header_type="UInt64">\n<UnstructuredGrid>\n'
             f'<Piece NumberOfPoints="{n}" NumberOfCells="{m}">\n<Points>\n',
             _data_array("Points", points), "</Points>\n<Cells>\n",
             _data_array("connectivity", cells.reshape(-1)),
             _data_array("offsets", np.arange(1, m + 1, dtype=np.int64) * k),
             _data_array("types", np.full(m, cell_type, dtype=np.uint8)), "</Cells>\n"]
    if point_data:
        parts.append("<PointData>\n")
        for name, v in point_data.items():
            v = np.asarray(v)
            if v.shape[:1] != (n,) or v.ndim > 2:
                raise ValueError(f"point_data[{name!r}] must have shape ({n},) or ({n}, c), got "
                                 f"{v.shape}")
            parts.append(_data_array(name, v))
        parts.append("</PointData>\n")
    parts.append("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")
    path = Path(path)
    path.write_text("".join(parts), encoding="ascii")
    return path
