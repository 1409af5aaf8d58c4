"""Fresh memory for outputs written once (efgkit.memory): fresh_array maps its own memory
from FRESH_MIN_BYTES on, and small_pages switches numpy's huge-page advice off for a block
only, restoring the caller's setting and leaving a user's explicit choice alone."""

import mmap

import numpy as np
import pytest

from efgkit.memory import FRESH_MIN_BYTES, fresh_array, small_pages

advice = pytest.importorskip("numpy._core.multiarray")._set_madvise_hugepage


def _advising() -> bool:
    """numpy's current huge-page advice (read by setting it back)."""
    now = advice(True)
    advice(now)
    return now


def _mapped(a: np.ndarray) -> bool:
    """Whether the memory under ``a`` is a memory map of its own."""
    while isinstance(a, np.ndarray):
        a = a.base
    return isinstance(a, memoryview) and isinstance(a.obj, mmap.mmap)


def test_fresh_array_maps_large_outputs_only():
    big = fresh_array(FRESH_MIN_BYTES // 8, np.float64)
    small = fresh_array((FRESH_MIN_BYTES // 8 - 1,), np.float64)
    assert _mapped(big) and not _mapped(small)
    big[:] = 1.5  # writable
    assert big.shape == (FRESH_MIN_BYTES // 8,) and float(big.sum()) == 1.5 * big.size


def test_small_pages_switches_the_advice_off_within_the_block_only(monkeypatch):
    monkeypatch.delenv("NUMPY_MADVISE_HUGEPAGE", raising=False)
    before = advice(True)
    try:
        with small_pages():
            assert _advising() is False
        assert _advising() is True
        with pytest.raises(RuntimeError), small_pages():  # restored on an error too
            raise RuntimeError
        assert _advising() is True
        advice(False)
        with small_pages():
            pass
        assert _advising() is False  # the caller's setting, whatever it was
    finally:
        advice(before)


def test_small_pages_leaves_a_users_choice_alone(monkeypatch):
    monkeypatch.setenv("NUMPY_MADVISE_HUGEPAGE", "1")
    before = advice(True)
    try:
        with small_pages():
            assert _advising() is True
    finally:
        advice(before)
