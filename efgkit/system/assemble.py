"""Stiffness and loads from shape operators at quadrature points (the lumped mass: :mod:`efgkit.system.mass`).

Stiffness (seed 003 Eq. 22a) with test functions v and trial functions phi
(v = phi for EFG; the MLPG test operator later):

    K_IJ = sum_q w_q B_I^v(x_q)^T D B_J^phi(x_q),   B_I = [[d_x, 0], [0, d_y], [d_y, d_x]] phi_I

DOFs are node-major interleaved (2 I + c), so K is a block-sparse matrix with
2 x 2 blocks. The compiled kernel visits each row I once, runs over the
quadrature points in I's test support and adds their contributions straight
into the row's blocks (no per-point dense matrices, no duplicate summation),
finding the row's pattern in the same pass (:mod:`efgkit.system.kernels`).
For Bubnov-Galerkin (v = phi) with a symmetric D it forms only the blocks
J >= I and writes K_JI = K_IJ^T (half the products). The rows are formed in
the order of the middle point of each function's point list (supports of
consecutive rows close together) by chunks on a thread pool; each row's sums
do not depend on that order or on the threads. The numpy reference
forms the same matrix with scipy.sparse products.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import bmat, csr_array, diags_array, vstack

from ..approx.shape import Shape
from ..jit import resolve_backend
from .block_stack import stack_2x2
from .dense_stiffness import DENSE_EXTRA, DENSE_WORK, dense_enrichment_blocks, dense_nodal_stiffness

__all__ = ["stiffness", "load_vector", "point_to_function_map"]


def point_to_function_map(shape: Shape):
    """For each shape function, the quadrature points in its support, ascending: CSR triplet
    (indptr (n_functions + 1,) int64, point (nnz,), slot (nnz,)) with
    ``shape.neighbours.idx[point, slot]`` the function."""
    import numba

    indptr, pos, _ = _lists(shape, numba.get_num_threads())
    point, slot = np.divmod(pos, shape.neighbours.idx.shape[1])
    return indptr, point, slot


def _lists(shape: Shape, threads: int):
    """The points of each function as (indptr, pos = q k + a) and whether the rows of the
    neighbour lists ascend (:func:`efgkit.system.kernels.count_points`, ``fill_points``):
    chunks of points counted, then filled, on ``threads`` threads; chunk c's entries of a
    function follow those of the chunks before it, so every list ascends."""
    from .kernels import count_points, fill_points

    nb = shape.neighbours
    spans = _spans(np.linspace(0, nb.idx.shape[0], _n_chunks(threads) + 1).astype(np.int64))
    counts = np.zeros((len(spans), shape.n_functions), np.int64)
    bad = _on_threads(lambda c: count_points(*spans[c], nb.idx, nb.mask, counts[c]),
                      range(len(spans)), threads)
    ends = np.cumsum(counts, axis=0)  # chunk c's entries of I follow those of c' < c
    indptr = np.zeros(shape.n_functions + 1, np.int64)
    if len(spans):
        np.cumsum(ends[-1], out=indptr[1:])
    starts = ends - counts + indptr[:-1]
    del ends
    pos = np.empty(int(indptr[-1]), np.int32 if nb.idx.size < 2**31 else np.int64)
    _on_threads(lambda c: fill_points(*spans[c], nb.idx, nb.mask, starts[c], pos),
                range(len(spans)), threads)
    return indptr, pos, sum(bad) == 0


def _n_chunks(threads: int) -> int:
    """Ranges of points or rows handed to the threads: several per thread (one code path on
    one thread; a thread stalled by the shared machine holds up a small range only)."""
    return 4 * max(threads, 2)


def _spans(bounds: np.ndarray) -> list:
    """Ranges ``(bounds[i], bounds[i + 1])`` as Python ints, the empty ones dropped."""
    b = np.unique(bounds).tolist()
    return list(zip(b[:-1], b[1:], strict=True))


def _on_threads(fn, items, threads: int) -> list:
    """``[fn(i) for i in items]`` on a pool of ``threads`` threads (the kernels release the
    GIL), handed out in order as threads come free."""
    items = list(items)
    if threads > 1 and len(items) > 1:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(threads) as pool:
            return list(pool.map(fn, items))
    return [fn(i) for i in items]


def _row_order(t_ptr: np.ndarray, t_pos: np.ndarray, k: int) -> np.ndarray:
    """The order in which the rows of K are formed: by the middle point of each function's
    point list (points ascending). The points come sorted by box (as the discretisation
    sorts them), so this sweeps the domain a strip of boxes at a time: consecutive rows have
    nearby supports, and the points they share are still in cache (on a 100k-unknown square
    the row pass took 0.70-0.76 s in this order against 0.88 s in node order, one thread).
    Empty functions go last."""
    n = len(t_ptr) - 1
    mid = np.full(n, np.iinfo(np.int64).max)
    has = t_ptr[1:] > t_ptr[:-1]
    mid[has] = t_pos[(t_ptr[:-1][has] + t_ptr[1:][has]) // 2] // k
    return np.argsort(mid, kind="stable")


def _row_chunks(t_ptr: np.ndarray, t_pos: np.ndarray, k: int, threads: int) -> tuple:
    """(order, chunks): the rows in :func:`_row_order` and ranges of positions in it holding
    about equal numbers of (function, point) pairs, for the thread pool."""
    n = len(t_ptr) - 1
    order = _row_order(t_ptr, t_pos, k)
    work = np.cumsum(np.diff(t_ptr)[order])  # (function, point) pairs up to each row
    cuts = np.searchsorted(work, np.linspace(0, work[-1] if n else 0, _n_chunks(threads) + 1)[1:-1])
    return order, _spans(np.concatenate([[0], cuts, [n]]))


def _compiled(test: Shape, trial: Shape, w: np.ndarray, D: np.ndarray,
              lists: tuple | None = None) -> csr_array:
    """K by the compiled row kernel (module docstring of :mod:`efgkit.system.kernels`): the
    rows in chunks of about equal numbers of (function, point) pairs, run on
    ``numba.get_num_threads()`` threads (the kernels release the GIL), then scalar CSR
    written by the same chunks of rows. ``lists``: the point lists of the test functions
    (:func:`_lists`) when the caller has them."""
    import numba

    from .kernels import block_rows, compile_vectorised, lower_part, scalar_rows

    threads = numba.get_num_threads()
    nb = trial.neighbours
    t_ptr, t_pos, ascending = _lists(test, threads) if lists is None else lists
    n, m = test.n_functions, trial.n_functions
    symmetric = test is trial and np.array_equal(D, D.T)  # K_JI = K_IJ^T: half the work
    order, chunks = _row_chunks(t_ptr, t_pos, test.ddx.shape[1], threads)
    width = nb.idx.shape[1] * (2 if symmetric else 4)  # about the blocks of a row

    def args(r):
        return (order, r[0], r[1], t_ptr, t_pos, test.ddx, test.ddy, nb.idx, nb.mask,
                trial.ddx, trial.ddy, w, D, symmetric, ascending, m, (r[1] - r[0]) * width)

    compile_vectorised(block_rows, *args((0, 0)))  # before the threads call it
    parts = _on_threads(lambda r: block_rows(*args(r)), chunks, threads)
    u_len = np.zeros(n, np.int64)  # the upper rows, stored in the order they were formed
    u_len[order] = np.concatenate([p[0] for p in parts] + [np.zeros(0, np.int64)])
    u_off = np.zeros(n, np.int64)
    u_off[order] = np.cumsum(u_len[order]) - u_len[order]
    u_cols = np.concatenate([p[1] for p in parts] + [np.zeros(0, np.int32)])
    u_data = np.concatenate([p[2] for p in parts] + [np.zeros((0, 2, 2))])
    del parts
    if symmetric:
        l_ptr, l_row, l_src = lower_part(u_off, u_len, u_cols)
    else:
        l_ptr, l_row, l_src = np.zeros(n + 1, np.int64), np.empty(0, np.int32), np.empty(0, np.int64)
    start = np.zeros(n + 1, np.int64)  # first scalar entry of block row I (of row 2 I)
    np.cumsum(4 * (np.diff(l_ptr) + u_len), out=start[1:])
    nnz = int(start[-1])
    index = np.int32 if max(nnz, 2 * m) < 2**31 else np.int64
    indptr = np.empty(2 * n + 1, index)
    indptr[0:2 * n:2] = start[:-1]
    indptr[1:2 * n:2] = (start[:-1] + start[1:]) // 2  # row 2 I + 1: second half of block row I
    indptr[2 * n] = nnz
    indices, values = np.empty(nnz, index), np.empty(nnz)
    rows = _spans(np.linspace(0, n, _n_chunks(threads) + 1).astype(np.int64))
    _on_threads(lambda r: scalar_rows(r[0], r[1], start, u_off, u_len, u_cols, u_data, l_ptr,
                                      l_row, l_src, indices, values), rows, threads)
    return csr_array((values, indices, indptr), shape=(2 * n, 2 * m))


def _stiffness_numpy(test: Shape, trial: Shape, w: np.ndarray, D: np.ndarray) -> csr_array:
    """Reference with scipy.sparse: the four products ``P_de = T_d^T diag(w) Phi_e`` of the
    test and trial derivative operators (d, e in {x, y}; ``P_yx = P_xy^T`` when test = trial),
    combined per block ``K_ab = sum_de D[i(a, d), j(b, e)] P_de`` with ``i(x, x) = 0`` (xx),
    ``i(y, y) = 1`` (yy), ``i(x, y) = i(y, x) = 2`` (xy), and interleaved (2 I + a, 2 J + b).
    Three products for Bubnov-Galerkin instead of five of the interleaved 2n-column B
    operators (3.5-4x faster on the quick-start example)."""
    voigt = {(0, 0): 0, (1, 1): 1, (0, 1): 2, (1, 0): 2}  # (component, derivative) -> Voigt row
    tv = [csr_array(t).T.tocsr() for t in (test.dx, test.dy)]
    wp = [csr_array((t.data * np.repeat(w, np.diff(t.indptr)), t.indices, t.indptr), shape=t.shape)
          for t in (csr_array(trial.dx), csr_array(trial.dy))]  # W Phi_e: rows scaled
    P = {(d, e): tv[d] @ wp[e] for d in (0, 1) for e in (0, 1) if test is not trial or (d, e) != (1, 0)}
    if test is trial:
        P[1, 0] = P[0, 1].T
    rows, cols, vals = [], [], []
    for a in (0, 1):
        for b in (0, 1):
            terms = [D[voigt[a, d], voigt[b, e]] * p for (d, e), p in P.items()
                     if D[voigt[a, d], voigt[b, e]] != 0]
            if terms:
                block = sum(terms[1:], terms[0]).tocoo()
                rows.append(2 * block.row + a)
                cols.append(2 * block.col + b)
                vals.append(block.data)
    shape = (2 * test.dx.shape[1], 2 * trial.dx.shape[1])
    if not vals:
        return csr_array(shape)
    return csr_array((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=shape)


def stiffness(trial: Shape, w: np.ndarray, D: np.ndarray, test: Shape | None = None,
              backend: str = "auto") -> csr_array:
    """Stiffness matrix, csr_array (2 n_test, 2 n_trial), seed 003 Eq. (22a).

    Parameters
    ----------
    trial : Shape
        Trial functions with derivatives at the quadrature points.
    w : ndarray, shape (n_points,)
        Quadrature weights.
    D : ndarray, shape (3, 3)
        Constitutive matrix (Voigt, engineering shear).
    test : Shape, optional
        Test functions (default: the trial functions, Bubnov-Galerkin).
    backend : {"auto", "numba", "numpy"}
        Compiled row kernel or scipy.sparse reference (they agree to 1e-12); "auto": numba
        from :data:`efgkit.jit.COMPILED_MIN` quadrature points on.

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic
    >>> from efgkit.nodes import generate_nodes
    >>> from efgkit.approx.mls import mls_shape
    >>> cloud = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    >>> xq = np.random.default_rng(0).random((400, 2))
    >>> K = stiffness(mls_shape(xq, cloud), np.full(400, 1 / 400), Elastic(1.0, 0.3).D)
    >>> K.shape, bool(abs(K - K.T).max() < 1e-12)
    ((50, 50), True)
    """
    test = trial if test is None else test
    w = np.asarray(w, dtype=float)
    backend = resolve_backend(backend, trial.shape[0])
    if trial.extra is not None or test.extra is not None:
        if test is trial:
            return _with_enrichment(trial, w, np.asarray(D, dtype=float), backend)
        if test.extra is not None:
            raise ValueError("test functions with enrichment unknowns are supported for "
                             "Bubnov-Galerkin (test = trial) only")
        return _petrov_enriched(trial, test, w, np.asarray(D, dtype=float), backend)
    if w.shape != (trial.shape[0],) or test.shape[0] != trial.shape[0]:
        raise ValueError(
            f"weights {w.shape} and operators {test.shape}, {trial.shape} must share n_points"
        )
    if trial.ddx is None or test.ddx is None:
        raise ValueError("stiffness needs shape-function derivatives (derivatives=True)")
    if backend == "numpy" and trial.shape[0] * test.shape[1] * trial.shape[1] <= DENSE_WORK:
        return dense_nodal_stiffness(test, trial, w, np.asarray(D, dtype=float))  # small: dense
    if backend == "numpy":
        return _stiffness_numpy(test, trial, w, np.asarray(D, dtype=float))
    return _compiled(test, trial, w, np.ascontiguousarray(D, float))


def _nodal_part(shape: Shape) -> Shape:
    return Shape(shape.neighbours, shape.values, shape.ddx, shape.ddy, shape.n_functions)


def _with_enrichment(shape: Shape, w, D, backend) -> csr_array:
    """[[K_nn, K_ne], [K_en, K_ee]]: the nodal block by the row kernel, the enrichment
    columns from the stresses of the enrichment unknowns: with ``S_ij`` the stress
    components of every unknown at the points (n_points, n_extra) and ``W = diag(w)``,
    the x rows of node I are ``(dx^T W S_xx + dy^T W S_xy)_I`` and the y rows
    ``(dy^T W S_yy + dx^T W S_xy)_I`` (``B_I^T sigma``), and ``K_ee = E_e^T W D E_e``."""
    e = shape.extra
    if e.gxx is None:
        raise ValueError("stiffness needs shape-function derivatives (derivatives=True)")
    nodal, lists = _nodal_part(shape), None
    if backend == "numba" and w.shape == (shape.shape[0],) and shape.ddx is not None:
        import numba  # the point lists of the functions formed once, for K_nn and K_ne

        lists = _lists(nodal, numba.get_num_threads())
        K_nn = _compiled(nodal, nodal, w, np.ascontiguousarray(D, float), lists)
    else:  # the checks and the reference path of stiffness()
        K_nn = stiffness(nodal, w, D, backend=backend)
    if backend == "numpy" and e.n <= DENSE_EXTRA:  # thin blocks: dense (dense_stiffness)
        return stack_2x2(K_nn, *dense_enrichment_blocks(shape, w, D))
    ops = (e.gxx, e.gyy, e.gxy, e.gyx)
    one = all(np.array_equal(o.indptr, e.gxx.indptr) and np.array_equal(o.indices, e.gxx.indices)
              for o in ops[1:])  # one pattern (the extrinsic columns): sums of the data arrays
    g = csr_array((e.gxy.data + e.gyx.data, e.gxx.indices, e.gxx.indptr), shape=e.gxx.shape) \
        if one else csr_array(e.gxy + e.gyx)  # gamma_xy = gxy + gyx entry by entry
    eps = (e.gxx, e.gyy, g)  # strain of each unknown, (n, n_extra)
    nf = shape.n_functions
    interleave = np.ravel(np.column_stack([np.arange(nf), nf + np.arange(nf)]))  # rows 2 I + c
    w_entry = np.repeat(w, np.diff(e.gxx.indptr)) if one else None

    def stresses(C):  # W C eps of every unknown: three (n_points, n_extra)
        if one:  # the sparse sums' values entry by entry (their exact zeros kept)
            return [csr_array((w_entry * sum(C[i, j] * eps[j].data for j in range(3) if C[i, j] != 0),
                               e.gxx.indices, e.gxx.indptr), shape=e.gxx.shape) for i in range(3)]
        return [csr_array(diags_array(w) @ sum(C[i, j] * eps[j] for j in range(3) if C[i, j] != 0))
                for i in range(3)]

    def product_rows(sig, chunk=131072):  # sum_q B_I^T sig: (2 n_functions, n_extra)
        kx = ky = 0
        for s in range(0, len(w), chunk):  # operators of a chunk of points at a time
            part = slice(s, s + chunk)
            sub = Shape(shape.neighbours.subset(part), None, shape.ddx[part], shape.ddy[part], nf)
            dxT, dyT = csr_array(sub.dx.T), csr_array(sub.dy.T)
            sx, sy, sxy = (csr_array(a[part]) for a in sig)
            kx = kx + dxT @ sx + dyT @ sxy
            ky = ky + dyT @ sy + dxT @ sxy
        return csr_array(vstack([csr_array(kx), csr_array(ky)], format="csr")[interleave])

    def nodal_rows(sig):  # the compiled rows, or the operator products of the reference
        return _extra_compiled(shape, sig, lists) if backend == "numba" else product_rows(sig)

    sig = stresses(D)
    K_ne = nodal_rows(sig)
    K_en = K_ne.T if np.array_equal(D, D.T) else nodal_rows(stresses(D.T)).T  # E^T D B
    if one and backend == "numba":  # the same sums by the compiled pass over the points
        from .enriched_kernels import ee_block

        data = [tuple(np.ascontiguousarray(a.data) for a in v) for v in (eps, sig)]
        K_ee = csr_array(ee_block(e.gxx.indptr, e.gxx.indices, *data, sig[0].shape[1]))
    else:
        K_ee = csr_array(sum(eps[i].T @ sig[i] for i in range(3)))
    return stack_2x2(K_nn, K_ne, csr_array(K_en), K_ee, compiled=backend == "numba")


# K_ne point by point into a dense (n_functions, 2, n_extra) array up to this many entries (64
# MB) with stress rows this full (extrinsic unknowns: all at every point; PU's few: the rows).
DENSE_EXTRA_MAX = 2**23
DENSE_EXTRA_FILL = 0.5


def _extra_compiled(shape: Shape, sig: list, lists: tuple | None = None) -> csr_array:
    """K_ne (2 n_functions, n_extra) = sum_q B_I^T sigma, ``sig`` the weighted stresses (xx,
    yy, xy) of the enrichment unknowns, each (n_points, n_extra): up to
    :data:`DENSE_EXTRA_MAX` entries of stress rows at least :data:`DENSE_EXTRA_FILL` full
    in one pass over the points into a dense array
    (:func:`efgkit.system.enriched_kernels.extra_dense`), else by rows over the functions' point lists
    (``lists`` of :func:`_lists`; :func:`efgkit.system.kernels.extra_rows`, chunks of rows on
    the thread pool); the same sums in the same order, the same K_ne to the bit. Entries
    that sum to exactly zero are dropped, as the sparse products of the reference do."""
    import numba

    from .enriched_kernels import extra_dense
    from .kernels import extra_rows

    n, n_extra = shape.n_functions, sig[0].shape[1]
    csr = [csr_array(a) for a in sig]
    parts3 = [a for c in csr for a in (c.indptr.astype(np.int64, copy=False),
                                       c.indices.astype(np.int32, copy=False),
                                       c.data.astype(float, copy=False))]
    full = max(c.nnz for c in csr) >= DENSE_EXTRA_FILL * csr[0].shape[0] * n_extra
    if full and 2 * n * n_extra <= DENSE_EXTRA_MAX:  # the dense kernel visits every unknown
        nb = shape.neighbours
        out = np.zeros((n, 2, n_extra))
        extra_dense(nb.idx, nb.mask, shape.ddx, shape.ddy, *parts3, out)
        return csr_array(out.reshape(2 * n, n_extra))  # rows 2 I + c; the zeros left out
    threads = numba.get_num_threads()
    t_ptr, t_pos, _ = _lists(shape, threads) if lists is None else lists
    order, chunks = _row_chunks(t_ptr, t_pos, shape.ddx.shape[1], threads)
    parts = _on_threads(lambda r: extra_rows(order, r[0], r[1], t_ptr, t_pos, shape.ddx,
                                             shape.ddy, *parts3, n_extra), chunks, threads)
    lens = np.zeros(n, np.int64)
    lens[order] = np.concatenate([p[0] for p in parts] + [np.zeros(0, np.int64)])
    cols = np.concatenate([p[1] for p in parts] + [np.zeros(0, np.int32)])
    vals = np.concatenate([p[2] for p in parts] + [np.zeros((0, 2))])
    rows = np.repeat(order, lens[order])  # the rows in the order they were formed
    K = csr_array((vals.T.ravel(), (np.concatenate([2 * rows, 2 * rows + 1]),
                                    np.concatenate([cols, cols]))), shape=(2 * n, n_extra))
    K.eliminate_zeros()
    return K


def _petrov_enriched(trial: Shape, test: Shape, w, D, backend) -> csr_array:
    """[K_nn | K_ne], (2 n_test, n_dofs): nodal test functions (MLPG) against the nodal and the
    enrichment trial unknowns; the rows of node I for the enrichment columns are
    ``sum_q w_q B^v_I(x_q)^T D eps(E_e)(x_q)``. The enrichment unknowns' own equations are
    the caller's (:func:`efgkit.methods.local.local_system`)."""
    K_nn = stiffness(_nodal_part(trial), w, D, test=test, backend=backend)
    e = trial.extra
    if e.gxx is None or test.ddx is None:
        raise ValueError("stiffness needs shape-function derivatives (derivatives=True)")
    eps = (e.gxx, e.gyy, csr_array(e.gxy + e.gyx))
    W = diags_array(w)
    sig = [csr_array(W @ sum(D[i, j] * eps[j] for j in range(3) if D[i, j] != 0)) for i in range(3)]
    dxT, dyT = csr_array(test.dx.T), csr_array(test.dy.T)
    nf = test.n_functions
    interleave = np.ravel(np.column_stack([np.arange(nf), nf + np.arange(nf)]))
    kx = csr_array(dxT @ sig[0] + dyT @ sig[2])
    ky = csr_array(dyT @ sig[1] + dxT @ sig[2])
    K_ne = csr_array(vstack([kx, ky], format="csr")[interleave])
    return csr_array(bmat([[K_nn, K_ne]], format="csr"))


def load_vector(shape: Shape, w: np.ndarray, values: np.ndarray) -> np.ndarray:
    """f_I = sum_q w_q phi_I(x_q) t(x_q), seed 003 Eq. (22b); shape (n_dofs,).

    ``values (n_points, 2)`` is the traction (boundary points) or body force.
    """
    nb = shape.neighbours
    v = np.asarray(values, dtype=float)
    f = np.zeros(shape.n_dofs)
    rows, cols = np.nonzero(nb.mask)
    contrib = (w[rows] * shape.values[rows, cols])[:, None] * v[rows]
    I = nb.idx[rows, cols]
    n2 = 2 * shape.n_functions
    f[0:n2:2] = np.bincount(I, contrib[:, 0], minlength=shape.n_functions)
    f[1:n2:2] = np.bincount(I, contrib[:, 1], minlength=shape.n_functions)
    if shape.extra is not None:
        f[n2:] = shape.extra.ux.T @ (w * v[:, 0]) + shape.extra.uy.T @ (w * v[:, 1])
    return f
