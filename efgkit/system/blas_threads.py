"""BLAS threads of the solves: one thread where BLAS works on vectors only.

CG, the preconditioner's set-up and the dense Cholesky of small systems call BLAS on
vectors or tiny matrices, where a second thread gains microseconds, while OpenBLAS's threads
spin between the calls and stall when the cores are busy (docs/performance.md,
solve_stage_notes and work_interleaved_notes).
"""

from __future__ import annotations

import contextlib
import functools

__all__ = ["SINGLE_BLAS_THREAD", "one_blas_thread", "single_blas_thread"]

SINGLE_BLAS_THREAD = True  # the iterative solves run with one BLAS thread (single_blas_thread)


@functools.cache
def _controller():
    """threadpoolctl's controller of the loaded BLAS libraries, found once per process (~8 ms;
    its ``limit`` then costs microseconds, a fresh ``threadpool_limits`` ~0.7 ms a call)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def one_blas_thread():
    """A context in which BLAS runs on one thread (the dense Cholesky of small systems)."""
    return _controller().limit(limits=1, user_api="blas")


def single_blas_thread():
    """:func:`one_blas_thread` for the iterative solves (a null context with
    :data:`SINGLE_BLAS_THREAD` off, the comparison runs of benchmarks/solve_stage.py).

    CG and the preconditioner's set-up call BLAS only on vectors (dot products, norms, the
    Arnoldi steps of pyamg's spectral-radius estimates), where a second thread gains
    microseconds, but OpenBLAS's threads spin between calls and stall when the cores are busy:
    on the 2-core machine shared with other jobs the Uzawa solve of the cracked plate (97k
    nodes) took 24-25 s of CPU in 13-15 s with two threads against 13-16 s in the same wall time
    with one, and pyamg's set-up 1.0-5.6 s against 0.5-1.4 s (docs/performance.md,
    solve_stage_notes)."""
    if not SINGLE_BLAS_THREAD:
        return contextlib.nullcontext()
    return one_blas_thread()
