"""Memory of the machine and the size guard: estimates of a peak allocation checked
against what is available, refused before anything is allocated (:mod:`efgkit.nodes`,
:mod:`efgkit.methods.discretize`, :mod:`efgkit.methods.local`); and fresh memory for large
outputs written once (:func:`fresh_array`, :func:`small_pages`)."""

from __future__ import annotations

import contextlib
import functools
import math
import os

import numpy as np

__all__ = ["ALWAYS_ALLOWED", "FALLBACK_MEMORY", "available_memory", "check_memory", "fresh_array",
           "small_pages"]

FALLBACK_MEMORY = 8e9  # bytes assumed available when the machine does not say
ALWAYS_ALLOWED = 2e9  # estimates below this pass whatever the machine reports


def available_memory() -> tuple[float, str]:
    """Bytes of memory a new allocation can take, and where the figure comes from:
    ``MemAvailable`` of ``/proc/meminfo`` (capped by a cgroup v2 ``memory.max``), else
    ``os.sysconf`` free pages, else :data:`FALLBACK_MEMORY`."""
    found = None
    try:
        with open("/proc/meminfo") as f:
            kb = [line.split()[1] for line in f if line.startswith("MemAvailable:")]
        found = float(kb[0]) * 1024, "MemAvailable in /proc/meminfo"
    except (OSError, ValueError, IndexError):
        try:
            found = (float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")),
                     "free pages from os.sysconf")
        except (AttributeError, ValueError, OSError):
            return FALLBACK_MEMORY, "a fixed limit: this machine does not report its memory"
    try:  # a container's limit
        with open("/sys/fs/cgroup/memory.max") as f, open("/sys/fs/cgroup/memory.current") as g:
            free = float(f.read()) - float(g.read())  # ValueError for "max": no limit
        if free < found[0]:
            found = max(free, 0.0), "the cgroup's memory.max"
    except (OSError, ValueError):
        pass
    return found


def check_memory(need: float, what: str, remedy: str) -> None:
    """Raise ValueError if the estimated peak ``need`` (bytes) exceeds :func:`available_memory`;
    below :data:`ALWAYS_ALLOWED` it always passes. The message is ``what`` (what was estimated
    from which arguments), the memory, then ``remedy``, where ``{factor}`` becomes the
    coarsening that would fit (memory falls like spacing^2)."""
    if need <= ALWAYS_ALLOWED:
        return
    have, source = available_memory()
    if need > have:
        factor = math.sqrt(need / max(have, ALWAYS_ALLOWED))
        raise ValueError(f"{what}: about {need / 1e9:.3g} GB in all, more than the "
                         f"{have / 1e9:.3g} GB of memory available ({source}). "
                         + remedy.format(factor=factor))


def fresh_array(shape, dtype) -> np.ndarray:
    """An uninitialised array of ``shape`` and ``dtype`` for a large output written once,
    allocated within :func:`small_pages`: numpy advises Linux to back arrays of 4 MB and more
    with transparent huge pages, and with the common ``madvise`` setting the first write to
    fresh memory then waits whenever the kernel must compact memory into huge pages, while
    4 kB pages fault in at a steady rate (the quadrature's 2.9M points and the chunks' sum of
    the streamed stiffness: docs/performance.md, stage_slopes_notes).

    Examples
    --------
    >>> a = fresh_array((2**21, 2), np.float64)
    >>> a.shape, a.dtype.name, a.flags.writeable, fresh_array(3, np.int32).shape
    ((2097152, 2), 'float64', True, (3,))
    """
    with small_pages():
        return np.empty(shape, dtype)


@contextlib.contextmanager
def small_pages():
    """Within the block numpy does not advise Linux to back its new arrays with transparent
    huge pages; its setting before is restored after, and left alone if the user chose it
    (the ``NUMPY_MADVISE_HUGEPAGE`` environment variable) or numpy cannot switch it.

    For loops that write much fresh memory once, such as the streamed stiffness: every chunk's
    K_c is kept until the chunks' sum, so the heap grows by all of them. Under the common
    ``defrag=madvise`` setting a first write to advised memory waits while the kernel compacts
    memory into 2 MB pages: on the cracked plate at 97k nodes, 40-45k faults cost 0.33-0.59 s
    of system time in the 12 K_c, against 104-107k faults of 4 kB pages in 0.23-0.25 s within
    this block, with the same user time (docs/performance.md, stage_slopes_notes).

    Examples
    --------
    >>> with small_pages():
    ...     a = np.ones(2**20)  # 8 MB, not advised
    """
    switch = _advice_switch()
    if switch is None or "NUMPY_MADVISE_HUGEPAGE" in os.environ:
        yield
        return
    before = switch(False)
    try:
        yield
    finally:
        switch(before)


@functools.cache
def _advice_switch():
    """numpy's switch of its huge-page advice (``flag -> previous flag``), or None."""
    try:
        from numpy._core.multiarray import _set_madvise_hugepage
    except ImportError:  # numpy < 2
        try:
            from numpy.core.multiarray import _set_madvise_hugepage
        except ImportError:
            return None
    return _set_madvise_hugepage
