"""Fresh memory for outputs written once (efgkit.memory): small_pages switches numpy's
huge-page advice off for a block only, restoring the caller's setting and leaving a user's
explicit choice alone; fresh_array allocates within it."""

import numpy as np
import pytest

import efgkit.memory as memory
from efgkit.memory import fresh_array, small_pages

advice = pytest.importorskip("numpy._core.multiarray")._set_madvise_hugepage


def _advising() -> bool:
    """numpy's current huge-page advice (read by setting it back)."""
    now = advice(True)
    advice(now)
    return now


def test_fresh_array_allocates_with_the_advice_off(monkeypatch):
    monkeypatch.delenv("NUMPY_MADVISE_HUGEPAGE", raising=False)
    flags = []

    def switch(flag):  # numpy's switch, recorded: flag -> the previous flag
        flags.append(flag)
        return True

    monkeypatch.setattr(memory, "_advice_switch", lambda: switch)
    a = fresh_array((3, 2), np.int32)
    assert a.shape == (3, 2) and a.dtype == np.int32 and a.flags.writeable
    assert flags == [False, True]  # off for the allocation, then the caller's setting back


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
