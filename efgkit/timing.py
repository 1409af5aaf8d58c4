"""Wall time per stage, with numba's compilation as a stage of its own.

A kernel compiles (or loads from numba's cache) the first time a stage calls it with new
argument types; that time belongs to no stage of the computation, so a
:class:`Stopwatch` moves it out of the stage that happened to trigger it into the stage
``"compile"``. Numba reports it through its ``numba:compiler_lock`` events, which wrap
type inference, code generation and cache loading; nested events are counted once.
"""

from __future__ import annotations

import sys
import threading
import time
from contextlib import contextmanager

__all__ = ["COMPILE", "Stopwatch", "compile_seconds", "watch_compiles"]

COMPILE = "compile"

_CLOCK = []  # the listener, once numba is imported (a plain run never imports it)


def watch_compiles() -> None:
    """Start counting numba's compile time (idempotent). The compiled-kernel modules call it
    when they are imported, before anything of theirs compiles; numba itself is imported only
    there, so that runs without compiled kernels start without it."""
    if _CLOCK:
        return
    from numba.core import event

    class CompileClock(event.Listener):
        """Seconds spent holding numba's compiler lock, outermost acquisitions only."""

        def __init__(self):
            self.seconds = 0.0
            self._local = threading.local()

        def on_start(self, ev):
            depth = getattr(self._local, "depth", 0)
            if depth == 0:
                self._local.t0 = time.perf_counter()
            self._local.depth = depth + 1

        def on_end(self, ev):
            self._local.depth -= 1
            if self._local.depth == 0:
                self.seconds += time.perf_counter() - self._local.t0

    _CLOCK.append(CompileClock())
    event.register("numba:compiler_lock", _CLOCK[0])


def compile_seconds() -> float:
    """Seconds this process has spent in numba's compiler (and cache loading) so far."""
    if not _CLOCK and "numba" in sys.modules:  # imported by someone else: count from now
        watch_compiles()
    return _CLOCK[0].seconds if _CLOCK else 0.0


class Stopwatch:
    """Seconds per named stage; numba compilation inside a stage goes to ``"compile"``.

    The stages (compile included) add up to the wall time of the timed blocks.

    Examples
    --------
    >>> sw = Stopwatch()
    >>> with sw.stage("sleep"):
    ...     time.sleep(0.01)
    >>> sw.timings["sleep"] >= 0.009, sw.timings.get("compile", 0.0) == 0.0
    (True, True)
    """

    def __init__(self, timings: dict | None = None):
        self.timings = {} if timings is None else dict(timings)
        self._t, self._c = time.perf_counter(), compile_seconds()

    def lap(self, name: str) -> None:
        """Add the time since the last lap (or the start) to stage ``name``, its numba
        compilation to ``"compile"``."""
        t, c = time.perf_counter(), compile_seconds()
        self.add(name, t - self._t - (c - self._c))
        if c > self._c:
            self.add(COMPILE, c - self._c)
        self._t, self._c = t, c

    def merge(self, timings: dict) -> None:
        """Add the stages of a timed call made since the last lap (its ``"total"`` left
        out) and start the next lap now."""
        for k, v in timings.items():
            if k != "total":
                self.add(k, v)
        self._t, self._c = time.perf_counter(), compile_seconds()

    def add(self, name: str, seconds: float) -> None:
        self.timings[name] = self.timings.get(name, 0.0) + seconds

    @contextmanager
    def stage(self, name: str):
        t0, c0 = time.perf_counter(), compile_seconds()
        try:
            yield
        finally:
            t, c = time.perf_counter(), compile_seconds()
            self.add(name, t - t0 - (c - c0))
            if c > c0:
                self.add(COMPILE, c - c0)
            self._t, self._c = t, c  # the next lap starts here
