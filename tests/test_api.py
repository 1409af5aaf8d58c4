"""The public API is explicit, and the code base stays lint-clean."""

import shutil
import subprocess
from pathlib import Path

import pytest

import efgkit


def test_every_name_in_all_resolves():
    assert efgkit.__all__ == sorted(efgkit.__all__)
    for name in efgkit.__all__:
        assert getattr(efgkit, name) is not None, name


def test_version_is_a_string():
    assert isinstance(efgkit.__version__, str) and efgkit.__version__


@pytest.mark.skipif(shutil.which("ruff") is None, reason="ruff is a test extra")
def test_ruff_clean():
    root = Path(__file__).resolve().parents[1]
    res = subprocess.run(["ruff", "check", "efgkit", "tests", "verification", "benchmarks"],
                         cwd=root, capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
