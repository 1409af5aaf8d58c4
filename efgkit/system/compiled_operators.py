"""Compiled operators of the iterative solve: the product with a symmetric matrix from its
upper triangle, the Chebyshev polynomial ``Y ~ Phi^-1`` and the multigrid V-cycle of the
auxiliary-space preconditioner (:mod:`efgkit.system.auxiliary`), on the numba kernels of
:mod:`efgkit.system.solve_kernels`.

Each does what its scipy / pyamg counterpart does (:func:`~efgkit.system.auxiliary.chebyshev_inverse`,
:func:`~efgkit.system.auxiliary.vcycle`, ``A @ x``) to round-off, in 0.5-0.6 of the time on
the 97k-node cracked plate (docs/performance.md, solve_stage_notes). They are taken for
systems of :data:`COMPILED_MIN_UNKNOWNS` unknowns and more (:func:`use_compiled`): below
that a solve is over before a first compilation (seconds, cached on disk after it) pays.

The product with ``A`` and the Chebyshev steps run on :func:`solve_threads` threads (numba's
``NUMBA_NUM_THREADS``, as the stiffness assembly; one if :data:`THREADED` is off): rows split
into one contiguous range per thread with equal numbers of stored entries, each range a
GIL-free kernel call, the first on the calling thread. The split depends on the thread count
only: the Chebyshev steps are row by row (the same to the bit on any thread count). With
:data:`THREADED` the product's rows are split into :data:`PRODUCT_PARTS` ranges on every
thread count (one thread runs them in turn), each summed into its own buffer, the buffers
added in a fixed order: the same to the bit on one thread and on two; against the one pass of
:func:`~efgkit.system.solve_kernels.symmetric_product` (``THREADED`` off) it
differs by round-off, ~1e-16 relative (at 97k nodes: CG 89 against 87 iterations, the
coefficients 2.9e-11 apart). The preconditioner stays a fixed linear operator; the thread
count never changes the result. The Gauss-Seidel sweeps of the V-cycle stay on one thread
(their order defines the smoother); its residual and transfer products are split by rows too
(row by row: the same to the bit).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array

__all__ = ["COMPILED_MIN_UNKNOWNS", "PRODUCT_PARTS", "SYMMETRY_TOL", "THREADED", "CompiledChebyshev",
           "CompiledVcycle", "SymmetricOperator", "on_threads", "product_operator", "row_split",
           "solve_threads", "sweeps_of", "use_compiled"]

# The iterative solves start at linalg.AUTO_AMG_THRESHOLD (20,000) unknowns under "auto".
COMPILED_MIN_UNKNOWNS = 20_000
SYMMETRY_TOL = 1e-12  # relative difference of A v from its upper triangle's (round-off: ~1e-15)
_SWEEPS = {"symmetric": (True, False), "forward": (True,), "backward": (False,)}
# Products with A and Chebyshev steps on numba.get_num_threads() threads (False: one thread).
# On by default: over 26 rounds on this shared 2-core machine (load 0.3-2.7) two threads took
# 0.76-1.15 of the one-thread solve stage, median 0.94 (CG 0.98); 0.83 at load < 1.9, but 1.03
# at load >= 1.9, when other jobs hold the second core (benchmarks/solve_threads.py;
# docs/performance.md, solve_stage_notes). Off: the one-pass product, as before.
THREADED = True
# Row ranges of the product with A when THREADED, on any thread count (one thread runs them in
# turn): the same sums, so the same result to the bit, on one thread and on two.
PRODUCT_PARTS = 2
_POOL: dict = {}


def solve_threads() -> int:
    """Threads of the product with ``A`` and the Chebyshev steps: ``numba.get_num_threads()``
    (``NUMBA_NUM_THREADS``) if :data:`THREADED`, else 1."""
    import numba

    return max(1, int(numba.get_num_threads())) if THREADED else 1


def row_split(indptr: np.ndarray, parts: int) -> np.ndarray:
    """Bounds (parts + 1,) of ``parts`` contiguous row ranges of a CSR matrix with row pointers
    ``indptr`` (n + 1,), with about equal numbers of stored entries each.

    Examples
    --------
    >>> row_split(np.array([0, 4, 5, 6, 7, 8]), 2).tolist()
    [0, 1, 5]
    """
    indptr = np.asarray(indptr, dtype=np.int64)
    bounds = np.searchsorted(indptr, np.arange(parts + 1) * (indptr[-1] / parts), side="left")
    bounds = np.clip(bounds, 0, len(indptr) - 1)
    bounds[0], bounds[-1] = 0, len(indptr) - 1
    return np.maximum.accumulate(bounds)


def on_threads(calls: list, threads: int | None = None) -> None:
    """Run the callables ``calls``: one after the other on this thread if ``threads`` is 1, else
    the first on this thread and the others on a pool's threads (the kernels release the GIL);
    returns when all have."""
    if len(calls) == 1 or threads == 1:
        for c in calls:
            c()
        return
    k = len(calls) - 1
    if k not in _POOL:
        from concurrent.futures import ThreadPoolExecutor

        _POOL[k] = ThreadPoolExecutor(k, thread_name_prefix="efgkit-solve")
    futures = [_POOL[k].submit(c) for c in calls[1:]]
    calls[0]()
    for f in futures:
        f.result()


def use_compiled(n: int) -> bool:
    """Whether a solve of ``n`` unknowns runs on the compiled operators (from
    :data:`COMPILED_MIN_UNKNOWNS` to 2**32 - 1 unknowns: their column indices are 32-bit).

    Examples
    --------
    >>> use_compiled(1_000), use_compiled(200_000)
    (False, True)
    """
    return COMPILED_MIN_UNKNOWNS <= n < 2**32


def _unsigned(M: csr_array) -> tuple[np.ndarray, np.ndarray]:
    """Row pointers (uint64) and column indices (uint32) of the CSR matrix ``M``."""
    return M.indptr.astype(np.uint64), M.indices.astype(np.uint32)


class SymmetricOperator:
    """``x -> A x`` for a symmetric sparse ``A`` (n, n), stored as its strict upper triangle
    (unsigned 32-bit indices) and its diagonal: half the memory traffic of a CSR product.
    With :data:`THREADED` its row ranges share buffers: one product at a time per operator.

    Attributes
    ----------
    shape : (n, n)
    dtype : float64

    Examples
    --------
    >>> A = csr_array(np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 2.0], [0.0, 2.0, 5.0]]))
    >>> (SymmetricOperator(A) @ np.ones(3)).tolist()
    [5.0, 6.0, 7.0]
    """

    def __init__(self, A):
        from .solve_kernels import upper_counts, upper_fill

        A = csr_array(A)
        n = A.shape[0]
        if A.shape != (n, n):
            raise ValueError(f"A must be square, got shape {A.shape}")
        counts = np.zeros(n, dtype=np.int64)
        upper_counts(A.indptr, A.indices, counts)
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(counts, out=indptr[1:])
        self.indices = np.empty(indptr[-1], dtype=np.uint32)
        self.data = np.empty(indptr[-1])
        self.diag = np.empty(n)
        upper_fill(A.indptr, A.indices, A.data, indptr, self.indices, self.data, self.diag)
        self.indptr = indptr.astype(np.uint64)
        self.shape, self.dtype = (n, n), np.dtype(float)
        self._splits: dict = {}

    def _split(self, parts: int) -> tuple:
        """Row bounds and one buffer per further part (its sums), per number of parts."""
        if parts not in self._splits:
            self._splits[parts] = (row_split(self.indptr, parts).tolist(),
                                   [np.empty(self.shape[0]) for _ in range(parts - 1)])
        return self._splits[parts]

    def diagonal(self) -> np.ndarray:
        """The diagonal of ``A`` (n,)."""
        return self.diag

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        """``A x`` (n,): one pass over the upper triangle, or if :data:`THREADED` its
        :data:`PRODUCT_PARTS` row ranges, each into its own buffer, on :func:`solve_threads`
        threads, the buffers added in a fixed order."""
        from .solve_kernels import symmetric_product, symmetric_product_part

        x = np.ascontiguousarray(x, dtype=float)
        y = np.empty_like(x)
        parts = max(1, min(PRODUCT_PARTS, self.shape[0])) if THREADED else 1
        if parts == 1:
            symmetric_product(self.indptr, self.indices, self.data, self.diag, x, y)
            return y
        bounds, extra = self._split(parts)
        outs = [y, *extra]
        args = (self.indptr, self.indices, self.data, self.diag, x)
        on_threads([lambda t=t: symmetric_product_part(*args, outs[t], bounds[t], bounds[t + 1], t == 0)
                    for t in range(parts)], solve_threads())
        for t in range(1, parts):  # fixed order: the same sums on every call and thread count
            lo = bounds[t]
            y[lo:] += extra[t - 1][lo:]
        return y

    matvec = __matmul__


def product_operator(A):
    """The product CG takes for the sparse matrix ``A`` (n, n): ``A`` itself below
    :data:`COMPILED_MIN_UNKNOWNS` unknowns, else its :class:`SymmetricOperator` (the SPD
    systems and the augmented stiffness of the Uzawa steps are symmetric; 6.3 against 10.8 ms
    per product at 97k nodes), unless its product with a random vector differs from the upper
    triangle's by more than :data:`SYMMETRY_TOL` (relative): a matrix that is not symmetric
    keeps its own product."""
    if not use_compiled(A.shape[0]):
        return A
    S = SymmetricOperator(A)
    v = np.random.default_rng(0).uniform(-1.0, 1.0, A.shape[0])
    Av = A @ v
    return S if np.abs(S @ v - Av).max() <= SYMMETRY_TOL * np.abs(Av).max() else A


class CompiledChebyshev:
    """``r -> p(F) r`` on (m, 2) blocks: the polynomial of
    :func:`~efgkit.system.auxiliary.chebyshev_inverse` (same steps, same coefficients; the
    result agrees to the bit), each step one pass over ``F`` (CSR (m, m))."""

    def __init__(self, F, degree: int, interval):
        F = csr_array(F)
        F.sort_indices()
        self.indptr, self.indices = _unsigned(F)
        self.data, self.degree = F.data, degree
        self.interval = tuple(float(v) for v in interval)
        self._splits: dict = {}

    def __call__(self, r: np.ndarray) -> np.ndarray:
        from .solve_kernels import chebyshev_rows, chebyshev_step

        threads = solve_threads()
        if threads > 1 and threads not in self._splits:
            self._splits[threads] = row_split(self.indptr, threads).tolist()
        bounds = self._splits.get(threads)
        a, b = self.interval
        theta, delta = (b + a) / 2, (b - a) / 2
        sigma = theta / delta
        rho = 1 / sigma
        res = np.array(r, dtype=float, order="C")
        x = np.zeros_like(res)
        d = res / theta
        d_next = np.empty_like(d)
        for _ in range(self.degree):
            rho_new = 1 / (2 * sigma - rho)
            args = (self.indptr, self.indices, self.data, x, res, d, d_next, rho_new * rho,
                    2 * rho_new / delta)
            if threads == 1:
                chebyshev_step(*args)
            else:
                on_threads([lambda a=args, lo=bounds[t], hi=bounds[t + 1]: chebyshev_rows(*a, lo, hi)
                             for t in range(threads)])
            d, d_next = d_next, d
            rho = rho_new
        return x


class _Level:
    """A level of a pyamg hierarchy as CSR with unsigned indices (explicit zeros dropped)."""

    def __init__(self, level):
        A = csr_array(level.A)
        A.eliminate_zeros()
        A.sort_indices()
        self.indptr, self.indices = _unsigned(A)
        self.data = A.data
        d = A.diagonal()
        self.diag_inv = np.divide(1.0, d, out=np.zeros_like(d), where=d != 0)
        self.P = _csr_unsigned(level.P)
        self.R = _csr_unsigned(level.R)


def _csr_unsigned(M):
    M = csr_array(M)
    M.eliminate_zeros()
    return (*_unsigned(M), M.data, M.shape[0])


def _product(M, x):
    """``M x`` for ``M`` from :func:`_csr_unsigned`, rows split over :func:`solve_threads`
    threads (each row's sum as on one thread: the same result to the bit)."""
    from .solve_kernels import csr_product

    indptr, indices, data, rows = M
    y = np.empty(rows)
    threads = solve_threads()
    if threads == 1:
        csr_product(indptr, indices, data, x, y)
        return y
    b = row_split(indptr, threads).tolist()
    on_threads([lambda lo=lo, hi=hi: csr_product(indptr[lo:hi + 1], indices, data, x, y[lo:hi])
                for lo, hi in zip(b[:-1], b[1:], strict=True)])
    return y


def sweeps_of(presmoother, postsmoother) -> list:
    """The Gauss-Seidel sweeps of pyamg smoother options, per level: ``[(pre, post), ...]``
    with ``pre`` / ``post`` tuples of sweep directions (True: forward), the last entry for all
    deeper levels as in pyamg. Only Gauss-Seidel without iterations or omega is taken.

    Examples
    --------
    >>> sweeps_of([("gauss_seidel", {"sweep": "symmetric"}), ("gauss_seidel", {"sweep": "forward"})],
    ...           ("gauss_seidel", {"sweep": "backward"}))
    [((True, False), (False,)), ((True,), (False,))]
    """
    def listed(spec):
        return list(spec) if isinstance(spec, list) else [spec]

    pre, post = listed(presmoother), listed(postsmoother)
    out = []
    for i in range(max(len(pre), len(post))):
        pair = []
        for spec in (pre[min(i, len(pre) - 1)], post[min(i, len(post) - 1)]):
            name, opts = spec if isinstance(spec, tuple) else (spec, {})
            if name != "gauss_seidel" or set(opts) - {"sweep"}:
                raise ValueError(f"the compiled V-cycle runs Gauss-Seidel sweeps only, got {spec!r}: "
                                 "use auxiliary.vcycle for other smoothers")
            pair.append(_SWEEPS[opts.get("sweep", "forward")])
        out.append(tuple(pair))
    return out


class CompiledVcycle:
    """``b -> V b``: one V-cycle of a pyamg smoothed-aggregation hierarchy from a zero guess
    with Gauss-Seidel sweeps before and after the coarse correction, as
    :func:`~efgkit.system.auxiliary.vcycle` runs it (pyamg's BSR sweeps are point-wise: the
    same sweeps on the CSR form of each level). ``sweeps``: per level ``(pre, post)``, each a
    tuple of sweep directions (True: forward), the last entry for the deeper levels
    (:func:`sweeps_of`); by default symmetric sweeps on both sides of every level. The cycle is
    symmetric when each level's ``post`` is its ``pre`` reversed and turned around."""

    def __init__(self, levels, coarse, sweeps=(((True, False), (True, False)),)):
        self.levels = [_Level(lv) for lv in levels[:-1]]
        self.coarse = coarse
        self.sweeps = [tuple(tuple(bool(f) for f in s) for s in pair) for pair in sweeps]

    def __call__(self, b: np.ndarray, i: int = 0) -> np.ndarray:
        from .solve_kernels import gauss_seidel_sweep

        if i == len(self.levels):
            return self.coarse.solve(b)
        lv = self.levels[i]
        b = np.ascontiguousarray(b, dtype=float)
        x = np.zeros_like(b)
        args = (lv.indptr, lv.indices, lv.data, lv.diag_inv, x, b)
        pre, post = self.sweeps[min(i, len(self.sweeps) - 1)]
        for forward in pre:
            gauss_seidel_sweep(*args, forward)
        r = b - _product((lv.indptr, lv.indices, lv.data, len(b)), x)
        x += _product(lv.P, self(_product(lv.R, r), i + 1))
        for forward in post:
            gauss_seidel_sweep(*args, forward)
        return x
