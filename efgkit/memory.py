"""Memory of the machine and the size guard: estimates of a peak allocation checked
against what is available, refused before anything is allocated (:mod:`efgkit.nodes`,
:mod:`efgkit.methods.discretize`, :mod:`efgkit.methods.local`)."""

from __future__ import annotations

import math
import os

__all__ = ["ALWAYS_ALLOWED", "FALLBACK_MEMORY", "available_memory", "check_memory"]

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
