"""Timing in turns for the benchmarks: variants run one after the other in every round (A, B,
A, B, ...), so that a shared machine's drift falls on all of them alike, and the bootstrap
interval of a median ratio of two of them."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

__all__ = ["take_turns", "median_interval"]


def take_turns(runs: dict[str, Callable[[], object]], rounds: int) -> dict[str, list[float]]:
    """Seconds (time.perf_counter) of each call of ``runs``, the variants taking turns for
    ``rounds`` rounds: ``{name: [s per round]}``."""
    times = {k: [] for k in runs}
    for _ in range(rounds):
        for k, fn in runs.items():
            t0 = time.perf_counter()
            fn()
            times[k].append(time.perf_counter() - t0)
    return times


def median_interval(ratio, rng: np.random.Generator) -> tuple[float, float]:
    """The 90 % bootstrap interval (2000 resamples) of the median of ``ratio``."""
    ratio = np.asarray(ratio)
    boot = np.median(rng.choice(ratio, size=(2000, len(ratio)), replace=True), axis=1)
    lo, hi = np.quantile(boot, [0.05, 0.95])
    return float(lo), float(hi)
