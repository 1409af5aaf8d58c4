"""Verification scripts run in quick mode, so they never rot; each must pass its checks."""

import importlib.util
import sys
from pathlib import Path

import pytest

VERIFICATION = Path(__file__).resolve().parents[1] / "verification"
SCRIPTS = sorted(p for p in VERIFICATION.glob("*.py") if not p.name.startswith("_"))
if str(VERIFICATION) not in sys.path:  # the scripts import their siblings (_report), as the CLI
    sys.path.insert(0, str(VERIFICATION))  # lets them


def load(path):
    spec = importlib.util.spec_from_file_location(f"verification_{path.stem}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.filterwarnings("ignore:bc='modified_mls'")
@pytest.mark.parametrize("path", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_quick(path, tmp_path):
    res = load(path).main(quick=True, out_dir=tmp_path)
    assert res["name"] == path.stem
    assert (tmp_path / f"{path.stem}_quick.json").exists()
    failed = [c for c in res["checks"] if not c["passed"]]
    assert not failed, failed
    for key, ref in res["reference"].items():
        assert ref["source"], key  # every reference value carries its source
