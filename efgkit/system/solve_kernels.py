"""Compiled (numba) kernels of the iterative solve: the products, Chebyshev steps and
Gauss-Seidel sweeps that CG with the auxiliary-space preconditioner spends its time in
(:mod:`efgkit.system.compiled_operators` wraps them).

Imported only for systems of :data:`efgkit.system.compiled_operators.COMPILED_MIN_UNKNOWNS`
unknowns and more, so that small solves neither import numba nor compile anything.

The matrices are CSR with unsigned 32-bit column indices and unsigned 64-bit row
pointers: numba emits no negative-index wrap-around code for unsigned indices, which
makes a CSR product as fast as scipy's ``csr_matvec`` (10.5 against 10.8 ms on the 18.2M
non-zeros of the 97k-node cracked plate; 19.6 ms with signed indices). Measured on that
system, one thread (docs/performance.md, solve_stage_notes):

* :func:`symmetric_product` reads the strict upper triangle once for both halves: 6.3
  against 10.8 ms for scipy's product with the full matrix (the product is bound by the
  memory traffic of the matrix, which it halves).
* :func:`chebyshev_step` does one step of the Chebyshev recurrence on two columns in one
  pass over the matrix: 7.1 against 13.1 ms for the six steps of ``Y`` (scipy's
  ``csr_matvecs`` on (n, 2) blocks, then the vector updates).
* :func:`gauss_seidel_sweep`: pyamg's point Gauss-Seidel (its BSR sweep is point-wise too),
  the V-cycle 22 against 41 ms.

The kernels do the same arithmetic as the scipy and pyamg calls they replace, in the same
order except for the symmetric product (each entry of the lower triangle taken from its
transpose): the Chebyshev steps agree to the bit, the V-cycle to 2e-15, the product to
1e-15 relative.
"""

from __future__ import annotations

from numba import njit

from ..timing import watch_compiles

__all__ = ["chebyshev_rows", "chebyshev_step", "csr_product", "gauss_seidel_sweep", "symmetric_product",
           "symmetric_product_part", "upper_counts", "upper_fill"]

watch_compiles()


@njit(cache=True, nogil=True)
def symmetric_product_part(indptr, indices, data, diag, x, y, lo, hi, first):  # pragma: no cover
    """The part of :func:`symmetric_product` of the upper-triangle rows ``lo <= i < hi``, for
    one thread of a row split: into ``y`` (n,), its own buffer, the diagonal term of every row
    if ``first`` (the part with ``lo = 0``), else zeros from ``lo`` on; then each row's sum
    into ``y_i`` and its transposed terms into ``y_j`` (``j > i >= lo``: entries below ``lo``
    are neither written nor read). ``A x`` is the first part's ``y`` plus each further part's
    ``y[lo:]``, added in a fixed order (:class:`~efgkit.system.compiled_operators.SymmetricOperator`)."""
    n = len(diag)
    if first:
        for i in range(n):
            y[i] = diag[i] * x[i]
    else:
        for i in range(lo, n):
            y[i] = 0.0
    for i in range(lo, hi):
        s = 0.0
        xi = x[i]
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            a = data[k]
            s += a * x[j]
            y[j] += a * xi
        y[i] += s


@njit(cache=True, nogil=True)
def symmetric_product(indptr, indices, data, diag, x, y):  # pragma: no cover - compiled
    """``y = A x`` (n,) for symmetric ``A`` given by its strict upper triangle (CSR, sorted or
    not) and its diagonal ``diag`` (n,): ``y_i = d_i x_i + sum_j>i a_ij x_j + sum_j<i a_ji x_j``
    (:func:`symmetric_product_part` on all rows)."""
    symmetric_product_part(indptr, indices, data, diag, x, y, 0, len(diag), True)


@njit(cache=True, nogil=True)
def csr_product(indptr, indices, data, x, y):  # pragma: no cover - compiled
    """``y = A x`` (n,) for CSR ``A``."""
    for i in range(len(indptr) - 1):
        s = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            s += data[k] * x[indices[k]]
        y[i] = s


@njit(cache=True, nogil=True)
def chebyshev_rows(indptr, indices, data, x, res, d, d_next, c_d, c_r, lo, hi):  # pragma: no cover
    """One step of the Chebyshev recurrence on (m, 2) arrays, rows ``lo <= i < hi``: ``x += d``,
    ``res -= F d``, ``d_next = c_d d + c_r res`` (Saad, Alg. 12.1; ``F`` CSR (m, m)). Each row
    reads ``d`` and writes its own row of ``x``, ``res``, ``d_next``: row ranges run on parallel
    threads with the same result to the bit."""
    for i in range(lo, hi):
        s0 = 0.0
        s1 = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            a = data[k]
            s0 += a * d[j, 0]
            s1 += a * d[j, 1]
        x[i, 0] += d[i, 0]
        x[i, 1] += d[i, 1]
        r0 = res[i, 0] - s0
        r1 = res[i, 1] - s1
        res[i, 0] = r0
        res[i, 1] = r1
        d_next[i, 0] = c_d * d[i, 0] + c_r * r0
        d_next[i, 1] = c_d * d[i, 1] + c_r * r1


@njit(cache=True, nogil=True)
def chebyshev_step(indptr, indices, data, x, res, d, d_next, c_d, c_r):  # pragma: no cover
    """:func:`chebyshev_rows` on all rows."""
    chebyshev_rows(indptr, indices, data, x, res, d, d_next, c_d, c_r, 0, len(indptr) - 1)


@njit(cache=True, nogil=True)
def gauss_seidel_sweep(indptr, indices, data, diag_inv, x, b, forward):  # pragma: no cover
    """One Gauss-Seidel sweep on ``A x = b`` in place, rows in increasing (``forward``) or
    decreasing order: ``x_i += (b_i - A_i x) diag_inv_i``; rows with ``diag_inv_i = 0`` (a zero
    diagonal) are left as they are, as pyamg's sweep leaves them."""
    n = len(diag_inv)
    for t in range(n):
        i = t if forward else n - 1 - t
        s = b[i]
        for k in range(indptr[i], indptr[i + 1]):
            s -= data[k] * x[indices[k]]
        x[i] += s * diag_inv[i]


@njit(cache=True, nogil=True)
def upper_counts(indptr, indices, counts):  # pragma: no cover - compiled
    """Entries right of the diagonal in each row of a CSR pattern, into ``counts`` (n,)."""
    for i in range(len(indptr) - 1):
        c = 0
        for k in range(indptr[i], indptr[i + 1]):
            if indices[k] > i:
                c += 1
        counts[i] = c


@njit(cache=True, nogil=True)
def upper_fill(indptr, indices, data, out_indptr, out_indices, out_data, diag):  # pragma: no cover
    """The strict upper triangle of a CSR matrix (signed indices, as scipy's) into ``out_*``
    (signed 64-bit row pointers from :func:`upper_counts`, unsigned 32-bit column indices) and
    its diagonal into ``diag`` (n,) (duplicate diagonal entries summed)."""
    for i in range(len(indptr) - 1):
        p = out_indptr[i]
        d = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            if j > i:
                out_indices[p] = j
                out_data[p] = data[k]
                p += 1
            elif j == i:
                d += data[k]
        diag[i] = d
