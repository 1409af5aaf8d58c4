"""When efgkit runs its compiled (numba) kernels and when their plain-numpy twins.

Compiling a kernel costs seconds (tens on a loaded machine) the first time it is used
after installation, and is cached after that; the compiled kernel saves about 10 us per
point over numpy. Below COMPILED_MIN points (the quick-start example has 36k) a run is
faster without compiling anything, so ``backend="auto"`` takes numpy there: the
quick-start examples start without a compile, and large problems, where the kernels
pay, compile them once.
"""

from __future__ import annotations

__all__ = ["BACKENDS", "COMPILED_MIN", "resolve_backend"]

BACKENDS = ("auto", "numba", "numpy")
COMPILED_MIN = 50_000


def resolve_backend(backend: str, n_points: int) -> str:
    """``"numba"`` or ``"numpy"`` for ``backend`` on ``n_points`` points.

    Examples
    --------
    >>> resolve_backend("auto", 1000), resolve_backend("auto", 10**6), resolve_backend("numba", 1)
    ('numpy', 'numba', 'numba')
    """
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
    if backend == "auto":
        return "numba" if n_points >= COMPILED_MIN else "numpy"
    return backend
